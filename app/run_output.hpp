// The files of a run in its output directory (DESIGN.md §6), set up only once every input is known good: the
// directory lock, the earlier run's files cleared (a fresh run) or continued (a restart), the particle maps.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "io/damage_fields.hpp"
#include "io/fields.hpp"
#include "io/vtk_writer.hpp"
#include "solver/effects/coupling.hpp"
#include "solver/effects/effects.hpp"
#include "solver/model/model.hpp"
#include "solver/scene.hpp"

namespace vitrum {

/// Holds `dir/.vitrum.lock` (with this process's pid) for the lifetime of the run: a second run into the same
/// directory is refused with the first one's pid (InputError); a lock whose process is gone is taken over.
class OutputLock {
public:
    explicit OutputLock(const std::filesystem::path& dir);
    ~OutputLock();
    OutputLock(const OutputLock&) = delete;
    OutputLock& operator=(const OutputLock&) = delete;

private:
    std::filesystem::path path_;
};

/// Removes what an earlier run left in `dir` (summary, checkpoints, series, maps, plots, measure files), so a
/// fresh run that fails leaves none of another run's results beside its own.
void clearEarlierOutputs(const std::filesystem::path& dir);

/// Writes the particle maps (maps/particles_<step>.vtu, maps.pvd) with the fields the scene's output.fields
/// asks for, and with effect coupling the CNEM mesh (maps/cnem_<step>.vtu, cnem.pvd). A store field is named
/// by its table (solver/model/field.hpp labelWithUnit); the derived ones by the table in run_output.cpp.
class MapWriter {
public:
    /// `restart_time` >= 0 continues the collections of a restarted run (entries up to that time kept).
    MapWriter(const std::filesystem::path& out, const Scene& scene, const Model& model, double restart_time);
    /// On a rank of a run over several ranks (model.part set): each rank writes its piece, rank 0 the .pvtu
    /// and maps.pvd (collective in what it writes, though no message is sent).
    MapWriter(const std::filesystem::path& out, const Scene& scene, const Model& model, double restart_time,
              int rank, int ranks);
    void write(Model& model, Effects& effects, long step, double time);

    /// Buffers of the derived fields, reused between maps.
    struct Buffers {
        std::vector<double> coordination, displacement, volumetric, density_change, slider, plastic_density;
        DamageFieldBuffers damage;
    };

private:
    std::filesystem::path out_;
    std::optional<PvdCollection> pvd_;
    PvdCollection cnem_pvd_;
    std::vector<OutputField> fields_;
    Buffers buffers_;
    CnemMapFields cnem_fields_;
    int rank_ = 0;
    int ranks_ = 1;
    bool pieces_ = false;
};

} // namespace vitrum
