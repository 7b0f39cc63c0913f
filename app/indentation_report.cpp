#include "app/indentation_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "io/atomic_file.hpp"
#include "kernels/views.hpp"
#include "kernels/strain.hpp"
#include "solver/errors.hpp"
#include "solver/measure/cracks.hpp"
#include "solver/measure/densified_zone.hpp"
#include "solver/measure/imprint.hpp"
#include "solver/model/sample.hpp"

namespace vitrum {

namespace fs = std::filesystem;

namespace {
constexpr double kPi = 3.14159265358979323846;

/// Radius of the sample's free top face (hemisphere, cylinder, sphere: its radius; box: half the smaller side).
double sampleRadius(const SampleParams& s) {
    return s.shape == SampleShape::Box ? 0.5 * std::min(s.size.x(), s.size.y()) : s.radius;
}

/// Paper Table 4 (Keryvin-type rows): V⁻, V⁺, V_d, D, L for the DEM row and the experiments.
struct Table4Row {
    const char* source;
    double v_minus, v_plus, v_d, depth, diagonal;
};
const Table4Row kTable4_01N[] = {{"paper DEM", 1.304, 0.136, 1.168, 0.159, 4.758},
                                 {"paper CNEM-DEM", 1.302, 0.131, 1.171, 0.159, 4.758},
                                 {"exp. Ji [8]", 0.727, 0.108, 0.605, 0.377, 4.707},
                                 {"exp. [32]", 1.034, 0.018, 0.952, 0.421, 5.157}};
const Table4Row kTable4_05N[] = {{"paper DEM", 14.534, 1.174, 13.360, 0.397, 9.318},
                                 {"paper CNEM-DEM", 13.628, 0.920, 12.708, 0.409, 9.957},
                                 {"exp. Ji [8]", 9.971, 1.138, 8.805, 0.908, 10.371}};
} // namespace

CrackParams crackParams(const Indenter& indenter, double mean_radius, double contact_radius) {
    CrackParams cp;
    cp.axis = indenter.tip; // the load axis passes through the tip (x, y)
    cp.surface = indenter.surface_level;
    cp.contact_radius = contact_radius;
    if (indenter.tool.kind == ToolKind::Vickers) {
        cp.square_half_side = contact_radius / std::sqrt(2.0); // the farthest contact point is a print corner
    }
    cp.band = 3.0 * mean_radius;
    return cp;
}

CrackPattern classifyReleased(const Model& model, const CrackParams& params) {
    return classifyReleased(model.particles, params);
}

CrackPattern classifyReleased(const Particles& p, const CrackParams& params) {
    std::vector<double> centres;
    for (std::size_t i = 0; i < p.size(); ++i) {
        if (p.released[i]) {
            for (int c = 0; c < 3; ++c) centres.push_back(p.initial_position[3 * i + c]);
        }
    }
    return classifyCracks(centres.size() / 3, centres.data(), params);
}

void writeCracksCsv(const fs::path& path, const Particles& p) {
    std::ostringstream cracks;
    cracks << "x0_um,y0_um,z0_um,x_um,y_um,z_um,release_step\n" << std::setprecision(7);
    for (std::size_t i = 0; i < p.size(); ++i) {
        if (!p.released[i]) continue;
        cracks << p.initial_position[3 * i] << "," << p.initial_position[3 * i + 1] << ","
               << p.initial_position[3 * i + 2] << "," << p.position[3 * i] << "," << p.position[3 * i + 1] << ","
               << p.position[3 * i + 2] << "," << p.release_step[i] << "\n";
    }
    writeFileAtomically(path.string(), cracks.str());
}

nlohmann::ordered_json crackJson(const CrackPattern& cr, const CrackParams& cp) {
    nlohmann::ordered_json m;
    m["cone_crack"] = cr.cone;
    m["cone_radius_um"] = cr.cone_radius;
    m["cone_angle_deg"] = cr.cone_angle;
    m["ring_coverage"] = cr.ring_coverage;
    m["radial_crack_count"] = cr.radial;
    m["median_crack"] = cr.median;
    m["lateral_crack"] = cr.lateral;
    m["lateral_crack_depth_um"] = cr.lateral_depth;
    m["crack_classification"] =
        "released particles (initial centres) about the load axis; contact radius a = " +
        std::to_string(cp.contact_radius) + " um, surface band " + std::to_string(cp.band) +
        " um; cone = a thin ring outside a covering >= 75 % of 24 sectors, cone_radius = median r of the band, "
        "cone_angle = flank to free surface (0: ring only); solver/measure/cracks.hpp";
    return m;
}

CrackSnapshots::CrackSnapshots(const Model& model, const Effects& effects, fs::path out)
    : CrackSnapshots(meanRadius(model.particles), effects, std::move(out), true) {}

CrackSnapshots::CrackSnapshots(double mean_radius, const Effects& effects, fs::path out, bool writes)
    : mean_radius_(mean_radius), out_(std::move(out)), writes_(writes) {
    const std::vector<StageParams>& st = effects.indenter->stages;
    for (std::size_t k = 0; k < st.size(); ++k) {
        if (st[k].kind == StageKind::Load) {
            first_load_ = static_cast<int>(k);
            break;
        }
    }
}

std::string CrackSnapshots::observations() const {
    nlohmann::ordered_json j;
    j["onset_taken"] = onset_taken_;
    j["unstable_taken"] = unstable_taken_;
    j["full_load_taken"] = full_load_taken_;
    j["max_force"] = max_force_;
    j["released_seen"] = released_seen_;
    j["last_contact_radius"] = last_contact_radius_;
    j["snapshots"] = json_;
    return nlohmann::ordered_json{{"crack_snapshots", j}}.dump();
}

void CrackSnapshots::restoreObservations(const std::string& text, const std::string& source) {
    try {
        const nlohmann::ordered_json all = nlohmann::ordered_json::parse(text);
        if (!all.contains("crack_snapshots")) {
            return; // written by a run without crack snapshots
        }
        const nlohmann::ordered_json& j = all.at("crack_snapshots");
        onset_taken_ = j.at("onset_taken").get<bool>();
        unstable_taken_ = j.at("unstable_taken").get<bool>();
        full_load_taken_ = j.at("full_load_taken").get<bool>();
        max_force_ = j.at("max_force").get<double>();
        released_seen_ = j.at("released_seen").get<long>();
        last_contact_radius_ = j.at("last_contact_radius").get<double>();
        json_ = j.at("snapshots");
    } catch (const nlohmann::json::exception& e) {
        throw InputError(source + ": attribute 'observations' is not the crack snapshots' record (" +
                         std::string(e.what()) + "); expected the JSON a vitrum run writes there");
    }
}

std::string CrackSnapshots::observe(const Model& model, const Effects& effects, long step, double time) {
    const Particles& p = model.particles;
    const Indenter& ind = *effects.indenter;
    // The contact radius now: the farthest particle from the axis in contact with the tool (tool-agnostic).
    double a = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        if (load3(ind.contact_force.data(), i).squaredNorm() > 0.0) {
            a = std::max(a, std::hypot(p.position[3 * i] - ind.tip.x(), p.position[3 * i + 1] - ind.tip.y()));
        }
    }
    long released = 0;
    for (std::uint8_t r : p.released) released += r;
    return observe(a, released, [&]() -> const Particles& { return p; }, ind, step, time);
}

std::string CrackSnapshots::observe(double a, long released, const std::function<const Particles&()>& released_particles,
                                    const Indenter& ind, long step, double time) {
    auto snapshot = [&](const std::string& tag, const CrackPattern& cr, const CrackParams& cp) {
        if (writes_) {
            writeCracksCsv(out_ / ("cracks_" + tag + ".csv"), released_particles());
        }
        nlohmann::ordered_json j = crackJson(cr, cp);
        j["step"] = step;
        j["time_ns"] = time;
        j["tool_depth_um"] = ind.depth();
        j["tool_force_N"] = ind.force() * 1e-3;
        j["released_particles"] = cr.released;
        if (writes_) { // the classification beside its particles: a run stopped later keeps it
            writeFileAtomically((out_ / ("cracks_" + tag + ".json")).string(), j.dump(2) + "\n");
        }
        json_[tag] = j;
        return tag;
    };
    if (!full_load_taken_ && first_load_ >= 0 && ind.stage > first_load_) {
        full_load_taken_ = true;
        const CrackParams cp = crackParams(ind, mean_radius_, std::max(a, last_contact_radius_));
        return snapshot("full_load", classifyReleased(released_particles(), cp), cp);
    }
    last_contact_radius_ = std::max(last_contact_radius_, a);
    if (ind.stage == first_load_) {
        const double f = ind.force();
        if (onset_taken_ && !unstable_taken_ && f < (1.0 - kPopIn) * max_force_) {
            unstable_taken_ = true;
            const CrackParams cp = crackParams(ind, mean_radius_, a);
            return snapshot("unstable", classifyReleased(released_particles(), cp), cp);
        }
        max_force_ = std::max(max_force_, f);
    }
    if (!onset_taken_ && a > 0.0 && ind.stage == first_load_) { // the onset is a loading event
        if (released > released_seen_) {
            released_seen_ = released;
            const CrackParams cp = crackParams(ind, mean_radius_, a);
            const CrackPattern cr = classifyReleased(released_particles(), cp);
            if (cr.cone) {
                onset_taken_ = true;
                return snapshot("onset", cr, cp);
            }
        }
    }
    return {};
}

void measureIndentation(const Scene& scene, const Model& model, const Effects& effects, const fs::path& out,
                        nlohmann::ordered_json& m, CrackSnapshots* cracks) {
    const Indenter& ind = *effects.indenter;
    const double mean_radius = meanRadius(model.particles);
    const Particles& p = model.particles;
    const std::size_t n = p.size();

    ImprintParams params;
    params.axis = scene.indenter.axis;
    const double rs = sampleRadius(model.sample);
    params.far_inner = 0.65 * rs;
    params.far_outer = 0.85 * rs;
    params.spacing = 0.25 * mean_radius;
    params.smoothing = 0.5 * mean_radius;
    const SurfaceGrid before =
        surfaceEnvelope(n, p.initial_position.data(), p.radius.data(), params.axis, params.far_outer, params.spacing);
    // The print of the bonded solid: released particles (fragments) are left out of the final surface.
    std::vector<double> kept_position, kept_reference, kept_radius;
    for (std::size_t i = 0; i < n; ++i) {
        if (p.fractureEnabled() && p.released[i]) continue;
        for (int c = 0; c < 3; ++c) {
            kept_position.push_back(p.position[3 * i + c]);
            kept_reference.push_back(p.initial_position[3 * i + c]);
        }
        kept_radius.push_back(p.radius[i]);
    }
    const SurfaceGrid after = surfaceEnvelope(kept_radius.size(), kept_position.data(), kept_radius.data(),
                                              params.axis, params.far_outer, params.spacing);
    const ImprintMetrics im = measureImprint(before, after, params);
    // The same metrics on the surface particles' own vertical displacement (solver/measure/imprint.hpp).
    const SurfaceGrid kept_before =
        kept_radius.size() == n ? before
                                : surfaceEnvelope(kept_radius.size(), kept_reference.data(), kept_radius.data(),
                                                  params.axis, params.far_outer, params.spacing);
    ImprintParams lagrangian_params = params;
    lagrangian_params.edge = PrintEdge::FlankSecant; // the print has no rim to return to (imprint.hpp)
    const ImprintMetrics lagrangian =
        imprintMetrics(surfaceDisplacementChange(before, kept_before, kept_reference.data(), kept_position.data(),
                                                 lagrangian_params),
                       before, lagrangian_params);

    m["V_minus_um3"] = im.v_minus;
    m["V_plus_um3"] = im.v_plus;
    m["V_plus_print_um3"] = im.v_plus_print;
    m["V_d_um3"] = im.v_d;
    m["depth_um"] = im.depth;
    m["diagonal_um"] = im.diagonal;
    m["diagonals_um"] = {im.diagonals[0], im.diagonals[1]};
    m["max_force_N"] = ind.max_force * 1e-3;
    m["max_depth_um"] = ind.max_depth;
    m["depth_at_max_force_um"] = ind.depth_at_max_force;
    // HV = 1.8544 F/L² (F in mN and L in µm give GPa).
    m["hardness_GPa"] = im.diagonal > 0.0 ? 1.8544 * ind.max_force / (im.diagonal * im.diagonal) : 0.0;
    m["tool_work_nJ"] = ind.work;
    m["relax_converged"] = ind.relax_converged;
    const std::string grid_text = "on a grid (spacing " + std::to_string(params.spacing) +
                                  " um), Gaussian-smoothed (sigma " + std::to_string(params.smoothing) +
                                  " um), far field = mean over r in [" + std::to_string(params.far_inner) + ", " +
                                  std::to_string(params.far_outer) + "] um, integrals over r < " +
                                  std::to_string(params.far_inner) + " um (V_plus_print_um3: r < L)";
    m["imprint_method"] = "upper envelope of the particles, after minus before, " + grid_text +
                          (p.fractureEnabled() ? "; released particles left out of the final surface" : "");
    m["far_field_offset_um"] = im.far_field;
    m["imprint_lagrangian"] = {
        {"V_minus_um3", lagrangian.v_minus},
        {"V_plus_um3", lagrangian.v_plus},
        {"V_plus_print_um3", lagrangian.v_plus_print},
        {"V_d_um3", lagrangian.v_d},
        {"depth_um", lagrangian.depth},
        {"diagonal_um", lagrangian.diagonal},
        {"diagonals_um", {lagrangian.diagonals[0], lagrangian.diagonals[1]}},
        {"far_field_offset_um", lagrangian.far_field},
        {"method", "vertical displacement of the particle that was the surface at each point (the owner of the "
                   "reference envelope), over the reference positions, " +
                       grid_text +
                       "; L from the secant through each half-diagonal's profile at 75 % and 25 % of the depth, "
                       "extended to the far-field level (V_plus_print_um3 over r < that L)" +
                       (p.fractureEnabled() ? "; released particles' layer counted as removed" : "")}};

    // Densified volume from the permanent volumetric strain: Σ Ω_i (−ε_v,i), Ω_i = particle volume / φ with φ
    // the sample's packing fraction (the cells tile the sample volume).
    std::vector<double> eps(n, 0.0);
    volumetricStrain(model.incidence.view(), model.bonds.i.data(), model.bonds.j.data(), p.initial_position.data(),
                     p.position.data(), eps.data());
    double solid = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        solid += 4.0 / 3.0 * kPi * p.radius[i] * p.radius[i] * p.radius[i];
    }
    const double phi = solid / shapeVolume(model.sample);
    auto cellVolume = [&](std::size_t i) { return 4.0 / 3.0 * kPi * p.radius[i] * p.radius[i] * p.radius[i] / phi; };
    double v_kin = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        v_kin -= cellVolume(i) * eps[i];
    }
    m["densified_volume_um3"] = v_kin;
    m["densified_volume_method"] = "integral of the residual volumetric strain det(F)-1 of each particle's bonded "
                                   "neighbourhood (least-squares F), cells of volume (4/3 pi R^3)/phi, phi = " +
                                   std::to_string(phi);
    std::vector<double> slider(n, 0.0);
    if (model.bonds.densificationEnabled()) {
        sliderVolumetricStrain(model.incidence.view(), model.bonds.slip.data(), slider.data());
        double v_slider = 0.0;
        double zone_depth = 0.0;
        double zone_radius = 0.0;
        // The densified zone: particles whose bonds slipped on average 10 % of the saturation slip.
        const double threshold = 0.1 * 3.0 * scene.densification.max_permanent_strain;
        for (std::size_t i = 0; i < n; ++i) {
            v_slider -= cellVolume(i) * slider[i];
            if (-slider[i] > threshold) {
                zone_depth = std::max(zone_depth, ind.surface_level - p.initial_position[3 * i + 2]);
                zone_radius = std::max(zone_radius, std::hypot(p.initial_position[3 * i] - params.axis.x(),
                                                               p.initial_position[3 * i + 1] - params.axis.y()));
            }
        }
        long slipped = 0;
        long saturated = 0;
        for (double e : model.bonds.slip) {
            slipped += e > 0.0;
            saturated += e >= scene.densification.max_permanent_strain;
        }
        m["slider_densified_volume_um3"] = v_slider;
        m["densified_bonds"] = slipped;
        m["saturated_bonds"] = saturated;
        m["densified_zone_depth_um"] = zone_depth;
        m["densified_zone_radius_um"] = zone_radius;
        const Bonds& b = model.bonds;
        const std::vector<double> rest_length = b.restLengths();
        const ZoneShape shape = densifiedZoneShape(b.size(), b.i.data(), b.j.data(), rest_length.data(),
                                                   b.section_radius.data(), b.slip.data(), p.initial_position.data(),
                                                   params.axis, ind.surface_level);
        m["densified_zone_shape"] = {
            {"slipped_bonds", shape.bonds},
            {"slip_volume_um3", shape.slip_volume},
            {"depth90_um", shape.depth90},
            {"radius90_um", shape.radius90},
            {"mean_depth_um", shape.mean_depth},
            {"mean_radius_um", shape.mean_radius},
            {"method", "bond slip volumes pi r~^2 l0 e_p at the bonds' reference midpoints: depth below the free "
                       "surface and distance from the load axis holding 90 % of the total, and their slip-volume-"
                       "weighted means (solver/measure/densified_zone.hpp)"}};
    }

    // Crack pattern (effect fracture): the released particles classified in the reference configuration
    // (solver/measure/cracks.hpp), with a = half the imprint diagonal (3.5 h_max, the Vickers ratio d = 7 h, when the
    // print has no diagonal); cracks.csv holds them for the Fig 15 views.
    if (p.fractureEnabled()) {
        // The final state about the largest contact seen (the residual print of a cracked sample is no
        // measure of the contact), or half the diagonal (3.5 h_max, the Vickers ratio d = 7 h, without one).
        double a = cracks && cracks->maxContactRadius() > 0.0 ? cracks->maxContactRadius()
                   : im.diagonal > 0.0                         ? 0.5 * im.diagonal
                                                               : 3.5 * ind.max_depth;
        const CrackParams cp = crackParams(ind, mean_radius, a);
        const CrackPattern cr = classifyReleased(model, cp);
        writeCracksCsv(out / "cracks.csv", p);
        nlohmann::ordered_json final_state = crackJson(cr, cp);
        final_state["released_particles"] = cr.released;
        nlohmann::ordered_json top = final_state;
        std::string instant = "final";
        if (cracks) {
            cracks->json()["final"] = final_state;
            for (const char* tag : {"unstable", "full_load"}) {
                if (cracks->json().contains(tag)) {
                    top = cracks->json()[tag];
                    instant = tag;
                    break;
                }
            }
        }
        m["crack_instant"] = instant; // the paper's Fig 15: just before unstable cracking, else at full load
        for (const char* key : {"cone_crack", "cone_radius_um", "cone_angle_deg", "ring_coverage",
                                "radial_crack_count", "median_crack", "lateral_crack", "lateral_crack_depth_um",
                                "crack_classification"}) {
            m[key] = top[key];
        }
        m["released_particles_at_crack_instant"] = top["released_particles"];
        m["tool_force_at_crack_instant_N"] = top.contains("tool_force_N") ? top["tool_force_N"]
                                                                          : nlohmann::ordered_json(ind.max_force * 1e-3);
    }

    // Plot data: the imprint on its grid, and a slab through the axis (y ≈ axis y) for the cut-away view.
    std::ostringstream imprint;
    imprint << "x_um,y_um,dh_um,dh_lagrangian_um\n" << std::setprecision(7);
    for (int iy = 0; iy < im.grid.ny; ++iy) {
        for (int ix = 0; ix < im.grid.nx; ++ix) {
            const std::size_t c = static_cast<std::size_t>(ix + im.grid.nx * iy);
            if (!std::isnan(im.dh[c])) {
                imprint << im.grid.x(ix) << "," << im.grid.y(iy) << "," << im.dh[c] << "," << lagrangian.dh[c] << "\n";
            }
        }
    }
    writeFileAtomically((out / "imprint.csv").string(), imprint.str());
    std::ostringstream cut;
    cut << "x_um,z_um,radius_um,volumetric_strain,slider_volumetric_strain,uz_um\n" << std::setprecision(7);
    for (std::size_t i = 0; i < n; ++i) {
        if (std::abs(p.initial_position[3 * i + 1] - params.axis.y()) < 1.5 * mean_radius) {
            cut << p.position[3 * i] << "," << p.position[3 * i + 2] << "," << p.radius[i] << "," << eps[i] << ","
                << slider[i] << "," << p.position[3 * i + 2] - p.initial_position[3 * i + 2] << "\n";
        }
    }
    writeFileAtomically((out / "cutaway.csv").string(), cut.str());
}

void printImprintTable(std::ostream& log, const Scene& scene, const nlohmann::ordered_json& m) {
    double target = 0.0;
    for (const StageParams& s : scene.stages) {
        target = std::max(target, s.until_force);
    }
    const bool light = std::abs(target * 1e-3 - 0.1) <= std::abs(target * 1e-3 - 0.5);
    log << "  imprint (F_max " << std::setprecision(4) << m["max_force_N"].get<double>()
        << " N)          V-/um3    V+/um3    Vd/um3     D/um      L/um\n";
    auto row = [&](const std::string& name, double a, double b, double c, double d, double e) {
        log << "    " << std::left << std::setw(26) << name << std::right << std::fixed << std::setprecision(3)
            << std::setw(9) << a << std::setw(10) << b << std::setw(10) << c << std::setw(10) << d << std::setw(10)
            << e << "\n"
            << std::defaultfloat;
    };
    row("vitrum", m["V_minus_um3"], m["V_plus_um3"], m["V_d_um3"], m["depth_um"], m["diagonal_um"]);
    if (m.contains("imprint_lagrangian")) {
        const nlohmann::ordered_json& l = m["imprint_lagrangian"];
        row("vitrum, surface particles", l["V_minus_um3"], l["V_plus_um3"], l["V_d_um3"], l["depth_um"],
            l["diagonal_um"]);
    }
    const std::string load = light ? "0.1 N" : "0.5 N";
    // Sharp indentation is self-similar (no length scale in the pyramid, the elasticity or the slider):
    // lengths go with √F and volumes with F^(3/2). A run at another load is shown scaled to the paper's.
    const double reference = light ? 0.1 : 0.5;
    const double f_max = m["max_force_N"].get<double>();
    if (f_max > 0.0 && std::abs(f_max / reference - 1.0) > 0.05) {
        const double l = std::sqrt(reference / f_max);
        const double v = l * l * l;
        row("vitrum scaled to " + load, v * m["V_minus_um3"].get<double>(), v * m["V_plus_um3"].get<double>(),
            v * m["V_d_um3"].get<double>(), l * m["depth_um"].get<double>(), l * m["diagonal_um"].get<double>());
    }
    if (light) {
        for (const Table4Row& r : kTable4_01N) {
            row(std::string(r.source) + " @" + load, r.v_minus, r.v_plus, r.v_d, r.depth, r.diagonal);
        }
    } else {
        for (const Table4Row& r : kTable4_05N) {
            row(std::string(r.source) + " @" + load, r.v_minus, r.v_plus, r.v_d, r.depth, r.diagonal);
        }
    }
    if (m.contains("slider_densified_volume_um3")) {
        log << "    densified volume (residual volumetric strain) " << m["densified_volume_um3"].get<double>()
            << " um3, (bond slips) " << m["slider_densified_volume_um3"].get<double>() << " um3; hardness "
            << m["hardness_GPa"].get<double>() << " GPa\n";
    }
}

void plotIndentation(std::ostream& log, const fs::path& out, bool verbose) {
    const fs::path script = fs::path(VITRUM_SOURCE_DIR) / "io" / "plot_indentation.py";
    if (!fs::exists(script)) {
        return;
    }
    const std::string command = "/usr/bin/python3 '" + script.string() + "' '" + out.string() + "' > '" +
                                (out / "plots.log").string() + "' 2>&1";
    const int rc = std::system(command.c_str());
    if (rc != 0) {
        log << "vitrum: plots not made (" << script.string() << " failed; see " << (out / "plots.log").string()
            << ")\n";
    } else if (verbose) {
        log << "  plots      " << (out / "plots").string()
            << "/{force_depth,imprint_top,imprint_top_particles,densified_cutaway"
            << (fs::exists(out / "cracks.csv") ? ",cracks" : "") << "}.png\n";
    }
}

} // namespace vitrum
