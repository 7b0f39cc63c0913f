// Unit tests for the output writers: SHA-256 vectors, CSV series, PVD index, VTU round trips, progress line.
#include "io/fields.hpp"
#include "io/progress.hpp"
#include "io/series_writer.hpp"
#include "io/sha256.hpp"
#include "io/vtk_writer.hpp"
#include "solver/errors.hpp"

#include <gtest/gtest.h>

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkObject.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <vector>

namespace vitrum {
namespace {

namespace fs = std::filesystem;

// Each test gets its own directory, removed afterwards, so runs in parallel (ctest -j) never collide.
class TempDir {
public:
    TempDir() {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        const auto stamp = std::chrono::steady_clock::now().time_since_epoch().count();
        path_ = fs::temp_directory_path() / ("vitrum_" + std::string(info->test_suite_name()) + "_" +
                                             info->name() + "_" + std::to_string(stamp));
        fs::create_directories(path_);
    }
    ~TempDir() {
        std::error_code ignored;
        fs::remove_all(path_, ignored);
    }
    fs::path operator/(const std::string& name) const { return path_ / name; }

private:
    fs::path path_;
};

std::string slurp(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

std::string sha256Of(std::string_view text) {
    Sha256 hash;
    hash.update(text);
    return hash.hexDigest();
}

// --- SHA-256: FIPS 180-2 appendix vectors ---------------------------------------------------------------

TEST(Sha256, KnownVectors) {
    EXPECT_EQ(sha256Of(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
    EXPECT_EQ(sha256Of("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    EXPECT_EQ(sha256Of("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
              "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
}

TEST(Sha256, MillionA) {
    // Fed in uneven pieces so partial-block buffering is exercised along with the whole-block path.
    const std::string chunk(997, 'a');
    Sha256 hash;
    std::size_t fed = 0;
    while (fed < 1000000) {
        const std::size_t take = std::min<std::size_t>(chunk.size(), 1000000 - fed);
        hash.update(chunk.data(), take);
        fed += take;
    }
    EXPECT_EQ(hash.hexDigest(), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(Sha256, SplitUpdatesAndRepeatedDigestAgree) {
    std::string message(300, '\0');
    for (std::size_t k = 0; k < message.size(); ++k)
        message[k] = static_cast<char>(k * 7 + 3);
    const std::string whole = sha256Of(message);
    for (std::size_t split : {1u, 55u, 56u, 63u, 64u, 65u, 128u, 299u}) {
        Sha256 hash;
        hash.update(message.data(), split);
        hash.update(message.data() + split, message.size() - split);
        EXPECT_EQ(hash.hexDigest(), whole) << "split at " << split;
        EXPECT_EQ(hash.hexDigest(), whole) << "digest must not disturb the state";
    }
}

TEST(Sha256, RandomBufferMatchesSha256sum) {
    if (std::system("command -v sha256sum > /dev/null 2>&1") != 0)
        GTEST_SKIP() << "sha256sum not available";
    TempDir dir;
    std::mt19937 random(20240611);
    std::string buffer(10240, '\0');
    for (char& byte : buffer)
        byte = static_cast<char>(random() & 0xff);
    const fs::path data = dir / "random.bin", sum = dir / "random.sha";
    std::ofstream(data, std::ios::binary) << buffer;
    const std::string command = "sha256sum '" + data.string() + "' > '" + sum.string() + "'";
    ASSERT_EQ(std::system(command.c_str()), 0);
    EXPECT_EQ(sha256Of(buffer), slurp(sum).substr(0, 64));
}

// --- CSV series -------------------------------------------------------------------------------------------

TEST(CsvSeries, HeaderAndRows) {
    TempDir dir;
    const fs::path path = dir / "series.csv";
    {
        SeriesWriter series(path.string(), {"time_ns", "force_N", "depth_um"});
        for (int k = 0; k < 5; ++k) {
            const std::vector<double> values = {0.5 * k, 1.0 / 3.0, 1e3 * k - 2e-7};
            series.row(values);
        }
        series.flush();
        const std::vector<double> short_row = {1.0, 2.0};
        EXPECT_THROW(series.row(short_row), RuntimeFailure);
    }
    std::istringstream lines(slurp(path));
    std::string line;
    std::vector<std::string> all;
    while (std::getline(lines, line))
        all.push_back(line);
    ASSERT_EQ(all.size(), 6u);
    EXPECT_EQ(all[0], "time_ns,force_N,depth_um");
    EXPECT_EQ(all[1], "0,0.3333333333,-2e-07");
    EXPECT_EQ(all[2], "0.5,0.3333333333,999.9999998");
}

TEST(CsvSeries, UnopenableFileThrowsWithPath) {
    const std::string path = "/nonexistent_vitrum_dir/series.csv";
    try {
        SeriesWriter series(path, {"time_ns"});
        FAIL() << "expected RuntimeFailure";
    } catch (const RuntimeFailure& error) {
        EXPECT_NE(std::string(error.what()).find(path), std::string::npos);
    }
}

// --- PVD index --------------------------------------------------------------------------------------------

TEST(Pvd, ListsEveryEntryAfterEachWrite) {
    TempDir dir;
    const fs::path path = dir / "maps.pvd";
    PvdCollection pvd(path.string());
    for (int k = 0; k < 3; ++k) {
        pvd.add(0.25 * k, "maps/particles_" + std::to_string(k) + ".vtu");
        pvd.write();
        const std::string text = slurp(path);
        EXPECT_EQ(text.rfind("<?xml", 0), 0u);
        EXPECT_NE(text.find("<VTKFile type=\"Collection\""), std::string::npos);
        EXPECT_NE(text.find("</Collection>\n</VTKFile>"), std::string::npos);
        for (int e = 0; e <= k; ++e)
            EXPECT_NE(text.find("file=\"maps/particles_" + std::to_string(e) + ".vtu\""), std::string::npos);
        EXPECT_FALSE(fs::exists(dir / "maps.pvd.tmp"));
    }
    EXPECT_NE(slurp(path).find("timestep=\"0.5\""), std::string::npos);
    pvd.add(1e-9, "a&b.vtu"); // shortest exact time text; the file name escaped for XML
    pvd.write();
    EXPECT_NE(slurp(path).find("timestep=\"1e-09\" group=\"\" part=\"0\" file=\"a&amp;b.vtu\""),
              std::string::npos);
}

// --- VTU round trips --------------------------------------------------------------------------------------

vtkSmartPointer<vtkUnstructuredGrid> readVtu(const fs::path& path) {
    vtkNew<vtkXMLUnstructuredGridReader> reader;
    reader->SetFileName(path.string().c_str());
    reader->Update();
    return reader->GetOutput();
}

TEST(Vtu, ParticlesRoundTripExactly) {
    TempDir dir;
    constexpr std::size_t n = 10;
    std::vector<double> positions(3 * n), radius(n), velocity(3 * n), damage(n);
    for (std::size_t p = 0; p < n; ++p) {
        for (int c = 0; c < 3; ++c) {
            positions[3 * p + c] = 1e-6 * (p + 0.1 * c) + 1.0 / 7.0; // not exactly representable in text
            velocity[3 * p + c] = -0.3 * p + c;
        }
        radius[p] = 2.5e-7 * (1.0 + 0.01 * p);
        damage[p] = p / 9.0;
    }
    const FieldView fields[] = {{"velocity_m_per_s", 3, velocity.data()}, {"damage", 1, damage.data()}};
    const fs::path path = dir / "particles.vtu";
    writeParticlesVtu(path.string(), n, positions.data(), radius.data(), fields);

    EXPECT_NE(slurp(path).find("compressor=\"vtkZLibDataCompressor\""), std::string::npos);
    EXPECT_NE(slurp(path).find("<AppendedData encoding=\"raw\">"), std::string::npos);

    const auto grid = readVtu(path);
    ASSERT_EQ(grid->GetNumberOfPoints(), static_cast<vtkIdType>(n));
    ASSERT_EQ(grid->GetNumberOfCells(), static_cast<vtkIdType>(n));
    EXPECT_EQ(grid->GetPoints()->GetDataType(), VTK_DOUBLE);
    for (std::size_t p = 0; p < n; ++p) {
        EXPECT_EQ(grid->GetCellType(static_cast<vtkIdType>(p)), VTK_VERTEX);
        double point[3];
        grid->GetPoint(static_cast<vtkIdType>(p), point);
        for (int c = 0; c < 3; ++c)
            EXPECT_EQ(point[c], positions[3 * p + c]);
    }
    vtkDataArray* read_radius = grid->GetPointData()->GetArray("radius");
    vtkDataArray* read_velocity = grid->GetPointData()->GetArray("velocity_m_per_s");
    vtkDataArray* read_damage = grid->GetPointData()->GetArray("damage");
    ASSERT_TRUE(read_radius && read_velocity && read_damage);
    EXPECT_EQ(read_radius->GetNumberOfComponents(), 1);
    EXPECT_EQ(read_velocity->GetNumberOfComponents(), 3);
    EXPECT_EQ(read_damage->GetNumberOfComponents(), 1);
    for (std::size_t p = 0; p < n; ++p) {
        const auto id = static_cast<vtkIdType>(p);
        EXPECT_EQ(read_radius->GetComponent(id, 0), radius[p]);
        EXPECT_EQ(read_damage->GetComponent(id, 0), damage[p]);
        for (int c = 0; c < 3; ++c)
            EXPECT_EQ(read_velocity->GetComponent(id, c), velocity[3 * p + c]);
    }
}

TEST(Vtu, BondsAreLineCellsWithCellData) {
    TempDir dir;
    const std::vector<double> positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    const std::vector<std::int32_t> i = {0, 0, 0, 1, 2}, j = {1, 2, 3, 2, 3};
    const std::vector<double> broken = {0, 1, 0, 0, 1};
    const FieldView fields[] = {{"broken", 1, broken.data()}};
    const fs::path path = dir / "bonds.vtu";
    writeBondsVtu(path.string(), 4, positions.data(), i.size(), i.data(), j.data(), fields);

    const auto grid = readVtu(path);
    EXPECT_EQ(grid->GetNumberOfPoints(), 4);
    ASSERT_EQ(grid->GetNumberOfCells(), static_cast<vtkIdType>(i.size()));
    vtkDataArray* read_broken = grid->GetCellData()->GetArray("broken");
    ASSERT_NE(read_broken, nullptr);
    for (vtkIdType b = 0; b < grid->GetNumberOfCells(); ++b) {
        EXPECT_EQ(grid->GetCellType(b), VTK_LINE);
        vtkNew<vtkIdList> ends;
        grid->GetCellPoints(b, ends);
        ASSERT_EQ(ends->GetNumberOfIds(), 2);
        EXPECT_EQ(ends->GetId(0), i[b]);
        EXPECT_EQ(ends->GetId(1), j[b]);
        EXPECT_EQ(read_broken->GetComponent(b, 0), broken[b]);
    }
}

TEST(Vtu, BadInputAndUnwritablePathThrowWithPath) {
    TempDir dir;
    const std::vector<double> positions = {0, 0, 0, 1, 0, 0};
    const std::vector<std::int32_t> i = {0}, j = {2}; // particle 2 does not exist
    const std::string bonds = (dir / "bonds.vtu").string();
    EXPECT_THROW(writeBondsVtu(bonds, 2, positions.data(), 1, i.data(), j.data(), {}), RuntimeFailure);

    const std::vector<double> radius = {1, 1};
    const std::string missing = "/nonexistent_vitrum_dir/particles.vtu";
    vtkObject::GlobalWarningDisplayOff(); // the expected failure would otherwise log a page of VTK errors
    try {
        writeParticlesVtu(missing, 2, positions.data(), radius.data(), {});
        ADD_FAILURE() << "expected RuntimeFailure";
    } catch (const RuntimeFailure& error) {
        EXPECT_NE(std::string(error.what()).find(missing), std::string::npos);
        EXPECT_NE(std::string(error.what()).find("No such file"), std::string::npos);
    }
    vtkObject::GlobalWarningDisplayOn();
}

// --- Progress ---------------------------------------------------------------------------------------------

TEST(Progress, FormatsPercentRateAndEta) {
    // 4200 steps in 3.5 s: 1200 steps/s, 5800 left -> 4.833 s -> 0:00:05.
    EXPECT_EQ(formatProgress(4200, 10000, 3.5, "F=1.2 N"),
              "[ 42.0%] step 4200/10000  1200 steps/s  ETA 0:00:05  | F=1.2 N");
    // 1 step/s with 3723 left -> 1 h 2 min 3 s.
    EXPECT_EQ(formatProgress(10, 3733, 10.0, ""), "[  0.3%] step 10/3733  1 steps/s  ETA 1:02:03");
    EXPECT_EQ(formatProgress(0, 100, 0.0, ""), "[  0.0%] step 0/100  - steps/s  ETA -");
    EXPECT_EQ(formatProgress(100, 100, 2.0, "").substr(0, 8), "[100.0%]");
    EXPECT_EQ(formatDuration(36000.4), "10:00:00");
}

TEST(Progress, NonInteractiveReportsOnIntervalAndAtFinish) {
    double now = 0.0;
    std::ostringstream out;
    ProgressReporter reporter(out, false, 100, 10.0, [&now] { return now; });
    for (long step = 1; step <= 100; ++step) {
        now = 0.25 * step; // 25 s in all: reports at 10 s and 20 s
        reporter.update(step, "");
    }
    reporter.finish();
    reporter.finish();
    EXPECT_EQ(out.str(), "[ 40.0%] step 40/100  4 steps/s  ETA 0:00:15\n"
                         "[ 80.0%] step 80/100  4 steps/s  ETA 0:00:05\n"
                         "[100.0%] step 100/100  4 steps/s  ETA 0:00:00\n");
}

TEST(Progress, ARestartsRateCountsOnlyTheStepsThisProcessRan) {
    // Restarted at step 9000 of 10000: 200 steps in 2 s are 100 steps/s (not 9200 / 2), 800 left -> 0:00:08.
    EXPECT_EQ(formatProgress(9200, 10000, 2.0, "", false, 9000),
              "[ 92.0%] step 9200/10000  100 steps/s  ETA 0:00:08");
    EXPECT_EQ(formatProgress(9000, 10000, 2.0, "", false, 9000),
              "[ 90.0%] step 9000/10000  - steps/s  ETA -");
    double now = 0.0;
    std::ostringstream out;
    ProgressReporter reporter(out, false, 10000, 10.0, [&now] { return now; });
    reporter.setFirstStep(9000);
    now = 12.0;
    reporter.update(9600, "");
    reporter.finish(); // 600 steps in 12 s: 50 steps/s, 400 left -> 8 s
    EXPECT_EQ(out.str(), "[ 96.0%] step 9600/10000  50 steps/s  ETA 0:00:08\n"
                         "[ 96.0%] step 9600/10000  50 steps/s  ETA 0:00:08\n");
}

TEST(Progress, InteractiveRedrawsOneLine) {
    double now = 0.0;
    std::ostringstream out;
    ProgressReporter reporter(out, true, 10, 10.0, [&now] { return now; });
    now = 0.05;
    reporter.update(1, "long probe text"); // too soon after the start: not drawn
    now = 1.0;
    reporter.update(5, "long probe text");
    reporter.update(6, ""); // within 0.2 s of the last draw: not drawn
    now = 2.0;
    reporter.finish();
    const std::string first = "[ 50.0%] step 5/10  5 steps/s  ETA 0:00:01  | long probe text";
    const std::string last = "[ 60.0%] step 6/10  3 steps/s  ETA 0:00:01";
    EXPECT_EQ(out.str(), "\r" + first + "\r" + last + std::string(first.size() - last.size(), ' ') + "\n");
}

} // namespace
} // namespace vitrum
