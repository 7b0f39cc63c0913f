// The replay driver: a main for a fuzz target's LLVMFuzzerTestOneInput where libFuzzer is not available (the
// gcc build of `make test`). It runs every file of the directories (or files) named on the command line through
// the target, then a deterministic mutation loop (fixed seed: the same inputs every run) over them, so a reader
// that starts crashing on a committed seed, a regression input or a near mutation of one fails ctest.
//   fuzz_X_replay [--mutations N] [--seed S] [--max-len L] [--report-slow MS] PATH...
// A finding aborts (fuzz_support.hpp); the input being run is written to replay-crash-<pid>.bin in the working
// directory first, and its origin printed, so it can be committed under tests/fuzz/regressions/<target>/.
#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

namespace fs = std::filesystem;

// What is running, for the crash handler (async-signal-safe: plain buffers only).
const std::uint8_t* g_data = nullptr;
std::size_t g_size = 0;
char g_origin[512] = "";

void onCrash(int signal) {
    char name[64];
    std::snprintf(name, sizeof name, "replay-crash-%d.bin", static_cast<int>(::getpid()));
    const int fd = ::open(name, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
        if (g_size > 0 && ::write(fd, g_data, g_size) < 0) {
        }
        ::close(fd);
    }
    const char* what = "\nreplay: crashed on input ";
    if (::write(STDERR_FILENO, what, std::strlen(what)) < 0 || ::write(STDERR_FILENO, g_origin, std::strlen(g_origin)) < 0 ||
        ::write(STDERR_FILENO, "; saved as ", 11) < 0 || ::write(STDERR_FILENO, name, std::strlen(name)) < 0 ||
        ::write(STDERR_FILENO, "\n", 1) < 0) {
    }
    ::signal(signal, SIG_DFL);
    ::raise(signal);
}

double g_slow_ms = -1.0; // --report-slow: inputs slower than this are named

void run(const std::vector<std::uint8_t>& input, const std::string& origin) {
    g_data = input.data();
    g_size = input.size();
    std::snprintf(g_origin, sizeof g_origin, "%s", origin.c_str());
    const auto start = std::chrono::steady_clock::now();
    LLVMFuzzerTestOneInput(input.data(), input.size());
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (g_slow_ms >= 0.0 && ms > g_slow_ms) {
        std::printf("replay: %.0f ms for %s\n", ms, origin.c_str());
    }
}

std::vector<std::uint8_t> readBytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// One libFuzzer-like mutation: flip, replace with an interesting byte, insert, erase, duplicate a span,
/// splice in a span of another input.
void mutate(std::vector<std::uint8_t>& x, const std::vector<std::vector<std::uint8_t>>& pool, std::mt19937_64& rng,
            std::size_t max_len) {
    auto below = [&rng](std::size_t n) { return n == 0 ? 0 : static_cast<std::size_t>(rng() % n); };
    static const std::uint8_t kBytes[] = {0, 1, 2, 0x7f, 0x80, 0xff, '\n', '=', '"', '[', ']', '.', ',', '-', '0', '9', 'e'};
    switch (rng() % 6) {
    case 0:
        if (!x.empty()) x[below(x.size())] ^= static_cast<std::uint8_t>(1u << below(8));
        break;
    case 1:
        if (!x.empty()) x[below(x.size())] = kBytes[below(sizeof kBytes)];
        break;
    case 2:
        x.insert(x.begin() + static_cast<std::ptrdiff_t>(below(x.size() + 1)), static_cast<std::uint8_t>(rng()));
        break;
    case 3:
        if (!x.empty()) {
            const std::size_t at = below(x.size());
            x.erase(x.begin() + static_cast<std::ptrdiff_t>(at),
                    x.begin() + static_cast<std::ptrdiff_t>(std::min(x.size(), at + 1 + below(8))));
        }
        break;
    case 4:
        if (!x.empty()) {
            const std::size_t at = below(x.size());
            const std::size_t n = std::min(x.size() - at, 1 + below(16));
            const std::vector<std::uint8_t> span(x.begin() + static_cast<std::ptrdiff_t>(at),
                                                 x.begin() + static_cast<std::ptrdiff_t>(at + n));
            x.insert(x.begin() + static_cast<std::ptrdiff_t>(below(x.size() + 1)), span.begin(), span.end());
        }
        break;
    default: {
        const std::vector<std::uint8_t>& other = pool[below(pool.size())];
        if (!other.empty()) {
            const std::size_t at = below(other.size());
            const std::size_t n = std::min(other.size() - at, 1 + below(32));
            x.insert(x.begin() + static_cast<std::ptrdiff_t>(below(x.size() + 1)),
                     other.begin() + static_cast<std::ptrdiff_t>(at), other.begin() + static_cast<std::ptrdiff_t>(at + n));
        }
        break;
    }
    }
    if (x.size() > max_len) x.resize(max_len);
}

} // namespace

int main(int argc, char** argv) {
    long mutations = 0;
    std::uint64_t seed = 1;
    std::size_t max_len = 4096;
    std::vector<fs::path> paths;
    for (int k = 1; k < argc; ++k) {
        const std::string arg = argv[k];
        if (arg == "--mutations" && k + 1 < argc) {
            mutations = std::atol(argv[++k]);
        } else if (arg == "--seed" && k + 1 < argc) {
            seed = std::strtoull(argv[++k], nullptr, 10);
        } else if (arg == "--report-slow" && k + 1 < argc) {
            g_slow_ms = std::atof(argv[++k]);
        } else if (arg == "--max-len" && k + 1 < argc) {
            max_len = std::strtoull(argv[++k], nullptr, 10);
        } else {
            paths.emplace_back(arg);
        }
    }
    for (const int s : {SIGSEGV, SIGABRT, SIGBUS, SIGFPE, SIGILL}) {
        ::signal(s, onCrash);
    }
    const auto start = std::chrono::steady_clock::now();
    std::vector<std::vector<std::uint8_t>> pool;
    std::vector<std::string> names;
    for (const fs::path& p : paths) {
        std::vector<fs::path> files;
        if (fs::is_directory(p)) {
            for (const fs::directory_entry& e : fs::directory_iterator(p)) {
                if (e.is_regular_file() && e.path().filename() != "README.md") files.push_back(e.path());
            }
        } else if (fs::is_regular_file(p)) {
            files.push_back(p);
        }
        std::sort(files.begin(), files.end()); // directory order is not stable; the mutation loop must be
        for (const fs::path& f : files) {
            pool.push_back(readBytes(f));
            names.push_back(f.string());
        }
    }
    for (std::size_t k = 0; k < pool.size(); ++k) {
        run(pool[k], names[k]);
    }
    if (pool.empty()) pool.emplace_back();
    std::mt19937_64 rng(seed);
    for (long m = 0; m < mutations; ++m) {
        const std::size_t from = static_cast<std::size_t>(rng() % pool.size());
        std::vector<std::uint8_t> x = pool[from];
        const int edits = 1 + static_cast<int>(rng() % 4);
        for (int e = 0; e < edits; ++e) mutate(x, pool, rng, max_len);
        run(x, "mutation " + std::to_string(m) + " (seed " + std::to_string(seed) + ") of " +
                   (from < names.size() ? names[from] : std::string("the empty input")));
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("replay: %zu inputs and %ld mutations, no finding (%.1f s)\n", names.size(), mutations, seconds);
    return 0;
}
