// Fracture and contact units (issue 5): the eq (10) stress of single bonds and point forces against the
// hand-computed tensor, the release criterion (bonds break exactly once), the Verlet list against brute
// force under its rebuild criterion, the contact law's conservation, the scene keys and errors, the step
// composition (an unlisted effect allocates nothing), the checkpoint of the new state, thread independence.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "io/checkpoint.hpp"
#include "io/scene_reader.hpp"
#include "kernels/bond_kernels.hpp"
#include "kernels/parallel.hpp"
#include "solver/errors.hpp"
#include "solver/effects/fracture.hpp"
#include "solver/effects/effects.hpp"
#include "solver/run/compose.hpp"
#include "support/test_support.hpp"

namespace vitrum {
namespace {

/// Two unit-density spheres of radius 0.5 on the x axis joined by one beam (E_μ 100 GPa, r̃ 0.5).
Model pair(double gap_strain) {
    Model m;
    m.particles = Particles::spheres({Vec3(0, 0, 0), Vec3(1, 0, 0)}, {0.5, 0.5}, 1.0);
    MaterialParams mat;
    mat.beam_young = 100.0;
    mat.radius_ratio = 0.5;
    m.bonds.add(m.particles, 0, 1, mat);
    m.incidence = Incidence::build(2, m.bonds);
    m.particles.position[3] = 1.0 + gap_strain; // stretch (or compress) along x
    return m;
}

TEST(VirialStress, StretchedBondIsTensionAlongTheBondAndCompressedIsNegative) {
    for (double strain : {1e-3, -1e-3}) {
        Model m = pair(strain);
        computeBeamLoads(m.bonds.view(), m.particles.view());
        std::vector<double> s(12, 0.0);
        const ParticleVolume volume{0.5};
        computeVirialStress(m.incidence.view(), m.bonds.view(), m.particles.view(), {}, {}, {}, volume, s.data());
        // Axial force on i: N = E S ε towards j (+x in tension); eq (10): σ_xx = (l · N)/(2Ω).
        const double area = std::numbers::pi * 0.25 * 0.25;
        const double N = 100.0 * area * strain;
        const double expected = (1.0 + strain) * N / (2.0 * volume.of(0.5));
        for (int p = 0; p < 2; ++p) {
            EXPECT_NEAR(s[6 * p], expected, 1e-12 * std::abs(expected));
            EXPECT_GT(s[6 * p] * strain, 0.0); // tension positive
            for (int c = 1; c < 6; ++c) {
                EXPECT_EQ(s[6 * p + c], 0.0);
            }
        }
        EXPECT_NEAR(hydrostaticStress(s.data()), expected / 3.0, 1e-15);
    }
}

TEST(VirialStress, SymmetrisedForBentBondsAndPointForcesUseTheirTrueBranch) {
    Model m = pair(0.0);
    m.particles.position[4] = 0.01; // j moved sideways: shear force and a bending couple
    computeBeamLoads(m.bonds.view(), m.particles.view());
    const Vec3 f(0.0, 0.0, -2.0);
    const std::vector<std::int32_t> who = {0};
    const std::vector<double> force = {f.x(), f.y(), f.z()};
    const std::vector<double> point = {0.0, 0.0, 0.5}; // top of particle 0
    const PointForceView external{1, who.data(), force.data(), point.data()};
    std::vector<double> s(12, 0.0);
    const ParticleVolume volume{1.0};
    computeVirialStress(m.incidence.view(), m.bonds.view(), m.particles.view(), {}, {}, external, volume, s.data());
    const Vec3 r = load3(m.particles.position.data(), 1) - load3(m.particles.position.data(), 0);
    const Vec3 F = load3(m.bonds.force.data(), 0);
    const double w = 1.0 / (2.0 * volume.of(0.5));
    const Eigen::Matrix3d bond = 0.5 * (r * F.transpose() + F * r.transpose()) * w;
    const Vec3 branch(0.0, 0.0, 0.5);
    const Eigen::Matrix3d tool = 0.5 * (branch * f.transpose() + f * branch.transpose()) * (2.0 * w);
    const Eigen::Matrix3d e0 = bond + tool;
    const double expected0[6] = {e0(0, 0), e0(1, 1), e0(2, 2), e0(0, 1), e0(1, 2), e0(0, 2)};
    const double expected1[6] = {bond(0, 0), bond(1, 1), bond(2, 2), bond(0, 1), bond(1, 2), bond(0, 2)};
    for (int c = 0; c < 6; ++c) {
        EXPECT_NEAR(s[c], expected0[c], 1e-12 * e0.cwiseAbs().maxCoeff());
        EXPECT_NEAR(s[6 + c], expected1[c], 1e-12 * bond.cwiseAbs().maxCoeff());
    }
    EXPECT_NE(s[3], 0.0); // the shear force gives xy
    EXPECT_LT(s[2], 0.0); // the tool presses on particle 0: compressive zz
}

TEST(VirialStress, ToolContactsEnterWithTheirContactPoints) {
    Model m = pair(0.0);
    Indenter indenter;
    indenter.contact_force.assign(6, 0.0);
    indenter.contact_force[2] = -3.0; // the tool presses particle 0 down (frictionless: along its normal)
    PointForces tool;
    toolPointForces(m, indenter, tool);
    ASSERT_EQ(tool.particle.size(), 1u);
    EXPECT_EQ(tool.particle[0], 0);
    EXPECT_EQ(load3(tool.point.data(), 0), Vec3(0.0, 0.0, 0.5)); // the top of particle 0 (R = 0.5)
    m.particles.enableFracture();
    Scene s;
    s.effects = {Effect::Elasticity, Effect::Fracture};
    s.fracture.packing_fraction = 1.0;
    Fracture fracture = makeFracture(s, m);
    computeStress(m, fracture, nullptr, &indenter);
    // σ_zz = (x_c − x)_z F_z / Ω = 0.5 · (−3) / ((4/3)π 0.5³): compressive.
    EXPECT_NEAR(m.particles.stress[2], 0.5 * -3.0 / ParticleVolume{1.0}.of(0.5), 1e-12);
    EXPECT_EQ(m.particles.stress[6 + 2], 0.0);
}

Model lattice_for_average() {
    Scene s;
    s.sample.lattice = Lattice::Fcc;
    s.sample.size = Vec3(3, 3, 3);
    s.sample.particles = 300;
    s.source_path = "<test>";
    return buildModel(s, 1.0);
}

TEST(VirialStress, NeighbourAveragingKeepsAUniformFieldAndDilutesASpike) {
    Model m = lattice_for_average();
    const std::size_t n = m.particles.size();
    std::vector<double> uniform(6 * n), out(6 * n);
    for (std::size_t q = 0; q < n; ++q) {
        for (int c = 0; c < 6; ++c) uniform[6 * q + c] = 0.1 * (c + 1);
    }
    averageOverBondedNeighbours(m.incidence.view(), m.bonds.view(), m.particles.view(), ParticleVolume{}, uniform.data(), out.data());
    for (std::size_t k = 0; k < out.size(); ++k) EXPECT_NEAR(out[k], uniform[k], 1e-15);
    // A spike on one particle of equal-sized neighbours: it keeps 1/(1 + z) of it, each neighbour 1/(1 + z_j).
    std::vector<double> spike(6 * n, 0.0);
    const std::size_t p = 40;
    spike[6 * p] = 1.0;
    averageOverBondedNeighbours(m.incidence.view(), m.bonds.view(), m.particles.view(), ParticleVolume{}, spike.data(), out.data());
    EXPECT_NEAR(out[6 * p], 1.0 / (1 + m.incidence.degree(p)), 1e-15);
    const auto first = static_cast<std::size_t>(m.incidence.entry[m.incidence.offset[p]] >> 1);
    const std::size_t neighbour = static_cast<std::size_t>(m.bonds.i[first]) == p ? static_cast<std::size_t>(m.bonds.j[first])
                                                                                 : static_cast<std::size_t>(m.bonds.i[first]);
    EXPECT_NEAR(out[6 * neighbour], 1.0 / (1 + m.incidence.degree(neighbour)), 1e-15);
    // A broken bond no longer links the two.
    m.bonds.broken[first] = 1;
    averageOverBondedNeighbours(m.incidence.view(), m.bonds.view(), m.particles.view(), ParticleVolume{}, spike.data(), out.data());
    EXPECT_EQ(out[6 * neighbour], 0.0);
    EXPECT_NEAR(out[6 * p], 1.0 / m.incidence.degree(p), 1e-15);
}

Model lattice(long particles, SampleShape shape = SampleShape::Box) {
    Scene s;
    s.sample.lattice = Lattice::Fcc;
    s.sample.shape = shape;
    s.sample.size = Vec3(3, 3, 3);
    s.sample.radius = 2.0;
    s.sample.particles = particles;
    s.source_path = "<test>";
    return buildModel(s, 1.0);
}

TEST(HydrostaticRelease, ReleasesOnTensionAboveTheStrengthAndBreaksEachBondExactlyOnce) {
    const HydrostaticRelease law{0.1};
    const double at[6] = {0.3001, 0.0, 0.0, 5.0, 5.0, 5.0}; // tr/3 just above 0.1; shear is ignored
    const double below[6] = {0.3, 0.0, 0.0, 0, 0, 0}; // tr/3 = 0.1: equal is not above
    const double compressive[6] = {-1, -1, -1, 0, 0, 0};
    EXPECT_TRUE(law.releases(at));
    EXPECT_FALSE(law.releases(below));
    EXPECT_FALSE(law.releases(compressive));

    Model m = lattice(500);
    m.particles.enableFracture();
    std::vector<std::uint8_t> first_broken;
    const std::vector<std::size_t> chosen = {3, 77, 78, 200};
    for (std::size_t p : chosen) {
        std::copy(at, at + 6, m.particles.stress.begin() + 6 * p);
    }
    const BondBreakView bonds{m.bonds.size(), m.bonds.i.data(), m.bonds.j.data(), m.bonds.broken.data()};
    const ReleaseCount c1 = applyHydrostaticRelease(law, m.particles.damageView(), m.incidence.view(), bonds, 12);
    EXPECT_EQ(c1.released, 4);
    std::set<std::size_t> expected_broken;
    for (std::size_t p : chosen) {
        EXPECT_EQ(m.particles.released[p], 1);
        EXPECT_EQ(m.particles.release_step[p], 12);
        EXPECT_EQ(m.particles.broken_bonds[p], m.incidence.degree(p));
        for (std::int32_t e = m.incidence.offset[p]; e < m.incidence.offset[p + 1]; ++e) {
            expected_broken.insert(static_cast<std::size_t>(m.incidence.entry[e] >> 1));
        }
    }
    EXPECT_EQ(c1.broken, static_cast<long long>(expected_broken.size())); // shared bonds (77–78) counted once
    for (std::size_t k = 0; k < m.bonds.size(); ++k) {
        EXPECT_EQ(m.bonds.broken[k], expected_broken.count(k) ? 1 : 0);
    }
    long long sum = 0;
    for (std::size_t p = 0; p < m.particles.size(); ++p) {
        sum += m.particles.broken_bonds[p];
        if (std::find(chosen.begin(), chosen.end(), p) == chosen.end()) {
            EXPECT_EQ(m.particles.released[p], 0);
            EXPECT_EQ(m.particles.release_step[p], -1);
        }
    }
    EXPECT_EQ(sum, 2 * c1.broken); // every broken bond is counted at both ends
    // The same stress again: nothing more breaks, nothing is released twice, release steps stay.
    const ReleaseCount c2 = applyHydrostaticRelease(law, m.particles.damageView(), m.incidence.view(), bonds, 13);
    EXPECT_EQ(c2.released, 0);
    EXPECT_EQ(c2.broken, 0);
    EXPECT_EQ(m.particles.release_step[3], 12);
    // Broken bonds carry no load from then on.
    computeBeamLoads(m.bonds.view(), m.particles.view());
    for (std::size_t k : expected_broken) {
        EXPECT_EQ(load3(m.bonds.force.data(), k), Vec3::Zero());
    }
}

TEST(ContactList, RebuildCriterionKeepsEveryContactDetected) {
    // Particles jiggle at random, by up to 0.3 of the skin per step, with sustained drifts: after every
    // update the list must hold every pair within the skin's margin of touching, compared with brute force.
    Model m = lattice(400);
    ContactList contacts;
    contacts.skin = 0.2 * m.particles.radius[0];
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<Vec3> drift(m.particles.size());
    for (Vec3& d : drift) d = Vec3(u(rng), u(rng), u(rng)) * 0.05 * contacts.skin;
    long long rebuilds = 0;
    for (int step = 0; step < 200; ++step) {
        for (std::size_t q = 0; q < m.particles.size(); ++q) {
            const Vec3 jiggle = Vec3(u(rng), u(rng), u(rng)) * 0.1 * contacts.skin;
            store3(m.particles.position.data(), q, load3(m.particles.position.data(), q) + drift[q] + jiggle);
        }
        rebuilds += contacts.update(m.particles, m.bonds, m.incidence) ? 1 : 0;
        std::set<std::pair<std::int32_t, std::int32_t>> listed;
        for (std::size_t k = 0; k < contacts.size(); ++k) {
            listed.insert({contacts.i[k], contacts.j[k]});
        }
        for (const auto& p : pairsWithinGap(m.particles, 0.0)) {
            ASSERT_TRUE(listed.count(p)) << "pair " << p.first << "-" << p.second << " touches at step " << step
                                         << " but is not listed";
        }
    }
    EXPECT_GT(rebuilds, 5);   // the criterion did fire
    EXPECT_LT(rebuilds, 200); // and not every step
    // A fresh build lists exactly the pairs within the skin, with their bonds.
    contacts.build(m.particles, m.bonds, m.incidence);
    const auto brute = pairsWithinGap(m.particles, contacts.skin);
    ASSERT_EQ(brute.size(), contacts.size());
    for (std::size_t k = 0; k < brute.size(); ++k) {
        EXPECT_EQ(brute[k], std::make_pair(contacts.i[k], contacts.j[k]));
    }
}

TEST(ContactList, BondedPairsAreMarkedAndHistoryIsCarriedAcrossRebuilds) {
    Model m = lattice(200);
    ContactList contacts;
    contacts.skin = 0.1;
    contacts.build(m.particles, m.bonds, m.incidence);
    std::size_t bonded = 0;
    for (std::size_t k = 0; k < contacts.size(); ++k) {
        if (contacts.bond[k] >= 0) {
            ++bonded;
            const auto b = static_cast<std::size_t>(contacts.bond[k]);
            EXPECT_EQ(m.bonds.i[b], contacts.i[k]);
            EXPECT_EQ(m.bonds.j[b], contacts.j[k]);
        }
    }
    EXPECT_EQ(bonded, m.bonds.size()); // fcc at spacing 2R: every bond is a touching pair
    contacts.tangential[3 * 5 + 1] = 0.25;
    const ContactHistory h = contacts.history();
    ASSERT_EQ(h.size(), 1u);
    contacts.restore(h);
    EXPECT_TRUE(contacts.update(m.particles, m.bonds, m.incidence)); // stale: rebuilt
    EXPECT_EQ(contacts.tangential[3 * 5 + 1], 0.25);
}

TEST(ContactLaw, BondedPairsGetNothingAndTouchingPairsConserveMomentum) {
    Model m = pair(-0.02); // overlapping by 2 %
    ContactList contacts;
    contacts.skin = 0.1;
    contacts.build(m.particles, m.bonds, m.incidence);
    ASSERT_EQ(contacts.size(), 1u);
    const LinearContact law = LinearContact::make(50.0, 0.5, 25.0, 0.3);
    m.particles.velocity = {0.0, 0.01, 0.0, 0.0, -0.02, 0.003};
    m.particles.angular_velocity = {0.1, 0.0, 0.2, 0.0, -0.1, 0.0};
    computeContactLoads(law, contacts.view(), m.particles.view(), m.particles.initial_position.data(),
                        m.bonds.broken.data(), 1e-3);
    EXPECT_EQ(contacts.active[0], 0); // still bonded
    m.bonds.broken[0] = 1;
    computeContactLoads(law, contacts.view(), m.particles.view(), m.particles.initial_position.data(),
                        m.bonds.broken.data(), 1e-3);
    ASSERT_EQ(contacts.active[0], 1);
    std::fill(m.particles.force.begin(), m.particles.force.end(), 0.0);
    std::fill(m.particles.torque.begin(), m.particles.torque.end(), 0.0);
    gatherContactLoads(contacts.incidenceView(), contacts.view(), m.particles.view());
    const Vec3 f0 = load3(m.particles.force.data(), 0);
    const Vec3 f1 = load3(m.particles.force.data(), 1);
    EXPECT_LT(f0.x(), 0.0); // pushed apart
    EXPECT_NE(f0.y(), 0.0); // friction from the sliding
    EXPECT_EQ(f0 + f1, Vec3::Zero());
    // Angular momentum balance: x₀ × F₀ + x₁ × F₁ + T₀ + T₁ = 0.
    const Vec3 moment = load3(m.particles.position.data(), 0).cross(f0) + load3(m.particles.position.data(), 1).cross(f1) +
                        load3(m.particles.torque.data(), 0) + load3(m.particles.torque.data(), 1);
    EXPECT_LT(moment.norm(), 1e-14 * f0.norm());
    // Coulomb: the tangential part never exceeds μ times the normal part.
    const Vec3 n(1, 0, 0);
    EXPECT_LE((f0 - f0.dot(n) * n).norm(), 0.3 * std::abs(f0.dot(n)) * (1 + 1e-12));
}

TEST(VirialStress, ContactForcesEnterLikeBondForcesAndCompressionIsNegative) {
    // Two unbonded spheres pressed together by 1 %: eq (10) with the contact force, σ_xx = l F_x/(2Ω) < 0.
    Model m;
    ContactList contacts;
    m.particles = Particles::spheres({Vec3(0, 0, 0), Vec3(1, 0, 0)}, {0.5, 0.5}, 1.0);
    m.incidence = Incidence::build(2, m.bonds);
    m.particles.position[3] = 0.99;
    contacts.skin = 0.1;
    contacts.build(m.particles, m.bonds, m.incidence);
    const LinearContact law = LinearContact::make(50.0, 1.0, 25.0, 0.3);
    computeContactLoads(law, contacts.view(), m.particles.view(), m.particles.initial_position.data(),
                        m.bonds.broken.data(), 1e-3);
    ASSERT_EQ(contacts.active[0], 1);
    std::vector<double> s(12, 0.0);
    const ParticleVolume volume{0.5};
    computeVirialStress(m.incidence.view(), m.bonds.view(), m.particles.view(), contacts.incidenceView(),
                        contacts.view(), {}, volume, s.data());
    const double force = -50.0 * 0.01; // on particle 0, along −x
    const double expected = 0.99 * force / (2.0 * volume.of(0.5));
    EXPECT_NEAR(s[0], expected, 1e-15);
    EXPECT_NEAR(s[6], expected, 1e-15);
    EXPECT_LT(s[0], 0.0);
    EXPECT_EQ(s[1], 0.0);
}

TEST(ContactFrequency, PowerIterationFindsThePairEigenvalueAndStaysBelowTheBound) {
    // One pair of equal spheres touching, no dashpot (e = 1): the mass-normalised contact stiffness has the
    // eigenvalues 2k_n/m (normal) and k_t (2/m + 2R²/J) = 7 k_t/m (tangential with rolling, J = 2/5 m R²);
    // with k_t = k_n/2 the top one is 3.5 k_n/m. The estimate (λ_R + ‖r‖) is on the safe side within 2 %.
    Model m;
    m.particles = Particles::spheres({Vec3(0, 0, 0), Vec3(1, 0, 0)}, {0.5, 0.5}, 1.0);
    m.incidence = Incidence::build(2, m.bonds);
    Scene s;
    s.effects = {Effect::Elasticity, Effect::Contact};
    s.contact.normal_stiffness = 10.0;
    s.contact.restitution = 1.0;
    const double exact = 3.5 * 10.0 / m.particles.mass[0];
    const double estimate = contactOmegaSquared(s, m);
    EXPECT_GE(estimate, exact * (1 - 1e-12));
    EXPECT_LE(estimate, 1.02 * exact);
    // On a lattice: between the pair value and the block-Gershgorin bound of 12 contacts per particle.
    Model l = lattice(500);
    const double lattice_estimate = contactOmegaSquared(s, l);
    const double bound = contactOmegaSquaredBound(contactLaw(s, l), l.particles.mass[0]);
    EXPECT_GT(lattice_estimate, 3.5 * contactLaw(s, l).normal_stiffness / l.particles.mass[0]);
    EXPECT_LT(lattice_estimate, bound);
    std::printf("fcc: contact omega^2 estimate %.4g, bound %.4g (ratio %.3f)\n", lattice_estimate, bound,
                lattice_estimate / bound);
    // Without the effect: nothing.
    Scene plain;
    EXPECT_EQ(contactOmegaSquared(plain, l), 0.0);
}

TEST(ContactLaw, InitialOverlapIsTheStressFreeState) {
    // A bonded pair created overlapping by 1 % breaks: no contact force until it is pushed closer.
    Model m = pair(0.0);
    ContactList contacts;
    m.particles.position[3] = 0.99;
    m.particles.initial_position[3] = 0.99;
    m.bonds.broken[0] = 1;
    contacts.skin = 0.1;
    contacts.build(m.particles, m.bonds, m.incidence);
    const LinearContact law = LinearContact::make(50.0, 0.5, 25.0, 0.3);
    computeContactLoads(law, contacts.view(), m.particles.view(), m.particles.initial_position.data(),
                        m.bonds.broken.data(), 1e-3);
    EXPECT_EQ(contacts.active[0], 0);
    m.particles.position[3] = 0.985;
    computeContactLoads(law, contacts.view(), m.particles.view(), m.particles.initial_position.data(),
                        m.bonds.broken.data(), 1e-3);
    EXPECT_EQ(contacts.active[0], 1);
    EXPECT_NEAR(contacts.force[0], -50.0 * 0.005, 1e-12);
}

TEST(FractureScene, KeysUnitsDefaultsAndRoundTrip) {
    const Scene s = parseScene("[units]\nstress = \"MPa\"\nforce = \"N\"\nlength = \"um\"\n[effects]\nlist = [\"fracture\"]\n"
                               "[sample]\nlattice = \"sc\"\n[fracture]\nhydrostatic_strength = 80\ncheck_every = 5\naveraging = \"neighbours\"\n"
                               "[contact]\nnormal_stiffness = 0.002\nrestitution = 0.3\nfriction = 0.2\n[time]\nduration = 1\n",
                               "f.toml");
    EXPECT_TRUE(s.hasEffect(Effect::Contact)); // fracture switches contact on
    EXPECT_DOUBLE_EQ(s.fracture.hydrostatic_strength, 0.08);
    EXPECT_EQ(s.fracture.check_every, 5);
    EXPECT_EQ(s.fracture.volume, FractureVolume::Packing);
    EXPECT_EQ(s.fracture.averaging, FractureAveraging::Neighbours);
    EXPECT_DOUBLE_EQ(s.fracture.packing_fraction, std::numbers::pi / 6.0); // sc
    EXPECT_DOUBLE_EQ(s.contact.normal_stiffness, 2.0);                      // 0.002 N/µm = 2 mN/µm
    EXPECT_DOUBLE_EQ(s.contact.restitution, 0.3);
    EXPECT_DOUBLE_EQ(s.contact.tangential_ratio, 0.5);
    EXPECT_TRUE(std::find(s.output.fields.begin(), s.output.fields.end(), OutputField::Damage) !=
                s.output.fields.end());
    const std::string resolved = resolvedSceneToml(s);
    EXPECT_EQ(resolvedSceneToml(parseScene(resolved, "f.toml")), resolved);
    const Scene d = parseScene("[effects]\nlist = [\"fracture\"]\n[sample]\nlattice = \"random\"\n[time]\nduration = 1\n", "f.toml");
    EXPECT_DOUBLE_EQ(d.fracture.packing_fraction, 0.63);
    EXPECT_DOUBLE_EQ(d.contact.normal_stiffness, 0.0); // default: the mean beam axial stiffness
    const std::string rd = resolvedSceneToml(d);
    EXPECT_EQ(resolvedSceneToml(parseScene(rd, "f.toml")), rd);
}

void expectError(const std::string& text, const std::string& part) {
    try {
        parseScene(text + "[time]\nduration = 1\n", "f.toml");
        ADD_FAILURE() << "no error for:\n" << text;
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
}

TEST(FractureScene, ErrorsNameFileLineAndKey) {
    expectError("[fracture]\nhydrostatic_strength = 1\n", "f.toml:1:1: table [fracture] is given but effects.list");
    expectError("[contact]\nfriction = 1\n", "f.toml:1:1: table [contact] is given but effects.list");
    expectError("[effects]\nlist = [\"fracture\"]\n[fracture]\nhydrostatic_strength = -1\n",
                "f.toml:4:24: key 'fracture.hydrostatic_strength': expected a number > 0 (in GPa), got -1");
    expectError("[effects]\nlist = [\"fracture\"]\n[fracture]\ncheck_every = 0\n",
                "f.toml:4:15: key 'fracture.check_every': expected an integer >= 1, got 0");
    expectError("[effects]\nlist = [\"fracture\"]\n[fracture]\nvolume = \"voronoi\"\n",
                "key 'fracture.volume': expected one of \"packing\", \"sphere\"");
    expectError("[effects]\nlist = [\"fracture\"]\n[fracture]\nvolume = \"sphere\"\npacking_fraction = 0.6\n",
                "f.toml:5:20: key 'fracture.packing_fraction': not used with volume = \"sphere\"");
    expectError("[effects]\nlist = [\"contact\"]\n[contact]\nrestitution = 0\n",
                "f.toml:4:15: key 'contact.restitution': expected a number in (0, 1], got 0");
    expectError("[effects]\nlist = [\"contact\"]\n[contact]\nstiffness = 1\n", "unknown key 'contact.stiffness'");
    expectError("[output]\nfields = [\"damage\"]\n", "field \"damage\" expected the effect \"fracture\"");
}

TEST(FractureStep, ComposedOnlyWhenListedAndUnlistedEffectsAllocateNothing) {
    Scene s;
    s.sample.particles = 200;
    s.source_path = "<test>";
    Model m = buildModel(s, 1.0);
    Effects fx = buildEffects(s, m);
    const Step plain = composeStep(m, fx);
    for (const Phase& ph : plain.phases()) {
        EXPECT_EQ(ph.label.find("fracture"), std::string::npos);
        EXPECT_EQ(ph.label.find("contacts"), std::string::npos);
    }
    EXPECT_TRUE(m.particles.stress.empty());
    EXPECT_TRUE(m.particles.released.empty());
    EXPECT_FALSE(fx.contact); // no neighbour list exists
    EXPECT_FALSE(fx.fracture);
    StepContext ctx{m, fx, 1e-4, 1e-4};
    Step again = composeStep(m, fx);
    again.advance(ctx);
    EXPECT_FALSE(fx.contact); // and stepping builds none

    s.effects = {Effect::Elasticity, Effect::Fracture, Effect::Contact};
    Model f = buildModel(s, 1.0);
    Effects f_fx = buildEffects(s, f);
    Step step = composeStep(f, f_fx);
    std::vector<std::string> labels;
    for (const Phase& ph : step.phases()) labels.push_back(ph.label);
    EXPECT_EQ(labels, (std::vector<std::string>{"integrate.kick_drift", "bonds.beam_loads", "bonds.gather",
                                                "contacts.update", "contacts.forces", "fracture.release",
                                                "integrate.kick"}));
    EXPECT_EQ(f.particles.stress.size(), 6 * f.particles.size());
    StepContext fc{f, f_fx, 1e-4, 1e-4};
    step.advance(fc);
    ASSERT_TRUE(f_fx.contact);
    EXPECT_EQ(f_fx.contact->list.builds, 1);
}

TEST(FractureCheckpoint, DamageStateAndContactHistoryRoundTrip) {
    Model m = lattice(200);
    ContactList contacts;
    m.particles.enableFracture();
    m.particles.released[7] = 1;
    m.particles.release_step[7] = 42;
    m.particles.broken_bonds[7] = 3;
    m.particles.stress[13] = 0.5;
    m.bonds.broken[2] = 1;
    contacts.skin = 0.1;
    contacts.build(m.particles, m.bonds, m.incidence);
    contacts.tangential[3 * 4 + 2] = -0.125;
    const auto dir = testing::freshTempDir("fracture-checkpoint");
    const std::string path = (dir / "state.h5").string();
    testing::writeStores(path, m.particles, m.bonds, CheckpointMeta{5, 0.5, 0.1, "x", std::string(64, 'a'), "v", {}},
                         &contacts);
    Particles p;
    Bonds b;
    ContactList restored;
    testing::readStores(path, p, b, &restored);
    const ContactHistory history = restored.history(); // restore() keeps it until the list's next build
    EXPECT_EQ(p.released, m.particles.released);
    EXPECT_EQ(p.release_step, m.particles.release_step);
    EXPECT_EQ(p.broken_bonds, m.particles.broken_bonds);
    EXPECT_EQ(p.stress, m.particles.stress);
    EXPECT_EQ(b.broken, m.bonds.broken);
    ASSERT_EQ(history.size(), 1u);
    EXPECT_EQ(history.i[0], contacts.i[4]);
    EXPECT_EQ(history.j[0], contacts.j[4]);
    EXPECT_EQ(history.tangential[2], -0.125);
    // Without the effect the state is stored empty and read back empty.
    Model plain = lattice(200);
    testing::writeStores(path, plain.particles, plain.bonds, CheckpointMeta{5, 0.5, 0.1, "x", std::string(64, 'a'), "v", {}});
    ContactList none;
    testing::readStores(path, p, b, &none);
    EXPECT_TRUE(p.released.empty());
    EXPECT_EQ(none.history().size(), 0u);
}

} // namespace
} // namespace vitrum
