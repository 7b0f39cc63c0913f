// Bad input, table-driven (issue 8): every malformed scene or command gives exit code 2 and a message that
// names the file, the line (where there is one), the key, and what was expected. Nothing is written. Then the
// corrupt packing and checkpoint files that fuzzing the readers found (issue 28, tests/fuzz/): exit 2 too.
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <hdf5.h>

#include "support/test_support.hpp"

namespace vitrum {
namespace {

namespace fs = std::filesystem;
using testing::freshTempDir;
using testing::readText;
using testing::runVitrum;

struct Malformed {
    const char* name;
    const char* scene;            ///< scene text ("" = no file written)
    std::vector<const char*> expect; ///< substrings the message must contain ("@F" = the scene path)
    const char* extra = "";       ///< extra command-line words
};

// A valid base that each case breaks in one place.
#define BASE_TIME "[time]\nduration = 0.01\n"

const Malformed kCases[] = {
    {"SyntaxUnclosedString", "[scene]\nname = \"x\n" BASE_TIME, {"@F:2:", "syntax"}},
    {"SyntaxBadTableHeader", "[scene\nname = \"x\"\n" BASE_TIME, {"@F:1:", "syntax"}},
    {"SyntaxDuplicateKey", "[scene]\nname = \"a\"\nname = \"b\"\n" BASE_TIME, {"@F:3:"}},
    {"UnknownTable", "[sceen]\nname = \"a\"\n" BASE_TIME, {"@F:1:", "sceen", "known tables"}},
    {"UnknownKey", "[sample]\npartcles = 10\n" BASE_TIME, {"@F:2:", "sample.partcles", "known keys"}},
    {"UnknownTimeKey", BASE_TIME "durration = 3\n", {"@F:3:", "time.durration"}},
    {"WrongTypeParticles", "[sample]\nparticles = \"many\"\n" BASE_TIME, {"@F:2:", "sample.particles", "integer"}},
    {"WrongTypeName", "[scene]\nname = 3\n" BASE_TIME, {"@F:2:", "scene.name", "string"}},
    // Issue 28 item 9: a name becomes the output's file names, so it is a plain file name.
    {"SceneNameIsAPath", "[scene]\nname = \"../../x\"\n" BASE_TIME, {"@F:2:8: key 'scene.name'", "plain file name"}},
    {"SceneNameEmpty", "[scene]\nname = \"\"\n" BASE_TIME, {"@F:2:8: key 'scene.name'", "plain file name"}},
    {"WrongTypeSize", "[sample]\nsize = 3.0\n" BASE_TIME, {"@F:2:", "sample.size"}},
    {"SizeWithTwoComponents", "[sample]\nsize = [1.0, 2.0]\n" BASE_TIME, {"@F:2:", "sample.size"}},
    {"UnknownLengthUnit", "[units]\nlength = \"furlong\"\n" BASE_TIME, {"@F:2:", "units.length", "um"}},
    {"UnknownStressUnit", "[units]\nstress = \"psi\"\n" BASE_TIME, {"@F:2:", "units.stress"}},
    {"UnknownTimeUnit", "[units]\ntime = \"fortnight\"\n" BASE_TIME, {"@F:2:", "units.time"}},
    {"NegativeRadius", "[sample]\nshape = \"sphere\"\nradius = -1.0\n" BASE_TIME, {"@F:3:", "sample.radius"}},
    {"ZeroHeight", "[sample]\nheight = 0.0\n" BASE_TIME, {"@F:2:", "sample.height"}},
    {"NegativeParticles", "[sample]\nparticles = -5\n" BASE_TIME, {"@F:2:", "sample.particles"}},
    {"UnknownShape", "[sample]\nshape = \"torus\"\n" BASE_TIME, {"@F:2:", "sample.shape", "hemisphere"}},
    // Particles of radius 0 (the shape's volume underflows): refused before the packer's grid (it crashed).
    {"RandomPackingOfATinySphere",
     "[sample]\nlattice = \"random\"\nshape = \"sphere\"\nradius = 5e-324\n" BASE_TIME,
     {"@F:4:10: key 'sample.radius'", "packing: radius = 4.94066e-324 um and particles = 1000", "mean radius 0 um"}},
    {"RandomPackingOfATinyBox",
     "[sample]\nlattice = \"random\"\nsize = [1e-120, 1e-120, 1e-120]\n" BASE_TIME,
     {"@F:3:8: key 'sample.size'", "packing: size = [1e-120, 1e-120, 1e-120] um and particles = 1000"}},
    {"ImpossiblePackingFraction", "[sample]\nlattice = \"random\"\npacking_fraction = 0.95\n" BASE_TIME,
     {"@F:3:", "sample.packing_fraction"}},
    {"ImpossibleCoordination", "[sample]\nlattice = \"random\"\ncoordination = 40.0\n" BASE_TIME,
     {"@F:3:", "sample.coordination"}},
    {"NegativeDensity", "[material]\ndensity = -2200\n" BASE_TIME, {"@F:2:", "material.density"}},
    {"PoissonAboveHalf", "[material]\nbeam_poisson_ratio = 0.5\n" BASE_TIME, {"@F:2:", "material.beam_poisson_ratio"}},
    {"MissingCalibrationFile", "[material]\ncalibration = \"nowhere/cal.toml\"\n" BASE_TIME,
     {"@F:2:", "material.calibration", "nowhere/cal.toml"}},
    {"UnknownEffect", "[effects]\nlist = [\"elasticity\", \"magic\"]\n" BASE_TIME, {"@F:2:", "magic"}},
    {"DuplicateEffect", "[effects]\nlist = [\"damping\", \"damping\"]\n[damping]\nkind = \"cundall\"\ncoefficient = 0.5\n" BASE_TIME,
     {"@F:2:", "damping"}},
    {"DampingTableWithoutEffect", "[damping]\nkind = \"cundall\"\ncoefficient = 0.5\n" BASE_TIME, {"@F:1:", "damping"}},
    {"DampingEffectWithoutTable", "[effects]\nlist = [\"damping\"]\n" BASE_TIME, {"@F", "damping"}},
    {"CundallCoefficientTooLarge", "[effects]\nlist = [\"damping\"]\n[damping]\nkind = \"cundall\"\ncoefficient = 1.5\n" BASE_TIME,
     {"@F:5:", "damping.coefficient"}},
    {"MissingDuration", "[scene]\nname = \"x\"\n", {"@F", "time.duration"}},
    {"SafetyRatioZero", "[time]\nduration = 1.0\nsafety_ratio = 0.0\n", {"@F:3:", "time.safety_ratio"}},
    {"BoundaryOnUndefinedSet", "[[boundary]]\nset = \"top\"\nkind = \"fixed\"\n" BASE_TIME, {"@F:2:", "top"}},
    {"VelocityBoundaryWithoutVelocity", "[sets]\ntop = \"top layer\"\n[[boundary]]\nset = \"top\"\nkind = \"velocity\"\n" BASE_TIME,
     {"@F", "velocity"}},
    {"FixedBoundaryWithDisplacement",
     "[sets]\ntop = \"top layer\"\n[[boundary]]\nset = \"top\"\nkind = \"fixed\"\ndisplacement = [0.0, 0.0, 1.0]\n" BASE_TIME,
     {"@F:6:", "displacement"}},
    {"UnknownBoundaryKind", "[sets]\ntop = \"top layer\"\n[[boundary]]\nset = \"top\"\nkind = \"glued\"\n" BASE_TIME,
     {"@F:5:", "kind"}},
    {"BadSelector", "[sets]\ntop = \"z >> 3\"\n" BASE_TIME, {"sets.top", "z >> 3"}},
    {"SelectorMatchesNothing", "[sets]\nfar = \"z > 1000\"\n" BASE_TIME, {"sets.far", "matches no particle"}},
    {"MeasureOnUndefinedSet", "[measure]\nkind = \"uniaxial\"\nloaded_set = \"nope\"\naxis = \"z\"\n" BASE_TIME,
     {"@F:3:", "nope"}},
    {"UniaxialOnASphere",
     "[sample]\nshape = \"sphere\"\n[sets]\ntop = \"top layer\"\n[measure]\nkind = \"uniaxial\"\nloaded_set = \"top\"\naxis = \"z\"\n" BASE_TIME,
     {"uniaxial", "sphere"}},
    {"UnknownOutputField", "[output]\nfields = [\"temperature\"]\n" BASE_TIME, {"@F:2:", "temperature"}},
    {"ReactionOfUndefinedSet", "[output]\nreactions = [\"nope\"]\n" BASE_TIME, {"@F:2:", "nope"}},
    {"CacheForALattice", "[sample]\nlattice = \"fcc\"\nfile = \"p.h5\"\n" BASE_TIME, {"sample.file", "random"}},
    {"OverrideBadValue", BASE_TIME, {"--set sample.particles=abc"}, "--set sample.particles=abc"},
    {"OverrideUnknownKey", BASE_TIME, {"sample.partcles"}, "--set sample.partcles=10"},
    {"OverrideWithoutEquals", BASE_TIME, {"sample.particles"}, "--set sample.particles"},
    {"MissingSceneFile", "", {"@F"}},
    {"UnwritableOutputDirectory", BASE_TIME, {"cannot create output directory"}, "--out /proc/vitrum-cannot-write"},
    // Issue 28: problems found after reading the scene name the line and the key too.
    {"SelectorWithoutANumberNamesItsLine", "[sets]\na = \"z >\"\n" BASE_TIME, {"@F:2:", "sets.a", "cannot read"}},
    {"PackerCountNamesItsLine", "[sample]\nlattice = \"random\"\nparticles = 2\n" BASE_TIME,
     {"@F:3:", "sample.particles", "min_bonds"}},
    {"PackingFileThatIsADirectory", "[sample]\nlattice = \"random\"\nparticles = 50\nfile = \"/\"\n" BASE_TIME,
     {"@F:4:", "sample.file", "not a regular file"}},
    {"CalibrationFileThatIsADirectory", "[material]\ncalibration = \"/\"\n" BASE_TIME,
     {"@F:2:", "material.calibration", "not a regular file"}},
    {"ArrayIndexBeyondAnyArray", BASE_TIME, {"load[18446744073709551616].pressure", "no [[load]] number"},
     "--set 'load[18446744073709551616].pressure=1'"},
};

class BadInput : public ::testing::TestWithParam<Malformed> {};

TEST_P(BadInput, ExitCode2AndAMessageNamingFileLineKey) {
    const Malformed& c = GetParam();
    const fs::path dir = freshTempDir("bad-input");
    const fs::path scene = dir / (std::string(c.name) + ".toml");
    if (*c.scene) {
        std::ofstream(scene) << c.scene;
    }
    std::string extra = c.extra;
    if (extra.find("--out") == std::string::npos) {
        extra += " --out " + (dir / "out").string();
    }
    const fs::path log = dir / "log.txt";
    EXPECT_EQ(runVitrum("run " + scene.string() + " " + extra, log), 2) << readText(log);
    const std::string text = readText(log);
    for (std::string want : c.expect) {
        if (want.rfind("@F", 0) == 0) {
            want = scene.string() + want.substr(2);
        }
        EXPECT_NE(text.find(want), std::string::npos) << "missing '" << want << "' in: " << text;
    }
    EXPECT_FALSE(fs::exists(dir / "out" / "summary.json"));
}

INSTANTIATE_TEST_SUITE_P(Scenes, BadInput, ::testing::ValuesIn(kCases),
                         [](const ::testing::TestParamInfo<Malformed>& info) { return std::string(info.param.name); });

// ---- Corrupt packing and checkpoint files (issue 28: what fuzzing the readers found, tests/fuzz/) ----------------

/// Edits the HDF5 file at `path` in place with the raw API.
void editHdf5(const fs::path& path, const std::function<void(hid_t)>& edit) {
    const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(file, 0) << path;
    edit(file);
    ASSERT_GE(H5Fclose(file), 0);
}

/// Replaces dataset `name` by one of `type` and shape `dims`, written only when it has elements and `fill`.
void replaceDataset(hid_t file, const char* name, hid_t type, std::vector<hsize_t> dims, const double* fill = nullptr) {
    ASSERT_GE(H5Ldelete(file, name, H5P_DEFAULT), 0) << name;
    const hid_t space = H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr);
    const hid_t set = H5Dcreate2(file, name, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    ASSERT_GE(set, 0) << name;
    if (fill) {
        hsize_t n = 1;
        for (const hsize_t d : dims) n *= d;
        const std::vector<double> values(n, *fill);
        ASSERT_GE(H5Dwrite(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), 0);
    }
    H5Dclose(set);
    H5Sclose(space);
}

// A packing whose centres claim 2^40 rows (written without data: the file stays small) asked the reader for
// 24 TB before any check (std::bad_alloc, exit 1 "run failed"); now bad input naming the dataset.
TEST(BadInputFiles, APackingDatasetClaimingMoreValuesThanTheFileHolds) {
    const fs::path dir = freshTempDir("bad-packing");
    const fs::path packing = dir / "p.h5";
    ASSERT_EQ(runVitrum("pack box --particles 50 --size 3,3,3 --packing-fraction 0.5 --threads 1 --out " + packing.string(), dir / "pack.log"), 0)
        << readText(dir / "pack.log");
    editHdf5(packing, [](hid_t file) { replaceDataset(file, "centres", H5T_IEEE_F64LE, {hsize_t{1} << 40, 3}); });
    const fs::path scene = dir / "scene.toml";
    std::ofstream(scene) << "[sample]\nlattice = \"random\"\nshape = \"box\"\nsize = [3.0, 3.0, 3.0]\nparticles = 50\n"
                            "file = \"p.h5\"\n" BASE_TIME;
    const fs::path log = dir / "run.log";
    EXPECT_EQ(runVitrum("run " + scene.string() + " --threads 1 --out " + (dir / "out").string(), log), 2) << readText(log);
    const std::string text = readText(log);
    for (const std::string want : {packing.string(), std::string("dataset 'centres' claims more values than the file")}) {
        EXPECT_NE(text.find(want), std::string::npos) << "missing '" << want << "' in: " << text;
    }
}

// Checkpoints of a small indentation with every effect that has checkpoint state but coupling: the state of an
// effect of the scene missing (the restarted run's next step read past the empty arrays: SIGSEGV), the
// indenter's controller not finite (the run went on from it). Each restart is bad input naming the checkpoint
// and the field.
TEST(BadInputFiles, CheckpointsThatDoNotFitTheScenesEffects) {
    const fs::path dir = freshTempDir("bad-checkpoint");
    const fs::path scene = dir / "indent.toml";
    std::ofstream(scene) << "[scene]\nname = \"indent\"\n[effects]\nlist = [\"elasticity\", \"densification\", "
                            "\"fracture\", \"contact\", \"indenter\", \"damping\"]\n[sample]\nlattice = \"fcc\"\n"
                            "shape = \"hemisphere\"\nradius = 1.2\nparticles = 40\n[densification]\nyield_stress = 7.13\n"
                            "tangent_modulus = 98.82\nmax_permanent_strain = 0.067\nproperty_evolution = false\n"
                            "[fracture]\n[contact]\n[indenter]\nkind = \"vickers\"\n[[stage]]\nkind = \"load\"\n"
                            "control = \"displacement\"\nspeed = 0.01\nuntil_force = 0.0001\n[damping]\n"
                            "kind = \"cundall\"\ncoefficient = 0.3\n[time]\nduration = 10.0\n[output]\nmaps = 0\n";
    const fs::path first = dir / "first";
    const std::string common = " --quiet --threads 1";
    ASSERT_EQ(runVitrum("run " + scene.string() + common + " --stop-after 20 --out " + first.string(), dir / "a.log"), 0)
        << readText(dir / "a.log");
    const double nan = std::numeric_limits<double>::quiet_NaN();
    struct Case {
        const char* name;
        std::function<void(hid_t)> edit;
        const char* expect;
    };
    const Case cases[] = {
        {"FractureStateMissing", [](hid_t f) { replaceDataset(f, "/particles/released", H5T_NATIVE_UINT8, {0, 1}); },
         "'/particles/released' holds 0 values, but the scene's run has"},
        {"DensificationStateMissing",
         [](hid_t f) {
             replaceDataset(f, "/bonds/slip", H5T_NATIVE_DOUBLE, {0, 1});
             replaceDataset(f, "/bonds/reference_strain", H5T_NATIVE_DOUBLE, {0, 1});
         },
         "'/bonds/slip' holds 0 values"},
        {"IndenterTipNotFinite", [&](hid_t f) { replaceDataset(f, "/indenter/tip", H5T_NATIVE_DOUBLE, {1, 3}, &nan); },
         "not finite"},
    };
    for (const Case& c : cases) {
        const fs::path state = dir / (std::string(c.name) + ".h5");
        fs::copy_file(first / "state.h5", state, fs::copy_options::overwrite_existing);
        editHdf5(state, c.edit);
        const fs::path out = dir / c.name;
        const fs::path log = dir / (std::string(c.name) + ".log");
        EXPECT_EQ(runVitrum("run " + scene.string() + common + " --out " + out.string() + " --restart " + state.string(), log), 2)
            << c.name << "\n" << readText(log);
        const std::string text = readText(log);
        for (const std::string want : {state.string(), std::string(c.expect)}) {
            EXPECT_NE(text.find(want), std::string::npos) << c.name << ": missing '" << want << "' in: " << text;
        }
        EXPECT_FALSE(fs::exists(out / "summary.json")) << c.name;
    }
}

} // namespace
} // namespace vitrum
