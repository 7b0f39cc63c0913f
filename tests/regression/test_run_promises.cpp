// What `vitrum run` promises a user about their files, each promise a test (issue 28): bad input writes
// nothing and leaves the output directory as it was; a restart continues the series and the maps; a complete
// run restarted is unchanged; two runs into one directory are refused; a scene name is a file name; an
// impossible time step or a tool beside the sample is bad input; CLI values are checked with a clear message; a
// final checkpoint that cannot be written is an error (exit 1), not a crash.
// The scene is the quickstart at 300 particles (about 12 000 steps, a few seconds).
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "support/test_support.hpp"

namespace vitrum {
namespace {

namespace fs = std::filesystem;
using testing::freshTempDir;
using testing::readText;
using testing::runVitrum;

const std::string kScene = std::string(VITRUM_SOURCE_DIR) + "/examples/paper/quickstart.toml";
const std::string kSmall = " --quiet --threads 1 --set sample.particles=300 --set 'sample.file=\"\"' --set output.maps=3";

/// Every file under `dir` with its bytes.
std::map<std::string, std::string> contents(const fs::path& dir) {
    std::map<std::string, std::string> out;
    for (const fs::directory_entry& e : fs::recursive_directory_iterator(dir)) {
        if (e.is_regular_file()) {
            out[fs::relative(e.path(), dir).string()] = readText(e.path());
        }
    }
    return out;
}

long lines(const fs::path& file) {
    std::ifstream in(file);
    long n = 0;
    for (std::string line; std::getline(in, line);) ++n;
    return n;
}

std::string run(const std::string& args, const fs::path& log, int expected) {
    const int rc = runVitrum(args, log);
    EXPECT_EQ(rc, expected) << args << "\n" << readText(log);
    return readText(log);
}

TEST(RunPromises, ARefusedRestartLeavesTheDirectoryAsItWas) {
    const fs::path dir = freshTempDir("promise-refused-restart");
    const fs::path out = dir / "out";
    run("run " + kScene + " --out " + out.string() + kSmall + " --stop-after 300", dir / "a.log", 0);
    const auto before = contents(out);
    ASSERT_TRUE(before.count("state.h5"));
    // Another scene (another seed): refused, and nothing in the directory changes.
    const std::string log = run("run " + kScene + " --out " + out.string() + kSmall + " --set scene.seed=7 --restart " +
                                    (out / "state.h5").string(),
                                dir / "b.log", 2);
    EXPECT_NE(log.find("another scene"), std::string::npos) << log;
    EXPECT_EQ(contents(out), before);
}

TEST(RunPromises, ARestartContinuesTheSeriesAndTheMapsAndACompleteRunRestartsToItself) {
    const fs::path dir = freshTempDir("promise-continue");
    const fs::path whole = dir / "whole", parts = dir / "parts";
    run("run " + kScene + " --out " + whole.string() + kSmall, dir / "whole.log", 0);
    run("run " + kScene + " --out " + parts.string() + kSmall + " --stop-after 5000", dir / "p1.log", 0);
    run("run " + kScene + " --out " + parts.string() + kSmall + " --restart " + (parts / "state.h5").string(),
        dir / "p2.log", 0);
    // The series and the map index of the chained run are those of the uninterrupted one.
    EXPECT_EQ(readText(parts / "series.csv"), readText(whole / "series.csv"));
    EXPECT_EQ(readText(parts / "maps.pvd"), readText(whole / "maps.pvd"));
    EXPECT_GT(lines(whole / "series.csv"), 10);
    const nlohmann::json a = testing::readSummary(whole), b = testing::readSummary(parts);
    EXPECT_EQ(a["state_sha256"], b["state_sha256"]);
    EXPECT_EQ(a["steps"], b["steps"]);
    // A complete run restarted takes no step and changes nothing.
    const auto done = contents(parts);
    const std::string log = run("run " + kScene + " --out " + parts.string() + kSmall + " --restart " +
                                    (parts / "state.h5").string(),
                                dir / "p3.log", 0);
    EXPECT_NE(log.find("complete run"), std::string::npos) << log;
    EXPECT_EQ(contents(parts), done);
}

TEST(RunPromises, TwoRunsIntoOneDirectoryAreRefusedWithTheFirstOnesPid) {
    const fs::path dir = freshTempDir("promise-lock");
    const fs::path out = dir / "out";
    fs::create_directories(out);
    // A live holder: this test process.
    std::ofstream(out / ".vitrum.lock") << ::getpid() << "\n";
    const std::string log = run("run " + kScene + " --out " + out.string() + kSmall + " --stop-after 10",
                                dir / "a.log", 2);
    EXPECT_NE(log.find("pid " + std::to_string(::getpid())), std::string::npos) << log;
    EXPECT_FALSE(fs::exists(out / "summary.json"));
    EXPECT_FALSE(fs::exists(out / "state.h5"));
    // A holder that is gone (a killed run): the lock is taken over, and released at the end.
    std::ofstream(out / ".vitrum.lock") << 2147483646 << "\n";
    run("run " + kScene + " --out " + out.string() + kSmall + " --stop-after 10", dir / "b.log", 0);
    EXPECT_TRUE(fs::exists(out / "state.h5"));
    EXPECT_FALSE(fs::exists(out / ".vitrum.lock"));
}

TEST(RunPromises, AFreshRunLeavesNoneOfAnEarlierRunsResults) {
    const fs::path dir = freshTempDir("promise-fresh");
    const fs::path out = dir / "out";
    run("run " + kScene + " --out " + out.string() + kSmall, dir / "a.log", 0);
    ASSERT_TRUE(fs::exists(out / "summary.json"));
    // The same directory, a new run that has not finished (stopped after 10 steps): none of the earlier run's
    // results may stand beside its checkpoint as if they were its own.
    run("run " + kScene + " --out " + out.string() + kSmall + " --stop-after 10", dir / "b.log", 0);
    EXPECT_TRUE(fs::exists(out / "state.h5"));
    EXPECT_FALSE(fs::exists(out / "summary.json"));
    EXPECT_FALSE(fs::exists(out / "imprint.csv"));
    EXPECT_FALSE(fs::exists(out / "plots"));
    EXPECT_EQ(lines(out / "series.csv"), 2); // the header and step 0
}

TEST(RunPromises, BadInputFoundAfterReadingTheSceneWritesNothing) {
    const fs::path dir = freshTempDir("promise-nothing-written");
    struct Case {
        const char* args;
        const char* expect;
    };
    const Case cases[] = {
        {" --set time.safety_ratio=1e-300", "time.safety_ratio"},
        {" --set time.duration=1e308", "time.duration"},
        {" --set indenter.stiffness=1e30", "indenter.stiffness"},
        {" --set indenter.axis_x=100", "the tool does not meet the sample"},
        {" --set 'scene.name=\"../../vitrum-name-escape\"'", "scene.name"},
        {" --set 'scene.name=\"\"'", "scene.name"},
        {" --set sample.particles=2000000000000", "sample.particles"},
    };
    for (const Case& c : cases) {
        const fs::path out = dir / "out";
        fs::remove_all(out);
        const std::string log = run("run " + kScene + " --out " + out.string() + kSmall + c.args, dir / "x.log", 2);
        EXPECT_NE(log.find(c.expect), std::string::npos) << c.args << "\n" << log;
        EXPECT_FALSE(fs::exists(out)) << c.args << ": the output directory was created";
    }
    // A name that is a path would have written beside the run's directory or the checkout; the probe's name is
    // one no checkout or temporary directory carries (a clone in /tmp/x made "x" a false alarm).
    EXPECT_FALSE(fs::exists(fs::path(VITRUM_SOURCE_DIR).parent_path() / "vitrum-name-escape"));
    EXPECT_FALSE(fs::exists(dir.parent_path() / "vitrum-name-escape"));
}

// The final checkpoint cannot be written: the run says so and exits 1, it does not crash. Two ways that hold
// for root too (the tests run as root, whom a read-only directory does not stop): the name state.h5 taken by a
// directory (the rename onto it fails), and a file-size limit the checkpoint does not fit in (every write
// beyond it fails with EFBIG, as on a full disk: HDF5's flush and close fail, the case that used to crash
// with SIGSEGV in HDF5's exit-time clean-up after the error was reported; io/checkpoint.hpp
// disableHdf5ExitCleanup). Only the final checkpoint is written (output.checkpoints = 0, no maps).
TEST(RunPromises, AFinalCheckpointThatCannotBeWrittenIsAnErrorNotACrash) {
    const fs::path dir = freshTempDir("promise-final-checkpoint");
    const std::string args = " --quiet --threads 1 --set sample.particles=300 --set 'sample.file=\"\"' "
                             "--set output.maps=0 --set output.checkpoints=0";
    {
        const fs::path out = dir / "taken";
        fs::create_directories(out / "state.h5" / "not-a-checkpoint");
        const std::string log = run("run " + kScene + " --out " + out.string() + args, dir / "taken.log", 1);
        EXPECT_NE(log.find("cannot write checkpoint '" + (out / "state.h5").string() + "'"), std::string::npos) << log;
        EXPECT_TRUE(fs::is_directory(out / "state.h5" / "not-a-checkpoint")) << "the run removed what held the name";
        EXPECT_FALSE(fs::exists(out / "state.h5.tmp"));
        EXPECT_FALSE(fs::exists(out / "summary.json"));
    }
    {
        // 200 blocks of 512 bytes (dash's ulimit -f): the scene, the series and the log fit, the checkpoint
        // (about 300 kB at 300 particles) does not. SIGXFSZ ignored, so the writes fail instead of killing.
        const fs::path out = dir / "full";
        const fs::path log = dir / "full.log";
        const fs::path script = dir / "full.sh";
        std::ofstream(script) << "trap '' XFSZ\nulimit -f 200\nexec '" << VITRUM_BINARY << "' run " << kScene
                              << " --out " << out.string() << args << "\n";
        const int status = std::system(("/bin/sh '" + script.string() + "' > '" + log.string() + "' 2>&1").c_str());
        ASSERT_TRUE(WIFEXITED(status)) << readText(log);
        EXPECT_EQ(WEXITSTATUS(status), 1) << "expected exit 1 (139: a crash)\n" << readText(log);
        const std::string text = readText(log);
        EXPECT_NE(text.find("cannot write checkpoint '" + (out / "state.h5").string() + "'"), std::string::npos) << text;
        EXPECT_FALSE(fs::exists(out / "state.h5"));
        EXPECT_FALSE(fs::exists(out / "state.h5.tmp"));
        EXPECT_TRUE(fs::exists(out / "series.csv"));
    }
}

TEST(RunPromises, CommandLineValuesAreCheckedWithAClearMessage) {
    const fs::path dir = freshTempDir("promise-cli");
    std::string log = run("run " + kScene + " --threads 0", dir / "a.log", 2);
    EXPECT_NE(log.find("--threads: expected a whole number >= 1, got '0'"), std::string::npos) << log;
    log = run("run " + kScene + " --stop-after 0", dir / "b.log", 2);
    EXPECT_NE(log.find("--stop-after: expected a whole number >= 1"), std::string::npos) << log;
    log = run("frobnicate", dir / "c.log", 2);
    EXPECT_NE(log.find("unknown subcommand 'frobnicate'"), std::string::npos) << log;
}

} // namespace
} // namespace vitrum
