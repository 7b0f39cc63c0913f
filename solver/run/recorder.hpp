// What a run records (series.csv rows, the progress line, the summary's probe keys): the probes every run
// has (energies, the largest speed, the reaction and mean displacement of each probed set), the scene's gauges
// (uniaxial: stress and strains of a bar; hydrostatic: the loaded hull's volume), then the columns of each
// effect (its seriesColumns / seriesValues hooks, solver/effects/effects.hpp), in that order. Units are in the
// column names.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "solver/measure/hydrostatic.hpp"
#include "solver/measure/material_test.hpp"
#include "solver/measure/uniaxial.hpp"
#include "solver/step/probes.hpp"

namespace vitrum {

struct Effects;
struct Scene;

class Recorder {
public:
    /// The probed sets are the scene's output.reactions and, with a uniaxial measure, its loaded set.
    Recorder(const Scene& scene, Model& model, Effects& effects);

    const std::vector<std::string>& columns() const { return columns_; }
    /// Evaluates every probe at `time` (the forces must be current): one row of columns().
    std::vector<double> record(long step, double time);
    /// The probes of the last record().
    const ProbeValues& last() const { return last_; }
    /// "KE … nJ  U … nJ  F_set … N  <effects>" of the last record(), for the progress line.
    std::string progressText() const;
    /// The probes' and gauges' summary keys into `measurements` (final energies, reactions, E and ν of a
    /// uniaxial test, the volume changes of a hydrostatic one).
    void summarize(nlohmann::ordered_json& measurements) const;
    /// The material test's gauge ([measure] kind = "material_test"), else null.
    const MaterialTestGauge* materialTest() const { return material_ ? &*material_ : nullptr; }
    /// Whether the last record() met a measurement's end ([measure] material_test stop_strain): the run ends.
    bool finished() const { return finished_; }

private:
    struct UniaxialSample {
        double stress, strain, extensometer, lateral;
    };
    const Scene& scene_;
    Model& model_;
    Effects& effects_;
    std::vector<std::size_t> probed_;
    std::vector<std::string> columns_;
    std::optional<UniaxialGauge> uniaxial_;
    std::size_t loaded_ = 0; ///< index of the loaded set in probed_
    std::optional<UniaxialSample> uniaxial_last_;
    std::optional<HydrostaticGauge> hydrostatic_;
    std::optional<MaterialTestGauge> material_;
    bool finished_ = false;
    ProbeValues last_;
};

} // namespace vitrum
