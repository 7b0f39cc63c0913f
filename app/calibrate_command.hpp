// `vitrum calibrate elastic`: sweeps of the beam radius ratio r̃ and Young's modulus E_μ over several packing
// seeds, each a quasi-static tensile test (examples/tensile-cylinder.toml by default), then least-squares fits
// of the paper's eqs (5)–(6), their inverse for the target (E, ν), and the calibration file.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/run_command.hpp"

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

/// `vitrum calibrate densification`: σ_μ^d, E_μ^t, ε_μ^pmax for Ji's macroscopic targets (P_d, P_s, ΔV/V₀)
/// by hydrostatic sphere tests run in-process (the `run` driver on the scene with overrides), searched in
/// the paper's order (solver/calibration/densification.hpp); finite-difference sensitivities at the result
/// (paper Figs 7–9); the result written as the [densification] section of the calibration file.
struct DensificationCalibrateOptions {
    std::string scene = "examples/hydrostatic-sphere.toml";
    std::vector<std::string> overrides; ///< --set for every run
    long particles = 0;                 ///< 0: the scene's; otherwise the sphere radius scales as N^(1/3)
    std::uint64_t seed = 1;             ///< packing seed
    std::vector<double> pressures = {4, 6, 8, 10, 12, 14, 16, 18, 20, 22, 25, 30}; ///< P_max, GPa
    double ramp = 10.0, hold = 5.0, release = 5.0, rest = 5.0;                     ///< ns
    double target_onset = 8.0;          ///< P_d, GPa (Ji)
    double target_saturation = 20.0;    ///< P_s, GPa
    double target_volume_change = 17.4; ///< ΔV/V₀, %
    std::vector<double> tolerances = {0.4, 1.2, 0.4}; ///< GPa, GPa, % (absolute; inside the acceptance 0.5, 1.5, 0.5)
    std::vector<double> start = {7.13, 98.82, 0.067};    ///< σ_μ^d (GPa), E_μ^t (GPa), ε_μ^pmax: paper Table 3
    int max_evaluations = 12;
    bool sensitivity = true;            ///< finite differences at the result
    std::vector<double> sensitivity_steps = {0.1, 20.0, 0.2}; ///< +10 % σ, +20 GPa E_t, +20 % ε
    std::string measure = "hull";       ///< residual volume change of: "hull" (whole sphere) or "interior"
    std::string out_dir = "out/densification-calibration";
    std::string output;                 ///< calibration file to write; "" = the scene's [material] calibration
    int threads = 0;
    std::string command_line;
};

int calibrateDensification(const DensificationCalibrateOptions& options);

/// `vitrum calibrate plasticity` (app/calibrate_plasticity.cpp): the particle cap law's elastic metric and
/// q_y, R from the virtual tests of `scenes`, written as the [plasticity] section of the calibration file, then
/// checked against every acceptance target on another packing.
struct PlasticityCalibrateOptions {
    std::string scenes = "examples/virtual-tests";
    std::string law = "bruns2020";      ///< the published law whose targets are fitted
    std::uint64_t seed = 1;             ///< the packing of the fit
    std::uint64_t check_seed = 2;       ///< the packing of the acceptance (0: none)
    std::vector<std::string> overrides; ///< --set for every run
    std::string out_dir = "out/plasticity-calibration";
    std::string output;                 ///< calibration file to write; "" = the scenes' [material] calibration
    int threads = 0;
    int iterations = 4;                 ///< Gauss–Newton steps at most
    double tolerance = 0.03;            ///< rms relative miss of the yield targets that ends the fit
    double metric_pressure = 25.0;      ///< GPa: the equation of state is fitted up to it
    std::vector<double> check_pressures = {7.2, 8, 10, 12, 14, 16, 18, 20, 25}; ///< GPa, hydrostatic acceptance
    std::string command_line;
};

int calibratePlasticity(const PlasticityCalibrateOptions& options);

/// Runs the `run` driver in-process with its log swallowed; returns its summary.json.
nlohmann::json runSceneQuietly(const RunOptions& run);

/// The whole text of a file (InputError naming it when it cannot be read).
std::string readTextFile(const std::string& path);

/// The shortest text that reads back as x exactly (what a --set override or a calibration value needs).
std::string shortestText(double x);

} // namespace vitrum
