// Unit tests for the HDF5 checkpoint: bitwise round trip of every field and the metadata, atomic
// replacement (no .tmp left, the previous checkpoint survives a failed write), and an InputError naming the
// file and the problem for every kind of bad input.
#include "io/checkpoint.hpp"
#include "solver/errors.hpp"
#include "solver/model/model.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <hdf5.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace vitrum {
namespace {

namespace fs = std::filesystem;
using testing::readStores;
using testing::writeStores;

/// A small bonded lattice with every field of both stores overwritten by random values (bond ends stay
/// valid particle indices), plus a few special doubles whose bits a lossy path would change.
Model perturbedModel(std::uint64_t seed) {
    Scene scene;
    scene.sample.shape = SampleShape::Box;
    scene.sample.size = Vec3(4, 4, 4);
    scene.sample.particles = 200;
    scene.source_path = "<test>";
    Model m = buildModel(scene, 1.0);

    std::mt19937_64 rng(seed);
    std::normal_distribution<double> gauss(0.0, 1.0);
    const auto randomise = [&](const Field&, auto& values) {
        using T = typename std::decay_t<decltype(values)>::value_type;
        for (T& v : values) {
            if constexpr (std::is_floating_point_v<T>) {
                v = gauss(rng);
            } else {
                v = static_cast<T>(rng());
            }
        }
    };
    forEachField(m.particles, randomise);
    const std::vector<std::int32_t> i = m.bonds.i;
    const std::vector<std::int32_t> j = m.bonds.j;
    forEachField(m.bonds, randomise);
    m.bonds.i = i;
    m.bonds.j = j;

    std::vector<double>& v = m.particles.velocity;
    v.at(0) = -0.0;
    v.at(1) = std::numeric_limits<double>::denorm_min();
    v.at(2) = std::numeric_limits<double>::infinity();
    v.at(3) = std::numeric_limits<double>::quiet_NaN();
    return m;
}

CheckpointMeta sampleMeta() {
    CheckpointMeta meta;
    meta.step = 123456789012LL;
    meta.time = 1.0 / 3.0;
    meta.dt = 2.718281828459045e-5;
    meta.scene_name = "indent-vickers-ε";
    meta.scene_sha256 = "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad";
    meta.vitrum_version = "0.1.0";
    return meta;
}

/// (name, raw bytes) of every field, through the same table the checkpoint uses; checkpoint.cpp asserts at
/// compile time that the table covers every member of the stores.
template <class Store> std::vector<std::pair<std::string, std::string>> fieldBytes(const Store& store) {
    std::vector<std::pair<std::string, std::string>> out;
    forEachField(store, [&](const Field& field, const auto& values) {
        out.emplace_back(field.name, std::string(reinterpret_cast<const char*>(values.data()),
                                           values.size() * sizeof(values[0])));
    });
    return out;
}

void expectSameState(const Particles& p, const Bonds& b, const Particles& q, const Bonds& c) {
    ASSERT_EQ(p.size(), q.size());
    ASSERT_EQ(b.size(), c.size());
    const auto pa = fieldBytes(p), pb = fieldBytes(q), ba = fieldBytes(b), bb = fieldBytes(c);
    for (std::size_t k = 0; k < pa.size(); ++k) {
        EXPECT_TRUE(pa[k].second == pb[k].second) << "particle field " << pa[k].first << " differs";
    }
    for (std::size_t k = 0; k < ba.size(); ++k) {
        EXPECT_TRUE(ba[k].second == bb[k].second) << "bond field " << ba[k].first << " differs";
    }
}

/// Runs `read` and expects an InputError whose message contains every one of `parts`.
void expectInputError(const std::function<void()>& read, std::initializer_list<std::string> parts) {
    try {
        read();
        ADD_FAILURE() << "no InputError thrown";
    } catch (const InputError& e) {
        const std::string message = e.what();
        for (const std::string& part : parts) {
            EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' not in: " << message;
        }
    }
}

/// Edits a checkpoint in place with the raw HDF5 API (to build malformed files).
void editCheckpoint(const fs::path& path, const std::function<void(hid_t)>& edit) {
    const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(file, 0);
    edit(file);
    ASSERT_GE(H5Fclose(file), 0);
}

/// Replaces dataset `name` of `file` by a (rows, cols) dataset of `type` filled with zeros.
void replaceDataset(hid_t file, const char* name, hid_t type, hsize_t rows, hsize_t cols) {
    ASSERT_GE(H5Ldelete(file, name, H5P_DEFAULT), 0);
    const hsize_t dims[2] = {rows, cols};
    const hid_t space = H5Screate_simple(2, dims, nullptr);
    const hid_t set = H5Dcreate2(file, name, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    ASSERT_GE(set, 0);
    const std::vector<std::uint64_t> zeros(rows * cols + 1, 0); // 8 bytes per value covers every type used
    ASSERT_GE(H5Dwrite(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, zeros.data()), 0);
    H5Dclose(set);
    H5Sclose(space);
}

class Checkpoint : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = testing::freshTempDir("checkpoint");
        model_ = perturbedModel(7);
        ASSERT_GT(model_.bonds.size(), 100u);
        path_ = (dir_ / "state.h5").string();
        writeStores(path_, model_.particles, model_.bonds, sampleMeta());
    }
    void TearDown() override {
        std::error_code ignored;
        fs::remove_all(dir_, ignored);
    }
    void readInto() {
        Particles p;
        Bonds b;
        readStores(path_, p, b);
    }

    fs::path dir_;
    Model model_;
    std::string path_;
};

TEST_F(Checkpoint, RoundTripIsBitwiseForEveryFieldAndTheMetadata) {
    Particles p;
    Bonds b;
    const CheckpointMeta meta = readStores(path_, p, b);
    expectSameState(model_.particles, model_.bonds, p, b);

    const CheckpointMeta expected = sampleMeta();
    EXPECT_EQ(meta.step, expected.step);
    EXPECT_EQ(std::memcmp(&meta.time, &expected.time, sizeof(double)), 0);
    EXPECT_EQ(std::memcmp(&meta.dt, &expected.dt, sizeof(double)), 0);
    EXPECT_EQ(meta.scene_name, expected.scene_name);
    EXPECT_EQ(meta.scene_sha256, expected.scene_sha256);
    EXPECT_EQ(meta.vitrum_version, expected.vitrum_version);

    // The incidence rebuilt from the restored bonds is the original one.
    const Incidence incidence = Incidence::build(p.size(), b);
    EXPECT_EQ(incidence.offset, model_.incidence.offset);
    EXPECT_EQ(incidence.entry, model_.incidence.entry);
}

TEST_F(Checkpoint, OverwritesAnExistingCheckpointAndLeavesNoTmp) {
    EXPECT_FALSE(fs::exists(path_ + ".tmp"));
    const Model other = perturbedModel(8);
    CheckpointMeta meta = sampleMeta();
    meta.step = 7;
    meta.scene_name = ""; // empty strings survive too
    writeStores(path_, other.particles, other.bonds, meta);
    EXPECT_FALSE(fs::exists(path_ + ".tmp"));

    Particles p;
    Bonds b;
    const CheckpointMeta back = readStores(path_, p, b);
    expectSameState(other.particles, other.bonds, p, b);
    EXPECT_EQ(back.step, 7);
    EXPECT_EQ(back.scene_name, "");
}

TEST_F(Checkpoint, NoBondsRoundTrips) {
    const Bonds none;
    writeStores(path_, model_.particles, none, sampleMeta());
    Particles p;
    Bonds b = model_.bonds;
    readStores(path_, p, b);
    expectSameState(model_.particles, none, p, b);
}

TEST_F(Checkpoint, FailedWriteKeepsThePreviousCheckpointAndRemovesItsTmp) {
    // A store whose mass field is short fails mid-write, after the .tmp file and some datasets exist.
    Particles broken = model_.particles;
    broken.mass.pop_back();
    EXPECT_THROW(writeStores(path_, broken, model_.bonds, sampleMeta()), RuntimeFailure);
    EXPECT_FALSE(fs::exists(path_ + ".tmp"));

    Particles p;
    Bonds b;
    const CheckpointMeta meta = readStores(path_, p, b);
    expectSameState(model_.particles, model_.bonds, p, b);
    EXPECT_EQ(meta.step, sampleMeta().step);
}

TEST_F(Checkpoint, WriteIntoAMissingDirectoryThrowsAndLeavesNothing) {
    const fs::path missing = dir_ / "no" / "such" / "dir";
    const std::string target = (missing / "state.h5").string();
    try {
        writeStores(target, model_.particles, model_.bonds, sampleMeta());
        ADD_FAILURE() << "no RuntimeFailure thrown";
    } catch (const RuntimeFailure& e) {
        EXPECT_NE(std::string(e.what()).find(target), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(dir_ / "no"));
}

TEST_F(Checkpoint, MissingFileIsAnInputError) {
    path_ = (dir_ / "absent.h5").string();
    expectInputError([&] { readInto(); }, {path_, "no such file"});
}

TEST_F(Checkpoint, TextFileIsAnInputError) {
    path_ = (dir_ / "scene.toml").string();
    std::ofstream(path_) << "[sample]\nshape = \"box\"\n";
    expectInputError([&] { readInto(); }, {path_, "not an HDF5 file"});
}

TEST_F(Checkpoint, TruncatedFileIsAnInputErrorAndLeavesTheStoresUntouched) {
    const std::string truncated = (dir_ / "truncated.h5").string();
    fs::copy_file(path_, truncated);
    fs::resize_file(truncated, fs::file_size(truncated) / 2);
    path_ = truncated;

    Particles p = model_.particles;
    Bonds b = model_.bonds;
    expectInputError([&] { readStores(path_, p, b); }, {truncated});
    expectSameState(model_.particles, model_.bonds, p, b);
}

TEST_F(Checkpoint, TruncatedAnywhereIsAnInputError) {
    const std::uintmax_t size = fs::file_size(path_);
    const std::string truncated = (dir_ / "truncated.h5").string();
    for (std::uintmax_t cut = 0; cut < size; cut += size / 23) {
        fs::copy_file(path_, truncated, fs::copy_options::overwrite_existing);
        fs::resize_file(truncated, cut);
        Particles p;
        Bonds b;
        EXPECT_THROW(readStores(truncated, p, b), InputError) << "cut at " << cut << " of " << size;
    }
}

TEST_F(Checkpoint, MissingDatasetIsNamed) {
    editCheckpoint(path_, [](hid_t file) { ASSERT_GE(H5Ldelete(file, "/particles/mass", H5P_DEFAULT), 0); });
    expectInputError([&] { readInto(); }, {path_, "missing dataset '/particles/mass'"});
}

TEST_F(Checkpoint, MissingAttributeIsNamed) {
    editCheckpoint(path_, [](hid_t file) { ASSERT_GE(H5Adelete(file, "scene_sha256"), 0); });
    expectInputError([&] { readInto(); }, {path_, "missing attribute 'scene_sha256'"});
}

TEST_F(Checkpoint, WrongTypeIsAnInputError) {
    const hsize_t n = model_.bonds.size();
    editCheckpoint(path_,
                   [n](hid_t file) { replaceDataset(file, "/bonds/broken", H5T_NATIVE_DOUBLE, n, 1); });
    expectInputError([&] { readInto(); }, {path_, "'/bonds/broken'", "uint8"});
}

TEST_F(Checkpoint, WrongShapeIsAnInputError) {
    const hsize_t n = model_.particles.size();
    editCheckpoint(
        path_, [n](hid_t file) { replaceDataset(file, "/particles/orientation", H5T_NATIVE_DOUBLE, n, 3); });
    expectInputError([&] { readInto(); }, {path_, "'/particles/orientation'", "shape"});
}

TEST_F(Checkpoint, OtherFormatVersionIsRefused) {
    editCheckpoint(path_, [](hid_t file) {
        const hid_t attr = H5Aopen(file, "format_version", H5P_DEFAULT);
        const std::int32_t version = kCheckpointFormatVersion + 1;
        ASSERT_GE(H5Awrite(attr, H5T_NATIVE_INT32, &version), 0);
        H5Aclose(attr);
    });
    expectInputError([&] { readInto(); },
                     {path_, "format version " + std::to_string(kCheckpointFormatVersion + 1)});
}

TEST_F(Checkpoint, BondIndexOutOfRangeIsAnInputError) {
    Bonds bad = model_.bonds;
    bad.j[5] = static_cast<std::int32_t>(model_.particles.size());
    writeStores(path_, model_.particles, bad, sampleMeta());
    expectInputError([&] { readInto(); }, {path_, "bond 5"});
}

} // namespace
} // namespace vitrum
