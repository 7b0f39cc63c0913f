// [densification], [fracture], [contact], [coupling]: the parameters of the effects beyond elasticity (the
// indenter's are in sections_indenter.cpp). Each table is read only when its effect is in effects.list.
#include <filesystem>
#include <numbers>

#include "io/scene/sections.hpp"
#include "io/units.hpp"
#include "solver/effects/plasticity.hpp"
#include "solver/model/sample.hpp"
#include "solver/errors.hpp"

namespace vitrum::scene_io {

/// A plain section written only when its effect is on.
template <class S, class Part>
Section effectSection(Effect effect, std::string meaning, Part part, const std::vector<Key<S>>& (*keys)(),
                      void (*read)(SceneReading&)) {
    Section s = plainSection<S>(std::string(nameOf(effect)), std::move(meaning), part, keys);
    s.read = read;
    const auto write = s.write;
    s.write = [write, effect](const Scene& scene, const Units& units, std::vector<std::string>& blocks) {
        if (scene.hasEffect(effect)) {
            write(scene, units, blocks);
        }
    };
    return s;
}

/// Where a message about an effect's table points: the table, or the effect's entry in effects.list.
const toml::source_region& tableOrEffect(const TableReader& table, const SceneReading& r, Effect effect) {
    return table.table() ? table.table()->source() : r.effectNode(effect)->source();
}

// --- [densification] ---------------------------------------------------------------------------------------

const std::vector<Key<DensificationParams>>& densificationKeys() {
    using S = DensificationParams;
    static const std::vector<Key<S>> keys = {
        number<S>("yield_stress", &S::yield_stress, Unit::Stress, kPositive,
                  "sigma_mu^d, the slider's yield stress")
            .defaultIs("7.13 GPa (paper Table 3), or the calibration's"),
        number<S>("tangent_modulus", &S::tangent_modulus, Unit::Stress, kNonNegative,
                  "E_mu^t, the slider's tangent modulus (below material.beam_young_modulus)")
            .defaultIs("98.82 GPa (paper Table 3), or the calibration's"),
        number<S>("max_permanent_strain", &S::max_permanent_strain, Unit::None, Range{0.0, 1.0, true, true},
                  "eps_mu^pmax, the permanent strain at saturation")
            .defaultIs("0.067 (paper Table 3), or the calibration's"),
        flag<S>("property_evolution", &S::property_evolution,
                "E and nu rise with densification (needs eqs 5-6: a calibration, or eq5, eq6_b0, eq6_b1)"),
        number<S>("young_gain", &S::young_gain, Unit::None, kNonNegative,
                  "relative rise of E at saturation (Ji)"),
        number<S>("poisson_gain", &S::poisson_gain, Unit::None, kNonNegative,
                  "relative rise of nu at saturation (capped at poisson_ratio_max)"),
        path<S>("calibration",
                "a calibration file for eqs 5-6 and the slider (default: [material] calibration)"),
        number<S>("young_modulus", &S::young, Unit::Stress, kPositive,
                  "E_0, the macroscopic modulus before densification")
            .defaultIs("the calibration's target, else 72.5 GPa"),
        number<S>("poisson_ratio", &S::poisson, Unit::None, Range{-1.0, 0.5, true, true},
                  "nu_0, before densification")
            .defaultIs("the calibration's target, else 0.17"),
        number<S>("poisson_ratio_max", &S::poisson_max, Unit::None, Range{-1.0, 0.5, true, true},
                  "the largest nu eq (5) is valid for")
            .defaultIs("the calibration's, else 0.25"),
        vector<S>("eq5", &S::eq5, Unit::None, kAny, "a_0, a_1, a_2 of eq (5)").defaultIs("the calibration's"),
        vector<S>("eq6_b0", &S::eq6_b0, Unit::Stress, kAny, "b_00, b_01, b_02 of eq (6)")
            .defaultIs("the calibration's"),
        vector<S>("eq6_b1", &S::eq6_b1, Unit::None, kAny, "b_10, b_11, b_12 of eq (6)")
            .defaultIs("the calibration's"),
    };
    return keys;
}

void readDensification(SceneReading& r) {
    const TableReader table = r.top.subtable("densification");
    if (!effectTable(table, r.scene, Effect::Densification)) {
        return;
    }
    DensificationParams& d = r.scene.densification;
    readKeys(table, densificationKeys(), d, r);
    const auto given = [&](const char* key) { return table.find(key) != nullptr; };
    // Eqs (5)-(6) and the slider's parameters: from this table's calibration file, else [material]'s; the
    // table's own keys override either.
    std::optional<CalibrationFile> own;
    if (const toml::node* node = table.find("calibration")) {
        const std::string file =
            std::filesystem::path(table.source().relativeToScene(*table.string("calibration")))
                .lexically_normal()
                .string();
        try {
            own = readCalibration(file);
        } catch (const InputError& e) {
            table.fail(*node, "key 'densification.calibration': " + std::string(e.what()));
        }
    }
    const std::optional<CalibrationFile>& calibration = own ? own : r.material_calibration;
    if (calibration && calibration->densification) {
        // `vitrum calibrate densification` wrote σ_μ^d, E_μ^t (GPa, the internal unit) and ε_μ^pmax.
        const DensificationParameters& slider = *calibration->densification;
        d.yield_stress = given("yield_stress") ? d.yield_stress : slider.yield_stress;
        d.tangent_modulus = given("tangent_modulus") ? d.tangent_modulus : slider.tangent_modulus;
        d.max_permanent_strain =
            given("max_permanent_strain") ? d.max_permanent_strain : slider.max_permanent_strain;
    }
    const Units& u = r.units;
    if (d.tangent_modulus >= r.scene.material.beam_young) {
        const toml::node* node = table.find("tangent_modulus");
        r.source.fail(
            node ? node->source() : r.effectNode(Effect::Densification)->source(),
            "key 'densification.tangent_modulus': expected a number below material.beam_young_modulus (" +
                shortest(u.fromInternal(r.scene.material.beam_young, Unit::Stress)) + " " +
                u.name(Unit::Stress) + "; the slider's hardening E E_t/(E - E_t) needs E_t < E), got " +
                shortest(u.fromInternal(d.tangent_modulus, Unit::Stress)));
    }
    if (calibration) {
        const ElasticCalibration& fit = calibration->fit;
        d.eq5 = given("eq5") ? d.eq5 : Vec3(fit.a[0], fit.a[1], fit.a[2]);
        d.eq6_b0 = given("eq6_b0") ? d.eq6_b0 : Vec3(fit.b0[0], fit.b0[1], fit.b0[2]);
        d.eq6_b1 = given("eq6_b1") ? d.eq6_b1 : Vec3(fit.b1[0], fit.b1[1], fit.b1[2]);
        d.young = given("young_modulus") ? d.young : calibration->target_young;
        d.poisson = given("poisson_ratio") ? d.poisson : calibration->target_poisson;
        d.poisson_max = given("poisson_ratio_max") ? d.poisson_max : fit.nu_max;
    }
    const bool explicit_eqs = given("eq5") && given("eq6_b0") && given("eq6_b1");
    if (d.property_evolution && !calibration && !explicit_eqs) {
        r.source.fail(
            tableOrEffect(table, r, Effect::Densification),
            "effect \"densification\" with property_evolution = true needs the calibrated eqs (5)-(6): "
            "expected densification.calibration or material.calibration (a file of vitrum calibrate "
            "elastic), or all of densification.eq5, eq6_b0, eq6_b1, or densification.property_evolution = "
            "false");
    }
    if (d.property_evolution && d.poisson > d.poisson_max) {
        r.source.fail(tableOrEffect(table, r, Effect::Densification),
                      "key 'densification.poisson_ratio': expected at most poisson_ratio_max (" +
                          shortest(d.poisson_max) + "), got " + shortest(d.poisson));
    }
}

Section densificationSection() {
    return effectSection<DensificationParams>(
        Effect::Densification,
        "Effect densification: the beams' spring-slider (paper §2.2, kernels/densification.hpp). Defaults: "
        "paper Table 3 and the macroscopic gains of Ji (paper Fig 4); eqs (5)-(6) come from the calibration "
        "file.",
        member<&Scene::densification>, &densificationKeys, readDensification);
}

// --- [plasticity] ------------------------------------------------------------------------------------------

const std::vector<Key<PlasticityParams>>& plasticityKeys() {
    using S = PlasticityParams;
    const auto custom = [](const S& p) { return p.law == CapLaw::Custom; };
    const auto sigmoid = [](const S& p) {
        return p.law == CapLaw::Custom && p.hardening == CapHardeningKind::Sigmoid;
    };
    const auto linear = [](const S& p) { return p.law == CapLaw::Custom && p.hardening == CapHardeningKind::Linear; };
    const auto notWithLaw = notUsedWith("law", &S::law);
    const auto notWithHardening = [](const S& p, const toml::node& node) {
        return p.law != CapLaw::Custom ? "not used with law = " + tomlString(nameOf(p.law)) + ", got " + describe(node)
                                       : "not used with hardening = " + tomlString(nameOf(p.hardening)) + ", got " +
                                             describe(node);
    };
    static const std::vector<Key<S>> keys = {
        choice<S>("law", &S::law,
                  "the cap law: a published silica (Bruns 2020, Kermouche 2008, Molnar 2017) or custom "
                  "(the keys below)"),
        number<S>("shear_limit", &S::shear_limit, Unit::Stress, kPositive,
                  "q_y, the flat shear limit of the particle law (C2); with a published law, the network's value "
                  "that gives that law's yield")
            .defaultIs("custom: 7.5 GPa; a published law: the calibration's fit to it, else its own q_y"),
        number<S>("cap_ratio", &S::cap_ratio, Unit::None, kPositive,
                  "R: the cap's half-axes are R q_y along p and q_y along q (C3); with a published law, as "
                  "shear_limit")
            .defaultIs("custom: 1.066; a published law: the calibration's fit to it, else its own R"),
        choice<S>("hardening", &S::hardening, "p_b(e): Bruns's sigmoid (H1-H2) or linear p_b0 + H e")
            .onlyWhen(custom, notWithLaw),
        number<S>("onset_pressure", &S::onset_pressure, Unit::Stress, kPositive,
                  "p_b0, the hydrostatic yield pressure of the virgin material")
            .onlyWhen(custom, notWithLaw),
        number<S>("saturation", &S::saturation, Unit::None, Range{0.0, 1.0, true, true},
                  "d_s, the densification (Delta rho / rho) at saturation")
            .onlyWhen(custom, notWithLaw),
        number<S>("sigmoid_amplitude", &S::sigmoid_amplitude, Unit::None, kPositive, "A of the sigmoid (H1)")
            .onlyWhen(sigmoid, notWithHardening),
        number<S>("sigmoid_pressure", &S::sigmoid_pressure, Unit::Stress, kPositive, "P_s of the sigmoid (H1)")
            .onlyWhen(sigmoid, notWithHardening),
        number<S>("hardening_modulus", &S::hardening_modulus, Unit::Stress, kNonNegative,
                  "H = dp_b/de of the linear hardening")
            .onlyWhen(linear, notWithHardening),
        number<S>("bulk_modulus", &S::bulk, Unit::Stress, kPositive,
                  "K_0 of the elastic law the strain is judged with: p = (K_0/K') (J^-K' - 1) (Murnaghan)")
            .defaultIs("the calibration file's [plasticity] fit, else K of the target E, nu of [material] calibration"),
        number<S>("bulk_modulus_slope", &S::bulk_slope, Unit::None, Range{0.0, 20.0, false, true},
                  "K' = dK/dp of that law (0: linear in the volumetric log-strain)")
            .defaultIs("the calibration file's [plasticity] fit, else 0"),
        number<S>("shear_modulus", &S::shear, Unit::Stress, kPositive, "G of that law")
            .defaultIs("the calibration file's [plasticity] fit, else G of the target E, nu"),
        choice<S>("averaging", &S::averaging,
                  "the strain judged: the least-squares F of the particle's own bonds, or of its bonds pooled with "
                  "those of its bonded neighbours (one ring) or of their neighbours too (two rings); \"none\" is "
                  "not stable under a tool (a contact particle's own F is ill-conditioned)"),
        integer<S>("check_every", &S::check_every, 1,
                   "steps between returns (the return is exact for any increment: 10 moves the virtual tests' "
                   "yield points by under 0.1 % and costs a tenth)"),
    };
    return keys;
}

void readPlasticity(SceneReading& r) {
    const TableReader table = r.top.subtable("plasticity");
    if (!effectTable(table, r.scene, Effect::Plasticity)) {
        return;
    }
    const Scene& scene = r.scene;
    PlasticityParams& p = r.scene.plasticity;
    // Not with densification or coupling: refused where effects.list is read (sections_sample.cpp).
    readKeys(table, plasticityKeys(), p, r);
    const PlasticityParams given = p; // q_y and R given beside a published law are the network's own
    const std::optional<CalibrationFile>& cal = r.material_calibration;
    const bool own_calibration = cal && cal->micro.beam_young == scene.material.beam_young &&
                                 cal->micro.radius_ratio == scene.material.radius_ratio;
    const std::optional<PlasticityCalibration> fit = own_calibration ? cal->plasticity : std::nullopt;
    // The cap: a published law's constants, with the particle law's q_y and R fitted to that law's targets
    // when the calibration holds such a fit (vitrum calibrate plasticity); custom keys as given.
    std::string cap_source = "custom keys";
    if (p.law != CapLaw::Custom) {
        const CapPlasticity c = publishedCapLaw(p.law);
        p.shear_limit = c.shear_limit;
        p.cap_ratio = c.cap_ratio;
        p.hardening = c.hardening.kind == CapHardening::Kind::Sigmoid ? CapHardeningKind::Sigmoid : CapHardeningKind::Linear;
        p.onset_pressure = c.hardening.onset_pressure;
        p.saturation = c.hardening.saturation;
        p.sigmoid_amplitude = c.hardening.sigmoid_amplitude;
        p.sigmoid_pressure = c.hardening.sigmoid_pressure;
        p.hardening_modulus = c.hardening.modulus;
        cap_source = "the published constants (no fit of this law in the calibration)";
        if (fit && fit->law == nameOf(p.law)) {
            p.shear_limit = fit->shear_limit;
            p.cap_ratio = fit->cap_ratio;
            cap_source = "q_y and R of the calibration's fit to this law's targets, its hardening as published";
        }
        bool overridden = false;
        const auto keep = [&](const char* key, auto PlasticityParams::*field) {
            if (table.find(key) != nullptr) {
                p.*field = given.*field;
                overridden = true;
            }
        };
        keep("shear_limit", &PlasticityParams::shear_limit);
        keep("cap_ratio", &PlasticityParams::cap_ratio);
        if (overridden) {
            cap_source = "its hardening as published, q_y and R as the table gives them";
        }
    }
    const bool bulk = table.find("bulk_modulus") != nullptr;
    const bool shear = table.find("shear_modulus") != nullptr;
    if (bulk != shear) {
        table.missing(bulk ? "shear_modulus" : "bulk_modulus",
                      std::string("a value beside plasticity.") + (bulk ? "bulk_modulus" : "shear_modulus") +
                          " (give both, or neither to take them from [material] calibration)");
    }
    if (bulk) {
        p.material_source = "explicit ([plasticity] bulk_modulus, bulk_modulus_slope, shear_modulus); cap: " + cap_source;
        return;
    }
    if (!own_calibration) {
        table.missing("bulk_modulus",
                      "the elastic law the strain is judged with: plasticity.bulk_modulus and "
                      "plasticity.shear_modulus, or [material] calibration with its own micro-parameters (the "
                      "packing's calibrated E, nu, or its [plasticity] fit)");
    }
    const bool slope = table.find("bulk_modulus_slope") != nullptr;
    if (fit) {
        p.bulk = fit->bulk;
        p.shear = fit->shear;
        p.bulk_slope = slope ? p.bulk_slope : fit->bulk_slope;
        p.material_source = "the [plasticity] fit of [material] calibration (K_0, K', G of the packing's virtual "
                            "tests); cap: " + cap_source;
        return;
    }
    p.bulk = cal->target_young / (3.0 * (1.0 - 2.0 * cal->target_poisson));
    p.shear = cal->target_young / (2.0 * (1.0 + cal->target_poisson));
    p.material_source = "[material] calibration: K, G of its target E, nu; cap: " + cap_source;
}

Section plasticitySection() {
    Section s = effectSection<PlasticityParams>(
        Effect::Plasticity,
        "Effect plasticity (issue 26; kernels/plastic_flow.hpp): silica's cap law (a flat shear limit and a "
        "hardening elliptic cap in p, q) on each particle's strain; the plastic strain moves the rest states of "
        "its bonds. Not with densification or coupling.",
        member<&Scene::plasticity>, &plasticityKeys, readPlasticity);
    s.write = [](const Scene& scene, const Units& units, std::vector<std::string>& blocks) {
        if (scene.hasEffect(Effect::Plasticity)) {
            // The source of K0, K', G, q_y, R is the run log's (it changes once they are written out here).
            std::string out = "[plasticity]   # as resolved: the elastic law and the network's q_y, R\n";
            writeKeys(out, plasticityKeys(), scene.plasticity, units);
            blocks.push_back(out);
        }
    };
    return s;
}

// --- [fracture] --------------------------------------------------------------------------------------------

const std::vector<Key<FractureParams>>& fractureKeys() {
    using S = FractureParams;
    static const std::vector<Key<S>> keys = {
        number<S>("hydrostatic_strength", &S::hydrostatic_strength, Unit::Stress, kPositive,
                  "sigma_f^hyd: a particle is released when its hydrostatic tension reaches it (eq 10)"),
        integer<S>("check_every", &S::check_every, 1, "steps between evaluations of the criterion"),
        choice<S>("volume", &S::volume,
                  "Omega_i: the particle's sphere over packing_fraction, the bare sphere, or its Delaunay "
                  "cell (R^3-weighted shares of the centres' tetrahedra; sums to the hull's volume)"),
        choice<S>(
            "averaging", &S::averaging,
            "the stress judged: eq (10) per particle, or its Omega-weighted mean with the bonded neighbours"),
        number<S>("packing_fraction", &S::packing_fraction, Unit::None, Range{0.0, 1.0, true, false},
                  "phi of Omega_i = (4/3) pi R^3 / phi")
            .onlyWhen([](const S& f) { return f.volume == FractureVolume::Packing; },
                      notUsedWith("volume", &S::volume))
            .defaultIs("the sample's: pi/6 (sc), pi/(3 sqrt 2) (fcc), sample.packing_fraction (random)"),
    };
    return keys;
}

void readFracture(SceneReading& r) {
    const TableReader table = r.top.subtable("fracture");
    if (!effectTable(table, r.scene, Effect::Fracture)) {
        return;
    }
    FractureParams& f = r.scene.fracture;
    readKeys(table, fractureKeys(), f, r);
    if (!table.find("packing_fraction")) {
        // Ω_i = sphere / φ with the sample's φ: random packings their target, lattices their exact value.
        f.packing_fraction = f.volume == FractureVolume::Sphere ? 1.0 : samplePackingFraction(r.scene.sample);
    }
}

Section fractureSection() {
    return effectSection<FractureParams>(
        Effect::Fracture,
        "Effect fracture (paper §3, eqs 7-10): per-particle virial stress and the hydrostatic release "
        "criterion. It switches contact on, and adds the damage and stress fields to the maps.",
        member<&Scene::fracture>, &fractureKeys, readFracture);
}

// --- [contact] ---------------------------------------------------------------------------------------------

const std::vector<Key<ContactParams>>& contactKeys() {
    using S = ContactParams;
    static const std::vector<Key<S>> keys = {
        number<S>("normal_stiffness", &S::normal_stiffness, Unit::Stiffness, kPositive, "k_n of the contacts")
            .writtenWhen([](const S& c) { return c.normal_stiffness > 0.0; },
                         "# normal_stiffness not given: the mean beam axial stiffness of the sample")
            .defaultIs("the mean beam axial stiffness E_mu S / l_0 of the sample"),
        number<S>("restitution", &S::restitution, Unit::None, Range{0.0, 1.0, true, false},
                  "coefficient of restitution e (the dashpot c_n = 2 zeta sqrt(m* k_n))"),
        number<S>("tangential_ratio", &S::tangential_ratio, Unit::None, kNonNegative, "k_t / k_n")
            .withNote("k_t / k_n"),
        number<S>("friction", &S::friction, Unit::None, kNonNegative, "Coulomb friction coefficient mu"),
        number<S>("skin_ratio", &S::skin_ratio, Unit::None, kPositive, "Verlet skin / mean particle radius")
            .withNote("skin / mean radius"),
    };
    return keys;
}

void readContact(SceneReading& r) {
    const TableReader table = r.top.subtable("contact");
    if (table.table() && !r.scene.hasEffect(Effect::Contact)) {
        table.fail(*table.table(),
                   "table [contact] is given but effects.list contains neither \"contact\" nor "
                   "\"fracture\" (expected one of them in effects.list, or no [contact] table)");
    }
    if (r.scene.hasEffect(Effect::Contact)) {
        readKeys(table, contactKeys(), r.scene.contact, r);
    }
}

Section contactSection() {
    return effectSection<ContactParams>(
        Effect::Contact,
        "Effect contact (on with fracture; kernels/contact.hpp): contacts between unbonded particles.",
        member<&Scene::contact>, &contactKeys, readContact);
}

// --- [coupling] --------------------------------------------------------------------------------------------

const std::vector<Key<CouplingParams>>& couplingKeys() {
    using S = CouplingParams;
    static const std::vector<Key<S>> keys = {
        number<S>("thickness", &S::thickness, Unit::Length, kPositive,
                  "bridging zone thickness: the shell R - thickness <= r <= R of the hemisphere"),
        number<S>("box", &S::box, Unit::Length, kPositive,
                  "CNEM box edge (the box is [-box/2, box/2]^2 x [-box, 0])"),
        integer<S>("nodes", &S::nodes, 100, "target CNEM node count"),
        choice<S>("profile", &S::profile, "the bridging weight's profile across the zone"),
        number<S>("multiplier_tolerance", &S::multiplier_tolerance, Unit::None, Range{0.0, 1.0, true, false},
                  "a node carries a multiplier above this x the largest support"),
        number<S>("stabilisation", &S::stabilisation, Unit::None, Range{0.0, 1.0},
                  "beta of the CNEM's linear-tet stabilisation"),
        number<S>("jitter", &S::jitter, Unit::None, Range{0.0, 0.45},
                  "interior node jitter, fraction of the spacing")
            .withNote("fraction of the node spacing"),
        choice<S>("lateral_faces", &S::lateral, "the CNEM box's lateral faces: free, or on rollers"),
        choice<S>("zone_check", &S::zone_check,
                  "APP-2: strict (any slip in the zone stops the run) or weighted (up to zone_tolerance)"),
        number<S>("zone_tolerance", &S::zone_tolerance, Unit::None, Range{0.0, 1.0, false, true},
                  "weighted: the largest continuum-weighted share of the slip volume in the zone")
            .withNote("largest continuum-weighted share of the slip volume in the zone"),
        number<S>("young_modulus", &S::young, Unit::Stress, kPositive,
                  "the continuum's E (with poisson_ratio)")
            .defaultIs("the target of [material] calibration"),
        number<S>("poisson_ratio", &S::poisson, Unit::None, Range{-1.0, 0.5, true, true},
                  "the continuum's nu (with young_modulus)")
            .defaultIs("the target of [material] calibration"),
        number<S>("density", &S::density, Unit::Density, kPositive, "the continuum's density")
            .writtenWhen([](const S& c) { return c.density > 0.0; },
                         "# density: measured on the packing (sum of particle masses / hemisphere volume)")
            .defaultIs("measured on the packing (sum of masses / hemisphere volume)"),
    };
    return keys;
}

void readCoupling(SceneReading& r) {
    const TableReader table = r.top.subtable("coupling");
    if (!effectTable(table, r.scene, Effect::Coupling)) {
        return;
    }
    const Scene& scene = r.scene;
    const Units& u = r.units;
    CouplingParams& c = r.scene.coupling;
    const toml::source_region& where = tableOrEffect(table, r, Effect::Coupling);
    // The paper's set-up (§4, Fig 12): the DEM hemisphere under the indented face, in a CNEM box.
    if (scene.sample.shape != SampleShape::Hemisphere) {
        r.source.fail(where,
                      "effect 'coupling': the coupled domain embeds a hemisphere sample (the paper's §4 "
                      "set-up), but sample.shape is \"" +
                          std::string(nameOf(scene.sample.shape)) +
                          "\" (expected sample.shape = \"hemisphere\")");
    }
    readKeys(table, couplingKeys(), c, r);
    const double R = scene.sample.radius;
    const double length = lengthFactor(u.system().length);
    const std::string& in_length = u.system().length;
    if (!(c.thickness < R)) {
        const toml::node* n = table.find("thickness");
        r.source.fail(n ? n->source() : where,
                      "key 'coupling.thickness': the bridging zone must lie inside the hemisphere (radius " +
                          shortest(R / length) + " " + in_length + "), got " +
                          shortest(c.thickness / length) + " " + in_length);
    }
    if (!(c.box > 2.0 * R)) {
        const toml::node* n = table.find("box");
        r.source.fail(
            n ? n->source() : where,
            "key 'coupling.box': the CNEM box must contain the hemisphere with room around it (expected "
            "more than 2 x sample.radius = " +
                shortest(2.0 * R / length) + " " + in_length + "), got " + shortest(c.box / length) + " " +
                in_length);
    }
    // The continuum's E and ν: explicit keys, else the calibration of the packing ([material] calibration:
    // the targets its micro-parameters reproduce on the fitted eqs 5-6). ρ: explicit, else measured on the
    // packing when the model is built (Σ m_i / V of the hemisphere: the DEM's own mass per volume).
    const bool young = table.find("young_modulus") != nullptr;
    const bool poisson = table.find("poisson_ratio") != nullptr;
    if (young != poisson) {
        table.missing(young ? "poisson_ratio" : "young_modulus",
                      std::string("a value beside coupling.") + (young ? "young_modulus" : "poisson_ratio") +
                          " (give both, or neither to take them from [material] calibration)");
    }
    if (young) {
        c.material_source = "explicit ([coupling] young_modulus, poisson_ratio)";
        return;
    }
    const std::optional<CalibrationFile>& cal = r.material_calibration;
    if (!cal || cal->micro.beam_young != scene.material.beam_young ||
        cal->micro.radius_ratio != scene.material.radius_ratio) {
        table.missing("young_modulus",
                      "the continuum's E and nu: coupling.young_modulus and coupling.poisson_ratio, or "
                      "[material] calibration with its own micro-parameters (the packing's calibrated E, "
                      "nu)");
    }
    c.young = cal->target_young;
    c.poisson = cal->target_poisson;
    c.material_source =
        "calibration of the packing ([material] calibration: the target E, nu its micro-parameters "
        "reproduce on the fitted eqs 5-6; eq 6 gives E = " +
        shortest(cal->fit.young(cal->micro.radius_ratio, cal->micro.beam_young)) + " GPa)";
}

Section couplingSection() {
    Section s = effectSection<CouplingParams>(Effect::Coupling,
                                              "Effect coupling (solver/effects/coupling.hpp): the DEM "
                                              "hemisphere embedded in an elastic CNEM box (the paper's §4, "
                                              "Fig 12), tied by an Arlequin bridging zone; the box's bottom "
                                              "face is clamped, its top face free.",
                                              member<&Scene::coupling>, &couplingKeys, readCoupling);
    s.write = [](const Scene& scene, const Units& units, std::vector<std::string>& blocks) {
        if (scene.hasEffect(Effect::Coupling)) {
            std::string out = "[coupling]   # continuum E, nu: " + scene.coupling.material_source + "\n";
            writeKeys(out, couplingKeys(), scene.coupling, units);
            blocks.push_back(out);
        }
    };
    return s;
}

} // namespace vitrum::scene_io
