#include "solver/measure/material_test.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "solver/effects/pressure_load.hpp"
#include "solver/errors.hpp"
#include "solver/model/surface.hpp"

namespace vitrum {

namespace {

using Mat3 = Eigen::Matrix3d;
using Six = std::array<double, 6>;

constexpr const char* kComponents[6] = {"xx", "yy", "zz", "xy", "yz", "xz"};

Six voigt(const Mat3& m) { return {m(0, 0), m(1, 1), m(2, 2), m(0, 1), m(1, 2), m(0, 2)}; }

/// σ : D for symmetric tensors in xx yy zz xy yz xz.
double contract(const Six& a, const Six& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + 2.0 * (a[3] * b[3] + a[4] * b[4] + a[5] * b[5]);
}

Six normalised(Six a) {
    const double n = std::sqrt(contract(a, a));
    for (double& v : a) v = n > 0.0 ? v / n : 0.0;
    return a;
}

Mat3 green(const Mat3& f) { return 0.5 * (f.transpose() * f - Mat3::Identity()); }

/// The least-squares gradient B A⁻¹ (identity when A is singular: no strain to report).
Mat3 gradientOf(const Mat3& a, const Mat3& b) {
    const double scale = a.trace();
    return a.determinant() > 1e-9 * scale * scale * scale ? Mat3(b * a.inverse()) : Mat3(Mat3::Identity());
}

double pressureOf(const Six& s) { return -(s[0] + s[1] + s[2]) / 3.0; }

double vonMisesOf(const Six& s) {
    const double p = pressureOf(s);
    const Six d{s[0] + p, s[1] + p, s[2] + p, s[3], s[4], s[5]};
    return std::sqrt(1.5 * contract(d, d));
}

} // namespace

MaterialTestGauge materialTestGauge(const Scene& scene, const Model& model) {
    MaterialTestGauge g;
    const Particles& p = model.particles;
    std::vector<std::int32_t> all(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) all[i] = static_cast<std::int32_t>(i);
    const double* x0 = p.initial_position.data();
    const HullSurface hull = convexHullOf(x0, all);
    const std::vector<std::array<double, 4>> planes = hullPlanes(hull, x0);
    const double depth = 2.0 * meanRadius(p);
    std::vector<char> inside(p.size(), 0);
    for (std::size_t i = 0; i < p.size(); ++i) {
        if (depthBelow(planes, load3(x0, i)) >= depth && !(p.flags[i] & kKinematic)) {
            inside[i] = 1;
            g.interior.push_back(static_cast<std::int32_t>(i));
        }
    }
    if (g.interior.size() < 4) {
        throw InputError(scene.source_path + ": [measure] kind = \"material_test\": the sample has " +
                         std::to_string(g.interior.size()) +
                         " particle(s) 2 mean radii below its surface; expected at least 4 (raise sample.particles)");
    }
    for (std::size_t k = 0; k < model.bonds.size(); ++k) {
        if (inside[static_cast<std::size_t>(model.bonds.i[k])] && inside[static_cast<std::size_t>(model.bonds.j[k])]) {
            g.interior_bonds.push_back(static_cast<std::int32_t>(k));
        }
    }
    g.initial_volume = convexHullVolume(x0, all);
    for (std::size_t b = 0; b < model.boundaries.size(); ++b) {
        const BoundaryCondition& bc = model.boundaries[b];
        if (bc.kind == BoundaryKind::Strain) {
            g.strain_boundary = static_cast<int>(b);
            g.direction = normalised(voigt(0.5 * (bc.gradient + bc.gradient.transpose())));
            g.path_start = 0.0;
            g.path_end = bc.ramp_time;
            return g;
        }
    }
    // Stress control: the path is the load that starts last (the axial load after a confinement).
    const LoadParams* path = nullptr;
    for (const LoadParams& l : scene.loads) {
        if (!path || l.start_time >= path->start_time) path = &l;
    }
    if (!path) {
        throw InputError(scene.source_path + ": [measure] kind = \"material_test\": expected a [[load]] (stress "
                         "path) or a [[boundary]] of kind \"strain\" (strain path) to drive the sample, found none");
    }
    g.direction = path->kind == LoadKind::Pressure
                      ? normalised(Six{-path->pressure, -path->pressure, -path->pressure, 0, 0, 0})
                      : normalised(Six{path->normal_stress.x(), path->normal_stress.y(), path->normal_stress.z(),
                                       path->shear_stress.x(), path->shear_stress.y(), path->shear_stress.z()});
    g.path_start = path->start_time;
    g.path_end = path->start_time + path->ramp_time;
    return g;
}

std::vector<std::string> materialTestColumns() {
    std::vector<std::string> c;
    for (const char* k : kComponents) c.push_back(std::string("stress_") + k + "_GPa");
    for (const char* k : kComponents) c.push_back(std::string("strain_") + k);
    for (const char* k : kComponents) c.push_back(std::string("chord_strain_") + k);
    c.push_back("chord_volumetric_strain");
    for (const char* k : kComponents) c.push_back(std::string("plastic_strain_") + k);
    c.push_back("mean_compaction");
    return c;
}

std::vector<double> materialTestRow(const MaterialTestGauge& g, const Model& model, const PressureLoads* loads,
                                    double time) {
    const Particles& p = model.particles;
    const double* x0 = p.initial_position.data();
    const double* x = p.position.data();
    // (T1) Every sum in index order: the same bits on any thread count.
    Six stress{};
    if (g.strain_boundary >= 0) {
        const BoundaryCondition& bc = model.boundaries[static_cast<std::size_t>(g.strain_boundary)];
        const std::vector<std::int32_t>& members = model.sets[bc.set].members;
        Vec3 centre = Vec3::Zero();
        for (std::int32_t m : members) centre += load3(x, static_cast<std::size_t>(m));
        centre /= static_cast<double>(members.size());
        Mat3 moment = Mat3::Zero();
        for (std::int32_t m : members) {
            const auto i = static_cast<std::size_t>(m);
            moment += (load3(x, i) - centre) * load3(p.force.data(), i).transpose();
        }
        const double volume =
            g.initial_volume * (Mat3::Identity() + bc.fieldAt(time).fraction * bc.gradient).determinant();
        stress = voigt(-0.5 * (moment + moment.transpose()) / volume);
    } else if (loads) {
        for (const PressureLoad& l : loads->loads) {
            if (l.params.kind == LoadKind::Pressure) {
                const double pressure = l.params.pressureAt(time);
                for (int c = 0; c < 3; ++c) stress[c] -= pressure;
            } else {
                const std::array<double, 6> s = l.params.stressAt(time);
                for (int c = 0; c < 6; ++c) stress[c] += s[c];
            }
        }
    }
    // (T2) The interior's affine gradient about its centroids.
    Vec3 c0 = Vec3::Zero(), c1 = Vec3::Zero();
    for (std::int32_t m : g.interior) {
        c0 += load3(x0, static_cast<std::size_t>(m));
        c1 += load3(x, static_cast<std::size_t>(m));
    }
    c0 /= static_cast<double>(g.interior.size());
    c1 /= static_cast<double>(g.interior.size());
    Mat3 a = Mat3::Zero(), b = Mat3::Zero();
    for (std::int32_t m : g.interior) {
        const Vec3 dX = load3(x0, static_cast<std::size_t>(m)) - c0;
        a += dX * dX.transpose();
        b += (load3(x, static_cast<std::size_t>(m)) - c1) * dX.transpose();
    }
    const Six strain = voigt(green(gradientOf(a, b)));
    // (T3) The interior bonds' chords.
    a.setZero();
    b.setZero();
    for (std::int32_t k : g.interior_bonds) {
        if (!model.bonds.broken.empty() && model.bonds.broken[static_cast<std::size_t>(k)]) continue;
        const auto i = static_cast<std::size_t>(model.bonds.i[static_cast<std::size_t>(k)]);
        const auto j = static_cast<std::size_t>(model.bonds.j[static_cast<std::size_t>(k)]);
        const Vec3 dX = load3(x0, j) - load3(x0, i);
        a += dX * dX.transpose();
        b += (load3(x, j) - load3(x, i)) * dX.transpose();
    }
    const Mat3 chord = gradientOf(a, b);
    const Six chord_strain = voigt(green(chord));
    // (T4)
    Six plastic{};
    double compaction = 0.0;
    if (p.plasticityEnabled()) {
        for (std::int32_t m : g.interior) {
            const auto i = static_cast<std::size_t>(m);
            for (int c = 0; c < 6; ++c) plastic[c] += p.plastic_strain[6 * i + c];
            compaction += p.compaction[i];
        }
        for (double& v : plastic) v /= static_cast<double>(g.interior.size());
        compaction /= static_cast<double>(g.interior.size());
    }
    std::vector<double> row;
    row.insert(row.end(), stress.begin(), stress.end());
    row.insert(row.end(), strain.begin(), strain.end());
    row.insert(row.end(), chord_strain.begin(), chord_strain.end());
    row.push_back(-std::log(chord.determinant()));
    row.insert(row.end(), plastic.begin(), plastic.end());
    row.push_back(compaction);
    return row;
}

double materialTestPlasticStrain(const std::vector<double>& row) {
    Six ep;
    std::copy(row.end() - 7, row.end() - 1, ep.begin()); // the plastic strain, before the mean compaction
    return std::sqrt(contract(ep, ep));
}

nlohmann::ordered_json materialTestResult(const MaterialTestGauge& g,
                                          const std::map<std::string, std::vector<double>>& series, double offset) {
    const std::vector<double>& t = series.at("time_ns");
    const std::size_t n = t.size();
    auto six = [&](const std::string& prefix, const std::string& suffix, std::size_t r) {
        Six v;
        for (int c = 0; c < 6; ++c) v[c] = series.at(prefix + kComponents[c] + suffix)[r];
        return v;
    };
    auto lerp = [](const Six& a, const Six& b, double f) {
        Six v;
        for (int c = 0; c < 6; ++c) v[c] = a[c] + f * (b[c] - a[c]);
        return v;
    };
    auto tensor = [](const Six& v) { return nlohmann::ordered_json(std::vector<double>(v.begin(), v.end())); };
    nlohmann::ordered_json out;
    out["control"] = g.strain_boundary >= 0 ? "strain" : "stress";
    out["direction"] = tensor(g.direction);
    out["interior_particles"] = g.interior.size();
    out["yield_offset"] = offset;
    out["components"] = "xx yy zz xy yz xz (tensor shear), stress tension positive, GPa";
    if (n == 0) {
        out["yielded"] = false;
        return out;
    }
    // The path's plastic strain counts from its start (a reloading cycle yields at the earlier maximum).
    std::size_t k0 = 0;
    while (k0 + 1 < n && t[k0] < g.path_start) ++k0;
    const Six ep0 = six("plastic_strain_", "", k0);
    std::vector<double> plastic(n), path_plastic(n), path_stress(n), path_strain(n);
    double max_path_stress = -INFINITY;
    for (std::size_t r = 0; r < n; ++r) {
        Six ep = six("plastic_strain_", "", r);
        for (int c = 0; c < 6; ++c) ep[c] -= ep0[c];
        plastic[r] = std::sqrt(contract(ep, ep));
        path_plastic[r] = contract(ep, g.direction);
        path_stress[r] = contract(six("stress_", "_GPa", r), g.direction);
        path_strain[r] = contract(six("strain_", "", r), g.direction);
        max_path_stress = std::max(max_path_stress, path_stress[r]);
    }
    out["max_path_stress_GPa"] = max_path_stress;
    // The elastic path modulus: least-squares slope of path stress on path strain over the rows of the path's
    // ramp before any plastic strain (|E^p| < offset/10).
    {
        double sx = 0, sy = 0, sxx = 0, sxy = 0;
        long count = 0;
        for (std::size_t r = 0; r < n; ++r) {
            if (t[r] < g.path_start || t[r] > g.path_end || plastic[r] >= 0.1 * offset) continue;
            sx += path_strain[r];
            sy += path_stress[r];
            sxx += path_strain[r] * path_strain[r];
            sxy += path_strain[r] * path_stress[r];
            ++count;
        }
        const double den = static_cast<double>(count) * sxx - sx * sx;
        if (count >= 3 && den > 0.0) out["elastic_path_modulus_GPa"] = (static_cast<double>(count) * sxy - sx * sy) / den;
    }
    // The yield point: the first crossing of |mean E^p − E^p(path start)| = offset on the path, interpolated.
    std::size_t k = k0;
    while (k < n && plastic[k] <= offset) ++k;
    out["yielded"] = k < n;
    if (k < n) {
        const double f = k == k0 ? 1.0 : (offset - plastic[k - 1]) / (plastic[k] - plastic[k - 1]);
        const std::size_t a = k == k0 ? k0 : k - 1;
        const Six s = lerp(six("stress_", "_GPa", a), six("stress_", "_GPa", k), f);
        out["yield_time_ns"] = t[a] + f * (t[k] - t[a]);
        out["yield_stress_GPa"] = tensor(s);
        out["yield_path_stress_GPa"] = contract(s, g.direction);
        out["yield_pressure_GPa"] = pressureOf(s);
        out["yield_von_mises_GPa"] = vonMisesOf(s);
        // The flow curve: the path stress at plastic path strains the run reached (first crossings).
        nlohmann::ordered_json flow = nlohmann::ordered_json::array();
        for (const double level : {0.01, 0.02, 0.05, 0.1, 0.15, 0.2, 0.25, 0.3}) {
            std::size_t r = k;
            while (r < n && path_plastic[r] < level) ++r;
            if (r == n || r == k0) break;
            const double h = (level - path_plastic[r - 1]) / (path_plastic[r] - path_plastic[r - 1]);
            const Six s_at = lerp(six("stress_", "_GPa", r - 1), six("stress_", "_GPa", r), h);
            Six ep_at = lerp(six("plastic_strain_", "", r - 1), six("plastic_strain_", "", r), h);
            for (int c = 0; c < 6; ++c) ep_at[c] -= ep0[c];
            flow.push_back({{"plastic_path_strain", level},
                            {"path_stress_GPa", contract(s_at, g.direction)},
                            {"stress_GPa", tensor(s_at)},
                            {"plastic_strain", tensor(ep_at)}});
        }
        out["flow_curve"] = flow;
    }
    const std::size_t last = n - 1;
    out["residual_stress_GPa"] = tensor(six("stress_", "_GPa", last));
    out["residual_strain"] = tensor(six("strain_", "", last));
    out["residual_plastic_strain"] = tensor(six("plastic_strain_", "", last));
    const Six e = six("strain_", "", last);
    // Density change of the interior from its affine F: ρ/ρ₀ − 1 = 1/det F − 1, det F from C = 2E + I.
    Mat3 c;
    c << 1 + 2 * e[0], 2 * e[3], 2 * e[5], 2 * e[3], 1 + 2 * e[1], 2 * e[4], 2 * e[5], 2 * e[4], 1 + 2 * e[2];
    out["residual_density_change"] = 1.0 / std::sqrt(c.determinant()) - 1.0;
    out["residual_mean_compaction"] = series.at("mean_compaction")[last];
    out["residual_mean_densification"] = std::expm1(series.at("mean_compaction")[last]);
    return out;
}

} // namespace vitrum
