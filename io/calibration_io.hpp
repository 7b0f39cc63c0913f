// The elastic calibration file (TOML): fitted coefficients of the paper's eqs (5)–(6), the micro-parameters
// for the targets, the packing it is valid for, and the raw tensile-test samples with their provenance.
// Scenes use it through [material] calibration = "path".
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <optional>

#include "solver/calibration/elastic.hpp"
#include "solver/calibration/densification.hpp"
#include "solver/scene.hpp"

namespace vitrum {

struct CalibrationRecord {
    CalibrationSample sample;
    std::uint64_t seed = 0;
    double kinetic_to_strain = 0.0; ///< quasi-static check of that test
};

/// The [plasticity] section of a calibration file: the particle law's elastic metric (cap_plasticity.hpp M1)
/// fitted to the packing's elastic virtual tests, GPa.
struct PlasticityCalibration {
    double bulk = 0.0;       ///< K₀
    double bulk_slope = 0.0; ///< K′
    double shear = 0.0;      ///< G
    std::string law;         ///< the published law whose targets the cap's micro-parameters were fitted to ("": none)
    double shear_limit = 0.0;///< q_y^μ, the particle law's shear limit for that law's targets
    double cap_ratio = 0.0;  ///< R^μ
};

struct CalibrationFile {
    ElasticCalibration fit;
    double target_young = 72.5;   ///< GPa
    double target_poisson = 0.17;
    double density = 2200.0;      ///< kg/m³
    double beam_poisson = 0.3;    ///< ν_μ (no influence on E, ν: paper §2.2.1)
    CalibrationSample micro;      ///< r̃, E_μ for the targets
    SampleParams packing;         ///< the packing the calibration is valid for (µm)
    std::vector<CalibrationRecord> records;
    std::string command;          ///< the command that regenerates the file
    std::string vitrum_version;
    /// [densification] of `vitrum calibrate densification` (σ_μ^d, E_μ^t in GPa, ε_μ^pmax), if the file has one.
    std::optional<DensificationParameters> densification;
    /// [plasticity] of `vitrum calibrate plasticity` (the cap law's elastic metric and micro-parameters), if any.
    std::optional<PlasticityCalibration> plasticity;
};

/// TOML text of the calibration file.
std::string calibrationToml(const CalibrationFile& file);

/// Reads the micro-parameters and fit of a calibration file (InputError with file:line on bad content), and
/// its [densification] table when there is one.
CalibrationFile readCalibration(const std::string& path);

/// The lines that open the sections `vitrum calibrate densification` and `vitrum calibrate plasticity` write
/// into a calibration file; a section runs from its marker to the next marker or the end of the file.
extern const char* const kDensificationSectionMarker;
extern const char* const kPlasticitySectionMarker;

/// `calibration_text` with the command section `section` (which starts with its marker line, then owns the
/// first [table] it holds) in place of the earlier one of the same marker, or appended; the other commands'
/// sections are kept. Throws InputError naming `path` when the text has that table outside such a section
/// (written by hand: the command would otherwise leave two).
std::string withCommandSection(const std::string& calibration_text, const std::string& section,
                               const std::string& path);

} // namespace vitrum
