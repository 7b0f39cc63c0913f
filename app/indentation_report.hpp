// Indentation results of `vitrum run` (effect indenter): the residual imprint metrics (solver/measure/imprint.hpp),
// the densified volume from the permanent volumetric strain (kernels/strain.hpp), the files the plots are
// made from (imprint.csv, cutaway.csv) and the plots themselves (io/plot_indentation.py).
#pragma once

#include <filesystem>
#include <functional>
#include <ostream>

#include <nlohmann/json.hpp>

#include "solver/measure/cracks.hpp"
#include "solver/effects/effects.hpp"
#include "solver/model/model.hpp"

namespace vitrum {

/// The crack classification's parameters for this run: the load axis through the tip, the free surface,
/// contact radius `contact_radius` (µm) and a surface band of 3 R̄.
CrackParams crackParams(const Indenter& indenter, double mean_radius, double contact_radius);
/// The crack pattern of the released particles (initial centres), solver/measure/cracks.hpp.
CrackPattern classifyReleased(const Model& model, const CrackParams& params);
CrackPattern classifyReleased(const Particles& particles, const CrackParams& params);
/// The released particles (initial and current centres, release step) as CSV, written atomically.
void writeCracksCsv(const std::filesystem::path& path, const Particles& particles);
/// The summary keys of a crack pattern (cone_radius_um, cone_angle_deg, radial_crack_count, ...).
nlohmann::ordered_json crackJson(const CrackPattern& pattern, const CrackParams& params);

/// Crack maps at the two instants of the paper's 30 N study (issue 9; effects fracture and indenter): the
/// onset, the first recorded step at which the released particles form a cone/ring crack (Fig 15: "at the
/// beginning of fracture"), and full load, the first recorded step after the first load stage ended. At each:
/// cracks_<tag>.csv and the classification with step, time, depth and force (json()); the caller writes a
/// particle map. The contact radius is measured: the farthest tool-contact particle from the axis.
class CrackSnapshots {
public:
    /// A force drop of 3 % of the running maximum: the recorded force of a loading tool rises monotonically
    /// without cracks (the 30 N runs show no drop before cracking), so 3 % is well above its noise and below
    /// the 10-30 % pop-ins of unstable cone/median cracking in glasses.
    static constexpr double kPopIn = 0.03;
    CrackSnapshots(const Model& model, const Effects& effects, std::filesystem::path out);
    /// With the sample's mean radius given (a rank holds part of it); `writes` false: no file is written here
    /// (the ranks other than 0 of a run over several ranks).
    CrackSnapshots(double mean_radius, const Effects& effects, std::filesystem::path out, bool writes);
    /// Call at every recorded step; returns the tag of the snapshot taken ("onset", "unstable", "full_load")
    /// or "". onset: the first closed ring while loading. unstable: the first pop-in while loading after
    /// the onset, the tool force falling kPopIn below its running maximum under a displacement-driven tool
    /// (crack growth that the load no longer has to drive; the paper's Fig 15 is the state just before).
    std::string observe(const Model& model, const Effects& effects, long step, double time);
    /// The same from what it decides on: the contact radius now (the farthest tool-contact particle from the
    /// axis), the released particles' count, and their store (`released_particles`, called only when a
    /// pattern is classified: on several ranks it gathers them).
    std::string observe(double contact_radius, long released, const std::function<const Particles&()>& released_particles,
                        const Indenter& indenter, long step, double time);
    const nlohmann::ordered_json& json() const { return json_; }
    nlohmann::ordered_json& json() { return json_; }
    /// The largest contact radius seen while loading, µm (the farthest contact point from the axis).
    double maxContactRadius() const { return last_contact_radius_; }
    /// What these snapshots have seen so far (the snapshots taken and the running values they decide on), as
    /// JSON text for a checkpoint; restoreObservations(text) continues from it, so a restarted run reports the
    /// snapshots taken before its restart. Throws InputError (naming `source`) on text it cannot read.
    std::string observations() const;
    void restoreObservations(const std::string& text, const std::string& source);

private:
    double mean_radius_;
    std::filesystem::path out_;
    bool writes_ = true;
    int first_load_ = -1;
    bool onset_taken_ = false, unstable_taken_ = false, full_load_taken_ = false;
    double max_force_ = 0.0; ///< running maximum of the tool force while loading, internal units
    long released_seen_ = 0;
    double last_contact_radius_ = 0.0;
    nlohmann::ordered_json json_ = nlohmann::ordered_json::object();
};

/// Fills `m` with the DESIGN.md §6 indentation keys and writes imprint.csv and cutaway.csv into `out`. With
/// the fracture effect the crack keys (cone_radius_um, ...) are those of the paper's Fig 15 instant from
/// `cracks` (the pop-in snapshot when there was one, else full load; `crack_instant` says which), the
/// imprint is the surface of the bonded solid (released particles left out, as fragments are brushed off a
/// print before it is measured), and the final state is classified too (crack_snapshots.final).
void measureIndentation(const Scene& scene, const Model& model, const Effects& effects,
                        const std::filesystem::path& out, nlohmann::ordered_json& m, CrackSnapshots* cracks);

/// The metrics beside the paper's Table 4 rows for the nearest load (0.1 N or 0.5 N).
void printImprintTable(std::ostream& log, const Scene& scene, const nlohmann::ordered_json& m);

/// Runs io/plot_indentation.py on `out` (plots/*.png) when python3 with matplotlib is there; says so if not.
void plotIndentation(std::ostream& log, const std::filesystem::path& out, bool verbose);

} // namespace vitrum
