// Helpers shared by the test tiers: temporary directories and running the vitrum executable.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/checkpoint.hpp"
#include "kernels/densification.hpp"
#include "solver/model/model.hpp"

namespace vitrum::testing {

/// A fresh, empty directory under the system temp dir, unique per call.
std::filesystem::path freshTempDir(const std::string& tag);

/// Runs the built `vitrum` binary with `args` (shell words); returns its exit code. Output goes to `log`.
int runVitrum(const std::string& args, const std::filesystem::path& log);

/// A regular FCC sample built by buildModel (shape "sphere", "hemisphere", "cube", …; radius µm; about
/// `particles` particles), for kernel tests that need a real bond network without a packing.
Model fccModel(SampleShape shape, double radius, int particles);

/// Random thermal-like velocities (normal, standard deviation `speed` km/s per component) and spins
/// (speed / R rad/ns), seeded.
void agitate(Model& model, unsigned seed, double speed);

/// Kinetic (translational + rotational) plus beam strain energy, nJ.
double totalEnergy(Model& model);

/// Largest axial strain |l − l₀|/l₀ over the unbroken bonds: a particle escaping its neighbours (or passing
/// through one) shows as a large bond strain.
double maxBondStrain(const Model& model);

/// Reads a whole text file.
std::string readText(const std::filesystem::path& path);

/// The summary.json a run wrote into `dir`.
nlohmann::json readSummary(const std::filesystem::path& dir);

/// The quickstart's overrides for a reduced indentation (tests/regression): 1 500 particles in a 3.4 µm
/// hemisphere (R̄ ≈ 0.23 µm, the quickstart's), to 4 mN at 50 m/s (1 % of the P-wave speed: quasi-static
/// enough for these checks), a 5 ns hold, up at 50 m/s, at most 20 ns of relax.
inline const std::string kReducedQuickstart =
    " --quiet --set sample.particles=1500 --set sample.radius=3.4 --set 'stage[0].until_force=0.004'"
    " --set 'stage[0].speed=0.05' --set 'stage[1].duration=5.0' --set 'stage[2].speed=0.05'"
    " --set 'stage[3].duration=20.0' --set time.duration=200.0";

/// The named columns of a CSV file with a header row (one vector of values per name, in row order); a name
/// that is not in the header gives an empty vector.
std::vector<std::vector<double>> readCsvColumns(const std::filesystem::path& path,
                                               const std::vector<std::string>& names);

/// A silica calibration of eqs (5)–(6) (examples/calibration/silica.toml as of commit 3305ac5), fixed here so
/// the tests do not move when the calibration is regenerated.
PropertyEvolution silicaEvolution();

/// An FCC sphere of 6 000 particles (≈ 37 000 bonds, a multiple of 4), every beam stretched, bent and
/// twisted; every 97th particle turned by 0.3–0.6 rad (its bonds leave the beam pass's series range), every
/// 41st bond broken; with `densify`, the densification state sized and every 13th bond densified earlier. For
/// the bond pass tests (lanes, fused sweep).
Model strainedBondModel(bool densify);

/// A spring-slider whose 0.5 GPa yield stress makes a good share of strainedBondModel's bonds slip in
/// compression (axial strains up to ≈ 1 %), hardening, with or without property evolution.
DensificationLaw lowYieldSlider(bool evolve, double young);

/// The SIMD lane widths of the beam pass this CPU can run (2 always; 4 with AVX2; 8 with AVX-512F).
/// The checkpoint of the bare stores, with the contact history of `contacts` when given (RunState around them).
void writeStores(const std::string& path, const Particles& particles, const Bonds& bonds, const CheckpointMeta& meta,
                 const ContactList* contacts = nullptr);
/// Reads the stores (and the contact history onto `contacts` when given) of such a checkpoint.
CheckpointMeta readStores(const std::string& path, Particles& particles, Bonds& bonds, ContactList* contacts = nullptr);

std::vector<int> availableLanes();

} // namespace vitrum::testing
