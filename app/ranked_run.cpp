#include "app/ranked_run.hpp"

#include <algorithm>
#include <fstream>
#include <limits>
#include <sstream>

#include <sys/resource.h>

#include "io/sha256.hpp"
#include "io/watchdog_report.hpp"
#include "solver/errors.hpp"

namespace vitrum {

namespace fs = std::filesystem;

namespace {

/// SHA-256 of this process's executable: two builds that differ in any byte differ here.
std::string executableSha256() {
    std::ifstream in("/proc/self/exe", std::ios::binary);
    Sha256 h;
    std::vector<char> buffer(1 << 20);
    while (in) {
        in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
        h.update(buffer.data(), static_cast<std::size_t>(in.gcount()));
    }
    return h.hexDigest();
}

} // namespace

void checkSameRun(Comm& comm, const std::string& scene_sha256) {
    if (comm.size() == 1) {
        return;
    }
    const std::string mine = executableSha256() + scene_sha256;
    const std::vector<std::byte> all = comm.allGather(std::as_bytes(std::span<const char>(mine.data(), mine.size())));
    const auto text = [&](int r) {
        return std::string(reinterpret_cast<const char*>(all.data()) + static_cast<std::size_t>(r) * mine.size(),
                           mine.size());
    };
    std::string problem;
    for (int r = 1; r < comm.size() && problem.empty(); ++r) {
        const std::string other = text(r);
        if (all.size() != mine.size() * static_cast<std::size_t>(comm.size())) {
            problem = "the ranks sent identities of different lengths";
        } else if (other.substr(0, 64) != text(0).substr(0, 64)) {
            problem = "rank " + std::to_string(r) + " runs another vitrum executable than rank 0 (SHA-256 " +
                      other.substr(0, 16) + "... against " + text(0).substr(0, 16) + "...)";
        } else if (other.substr(64) != text(0).substr(64)) {
            problem = "rank " + std::to_string(r) + " resolved another scene than rank 0 (scene_sha256 " +
                      other.substr(64, 16) + "... against " + text(0).substr(64, 16) +
                      "...: another scene file, --set or calibration file)";
        }
    }
    agreed(comm, [&] {
        if (!problem.empty()) {
            throw InputError("the MPI ranks of this run disagree: " + problem +
                             "; expected every rank to run the same build on the same scene (one mpirun command "
                             "line, one installed binary)");
        }
    });
}

void gatherWhole(Domain& domain, Model& local, Effects& effects, WholeModel& whole) {
    gatherStores(domain, local, whole.model.particles, whole.model.bonds);
    std::vector<double> tool;
    if (effects.indenter) {
        tool = gatherParticleField(domain, local, effects.indenter->contact_force, 3);
    }
    if (domain.comm->rank() != 0) {
        return;
    }
    whole.model.incidence = Incidence::build(whole.model.particles.size(), whole.model.bonds);
    whole.effects.densification = effects.densification;
    whole.effects.damping = effects.damping;
    whole.effects.fracture = effects.fracture;
    whole.effects.contact = effects.contact;
    whole.effects.indenter = effects.indenter;
    whole.effects.plasticity = effects.plasticity;
    if (whole.effects.indenter) {
        whole.effects.indenter->contact_force = std::move(tool);
    }
}

void writeRankedCheckpoint(Domain& domain, const std::string& path, const CheckpointMeta& meta, Model& local,
                           Effects& effects) {
    Particles particles;
    Bonds bonds;
    gatherStores(domain, local, particles, bonds);
    ContactHistory history;
    if (effects.contact) {
        history = gatherContactHistory(domain, local, effects.contact->list, domain.pairs);
    }
    agreed(*domain.comm, [&] {
        if (domain.comm->rank() != 0) {
            return;
        }
        ContactList springs;
        springs.restore(history);
        RunState state{particles, bonds, effects.contact ? &springs : nullptr,
                       effects.indenter ? &*effects.indenter : nullptr, std::nullopt};
        writeCheckpoint(path, meta, state);
    });
}

Particles gatherReleased(Domain& domain, Model& local) {
    // Only what the crack measurement reads: centres now and at the start, the release step, the flag.
    const Particles& p = local.particles;
    std::vector<double> rows; // x0 y0 z0 x y z step
    for (std::size_t i = 0; i < local.part->owned; ++i) {
        if (p.released[i]) {
            rows.insert(rows.end(), {p.initial_position[3 * i], p.initial_position[3 * i + 1], p.initial_position[3 * i + 2],
                                     p.position[3 * i], p.position[3 * i + 1], p.position[3 * i + 2],
                                     static_cast<double>(p.release_step[i])});
        }
    }
    const std::vector<double> all = valuesOf<double>(domain.comm->allGather(bytesOf(rows)));
    Particles out;
    const std::size_t n = all.size() / 7;
    out.initial_position.resize(3 * n);
    out.position.resize(3 * n);
    out.release_step.resize(n);
    out.released.assign(n, 1);
    out.radius.assign(n, 0.0); // size() counts these
    for (std::size_t k = 0; k < n; ++k) {
        for (int c = 0; c < 3; ++c) {
            out.initial_position[3 * k + c] = all[7 * k + c];
            out.position[3 * k + c] = all[7 * k + 3 + c];
        }
        out.release_step[k] = static_cast<std::int64_t>(all[7 * k + 6]);
    }
    return out;
}

double maxOverRanks(Domain& domain, double value) { return domain.comm->maxOf(value); }

double minRadius(Domain* domain, const Model& model) {
    const std::size_t n = ownedCount(model);
    double r = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < n; ++i) {
        r = std::min(r, model.particles.radius[i]);
    }
    return domain ? -domain->comm->maxOf(-r) : r;
}

std::string rankLine(Domain& domain, const Model& local) {
    Comm& comm = *domain.comm;
    const auto owned = static_cast<long long>(local.part->owned);
    const auto ghosts = static_cast<long long>(local.particles.size() - local.part->owned);
    long long cut = 0;
    for (std::size_t k = 0; k < local.bonds.size(); ++k) {
        cut += (static_cast<std::size_t>(local.bonds.i[k]) >= local.part->owned ||
                static_cast<std::size_t>(local.bonds.j[k]) >= local.part->owned)
                   ? 1
                   : 0;
    }
    const long long most = comm.maxOf(owned), fewest = comm.minOf(owned);
    const long long all_ghosts = comm.sumOf(ghosts), all_cut = comm.sumOf(cut);
    std::ostringstream s;
    s << "  ranks      " << comm.size() << " MPI ranks x " << threadCount() << " threads: " << fewest << " to "
      << most << " particles each (id ranges of the Morton order), " << all_ghosts << " ghosts, " << all_cut / 2
      << " bonds cut (computed on both ranks)\n";
    return s.str();
}

void throwTogether(Comm& comm, const std::exception_ptr& error) {
    if (comm.size() == 1 || comm.rank() == 0) {
        comm.noteAgreedFailure();
        std::rethrow_exception(error);
    }
    throw PeerFailure{exitCodeOf(error), 0};
}

std::string reportRankedInstability(Domain& domain, const fs::path& out, const CheckpointMeta& meta, double dt_critical,
                                    Model& local, Effects& effects, StateSnapshot& last_good,
                                    const GlobalPairs& last_good_pairs, WholeModel& whole, long particle) {
    gatherWhole(domain, local, effects, whole);
    ContactList active;
    if (effects.contact) {
        active = gatherActivePairs(domain, local, effects.contact->list);
    }
    // The last good state: the snapshot's own stores (taken on this rank's layout of the time) gathered.
    StateSnapshot good;
    good.step = last_good.step;
    good.time = last_good.time;
    if (last_good.step >= 0) {
        Model then;
        last_good.complete(local);
        then.particles = last_good.particles;
        then.bonds = last_good.bonds;
        then.part = local.part;
        gatherStores(domain, then, good.particles, good.bonds);
        if (last_good.contacts) {
            ContactList springs;
            springs.restore(gatherContactHistory(domain, then, *last_good.contacts, last_good_pairs));
            good.contacts = std::move(springs);
        }
        good.indenter = last_good.indenter;
    }
    if (domain.comm->rank() != 0) {
        return {};
    }
    if (whole.effects.contact) {
        whole.effects.contact->list = std::move(active);
    }
    return reportInstability(out, meta, dt_critical, whole.model, whole.effects, good, particle);
}

double peakRssMiB() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return static_cast<double>(usage.ru_maxrss) / 1024.0; // ru_maxrss is in KiB on Linux
}

} // namespace vitrum
