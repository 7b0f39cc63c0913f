#include "solver/halo/comm.hpp"

#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <type_traits>

#include "solver/errors.hpp"

#ifdef VITRUM_HAVE_MPI
#include <mpi.h>
#endif

namespace vitrum {

namespace {

#ifdef VITRUM_HAVE_MPI
/// Whether an MPI launcher started this process (Open MPI, PMIx, MPICH/Hydra set these): only then is MPI
/// initialised, so a plain `vitrum run` never touches MPI (no singleton start-up, same as a build without it).
bool launchedByMpi() {
    for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE", "PMI_RANK"}) {
        if (std::getenv(name) != nullptr) {
            return true;
        }
    }
    return false;
}

void check(int code, const char* what) {
    if (code != MPI_SUCCESS) {
        char text[MPI_MAX_ERROR_STRING];
        int length = 0;
        MPI_Error_string(code, text, &length);
        throw std::runtime_error(std::string(what) + ": " + std::string(text, static_cast<std::size_t>(length)));
    }
}

/// Counts and displacements in bytes for the v-collectives (int: MPI's count type; each message < 2 GiB).
std::vector<int> displacements(const std::vector<int>& counts) {
    std::vector<int> d(counts.size(), 0);
    for (std::size_t k = 1; k < counts.size(); ++k) {
        d[k] = d[k - 1] + counts[k - 1];
    }
    return d;
}

int byteCount(std::size_t n) {
    if (n > static_cast<std::size_t>(2147483647)) {
        throw std::runtime_error("MPI message of " + std::to_string(n) + " bytes exceeds 2 GiB");
    }
    return static_cast<int>(n);
}
#endif

} // namespace

int exitCodeOf(const std::exception_ptr& error) {
    try {
        std::rethrow_exception(error);
    } catch (const InputError&) {
        return 2;
    } catch (const PeerFailure& f) {
        return f.code;
    } catch (...) {
        return 1;
    }
}

bool Comm::built() {
#ifdef VITRUM_HAVE_MPI
    return true;
#else
    return false;
#endif
}

Comm::Comm() {
#ifdef VITRUM_HAVE_MPI
    if (launchedByMpi()) {
        int provided = 0;
        check(MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
        MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
        MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
        MPI_Comm_size(MPI_COMM_WORLD, &size_);
        active_ = true;
    }
#endif
}

Comm& Comm::world() {
    static Comm comm;
    return comm;
}

std::vector<std::byte> Comm::allGather(std::span<const std::byte> mine) const {
    if (!active_) {
        return {mine.begin(), mine.end()};
    }
#ifdef VITRUM_HAVE_MPI
    const int count = byteCount(mine.size());
    std::vector<int> counts(static_cast<std::size_t>(size_));
    check(MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD), "MPI_Allgather");
    const std::vector<int> at = displacements(counts);
    std::vector<std::byte> all(static_cast<std::size_t>(at.back()) + static_cast<std::size_t>(counts.back()));
    check(MPI_Allgatherv(mine.data(), count, MPI_BYTE, all.data(), counts.data(), at.data(), MPI_BYTE, MPI_COMM_WORLD),
          "MPI_Allgatherv");
    return all;
#else
    return {};
#endif
}

std::vector<std::byte> Comm::allGatherEqual(std::span<const std::byte> mine) const {
    if (!active_) {
        return {mine.begin(), mine.end()};
    }
#ifdef VITRUM_HAVE_MPI
    const int count = byteCount(mine.size());
    std::vector<std::byte> all(mine.size() * static_cast<std::size_t>(size_));
    check(MPI_Allgather(mine.data(), count, MPI_BYTE, all.data(), count, MPI_BYTE, MPI_COMM_WORLD), "MPI_Allgather");
    return all;
#else
    return {};
#endif
}

std::vector<std::byte> Comm::gather(std::span<const std::byte> mine, int root) const {
    (void)root;
    if (!active_) {
        return {mine.begin(), mine.end()};
    }
#ifdef VITRUM_HAVE_MPI
    const int count = byteCount(mine.size());
    std::vector<int> counts(static_cast<std::size_t>(size_));
    check(MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, root, MPI_COMM_WORLD), "MPI_Gather");
    std::vector<std::byte> all;
    std::vector<int> at;
    if (rank_ == root) {
        at = displacements(counts);
        std::size_t total = 0;
        for (int c : counts) total += static_cast<std::size_t>(c);
        byteCount(total);
        all.resize(total);
    }
    check(MPI_Gatherv(mine.data(), count, MPI_BYTE, all.data(), counts.data(), at.data(), MPI_BYTE, root,
                      MPI_COMM_WORLD),
          "MPI_Gatherv");
    return all;
#else
    return {};
#endif
}

void Comm::gatherEach(std::span<const std::byte> mine,
                      const std::function<void(int, std::span<const std::byte>)>& take) const {
    if (!active_ || size_ == 1) {
        take(0, mine);
        return;
    }
#ifdef VITRUM_HAVE_MPI
    if (rank_ != 0) {
        long long size = static_cast<long long>(mine.size());
        check(MPI_Send(&size, 1, MPI_LONG_LONG, 0, 28, MPI_COMM_WORLD), "MPI_Send");
        check(MPI_Send(mine.data(), byteCount(mine.size()), MPI_BYTE, 0, 29, MPI_COMM_WORLD), "MPI_Send");
        return;
    }
    take(0, mine);
    std::vector<std::byte> buffer;
    for (int r = 1; r < size_; ++r) {
        long long size = 0;
        check(MPI_Recv(&size, 1, MPI_LONG_LONG, r, 28, MPI_COMM_WORLD, MPI_STATUS_IGNORE), "MPI_Recv");
        buffer.resize(static_cast<std::size_t>(size));
        check(MPI_Recv(buffer.data(), byteCount(buffer.size()), MPI_BYTE, r, 29, MPI_COMM_WORLD, MPI_STATUS_IGNORE),
              "MPI_Recv");
        take(r, buffer);
    }
#endif
}

void Comm::broadcast(std::vector<std::byte>& bytes, int root) const {
    (void)bytes;
    (void)root;
    if (!active_) {
        return;
    }
#ifdef VITRUM_HAVE_MPI
    long long size = static_cast<long long>(bytes.size());
    check(MPI_Bcast(&size, 1, MPI_LONG_LONG, root, MPI_COMM_WORLD), "MPI_Bcast");
    bytes.resize(static_cast<std::size_t>(size));
    check(MPI_Bcast(bytes.data(), byteCount(bytes.size()), MPI_BYTE, root, MPI_COMM_WORLD), "MPI_Bcast");
#endif
}

void Comm::exchange(const std::vector<int>& peers, const std::vector<std::span<const std::byte>>& send,
                    const std::vector<std::span<std::byte>>& recv) const {
    (void)peers;
    (void)send;
    (void)recv;
    if (!active_) {
        return;
    }
#ifdef VITRUM_HAVE_MPI
    std::vector<MPI_Request> requests;
    requests.reserve(2 * peers.size());
    for (std::size_t k = 0; k < peers.size(); ++k) {
        if (!recv[k].empty()) {
            MPI_Request r;
            check(MPI_Irecv(recv[k].data(), byteCount(recv[k].size()), MPI_BYTE, peers[k], 27, MPI_COMM_WORLD, &r),
                  "MPI_Irecv");
            requests.push_back(r);
        }
    }
    for (std::size_t k = 0; k < peers.size(); ++k) {
        if (!send[k].empty()) {
            MPI_Request r;
            check(MPI_Isend(send[k].data(), byteCount(send[k].size()), MPI_BYTE, peers[k], 27, MPI_COMM_WORLD, &r),
                  "MPI_Isend");
            requests.push_back(r);
        }
    }
    check(MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE), "MPI_Waitall");
#endif
}

std::vector<std::vector<std::byte>> Comm::allToAll(const std::vector<std::vector<std::byte>>& out) const {
    if (!active_) {
        return out;
    }
#ifdef VITRUM_HAVE_MPI
    const auto n = static_cast<std::size_t>(size_);
    std::vector<int> send_counts(n), recv_counts(n);
    for (std::size_t q = 0; q < n; ++q) {
        send_counts[q] = byteCount(out[q].size());
    }
    check(MPI_Alltoall(send_counts.data(), 1, MPI_INT, recv_counts.data(), 1, MPI_INT, MPI_COMM_WORLD), "MPI_Alltoall");
    const std::vector<int> send_at = displacements(send_counts), recv_at = displacements(recv_counts);
    std::vector<std::byte> packed(static_cast<std::size_t>(send_at.back()) + static_cast<std::size_t>(send_counts.back()));
    for (std::size_t q = 0; q < n; ++q) {
        if (!out[q].empty()) {
            std::memcpy(packed.data() + send_at[q], out[q].data(), out[q].size());
        }
    }
    std::vector<std::byte> unpacked(static_cast<std::size_t>(recv_at.back()) + static_cast<std::size_t>(recv_counts.back()));
    check(MPI_Alltoallv(packed.data(), send_counts.data(), send_at.data(), MPI_BYTE, unpacked.data(),
                        recv_counts.data(), recv_at.data(), MPI_BYTE, MPI_COMM_WORLD),
          "MPI_Alltoallv");
    std::vector<std::vector<std::byte>> in(n);
    for (std::size_t q = 0; q < n; ++q) {
        in[q].assign(unpacked.begin() + recv_at[q], unpacked.begin() + recv_at[q] + recv_counts[q]);
    }
    return in;
#else
    return out;
#endif
}

namespace {
enum class Reduction { Max, Min, Sum };

/// One value reduced over every rank when the run has ranks (collective), else the value itself.
template <class T> T allReduce(bool active, T value, Reduction op) {
#ifdef VITRUM_HAVE_MPI
    if (active) {
        const MPI_Op mpi_op = op == Reduction::Max ? MPI_MAX : op == Reduction::Min ? MPI_MIN : MPI_SUM;
        const MPI_Datatype type = std::is_same_v<T, double> ? MPI_DOUBLE : MPI_LONG_LONG;
        check(MPI_Allreduce(MPI_IN_PLACE, &value, 1, type, mpi_op, MPI_COMM_WORLD), "MPI_Allreduce");
    }
#else
    (void)active;
    (void)op;
#endif
    return value;
}
} // namespace

double Comm::maxOf(double value) const { return allReduce(active_, value, Reduction::Max); }
long long Comm::maxOf(long long value) const { return allReduce(active_, value, Reduction::Max); }
long long Comm::minOf(long long value) const { return allReduce(active_, value, Reduction::Min); }
long long Comm::sumOf(long long value) const { return allReduce(active_, value, Reduction::Sum); }

void Comm::barrier() const {
#ifdef VITRUM_HAVE_MPI
    if (active_) {
        MPI_Barrier(MPI_COMM_WORLD);
    }
#endif
}

void Comm::abort(int code) const {
#ifdef VITRUM_HAVE_MPI
    if (active_) {
        MPI_Abort(MPI_COMM_WORLD, code);
    }
#endif
    std::exit(code);
}

void Comm::finalize() {
#ifdef VITRUM_HAVE_MPI
    if (active_) {
        int done = 0;
        MPI_Finalized(&done);
        if (!done) {
            MPI_Finalize();
        }
    }
#endif
    active_ = false;
    rank_ = 0;
    size_ = 1;
}

} // namespace vitrum
