// The benchmark input shared by bench_kernels.cpp and bench_layout.cpp: an FCC lattice in a 10 µm cube built
// by vitrum::buildModel (Morton-ordered particles, bonds sorted by (i, j)), perturbed so that every beam is
// stretched, bent and twisted, with small random velocities and spins. Built once per size (one cache for
// the whole binary: an inline function's static is shared between translation units).
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <random>

#include "kernels/bond_kernels.hpp"
#include "kernels/pages.hpp"
#include "kernels/timestep.hpp"
#include "kernels/views.hpp"
#include "solver/model/model.hpp"
#include "solver/scene.hpp"

namespace vitrum_bench {

using vitrum::Quat;
using vitrum::Vec3;

struct BenchModel {
    vitrum::Scene scene;
    vitrum::Model model;
    double dt = 0.0; // 0.1 × critical time step, ns
    double bonds_per_particle() const {
        return static_cast<double>(model.bonds.size()) / static_cast<double>(model.particles.size());
    }
};

/// FCC lattice of about n particles in a 10 µm cube with the default glass micro-parameters, perturbed
/// (see the file header). Deterministic: fixed seed.
inline std::unique_ptr<BenchModel> makeModel(long n, bool place = true) {
    auto bm = std::make_unique<BenchModel>();
    bm->scene.name = "bench";
    bm->scene.sample.lattice = vitrum::Lattice::Fcc;
    bm->scene.sample.shape = vitrum::SampleShape::Box;
    bm->scene.sample.size = Vec3(10, 10, 10);
    bm->scene.sample.particles = n;
    bm->model = vitrum::buildModel(bm->scene, 1.0);

    vitrum::Particles& p = bm->model.particles;
    const double radius = p.radius[0];
    std::mt19937_64 rng(0x5eed + static_cast<std::uint64_t>(n));
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (std::size_t i = 0; i < p.size(); ++i) {
        for (int c = 0; c < 3; ++c) {
            p.position[3 * i + c] += 1e-3 * radius * u(rng);
        }
        const Vec3 axis = Vec3(u(rng), u(rng), u(rng)).normalized();
        const Quat tilt(Eigen::AngleAxisd(1e-3 * u(rng), axis));
        vitrum::storeQuat(p.orientation.data(), i, (tilt * vitrum::loadQuat(p.orientation.data(), i)).normalized());
    }

    // Time step first (it depends on stiffness and mass only), then velocities scaled to move a particle by
    // about 1e-4 R per step and spin it by about 1e-4 rad per step: small enough that thousands of benchmark
    // steps stay in the small-strain regime, large enough that every branch does its work.
    const vitrum::CriticalTimeStep crit =
        vitrum::criticalTimeStep(bm->model.incidence.view(), bm->model.bonds.view(), p.view());
    bm->dt = 0.1 * crit.dt;
    const double v_scale = 1e-4 * radius / bm->dt;
    const double w_scale = 1e-4 / bm->dt;
    for (std::size_t i = 0; i < p.size(); ++i) {
        for (int c = 0; c < 3; ++c) {
            p.velocity[3 * i + c] = v_scale * u(rng);
            p.angular_velocity[3 * i + c] = w_scale * u(rng);
        }
    }
    // Loads consistent with the perturbed state, so the first timed gather/kick sees real forces.
    vitrum::computeBeamLoads(bm->model.bonds.view(), p.view());
    vitrum::gatherBondLoads(bm->model.incidence.view(), bm->model.bonds.view(), p.view());
    if (place) {
        vitrum::placeModelArrays(bm->model); // as a run places them (app/run_command.cpp); BM_Pages compares
    }
    return bm;
}

inline BenchModel& modelFor(long n) {
    static std::map<long, std::unique_ptr<BenchModel>> cache;
    auto it = cache.find(n);
    if (it == cache.end()) {
        it = cache.emplace(n, makeModel(n)).first;
    }
    return *it->second;
}

/// Densification law with the defaults of a scene (paper Table 3 slider) and the eqs 5–6 coefficients of
/// examples/calibration/silica.toml, so that the property evolution is on (the branch a run takes).
inline void enableDensification(BenchModel& bm) {
    vitrum::DensificationParams& d = bm.scene.densification;
    d.eq5 = Vec3(1.2843127090809194, -3.687196402506809, 1.8988946425383515);
    d.eq6_b0 = Vec3(-0.5723466906322119, 1.7381374611540705, -1.1751869518960338);
    d.eq6_b1 = Vec3(0.19265411354365053, -0.8921007573410387, 1.485284568135907);
    if (bm.model.bonds.slip.size() != bm.model.bonds.size()) {
        bm.model.bonds.enableDensification();
        vitrum::placeOnPages(bm.model.bonds.slip, vitrum::PagePolicy::Huge); // as placeModelArrays would
        vitrum::placeOnPages(bm.model.bonds.reference_strain, vitrum::PagePolicy::Huge);
    }
}

} // namespace vitrum_bench
