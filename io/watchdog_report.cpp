#include "io/watchdog_report.hpp"

#include <algorithm>
#include <sstream>

#include "io/fields.hpp"
#include "io/vtk_writer.hpp"

namespace vitrum {

namespace fs = std::filesystem;

std::string reportInstability(const fs::path& out, CheckpointMeta run, double dt_critical, const Model& model,
                              const Effects& effects, StateSnapshot& last_good, long particle) {
    const double dt = run.dt;
    const InstabilityDiagnosis d = diagnoseInstability(model, effects, particle, dt / dt_critical);
    std::ostringstream s;
    s << "\n  " << d.particle << ";\n  " << d.bond << ".\n  likely cause: " << causeName(d.cause) << ": "
      << d.advice << ".";
    if (last_good.step >= 0) {
        const fs::path path = out / "last_good_state.h5";
        try {
            run.step = last_good.step;
            run.time = last_good.time;
            last_good.complete(model);
            writeCheckpoint(path.string(), run, last_good.state());
            s << "\n  wrote the last good state (step " << last_good.step << ", t = " << last_good.time << " ns) to "
              << path.string() << " (a checkpoint: --restart continues from it)";
        } catch (const std::exception& e) {
            s << "\n  could not write the last good state: " << e.what();
        }
    }
    if (particle >= 0) {
        double max_radius = 0.0;
        for (double r : model.particles.radius) max_radius = std::max(max_radius, r);
        const double reach = 6.0 * max_radius;
        const Neighbourhood n = gatherNeighbourhood(model, particle, reach);
        const fs::path particles_vtu = out / "watchdog_particles.vtu", bonds_vtu = out / "watchdog_bonds.vtu";
        try {
            const std::vector<FieldView> fields = {{"displacement_um", 3, n.displacement.data()},
                                                   {"velocity_km_per_s", 3, n.velocity.data()},
                                                   {"angular_velocity_rad_per_ns", 3, n.angular_velocity.data()},
                                                   {"force_mN", 3, n.force.data()},
                                                   {"culprit", 1, n.culprit.data()}};
            writeParticlesVtu(particles_vtu.string(), n.members.size(), n.position.data(), n.radius.data(), fields);
            const std::vector<FieldView> bond_fields = {{"axial_strain", 1, n.bond_strain.data()},
                                                        {"force_mN", 1, n.bond_force.data()}};
            writeBondsVtu(bonds_vtu.string(), n.members.size(), n.position.data(), n.bond_i.size(), n.bond_i.data(),
                          n.bond_j.data(), bond_fields);
            s << "\n  wrote the failed state's neighbourhood (" << n.members.size() << " particles and "
              << n.bond_i.size() << " bonds within " << reach << " um of particle " << particle << ") to "
              << particles_vtu.string() << " and " << bonds_vtu.string();
        } catch (const std::exception& e) {
            s << "\n  could not write the neighbourhood maps: " << e.what();
        }
    }
    return s.str();
}

} // namespace vitrum
