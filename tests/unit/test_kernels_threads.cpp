// Kernel results must not depend on the thread count (STYLE.md rules 5 and 10): each kernel is run with 1
// and 2 threads on the same input and the outputs are compared bit for bit.
#include <cstring>
#include <random>

#include <gtest/gtest.h>

#include "kernels/beam.hpp"
#include "kernels/bond_kernels.hpp"
#include "kernels/integrate.hpp"
#include "kernels/parallel.hpp"
#include "kernels/timestep.hpp"
#include "solver/model/model.hpp"
#include "support/test_support.hpp"

namespace vitrum {
namespace {

Model agitatedLattice() {
    Model m =
        testing::fccModel(SampleShape::Sphere, 3.0, 6000); // > several reduction chunks (kReduceChunk = 512)
    std::mt19937_64 rng(1);
    std::normal_distribution<double> g(0.0, 1e-3);
    for (double& x : m.particles.position) x += g(rng);
    for (std::size_t i = 0; i < m.particles.size(); ++i) {
        const Quat q(Eigen::AngleAxisd(g(rng) * 10, Vec3(g(rng), g(rng), g(rng)).normalized()));
        storeQuat(m.particles.orientation.data(), i, q);
    }
    for (double& v : m.particles.velocity) v = g(rng);
    for (double& w : m.particles.angular_velocity) w = g(rng);
    return m;
}

struct Outputs {
    std::vector<double> force, torque, bond_force;
    double energy = 0.0;
    KineticEnergy kinetic;
    CriticalTimeStep dt;
};

Outputs runKernels(int threads) {
    setThreadCount(threads);
    Model m = agitatedLattice();
    Outputs o;
    computeBeamLoads(m.bonds.view(), m.particles.view(), BondViscousDamping{0.1});
    gatherBondLoads(m.incidence.view(), m.bonds.view(), m.particles.view());
    cundallLocalDamping(m.particles.view(), 0.5);
    halfKick(m.particles.view(), 1e-3);
    drift(m.particles.view(), 1e-3);
    o.force = m.particles.force;
    o.torque = m.particles.torque;
    o.bond_force = m.bonds.force;
    o.energy = beamStrainEnergy(m.bonds.view(), m.particles.view());
    o.kinetic = kineticEnergy(m.particles.view());
    o.dt = criticalTimeStep(m.incidence.view(), m.bonds.view(), m.particles.view());
    return o;
}

bool sameBits(const std::vector<double>& a, const std::vector<double>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

TEST(KernelThreads, OneAndTwoThreadsGiveIdenticalBits) {
    const int saved = threadCount();
    const Outputs one = runKernels(1);
    const Outputs two = runKernels(2);
    setThreadCount(saved);
    ASSERT_GT(one.force.size(), 3u * 4000u);
    EXPECT_TRUE(sameBits(one.bond_force, two.bond_force));
    EXPECT_TRUE(sameBits(one.force, two.force));
    EXPECT_TRUE(sameBits(one.torque, two.torque));
    EXPECT_EQ(std::memcmp(&one.energy, &two.energy, sizeof(double)), 0);
    EXPECT_EQ(std::memcmp(&one.kinetic.translational, &two.kinetic.translational, sizeof(double)), 0);
    EXPECT_EQ(std::memcmp(&one.kinetic.rotational, &two.kinetic.rotational, sizeof(double)), 0);
    EXPECT_EQ(one.dt.dt, two.dt.dt);
    EXPECT_EQ(one.dt.particle, two.dt.particle);
}

TEST(KernelThreads, GatherMatchesSerialSumAndBalancesForces) {
    // The CSR gather must equal a plain serial scatter of the bond loads (to rounding: the order of the
    // additions differs), and the total bond force on the system must vanish (action = reaction) to
    // rounding of the sum: |Σ F| ≤ 1e-12 Σ |F|.
    Model m = agitatedLattice();
    computeBeamLoads(m.bonds.view(), m.particles.view());
    gatherBondLoads(m.incidence.view(), m.bonds.view(), m.particles.view());
    std::vector<double> f(m.particles.force.size(), 0.0);
    for (std::size_t k = 0; k < m.bonds.size(); ++k) {
        for (int c = 0; c < 3; ++c) {
            f[3 * m.bonds.i[k] + c] += m.bonds.force[3 * k + c];
            f[3 * m.bonds.j[k] + c] -= m.bonds.force[3 * k + c];
        }
    }
    Vec3 total = Vec3::Zero();
    double magnitude = 0.0;
    for (std::size_t i = 0; i < m.particles.size(); ++i) {
        const Vec3 gathered = load3(m.particles.force.data(), i);
        EXPECT_LT((gathered - load3(f.data(), i)).norm(), 1e-12 * (gathered.norm() + 1e-30));
        total += gathered;
        magnitude += gathered.norm();
    }
    EXPECT_LT(total.norm(), 1e-12 * magnitude);
}

TEST(Integrator, RotationSeriesMatchesTheExponentialMap) {
    // drift turns each particle by the exact exponential map; below 0.25 rad per step it uses Taylor series
    // for sin and cos (kernels/integrate.cpp). Compared here with the libm form Quat(AngleAxis(|ω|Δt, ω̂)) q
    // for turns from 1e-12 to 1 rad per step, on both sides of the series limit: the two must agree to a few
    // ulp, 1e-15 on every quaternion component (the series' truncation bounds are ≤ 2.3e-17 relative; the
    // rest is rounding of the products and of the renormalisation, the same in both forms).
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const int n = 4000;
    std::vector<double> position(3 * n, 0.0), velocity(3 * n, 0.0), orientation(4 * n), spin(3 * n);
    std::vector<Quat> expected(n);
    const double dt = 1e-3;
    for (int i = 0; i < n; ++i) {
        const Quat q0 = Quat(Eigen::AngleAxisd(3.0 * u(rng), Vec3(u(rng), u(rng), u(rng)).normalized()));
        const double turn = std::pow(10.0, -12.0 + 12.0 * (0.5 + 0.5 * u(rng))); // rad per step
        const Vec3 w = (turn / dt) * Vec3(u(rng), u(rng), u(rng)).normalized();
        storeQuat(orientation.data(), static_cast<std::size_t>(i), q0);
        store3(spin.data(), static_cast<std::size_t>(i), w);
        expected[static_cast<std::size_t>(i)] = (Quat(Eigen::AngleAxisd(w.norm() * dt, w / w.norm())) * q0).normalized();
    }
    ParticleView p;
    p.n = static_cast<std::size_t>(n);
    p.position = position.data();
    p.velocity = velocity.data();
    p.orientation = orientation.data();
    p.angular_velocity = spin.data();
    drift(p, dt);
    double worst = 0.0;
    for (int i = 0; i < n; ++i) {
        const Quat got = loadQuat(orientation.data(), static_cast<std::size_t>(i));
        worst = std::max(worst, (got.coeffs() - expected[static_cast<std::size_t>(i)].coeffs()).cwiseAbs().maxCoeff());
    }
    RecordProperty("worst_component_difference", std::to_string(worst / 1e-16) + "e-16");
    EXPECT_LT(worst, 1e-15);
}

} // namespace
} // namespace vitrum
