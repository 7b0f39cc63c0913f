// The one home of MPI in vitrum (issue 27): every MPI call of the code base is in comm.cpp. A run started by an
// MPI launcher (mpirun, mpiexec) in a build with MPI (CMake VITRUM_MPI) runs on the world communicator's ranks;
// anything else is one process and none of this calls MPI. The rest of the code sees ranks, byte buffers and
// the collective operations below, never an MPI type. MPI is called from the thread that runs the step,
// outside OpenMP regions (MPI_THREAD_FUNNELED).
//
// Determinism: no floating-point sum goes through MPI (MPI_Reduce's order is unspecified); sums use the fixed
// tree of kernels/parallel.hpp, for which this class is the all-gather (ReduceExchange). Max, min and integer
// sums are exact in any order and use allReduce.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <exception>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "kernels/parallel.hpp"

namespace vitrum {

class Comm final : public ReduceExchange {
public:
    /// The process's communicator: MPI_COMM_WORLD, initialised on first use when the process was started by an
    /// MPI launcher and the build has MPI; else a one-rank stand-in that calls no MPI.
    static Comm& world();
    /// Whether this build can run on several ranks (CMake VITRUM_MPI found an MPI library).
    static bool built();

    int rank() const { return rank_; }
    int size() const { return size_; }
    /// True when MPI is initialised (a launcher started this process, even on one rank).
    bool active() const { return active_; }

    /// Every rank's bytes concatenated in rank order (collective).
    std::vector<std::byte> allGather(std::span<const std::byte> mine) const override;
    std::vector<std::byte> allGatherEqual(std::span<const std::byte> mine) const override;
    /// Every rank's bytes concatenated in rank order on `root`, empty elsewhere (collective).
    std::vector<std::byte> gather(std::span<const std::byte> mine, int root = 0) const;
    /// Every rank's bytes handed to `take(rank, bytes)` on rank 0, one rank after the other in rank order
    /// (collective): rank 0 holds one rank's bytes at a time, not all of them.
    void gatherEach(std::span<const std::byte> mine,
                    const std::function<void(int, std::span<const std::byte>)>& take) const;
    /// `bytes` of `root` on every rank (collective; the size travels too).
    void broadcast(std::vector<std::byte>& bytes, int root = 0) const;
    /// Sends send[k] to peers[k] and receives recv[k] from peers[k] (sizes known on both sides; collective
    /// among the peers; a rank may be its own peer only with empty buffers).
    void exchange(const std::vector<int>& peers, const std::vector<std::span<const std::byte>>& send,
                  const std::vector<std::span<std::byte>>& recv) const;
    /// Variable sizes to every rank: out[q] goes to rank q; returns what each rank sent here (collective).
    std::vector<std::vector<std::byte>> allToAll(const std::vector<std::vector<std::byte>>& out) const;

    double maxOf(double value) const;
    long long maxOf(long long value) const;
    long long minOf(long long value) const;
    /// Exact integer sum (collective).
    long long sumOf(long long value) const;
    void barrier() const;
    /// Ends every rank of the run with `code` (MPI_Abort); on one process, std::exit(code).
    [[noreturn]] void abort(int code) const;
    /// MPI_Finalize (idempotent); call once before a normal exit.
    void finalize();
    /// Marks this rank's failure as one every rank knows of (agreed, throwTogether): it may finalize instead
    /// of aborting the others, which are ending too.
    void noteAgreedFailure() { agreed_failure_ = true; }
    bool failureAgreed() const { return agreed_failure_; }

    Comm(const Comm&) = delete;
    Comm& operator=(const Comm&) = delete;
    ~Comm() override = default;

private:
    Comm();
    int rank_ = 0;
    int size_ = 1;
    bool active_ = false;
    bool agreed_failure_ = false;
};

/// Thrown on the ranks that did not fail when another did (agreed): ends them quietly with the exit code of the
/// rank that failed, whose own exception carries the message (printed once).
struct PeerFailure {
    int code = 1;
    int rank = 0;
};

/// The exit code of an exception: 2 for bad input (InputError), 1 for anything else.
int exitCodeOf(const std::exception_ptr& error);

/// Runs `body` on every rank and agrees on its outcome (collective): if it threw on some ranks, the lowest of
/// them rethrows its exception and every other rank throws PeerFailure with that rank's exit code, so a
/// failure anywhere ends the run everywhere, with one message, instead of leaving the others waiting in the
/// next collective. `body` itself must make no collective call that a failing rank could skip.
template <class Body>
void agreed(Comm& comm, Body&& body) {
    std::exception_ptr error;
    try {
        body();
    } catch (...) {
        error = std::current_exception();
    }
    if (comm.size() == 1) {
        if (error) std::rethrow_exception(error);
        return;
    }
    const long long failing = comm.minOf(error ? comm.rank() : comm.size());
    if (failing == comm.size()) {
        return;
    }
    const long long code = comm.maxOf(error && failing == comm.rank() ? static_cast<long long>(exitCodeOf(error)) : 0LL);
    if (failing == comm.rank()) {
        comm.noteAgreedFailure();
        std::rethrow_exception(error);
    }
    throw PeerFailure{static_cast<int>(code), static_cast<int>(failing)};
}

/// Byte views of a vector of plain values (what travels in a message).
template <class T>
std::span<const std::byte> bytesOf(const std::vector<T>& v) {
    return std::as_bytes(std::span<const T>(v.data(), v.size()));
}
template <class T>
std::span<std::byte> writableBytesOf(std::vector<T>& v) {
    return std::as_writable_bytes(std::span<T>(v.data(), v.size()));
}
/// A vector of T from bytes (a whole number of values).
template <class T>
std::vector<T> valuesOf(std::span<const std::byte> bytes) {
    std::vector<T> v(bytes.size() / sizeof(T));
    if (!v.empty()) {
        std::memcpy(static_cast<void*>(v.data()), bytes.data(), v.size() * sizeof(T));
    }
    return v;
}

} // namespace vitrum
