#include "app/run_output.hpp"

#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fstream>

#include <fcntl.h>
#include <unistd.h>

#include "kernels/strain.hpp"
#include "solver/errors.hpp"

namespace vitrum {

namespace fs = std::filesystem;

OutputLock::OutputLock(const fs::path& dir) : path_(dir / ".vitrum.lock") {
    for (int attempt = 0; attempt < 2; ++attempt) {
        const int fd = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0644);
        if (fd >= 0) {
            const std::string pid = std::to_string(::getpid()) + "\n";
            const bool written = ::write(fd, pid.data(), pid.size()) == static_cast<ssize_t>(pid.size());
            ::close(fd);
            if (!written) {
                fs::remove(path_);
                throw RuntimeFailure("cannot write the lock " + path_.string());
            }
            return;
        }
        if (errno != EEXIST) {
            throw InputError("cannot lock the output directory " + dir.string() + ": " + std::strerror(errno));
        }
        long holder = 0;
        std::ifstream(path_) >> holder;
        if (holder > 0 && (::kill(static_cast<pid_t>(holder), 0) == 0 || errno == EPERM)) {
            throw InputError("the output directory " + dir.string() + " is in use by another vitrum run (pid " +
                             std::to_string(holder) + ", " + path_.string() +
                             "); choose another --out, or wait for it to finish");
        }
        std::error_code ignored; // the holder is gone (killed): its lock is stale
        fs::remove(path_, ignored);
    }
    throw InputError("cannot lock the output directory " + dir.string() + " (" + path_.string() + ")");
}

OutputLock::~OutputLock() {
    std::error_code ignored;
    fs::remove(path_, ignored);
}

void clearEarlierOutputs(const fs::path& dir) {
    std::error_code ignored;
    for (const char* name : {"summary.json", "state.h5", "state.h5.tmp", "last_good_state.h5", "series.csv",
                             "maps.pvd", "cnem.pvd", "measure.json", "imprint.csv", "cutaway.csv", "cracks.csv",
                             "cracks_onset.csv", "cracks_unstable.csv", "cracks_full_load.csv", "cracks_onset.json",
                             "cracks_unstable.json", "cracks_full_load.json", "plots.log",
                             "watchdog_particles.vtu", "watchdog_bonds.vtu"}) {
        fs::remove(dir / name, ignored);
    }
    fs::remove_all(dir / "plots", ignored);
    if (fs::is_directory(dir / "maps", ignored)) {
        for (const fs::directory_entry& e : fs::directory_iterator(dir / "maps", ignored)) {
            const std::string name = e.path().filename().string();
            const bool map = e.path().extension() == ".vtu" || e.path().extension() == ".pvtu";
            if (map && (name.rfind("particles_", 0) == 0 || name.rfind("cnem_", 0) == 0)) {
                fs::remove(e.path(), ignored);
            }
        }
    }
}

namespace {

using Buffers = MapWriter::Buffers;

/// The fields a map can hold beyond the particle store's own (output.fields names; solver/scene.hpp).
struct DerivedField {
    const char* name;
    void (*add)(Model&, Effects&, Buffers&, std::vector<FieldView>&);
};

const DerivedField kDerivedFields[] = {
    {"displacement",
     [](Model& m, Effects&, Buffers& b, std::vector<FieldView>& views) {
         const Particles& p = m.particles;
         b.displacement.resize(p.position.size());
         for (std::size_t k = 0; k < p.position.size(); ++k) {
             b.displacement[k] = p.position[k] - p.initial_position[k];
         }
         views.push_back({"displacement_um", 3, b.displacement.data()});
     }},
    {"coordination",
     [](Model& m, Effects&, Buffers& b, std::vector<FieldView>& views) {
         b.coordination.resize(ownedCount(m)); // the incidence's rows (a rank's: its owned particles)
         for (std::size_t i = 0; i < b.coordination.size(); ++i) {
             b.coordination[i] = m.incidence.degree(i);
         }
         views.push_back({"coordination", 1, b.coordination.data()});
     }},
    {"densification",
     // Residual volumetric strain of the bonded neighbourhood (kernels/strain.hpp), the density change it
     // implies, the slider's own measure (−3 × mean bond slip) when densifying, and the cap law's state.
     [](Model& m, Effects& fx, Buffers& b, std::vector<FieldView>& views) {
         const Particles& p = m.particles;
         b.volumetric.assign(p.size(), 0.0);
         b.density_change.assign(p.size(), 0.0);
         volumetricStrain(m.incidence.view(), m.bonds.i.data(), m.bonds.j.data(), p.initial_position.data(),
                          p.position.data(), b.volumetric.data());
         for (std::size_t i = 0; i < p.size(); ++i) {
             b.density_change[i] = -b.volumetric[i] / (1.0 + b.volumetric[i]);
         }
         views.push_back({"volumetric_strain", 1, b.volumetric.data()});
         views.push_back({"density_change", 1, b.density_change.data()});
         if (fx.densification) {
             b.slider.assign(p.size(), 0.0);
             sliderVolumetricStrain(m.incidence.view(), m.bonds.slip.data(), b.slider.data());
             views.push_back({"slider_volumetric_strain", 1, b.slider.data()});
         }
         if (fx.plasticity) { // the cap law's own state: Δρ/ρ = exp(e) − 1 and γ̄
             b.plastic_density.resize(p.size());
             for (std::size_t i = 0; i < p.size(); ++i) {
                 b.plastic_density[i] = std::expm1(p.compaction[i]);
             }
             views.push_back({"plastic_density_change", 1, b.plastic_density.data()});
             views.push_back({"plastic_shear_strain", 1, p.plastic_shear.data()});
         }
     }},
    {"tool",
     [](Model&, Effects& fx, Buffers&, std::vector<FieldView>& views) {
         if (fx.indenter) {
             views.push_back({"tool_contact_force_mN", 3, fx.indenter->contact_force.data()});
         }
     }},
    {"damage",
     [](Model& m, Effects&, Buffers& b, std::vector<FieldView>& views) {
         appendDamageFields(OutputField::Damage, m.particles, b.damage, views);
     }},
    {"stress",
     [](Model& m, Effects&, Buffers& b, std::vector<FieldView>& views) {
         appendDamageFields(OutputField::Stress, m.particles, b.damage, views);
     }},
    // The radius is every map's glyph size already (writeParticlesVtu).
    {"radius", [](Model&, Effects&, Buffers&, std::vector<FieldView>&) {}},
};

} // namespace

MapWriter::MapWriter(const fs::path& out, const Scene& scene, const Model&, double restart_time)
    : out_(out),
      pvd_(restart_time >= 0.0 ? PvdCollection::continuing((out / "maps.pvd").string(), restart_time)
                               : PvdCollection((out / "maps.pvd").string())),
      cnem_pvd_(restart_time >= 0.0 ? PvdCollection::continuing((out / "cnem.pvd").string(), restart_time)
                                    : PvdCollection((out / "cnem.pvd").string())),
      fields_(scene.output.fields) {}

MapWriter::MapWriter(const fs::path& out, const Scene& scene, const Model& model, double restart_time, int rank,
                     int ranks)
    : out_(out), cnem_pvd_((out / "cnem.pvd").string()), fields_(scene.output.fields), rank_(rank), ranks_(ranks),
      pieces_(model.part.has_value()) {
    if (rank == 0) {
        pvd_ = restart_time >= 0.0 ? PvdCollection::continuing((out / "maps.pvd").string(), restart_time)
                                   : PvdCollection((out / "maps.pvd").string());
    }
}

void MapWriter::write(Model& model, Effects& effects, long step, double time) {
    Particles& p = model.particles;
    std::vector<FieldView> views;
    for (const OutputField f : fields_) {
        const std::string_view name = nameOf(f);
        bool found = false;
        for (const DerivedField& d : kDerivedFields) {
            if (!found && name == d.name) {
                d.add(model, effects, buffers_, views);
                found = true;
            }
        }
        forEachField(p, [&](const Field& field, const auto& values) {
            if constexpr (std::is_same_v<std::decay_t<decltype(values)>, std::vector<double>>) {
                if (!found && name == field.name && !values.empty()) {
                    views.push_back({labelWithUnit(field), field.components, values.data()});
                    found = true;
                }
            }
        });
    }
    char name[64];
    if (pieces_) {
        // One piece per rank (its owned particles: the stores' first rows), and rank 0's .pvtu over them.
        const std::size_t owned = ownedCount(model);
        std::snprintf(name, sizeof name, "maps/particles_%08ld_r%d.vtu", step, rank_);
        writeParticlesVtu((out_ / name).string(), owned, p.position.data(), p.radius.data(), views);
        if (rank_ == 0) {
            std::vector<std::string> pieces;
            for (int r = 0; r < ranks_; ++r) {
                std::snprintf(name, sizeof name, "particles_%08ld_r%d.vtu", step, r);
                pieces.push_back(name);
            }
            std::snprintf(name, sizeof name, "maps/particles_%08ld.pvtu", step);
            writeParticlesPvtu((out_ / name).string(), pieces, views);
            pvd_->add(time, name);
            pvd_->write();
        }
        return;
    }
    std::snprintf(name, sizeof name, "maps/particles_%08ld.vtu", step);
    writeParticlesVtu((out_ / name).string(), p.size(), p.position.data(), p.radius.data(), views);
    pvd_->add(time, name);
    pvd_->write();
    if (effects.coupling) {
        // Effect coupling: the CNEM continuum as a second series (its domain tetrahedra, deformed), with
        // displacement, velocity, smoothed strain and stress, and the partition weight α_c per node.
        CoupledContinuum& c = *effects.coupling;
        cnemMapFields(c, cnem_fields_);
        const std::vector<FieldView> cnem_views = {{"displacement_um", 3, c.cnem.displacement.data()},
                                                   {"velocity_km_per_s", 3, c.cnem.velocity.data()},
                                                   {"strain", 6, cnem_fields_.strain.data()},
                                                   {"stress_GPa", 6, cnem_fields_.stress.data()},
                                                   {"weight_alpha_c", 1, cnem_fields_.weight.data()}};
        std::snprintf(name, sizeof name, "maps/cnem_%08ld.vtu", step);
        writeTetsVtu((out_ / name).string(), c.cnem.nodes(), cnem_fields_.position.data(), c.cnem.mesh.tetCount(),
                     c.cnem.mesh.tet.data(), cnem_views);
        cnem_pvd_.add(time, name);
        cnem_pvd_.write();
    }
}

} // namespace vitrum
