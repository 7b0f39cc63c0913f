// Bad input, table-driven (issue 8): every malformed scene or command gives exit code 2 and a message that
// names the file, the line (where there is one), the key, and what was expected. Nothing is written.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

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

} // namespace
} // namespace vitrum
