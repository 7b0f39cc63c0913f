// Helpers shared by the test tiers: temporary directories and running the vitrum executable.
#pragma once

#include <filesystem>
#include <string>

#include "solver/model.hpp"

namespace vitrum::testing {

/// A fresh, empty directory under the system temp dir, unique per call.
std::filesystem::path freshTempDir(const std::string& tag);

/// Runs the built `vitrum` binary with `args` (shell words); returns its exit code. Output goes to `log`.
int runVitrum(const std::string& args, const std::filesystem::path& log);

/// Random thermal-like velocities (normal, standard deviation `speed` km/s per component) and spins
/// (speed / R rad/ns), seeded.
void agitate(Model& model, unsigned seed, double speed);

/// Kinetic (translational + rotational) plus beam strain energy, nJ.
double totalEnergy(Model& model);

/// Reads a whole text file.
std::string readText(const std::filesystem::path& path);

} // namespace vitrum::testing
