// test support helpers
#include "support/test_support.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>

#include <unistd.h>

#include "kernels/bond_kernels.hpp"
#include "kernels/integrate.hpp"

namespace vitrum::testing {

std::filesystem::path freshTempDir(const std::string& tag) {
    static std::atomic<int> counter{0};
    const auto stamp = std::chrono::steady_clock::now().time_since_epoch().count();
    const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                      ("vitrum-" + tag + "-" + std::to_string(::getpid()) + "-" +
                                       std::to_string(stamp) + "-" + std::to_string(counter++));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

int runVitrum(const std::string& args, const std::filesystem::path& log) {
    const std::string cmd = std::string(VITRUM_BINARY) + " " + args + " > '" + log.string() + "' 2>&1";
    const int status = std::system(cmd.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

void agitate(Model& m, unsigned seed, double speed) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> g(0.0, speed);
    for (std::size_t k = 0; k < m.particles.velocity.size(); ++k) {
        m.particles.velocity[k] = g(rng);
        m.particles.angular_velocity[k] = g(rng) / m.particles.radius[k / 3];
    }
}

double totalEnergy(Model& m) {
    const KineticEnergy k = kineticEnergy(m.particles.view());
    return k.translational + k.rotational + beamStrainEnergy(m.bonds.view(), m.particles.view());
}

Model fccModel(SampleShape shape, double radius, int particles) {
    Scene s;
    s.sample.lattice = Lattice::Fcc;
    s.sample.shape = shape;
    s.sample.radius = radius;
    s.sample.particles = particles;
    s.source_path = "<test>";
    return buildModel(s, 1.0);
}

PropertyEvolution silicaEvolution() {
    PropertyEvolution e;
    e.a = {1.289909578910843, -3.792113559430187, 2.381399216042253};
    e.b0 = {-0.7066063942831287, 2.1324617475069285, -1.445761720071556};
    e.b1 = {0.18795409536328947, -0.869944534247202, 1.465802490870222};
    e.young = 72.5;
    e.poisson = 0.17;
    e.poisson_max = 0.2494778890865429;
    return e;
}

double maxBondStrain(const Model& m) {
    double worst = 0.0;
    for (std::size_t k = 0; k < m.bonds.size(); ++k) {
        if (m.bonds.broken[k]) continue;
        const Vec3 d = load3(m.particles.position.data(), static_cast<std::size_t>(m.bonds.j[k])) -
                       load3(m.particles.position.data(), static_cast<std::size_t>(m.bonds.i[k]));
        worst = std::max(worst, std::abs(d.norm() - m.bonds.rest_length[k]) / m.bonds.rest_length[k]);
    }
    return worst;
}

std::string readText(const std::filesystem::path& path) {
    std::ifstream in(path);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

nlohmann::json readSummary(const std::filesystem::path& dir) {
    return nlohmann::json::parse(readText(dir / "summary.json"));
}

std::vector<std::vector<double>> readCsvColumns(const std::filesystem::path& path,
                                               const std::vector<std::string>& names) {
    std::istringstream in(readText(path));
    std::string line;
    std::getline(in, line);
    std::vector<std::string> header;
    for (std::stringstream h(line); std::getline(h, line, ',');) {
        header.push_back(line);
    }
    std::vector<std::vector<double>> columns(names.size());
    while (std::getline(in, line)) {
        std::vector<std::string> cells;
        for (std::stringstream r(line); std::getline(r, line, ',');) {
            cells.push_back(line);
        }
        for (std::size_t k = 0; k < names.size(); ++k) {
            const auto at = std::find(header.begin(), header.end(), names[k]);
            const auto c = static_cast<std::size_t>(at - header.begin());
            if (at != header.end() && c < cells.size()) {
                columns[k].push_back(std::stod(cells[c]));
            }
        }
    }
    return columns;
}

std::vector<int> availableLanes() {
    std::vector<int> widths{2};
    if (__builtin_cpu_supports("avx2")) {
        widths.push_back(4);
    }
    if (__builtin_cpu_supports("avx512f")) {
        widths.push_back(8);
    }
    return widths;
}

/// An FCC sphere of 6 000 particles (its bond count is a multiple of 4 by symmetry; the passes below take all
/// but its last bond, `passView`, an odd count, so the last block of the 4- and 8-lane passes is partial),
/// every beam stretched, bent and twisted; every 97th particle turned by 0.3–0.6 rad (its bonds leave the
/// series range), every 41st bond broken; with densification, bonds already slipped and bonds that slip now.
Model strainedBondModel(bool densify) {
    Model m = fccModel(SampleShape::Sphere, 3.0, 6000);
    agitate(m, 7, 1e-3);
    std::mt19937_64 rng(3);
    std::normal_distribution<double> g(0.0, 2e-3);
    for (double& x : m.particles.position) x += g(rng);
    for (std::size_t q = 0; q < m.particles.size(); ++q) {
        const double angle = q % 97 == 0 ? 0.3 + 0.15 * static_cast<double>(q % 3) : 10.0 * g(rng);
        const Quat turn(Eigen::AngleAxisd(angle, Vec3(1.0 + g(rng), 0.5, -0.2).normalized()));
        storeQuat(m.particles.orientation.data(), q, turn * loadQuat(m.particles.orientation.data(), q));
    }
    for (std::size_t k = 0; k < m.bonds.size(); k += 41) {
        m.bonds.broken[k] = 1;
    }
    if (densify) {
        m.bonds.enableDensification();
        for (std::size_t k = 3; k < m.bonds.size(); k += 13) {
            m.bonds.slip[k] = 0.01 + 0.001 * static_cast<double>(k % 7); // densified earlier
            m.bonds.reference_strain[k] = -m.bonds.slip[k];
        }
    }
    return m;
}

DensificationLaw lowYieldSlider(bool evolve, double young) {
    DensificationLaw law;
    // A yield stress low enough that the agitated lattice (axial strains up to ≈ 1 %) slips in a good share
    // of its bonds in compression, and a hardening slider, so both slider branches run.
    law.slider = SpringSlider::make(0.5, 98.82, 0.067, young);
    law.evolve = evolve;
    law.evolution = silicaEvolution();
    return law;
}

void writeStores(const std::string& path, const Particles& particles, const Bonds& bonds, const CheckpointMeta& meta,
                 const ContactList* contacts) {
    Particles p = particles;
    Bonds b = bonds;
    ContactList list = contacts ? *contacts : ContactList{};
    writeCheckpoint(path, meta, RunState{p, b, contacts ? &list : nullptr, nullptr, std::nullopt});
}

CheckpointMeta readStores(const std::string& path, Particles& particles, Bonds& bonds, ContactList* contacts) {
    RunState state{particles, bonds, contacts, nullptr, std::nullopt};
    return readCheckpoint(path, state);
}

} // namespace vitrum::testing
