// `vitrum calibrate elastic`: sweeps of the beam radius ratio r̃ and Young's modulus E_μ over several packing
// seeds, each a quasi-static tensile test (examples/tensile-cylinder.toml by default), then least-squares fits
// of the paper's eqs (5)–(6), their inverse for the target (E, ν), and the calibration file.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace vitrum {

struct CalibrateOptions {
    std::string scene = "examples/tensile-cylinder.toml";
    std::vector<double> radius_ratios = {0.4, 0.5, 0.6, 0.7, 0.8};
    std::vector<double> beam_youngs = {300.0, 500.0}; ///< GPa
    std::vector<std::uint64_t> seeds = {1, 2, 3};
    std::vector<std::string> overrides;               ///< --set for every tensile test
    std::string out_dir = "out/calibration";
    std::string output = "examples/calibration/silica.toml";
    double target_young = 72.5;   ///< GPa
    double target_poisson = 0.17;
    int threads = 0;
    std::string command_line;     ///< recorded in the calibration file
};

int calibrateElastic(const CalibrateOptions& options);

} // namespace vitrum
