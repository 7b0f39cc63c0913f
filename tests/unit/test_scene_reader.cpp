// io/scene_reader: TOML → Scene, units, overrides, error messages, and the resolved-scene round trip.
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "io/packing_io.hpp"
#include "io/sample_cache.hpp"
#include "io/scene/sections.hpp"
#include "io/scene_reader.hpp"
#include "io/units.hpp"
#include "solver/errors.hpp"
#include "support/test_support.hpp"

namespace vitrum {
namespace {

constexpr const char* kMinimal = "[time]\nduration = 1.0\n";

const char* const kFull = R"([scene]
name = "round \"trip\" \u00e9"
seed = 42

[units]
length = "mm"
stress = "MPa"
force = "mN"
time = "us"

[effects]
list = ["damping"]

[sample]
lattice = "sc"
shape = "cylinder"
size = [0.1, 0.2, 0.3]
radius = 0.0123
height = 0.045
particles = 5000
bond_tolerance = 0.1

[material]
density = 2203.7
beam_young_modulus = 414000
beam_poisson_ratio = 0.17
beam_radius_ratio = 0.57

[sets]
top = "z > 0.044"
bottom = "z < 0.001"
side-wall = "r > 0.012"

[[boundary]]
set = "bottom"
kind = "fixed"

[[boundary]]
set = "top"
kind = "velocity"
velocity = [0, 0.1, -0.3]

[[boundary]]
set = "side-wall"
kind = "displacement"
displacement = [1e-4, 0, 3.3e-5]
ramp_time = 0.25

[damping]
kind = "cundall"
coefficient = 0.05

[time]
safety_ratio = 0.2
duration = 1.5

[measure]
kind = "uniaxial"
loaded_set = "top"
axis = "y"

[output]
every = 50
maps = 0
checkpoints = 3
fields = ["displacement", "radius"]
reactions = ["top", "bottom"]
)";

/// The message of the InputError that parsing `text` must throw.
std::string errorOf(const std::string& text, const std::vector<std::string>& overrides = {}) {
    try {
        parseScene(text, "q.toml", overrides);
    } catch (const InputError& e) {
        return e.what();
    }
    ADD_FAILURE() << "no InputError for:\n" << text;
    return "";
}

void expectMentions(const std::string& message, std::initializer_list<std::string> parts) {
    for (const std::string& part : parts) {
        EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' missing from: " << message;
    }
}

void expectSameVec(const Vec3& a, const Vec3& b) {
    for (int i = 0; i < 3; ++i) {
        EXPECT_EQ(a[i], b[i]) << "component " << i;
    }
}

/// The parts of the scene that differ, for the message of a failed comparison.
std::string differences(const Scene& a, const Scene& b) {
    std::string out;
    const auto check = [&](bool same, const char* part) {
        if (!same) {
            out += std::string(out.empty() ? "" : ", ") + part;
        }
    };
    check(a.name == b.name && a.seed == b.seed, "[scene]");
    check(a.units == b.units, "units");
    check(a.effects == b.effects, "effects");
    check(a.sample == b.sample, "sample");
    check(a.material == b.material, "material");
    check(a.sets == b.sets, "sets");
    check(a.boundaries == b.boundaries, "boundaries");
    check(a.loads == b.loads, "loads");
    check(a.damping == b.damping, "damping");
    check(a.densification == b.densification, "densification");
    check(a.plasticity == b.plasticity, "plasticity");
    check(a.fracture == b.fracture, "fracture");
    check(a.contact == b.contact, "contact");
    check(a.indenter == b.indenter, "indenter");
    check(a.stages == b.stages, "stages");
    check(a.coupling == b.coupling, "coupling");
    check(a.time == b.time, "time");
    check(a.measure == b.measure, "measure");
    check(a.output == b.output, "output");
    check(a.source_path == b.source_path, "source_path");
    return "differs in: " + out;
}

/// read -> resolvedSceneToml -> read gives the same scene, every member exactly (the resolved TOML must
/// reproduce every double bit for bit), and the same resolved text. Where values came from is not a value:
/// the resolved scene gives the calibrated numbers instead of the calibration file, so material.calibration
/// reads back empty and coupling.material_source, plasticity.material_source as explicit; those are carried
/// over before comparing.
void expectRoundTrip(const Scene& scene) {
    const std::string resolved = resolvedSceneToml(scene);
    Scene back = parseScene(resolved, scene.source_path);
    back.material.calibration = scene.material.calibration;
    back.coupling.material_source = scene.coupling.material_source;
    back.plasticity.material_source = scene.plasticity.material_source;
    EXPECT_TRUE(back == scene) << differences(scene, back) << "\n" << resolved;
    EXPECT_EQ(resolvedSceneToml(back), resolved);
}

TEST(SceneReader, FullSceneIsReadAndRoundTripsThroughResolvedToml) {
    const Scene scene = parseScene(kFull, "q.toml");
    EXPECT_EQ(scene.name, "round \"trip\" \u00e9");
    EXPECT_EQ(scene.effects, (std::vector<Effect>{Effect::Elasticity, Effect::Damping}));
    ASSERT_EQ(scene.sets.size(), 3u); // file order, not the key order toml++ stores them in
    EXPECT_EQ(scene.sets[0].name, "top");
    EXPECT_EQ(scene.sets[2].name, "side-wall");
    EXPECT_EQ(scene.boundaries[1].kind, BoundaryKind::Velocity);
    EXPECT_EQ(scene.damping.kind, DampingKind::CundallLocal);
    EXPECT_TRUE(scene.measure.uniaxial());
    EXPECT_EQ(scene.measure.axis, 1);

    const std::string resolved = resolvedSceneToml(scene);
    EXPECT_NE(resolved.find("# Scene resolved by vitrum"), std::string::npos);
    EXPECT_NE(resolved.find("kg/m^3"), std::string::npos);
    expectRoundTrip(scene);
}

TEST(SceneReader, DefaultsAreFilledInAndRoundTrip) {
    const Scene scene = parseScene(kMinimal, "q.toml");
    const Scene defaults;
    EXPECT_EQ(scene.effects, defaults.effects);
    EXPECT_EQ(scene.sample.particles, defaults.sample.particles);
    EXPECT_EQ(scene.material.density, defaults.material.density);
    EXPECT_EQ(scene.source_path, "q.toml");
    const std::string resolved = resolvedSceneToml(scene);
    EXPECT_NE(resolved.find("particles = 1000"), std::string::npos) << resolved;
    expectRoundTrip(scene);
}

TEST(SceneReader, AwkwardValuesRoundTripInEveryUnit) {
    for (const std::string& length : unitNames(Quantity::Length)) {
        for (const std::string& time : unitNames(Quantity::Time)) {
            for (const std::string& stress : unitNames(Quantity::Stress)) {
                SCOPED_TRACE("defaults in " + length + " " + time + " " + stress);
                const Scene defaults =
                    parseScene(kMinimal, "q.toml",
                               {"units.length=\"" + length + "\"", "units.time=\"" + time + "\"",
                                "units.stress=\"" + stress + "\""});
                expectRoundTrip(defaults);
            }
            for (const char* value : {"0.1", "0.3", "0.3333333333333333", "123.456", "7e-5", "2.2"}) {
                const std::string v = value;
                const Scene scene = parseScene(
                    "[sets]\na = \"all\"\n", "q.toml",
                    {"units.length=\"" + length + "\"", "units.time=\"" + time + "\"", "units.stress=\"kPa\"",
                     "sample.radius=" + v, "sample.size=[" + v + ", 1, " + v + "]", "time.duration=" + v,
                     "material.density=" + v, "material.beam_young_modulus=" + v,
                     "boundary=[{set=\"a\", kind=\"velocity\", velocity=[" + v + ", -" + v + ", 0]}]"});
                SCOPED_TRACE(length + " " + time + " " + v);
                expectRoundTrip(scene);
            }
        }
    }
}

// Every section of a scene, each key given a value other than its default, in units other than the defaults
// (so that every conversion is exercised): with the variants below it gives every key of every section.
const std::map<std::string, std::string> kEverySection = {
    {"scene", "[scene]\nname = \"every key\"\nseed = 42\n"},
    {"units", "[units]\nlength = \"mm\"\nstress = \"MPa\"\nforce = \"mN\"\ntime = \"us\"\n"},
    {"effects", "[effects]\nlist = [\"damping\", \"densification\", \"indenter\", \"fracture\", \"contact\", "
                "\"coupling\"]\n"},
    {"sample",
     "[sample]\nlattice = \"random\"\nshape = \"hemisphere\"\nsize = [0.1, 0.2, 0.3]\nradius = 0.0123\n"
     "height = 0.045\nparticles = 5000\nbond_tolerance = 0.1\nradius_dispersion = 0.15\n"
     "packing_fraction = 0.6\ncoordination = 6.5\nfile = \"cache.h5\"\n"},
    {"material", "[material]\ndensity = 2203.7\nbeam_young_modulus = 414000\nbeam_poisson_ratio = 0.17\n"
                 "beam_radius_ratio = 0.6\n"},
    {"sets", "[sets]\ntop = \"z > -0.001\"\ndome = \"dome\"\nside-wall = \"r > 0.012\"\n"},
    {"boundary",
     "[[boundary]]\nset = \"dome\"\nkind = \"fixed\"\n"
     "[[boundary]]\nset = \"top\"\nkind = \"velocity\"\nvelocity = [0, 0.1, -0.3]\n"
     "[[boundary]]\nset = \"side-wall\"\nkind = \"displacement\"\ndisplacement = [1e-4, 0, 3.3e-5]\n"
     "ramp_time = 0.25\n"
     "[[boundary]]\nset = \"top\"\nkind = \"strain\"\nnormal_strain = [0, 0, -0.05]\n"
     "shear_strain = [0.1, 0, 0.02]\nramp_time = 0.5\n"},
    {"load",
     "[[load]]\nset = \"top\"\nkind = \"pressure\"\npressure = 3000\nramp_time = 0.002\nhold_time = 0.001\n"
     "release_time = 0.003\n"
     "[[load]]\nset = \"dome\"\nkind = \"stress\"\nnormal_stress = [-2000, 0, 150]\nshear_stress = [0, 700, -30]\n"
     "start_time = 0.001\nramp_time = 0.004\n"},
    {"damping", "[damping]\nkind = \"cundall\"\ncoefficient = 0.05\n"},
    {"densification",
     "[densification]\nyield_stress = 7130\ntangent_modulus = 98820\nmax_permanent_strain = 0.05\n"
     "property_evolution = true\nyoung_gain = 0.4\npoisson_gain = 0.5\nyoung_modulus = 70000\n"
     "poisson_ratio = 0.18\npoisson_ratio_max = 0.24\neq5 = [1.2, -3.5, 1.9]\n"
     "eq6_b0 = [-570, 1700, -1100]\neq6_b1 = [0.2, -0.9, 1.5]\n"},
    {"indenter", "[indenter]\nkind = \"vickers\"\nface_angle_deg = 130.0\nheight = 0.0025\nstiffness = 2.5\n"
                 "damping_ratio = 0.1\nfriction = 0.2\ngap = 2e-5\naxis_x = 0.001\naxis_y = -0.0005\n"},
    {"stage", "[[stage]]\nkind = \"load\"\ncontrol = \"displacement\"\nspeed = 0.01\nuntil_force = 30\n"
              "slow_band = 0.1\n"
              "[[stage]]\nkind = \"hold\"\ncontrol = \"force\"\nduration = 0.02\n"
              "[[stage]]\nkind = \"unload\"\nspeed = 0.02\nuntil_force = 1.5\n"
              "[[stage]]\nkind = \"relax\"\nspeed = 0.005\nduration = 0.1\nkinetic_tolerance = 2e-4\n"
              "settle = 0.03\n"},
    {"fracture", "[fracture]\nhydrostatic_strength = 80\ncheck_every = 5\nvolume = \"packing\"\n"
                 "averaging = \"neighbours\"\npacking_fraction = 0.62\n"},
    {"contact",
     "[contact]\nnormal_stiffness = 4.0\nrestitution = 0.3\ntangential_ratio = 0.4\nfriction = 0.25\n"
     "skin_ratio = 0.3\n"},
    {"coupling",
     "[coupling]\nthickness = 0.0015\nbox = 0.026\nnodes = 5000\nprofile = \"cubic\"\n"
     "multiplier_tolerance = 0.05\nstabilisation = 0.1\njitter = 0.2\nlateral_faces = \"roller\"\n"
     "zone_check = \"weighted\"\nzone_tolerance = 0.002\nyoung_modulus = 71000\npoisson_ratio = 0.2\n"
     "density = 2300\n"},
    {"time", "[time]\nsafety_ratio = 0.2\nduration = 1.5\n"},
    {"precision", "[precision]\nbond_reference = \"float\"\n"},
    {"measure", "[measure]\nkind = \"uniaxial\"\nloaded_set = \"top\"\naxis = \"y\"\n"},
    {"output",
     "[output]\nevery = 50\nmaps = 0\ncheckpoints = 3\nfields = [\"displacement\", \"radius\", \"damage\"]\n"
     "reactions = [\"top\", \"dome\"]\nlast_good_state = false\n"},
};

std::string sceneOf(std::map<std::string, std::string> sections,
                    const std::map<std::string, std::string>& replaced = {}) {
    for (const auto& [name, text] : replaced) {
        sections[name] = text;
    }
    std::string out;
    for (const auto& [name, text] : sections) {
        out += text + "\n";
    }
    return out;
}

/// kEverySection and variants for the keys that exclude each other (the tool kinds, a displacement-
/// controlled hold, the bare-sphere fracture volume, a cut instead of a packing, calibration files instead of
/// the parameters they give).
std::vector<std::string> everyKeyScenes() {
    const std::string packing = std::string(VITRUM_SOURCE_DIR) + "/tests/data/packing-box-200-seed1.h5";
    const std::string calibration = std::string(VITRUM_SOURCE_DIR) + "/examples/calibration/silica.toml";
    return {
        sceneOf(kEverySection),
        sceneOf(kEverySection,
                {{"indenter", "[indenter]\nkind = \"cone\"\nhalf_angle_deg = 60.0\nheight = 0.002\n"},
                 {"stage", "[[stage]]\nkind = \"load\"\nspeed = 0.01\nuntil_force = 30\n"
                           "[[stage]]\nkind = \"hold\"\ncontrol = \"displacement\"\nduration = 0.02\n"},
                 {"fracture", "[fracture]\nvolume = \"sphere\"\n"},
                 {"damping", "[damping]\nkind = \"bond-viscous\"\ncoefficient = 0.7\n"},
                 {"sample",
                  "[sample]\nlattice = \"random\"\nshape = \"hemisphere\"\nradius = 0.003\ncut_from = \"" +
                      packing + "\"\ncut_offset = [0.001, 0.002, 0.003]\n"},
                 {"coupling", "[coupling]\nthickness = 0.001\nbox = 0.007\nyoung_modulus = 71000\n"
                              "poisson_ratio = 0.2\n"}}),
        sceneOf(kEverySection, {{"indenter", "[indenter]\nkind = \"sphere\"\nradius = 0.004\n"},
                                {"damping", "[damping]\nkind = \"none\"\n"},
                                {"material", "[material]\ncalibration = \"" + calibration + "\"\n"},
                                {"densification", "[densification]\ncalibration = \"" + calibration + "\"\n"},
                                {"coupling", "[coupling]\nthickness = 0.0015\nbox = 0.026\n"}}),
        // Plasticity excludes densification: a custom law with each hardening; the preset with the
        // calibration's elastic law.
        sceneOf(kEverySection,
                {{"effects", "[effects]\nlist = [\"damping\", \"plasticity\", \"indenter\", \"fracture\"]\n"},
                 {"densification", ""},
                 {"coupling", ""},
                 {"plasticity", "[plasticity]\nlaw = \"custom\"\nshear_limit = 7000\ncap_ratio = 1.2\n"
                                "hardening = \"sigmoid\"\nonset_pressure = 7500\nsaturation = 0.2\n"
                                "sigmoid_amplitude = 3000\nsigmoid_pressure = 1800\nbulk_modulus = 43000\n"
                                "bulk_modulus_slope = 1.2\nshear_modulus = 34000\naveraging = \"none\"\n"
                                "check_every = 4\n"},
                 {"measure", "[measure]\nkind = \"material_test\"\noffset = 0.003\nstop_strain = 0.05\n"}}),
        sceneOf(kEverySection,
                {{"effects", "[effects]\nlist = [\"damping\", \"plasticity\", \"indenter\", \"fracture\"]\n"},
                 {"densification", ""},
                 {"coupling", ""},
                 {"material", "[material]\ncalibration = \"" + calibration + "\"\n"},
                 {"plasticity", "[plasticity]\nlaw = \"custom\"\nhardening = \"linear\"\nhardening_modulus = 90000\n"}}),
        sceneOf(kEverySection,
                {{"effects", "[effects]\nlist = [\"damping\", \"plasticity\", \"indenter\", \"fracture\"]\n"},
                 {"densification", ""},
                 {"coupling", ""},
                 {"material", "[material]\ncalibration = \"" + calibration + "\"\n"},
                 {"plasticity", "[plasticity]\nlaw = \"kermouche2008\"\n"}}),
    };
}

// The round trip read -> resolvedSceneToml -> read compares whole scenes (Scene::operator==), so these
// scenes, which give every key of every section of the key tables, test the reading, conversion and writing
// of each.
TEST(SceneReader, EveryKeyOfEverySectionRoundTrips) {
    const std::vector<std::string> scenes = everyKeyScenes();
    for (const std::string& text : scenes) {
        SCOPED_TRACE(text);
        const Scene scene = parseScene(text, "q.toml");
        expectRoundTrip(scene);
    }
    // Every key of the tables is given in one of them ([sets] has free names).
    std::vector<toml::table> documents;
    for (const std::string& text : scenes) {
        documents.push_back(toml::parse(text));
    }
    for (const scene_io::Section& section : scene_io::sceneSections()) {
        for (const scene_io::KeyDoc& key : section.docs()) {
            bool given = section.name == "sets";
            for (const toml::table& root : documents) {
                const toml::node* node = root.get(section.name);
                if (const toml::array* array = node ? node->as_array() : nullptr) {
                    for (const toml::node& element : *array) {
                        given = given || element.as_table()->contains(key.name);
                    }
                } else if (node && node->as_table()->contains(key.name)) {
                    given = true;
                }
            }
            EXPECT_TRUE(given) << section.name << "." << key.name << " is in no scene of the round trip";
        }
    }
}

// The example scenes (examples/*.toml, examples/*/*.toml; the calibration files beside them are not scenes).
TEST(SceneReader, ExampleScenesRoundTrip) {
    const std::filesystem::path examples = std::filesystem::path(VITRUM_SOURCE_DIR) / "examples";
    std::vector<std::filesystem::path> files;
    const auto add = [&](const std::filesystem::path& dir) {
        for (const auto& entry : std::filesystem::directory_iterator(dir)) {
            if (entry.path().extension() == ".toml" &&
                toml::parse_file(entry.path().string()).contains("scene")) {
                files.push_back(entry.path());
            }
        }
    };
    add(examples);
    for (const auto& entry : std::filesystem::directory_iterator(examples)) {
        if (entry.is_directory()) {
            add(entry.path());
        }
    }
    EXPECT_GE(files.size(), 12u);
    for (const std::filesystem::path& file : files) {
        SCOPED_TRACE(file.string());
        expectRoundTrip(readScene(file.string()));
    }
}

TEST(SceneReader, ConvertsUnitsToInternal) {
    const Scene scene = parseScene(kFull, "q.toml");
    EXPECT_DOUBLE_EQ(scene.sample.size.x(), 100.0); // 0.1 mm
    EXPECT_DOUBLE_EQ(scene.sample.radius, 12.3);
    EXPECT_DOUBLE_EQ(scene.material.beam_young, 414.0); // 414000 MPa
    EXPECT_DOUBLE_EQ(scene.material.density, 2.2037);   // kg/m³ → 10³ kg/m³
    EXPECT_DOUBLE_EQ(scene.time.duration, 1500.0);      // 1.5 us
    EXPECT_DOUBLE_EQ(scene.boundaries[2].ramp_time, 250.0);
    EXPECT_DOUBLE_EQ(scene.boundaries[1].value.z(), -0.3); // 0.3 mm/us = 0.3 µm/ns
    EXPECT_DOUBLE_EQ(scene.boundaries[2].value.x(), 0.1);  // 1e-4 mm

    const Scene um_us = parseScene("[units]\nlength = \"um\"\ntime = \"us\"\n[sets]\ns = \"all\"\n"
                                   "[[boundary]]\nset = \"s\"\nkind = \"velocity\"\nvelocity = [0, 0, -2]\n"
                                   "[time]\nduration = 3\n",
                                   "q.toml");
    EXPECT_DOUBLE_EQ(um_us.boundaries[0].value.z(), -2e-3); // µm/µs → µm/ns (km/s)
    EXPECT_DOUBLE_EQ(um_us.time.duration, 3000.0);

    // Factors below 1 divide by an exact power of ten, so round numbers stay round.
    const Scene nm =
        parseScene("[units]\nlength = \"nm\"\nstress = \"Pa\"\n[sample]\nradius = 100\n"
                   "[material]\nbeam_young_modulus = 7e10\ndensity = 2200\n[time]\nduration = 1\n",
                   "q.toml");
    EXPECT_EQ(nm.sample.radius, 0.1);
    EXPECT_EQ(nm.material.beam_young, 70.0);
    EXPECT_EQ(nm.material.density, 2.2);
    EXPECT_EQ(forceFactor("N"), 1e3);
    EXPECT_THROW(lengthFactor("km"), std::invalid_argument);
}

TEST(SceneReader, UnknownKeyNamesLineKeyAndKnownKeys) {
    const std::string message = errorOf("[time]\nduration = 1\n\n[sample]\nparticles = 10\npartcles = 5\n");
    expectMentions(message,
                   {"q.toml:6:1:", "unknown key 'sample.partcles'", "known keys in [sample]: lattice"});
    expectMentions(errorOf("[time]\nduration = 1\n[sampel]\n"),
                   {"q.toml:3:", "unknown key 'sampel'", "known tables"});
}

TEST(SceneReader, WrongTypeSaysExpectedAndFound) {
    expectMentions(
        errorOf("[time]\nduration = 1\n[sample]\nparticles = \"many\"\n"),
        {"q.toml:4:13:", "key 'sample.particles'", "expected an integer >= 2", "got the string \"many\""});
    expectMentions(errorOf("[time]\nduration = 1\n[sample]\nparticles = 2000.0\n"),
                   {"q.toml:4:13:", "key 'sample.particles'", "got 2000.0"});
    expectMentions(
        errorOf("[time]\nduration = 1\n[sample]\nsize = [1, 2]\n"),
        {"q.toml:4:8:", "key 'sample.size'", "an array of 3 numbers", "got an array of 2 elements"});
    expectMentions(errorOf("sample = 3\n[time]\nduration = 1\n"),
                   {"q.toml:1:10:", "key 'sample'", "a table"});
}

TEST(SceneReader, OutOfRangeSaysRangeAndValue) {
    expectMentions(errorOf("[time]\nduration = 1\n[sample]\nparticles = -5\n"),
                   {"q.toml:4:13:", "key 'sample.particles'", "expected an integer >= 2, got -5"});
    expectMentions(errorOf("[time]\nduration = 1\n[material]\nbeam_poisson_ratio = 0.5\n"),
                   {"q.toml:4:22:", "key 'material.beam_poisson_ratio'", "a number in (-1, 0.5)", "got 0.5"});
    expectMentions(errorOf("[time]\nduration = 1\n[sample]\nsize = [1, -2, 3]\n"),
                   {"q.toml:4:12:", "key 'sample.size[1]'", "a number > 0 (in um)", "got -2"});
    expectMentions(errorOf("[time]\nduration = 1\n[units]\nlength = \"km\"\n"),
                   {"q.toml:4:10:", "key 'units.length'", "one of \"m\", \"mm\", \"um\", \"nm\""});
    expectMentions(errorOf("[time]\nduration = inf\n"), {"q.toml:2:12:", "key 'time.duration'", "got inf"});
}

TEST(SceneReader, EffectsAreCheckedByName) {
    expectMentions(
        errorOf("[effects]\nlist = [\"elasticity\", \"plastic\"]\n[time]\nduration = 1\n"),
        {"q.toml:2:23:", "key 'effects.list'", "unknown effect \"plastic\"", "known effects: elasticity"});
    // The cap law's compaction and the beams' slider are two homes of densification: refused together, at the
    // other effect's entry.
    expectMentions(errorOf("[effects]\nlist = [\"plasticity\", \"densification\"]\n[plasticity]\n"
                           "bulk_modulus = 43\nshear_modulus = 34\n[time]\nduration = 1\n"),
                   {"q.toml:2:23:", "key 'effects.list'", "effect \"plasticity\" cannot be combined with \"densification\""});
    // A preset's hardening is the preset's: a hardening key beside it is refused. Its q_y and R are the
    // network's (the calibration's fit by default) and may be given: the resolved scene writes them so.
    expectMentions(errorOf("[effects]\nlist = [\"plasticity\"]\n[plasticity]\nlaw = \"bruns2020\"\n"
                           "onset_pressure = 7.0\nbulk_modulus = 43\nshear_modulus = 34\n[time]\nduration = 1\n"),
                   {"q.toml:5:18:", "key 'plasticity.onset_pressure'", "not used with law = \"bruns2020\""});
    const Scene given = parseScene("[effects]\nlist = [\"plasticity\"]\n[plasticity]\nlaw = \"bruns2020\"\n"
                                   "shear_limit = 7.0\ncap_ratio = 0.9\nbulk_modulus = 43\nshear_modulus = 34\n"
                                   "[time]\nduration = 1\n",
                                   "q.toml");
    EXPECT_EQ(given.plasticity.shear_limit, 7.0);
    EXPECT_EQ(given.plasticity.cap_ratio, 0.9);
    EXPECT_EQ(given.plasticity.onset_pressure, 8.0); // Bruns's, as published
    // Without an elastic law to judge the strain with: missing, with what to give.
    expectMentions(errorOf("[effects]\nlist = [\"plasticity\"]\n[time]\nduration = 1\n"),
                   {"missing key 'plasticity.bulk_modulus'", "[material] calibration"});
    // Every known effect is available now; coupling on a sample it cannot embed says so at its entry.
    expectMentions(errorOf("[effects]\nlist = [\"coupling\"]\n[time]\nduration = 1\n"),
                   {"q.toml:2:9:", "effect 'coupling'", "expected sample.shape = \"hemisphere\""});
    expectMentions(errorOf("[effects]\nlist = [\"elasticity\", \"elasticity\"]\n[time]\nduration = 1\n"),
                   {"q.toml:2:23:", "key 'effects.list'", "listed twice", "q.toml:2:9"});
}

TEST(SceneReader, BoundaryMustReferenceDefinedSet) {
    const std::string scene = "[time]\nduration = 1\n[sets]\nbottom = \"z < 1\"\ntop = \"z > 9\"\n"
                              "[[boundary]]\nset = \"botom\"\nkind = \"fixed\"\n";
    expectMentions(errorOf(scene), {"q.toml:7:7:", "key 'boundary[0].set'",
                                    "a set defined in [sets] (bottom, top)", "got the string \"botom\""});
    expectMentions(errorOf("[time]\nduration = 1\n[sets]\nb = \"all\"\n[[boundary]]\nset = \"b\"\nkind = "
                           "\"fixed\"\nvelocity = [1, 0, 0]\n"),
                   {"q.toml:8:12:", "key 'boundary[0].velocity'", "not used with kind = \"fixed\""});
    expectMentions(errorOf("[time]\nduration = 1\n[sets]\nb = \"all\"\n[[boundary]]\nset = \"b\"\nkind = "
                           "\"velocity\"\n"),
                   {"q.toml:5:1:", "missing key 'boundary[0].velocity'"});
    expectMentions(errorOf("[time]\nduration = 1\n[sets]\n2nd = \"all\"\n"),
                   {"q.toml:4:1:", "key 'sets.2nd'", "[A-Za-z_][A-Za-z0-9_-]*"});
}

TEST(SceneReader, OverrideSetsValues) {
    const Scene scene =
        parseScene(kFull, "q.toml", {"sample.particles=2000", "scene.name=\"x\"", "sample.size=[1,2,3]"});
    EXPECT_EQ(scene.sample.particles, 2000);
    EXPECT_EQ(scene.name, "x");
    EXPECT_DOUBLE_EQ(scene.sample.size.z(), 3000.0); // the file's units (mm) apply to overrides too
    EXPECT_EQ(scene.sample.lattice, Lattice::Sc);    // the rest of [sample] is kept
}

TEST(SceneReader, OverrideCreatesMissingTables) {
    const Scene scene = parseScene("[scene]\nname = \"a\"\n", "q.toml",
                                   {"time.duration=2", "output.every=7", "effects.list=[\"damping\"]",
                                    "damping={kind=\"bond-viscous\", coefficient=0.4}"});
    EXPECT_EQ(scene.time.duration, 2.0);
    EXPECT_EQ(scene.output.every, 7);
    EXPECT_EQ(scene.damping.kind, DampingKind::BondViscous);
    EXPECT_EQ(scene.damping.coefficient, 0.4);
}

TEST(SceneReader, OverrideErrorsNameTheOverride) {
    expectMentions(errorOf(kMinimal, {"sample.particles=abc"}),
                   {"--set sample.particles=abc: ", "key 'sample.particles'", "expected a TOML value"});
    expectMentions(errorOf(kMinimal, {"sample.particles=-1"}),
                   {"--set sample.particles=-1: key 'sample.particles': expected an integer >= 2, got -1"});
    expectMentions(errorOf(kMinimal, {"sample.partcles=5"}),
                   {"--set sample.partcles=5: unknown key 'sample.partcles'"});
    expectMentions(errorOf(kMinimal, {"sample.particles"}), {"--set sample.particles:", "dotted.key=value"});
}

TEST(SceneReader, SyntaxErrorReportsLine) {
    expectMentions(errorOf("[time]\nduration = 1\n[sample]\nparticles = \n"),
                   {"q.toml:4:", "TOML syntax error"});
    expectMentions(errorOf("[time]\nduration = 1\nduration = 2\n"), {"q.toml:3:", "duration"});
}

TEST(SceneReader, DurationIsRequired) {
    expectMentions(errorOf("[scene]\nname = \"a\"\n\n[time]\nsafety_ratio = 0.2\n"),
                   {"q.toml:4:1:", "missing key 'time.duration' in [time]", "a number > 0 (in ns)"});
    expectMentions(errorOf("[scene]\nname = \"a\"\n"),
                   {"q.toml: missing key 'time.duration'", "no [time] table"});
}

TEST(SceneReader, DampingTableAndEffectMustAgree) {
    expectMentions(errorOf("[time]\nduration = 1\n[damping]\nkind = \"cundall\"\ncoefficient = 0.1\n"),
                   {"q.toml:3:1:", "[damping]", "effects.list does not contain \"damping\""});
    expectMentions(
        errorOf("[effects]\nlist = [\"elasticity\", \"damping\"]\n[time]\nduration = 1\n"),
        {"q.toml:2:23:", "key 'effects.list'", "expected a [damping] table with kind and coefficient"});
    expectMentions(errorOf("[effects]\nlist = [\"damping\"]\n[damping]\nkind = \"cundall\"\ncoefficient = 1\n"
                           "[time]\nduration = 1\n"),
                   {"q.toml:5:15:", "key 'damping.coefficient'",
                    "a number in [0, 1) (for kind = \"cundall\")", "got 1"});
    expectMentions(
        errorOf("[effects]\nlist = [\"damping\"]\n[damping]\nkind = \"none\"\ncoefficient = 0.2\n"
                "[time]\nduration = 1\n"),
        {"q.toml:5:15:", "key 'damping.coefficient'", "expected 0 (for kind = \"none\"), got 0.2"});
}

TEST(SceneReader, ReadsFilesAndReportsMissingOnes) {
    const std::filesystem::path dir = testing::freshTempDir("scene-reader");
    const std::string path = (dir / "s.toml").string();
    std::ofstream(path) << kMinimal << "[sample]\nparticles = 1\n";
    try {
        readScene(path);
        ADD_FAILURE() << "no InputError";
    } catch (const InputError& e) {
        expectMentions(e.what(), {path + ":4:13:", "key 'sample.particles'"});
    }
    EXPECT_EQ(readScene(path, {"sample.particles=8"}).source_path, path);
    try {
        readScene((dir / "absent.toml").string());
        ADD_FAILURE() << "no InputError";
    } catch (const InputError& e) {
        expectMentions(e.what(), {"cannot open scene file '" + (dir / "absent.toml").string() + "'"});
    }
    std::filesystem::remove_all(dir);
}

// A relax stage's settle window: read in the scene's time unit, written back only when set (a scene without it
// resolves as it did before the key existed), refused on other stage kinds and when it cannot fit the stage.
TEST(SceneReader, RelaxSettleWindowIsReadRoundTripsAndIsChecked) {
    const std::string quickstart = std::string(VITRUM_SOURCE_DIR) + "/examples/paper/quickstart.toml";
    const Scene plain = readScene(quickstart);
    EXPECT_EQ(plain.stages[3].settle, 0.0);
    EXPECT_EQ(resolvedSceneToml(plain).find("settle"), std::string::npos);
    const Scene settled = readScene(quickstart, {"stage[3].settle=20.0"});
    EXPECT_EQ(settled.stages[3].settle, 20.0); // ns, the quickstart's time unit
    const std::string text = resolvedSceneToml(settled);
    EXPECT_NE(text.find("settle = 20"), std::string::npos) << text;
    EXPECT_EQ(parseScene(text, settled.source_path).stages[3].settle, 20.0);
    auto message = [&](const std::string& set) {
        try {
            readScene(quickstart, {set});
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        ADD_FAILURE() << "no InputError for --set " << set;
        return std::string();
    };
    expectMentions(message("stage[3].settle=100.0"), {"stage[3].settle", "expected less than stage[3].duration"});
    expectMentions(message("stage[0].settle=1.0"), {"stage[0].settle", "not used with kind = \"load\""});
    expectMentions(message("stage[3].settle=-1.0"), {"stage[3].settle"});
}

// [sample] cut_from: the path is resolved against the scene file and stored absolute (so the resolved scene
// reads back the same file), the offset is converted like any length, the packer's keys beside it are
// refused with line and key, and loadOrBuildSample returns the cut (cutPacking's count, not a new packing).
TEST(SceneReader, SampleCutFromAPackingFile) {
    const std::filesystem::path dir = testing::freshTempDir("scene-cut");
    PackingParams box;
    box.shape = SampleShape::Box;
    box.size = Vec3(4.0, 4.0, 3.0);
    box.particles = 600;
    savePacking((dir / "box.h5").string(), packRandom(box));
    const std::string head = std::string(kMinimal) +
                             "[units]\nlength = \"mm\"\n[sample]\nlattice = \"random\"\n"
                             "shape = \"hemisphere\"\nradius = 0.0015\ncut_from = \"box.h5\"\n";
    const std::string path = (dir / "s.toml").string();
    std::ofstream(path) << head << "cut_offset = [0.002, 0.002, 0.003]\n";
    const Scene scene = readScene(path);
    EXPECT_EQ(scene.sample.cut_from, std::filesystem::absolute(dir / "box.h5").lexically_normal().string());
    expectSameVec(scene.sample.cut_offset, Vec3(2.0, 2.0, 3.0)); // mm → µm
    expectRoundTrip(scene);

    const SampleSource cut = loadOrBuildSample(scene);
    const Packing direct =
        cutPacking(loadPacking((dir / "box.h5").string()), scene.sample, Vec3(2.0, 2.0, 3.0));
    EXPECT_EQ(cut.sample.sample.centres, direct.sample.centres);
    EXPECT_EQ(cut.sample.pairs, direct.bond_pairs);
    EXPECT_LT(cut.sample.sample.centres.size(), 600u);
    EXPECT_NE(cut.origin.find("cut from"), std::string::npos) << cut.origin;

    auto errorIn = [&](const std::string& text) -> std::string {
        std::ofstream(path) << text;
        try {
            readScene(path);
        } catch (const InputError& e) {
            return e.what();
        }
        return "no InputError";
    };
    expectMentions(errorIn(head + "particles = 500\n"),
                   {path + ":10:13:", "key 'sample.particles': not used with sample.cut_from"});
    expectMentions(errorIn(head + "file = \"cache.h5\"\n"),
                   {"key 'sample.file': not used with sample.cut_from"});
    const std::string absent =
        std::string(kMinimal) + "[sample]\nlattice = \"random\"\ncut_from = \"none.h5\"\n";
    expectMentions(errorIn(absent), {"key 'sample.cut_from': no packing file at", "none.h5"});
    expectMentions(errorIn(std::string(kMinimal) + "[sample]\ncut_from = \"box.h5\"\n"),
                   {"key 'sample.cut_from'", "expected lattice = \"random\", got \"fcc\""});
    expectMentions(errorIn(std::string(kMinimal) + "[sample]\ncut_offset = [1, 2, 3]\n"),
                   {"key 'sample.cut_offset': used only with sample.cut_from"});
    std::filesystem::remove_all(dir);
}

} // namespace
} // namespace vitrum
