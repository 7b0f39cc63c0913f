#include "fuzz_support.hpp"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <streambuf>
#include <system_error>
#include <typeinfo>

#include "io/scene_reader.hpp"
#include "kernels/parallel.hpp"
#include "solver/errors.hpp"

namespace vitrum::fuzz {

namespace fs = std::filesystem;

void finding(std::string_view target, const std::string& what) {
    std::fprintf(stderr, "FUZZ FINDING [%.*s]: %s\n", static_cast<int>(target.size()), target.data(), what.c_str());
    std::fflush(stderr);
    std::abort();
}

void expectAcceptedOrInputError(std::string_view target, const std::function<void()>& body) {
    static const bool verbose = std::getenv("VITRUM_FUZZ_VERBOSE") != nullptr; // what each input gets
    try {
        body();
        if (verbose) std::fprintf(stderr, "[%.*s] accepted\n", static_cast<int>(target.size()), target.data());
    } catch (const InputError& e) {
        if (std::string_view(e.what()).empty()) {
            finding(target, "InputError without a message");
        }
        if (verbose) std::fprintf(stderr, "[%.*s] refused: %s\n", static_cast<int>(target.size()), target.data(), e.what());
    } catch (const std::exception& e) {
        finding(target, std::string("exception other than InputError (") + typeid(e).name() + "): " + e.what());
    } catch (...) {
        finding(target, "exception that is not a std::exception");
    }
}

void expectResolvedRoundTrip(std::string_view target, const Scene& scene, const std::string& source) {
    const std::string resolved = resolvedSceneToml(scene);
    try {
        const std::string again = resolvedSceneToml(parseScene(resolved, source));
        if (again != resolved) {
            finding(target, "the resolved scene does not read back to itself:\n" + resolved + "\n--- read back ---\n" + again);
        }
    } catch (const std::exception& e) {
        finding(target, std::string("the resolved scene is refused: ") + e.what() + "\n" + resolved);
    }
}

namespace {

struct Scratch {
    std::string path;
    Scratch() {
        const fs::path base = fs::is_directory("/dev/shm") ? fs::path("/dev/shm") : fs::temp_directory_path();
        std::string pattern = (base / "vitrum-fuzz-XXXXXX").string();
        if (::mkdtemp(pattern.data()) == nullptr) {
            std::fprintf(stderr, "fuzz: cannot make a scratch directory under %s\n", base.c_str());
            std::abort();
        }
        path = pattern;
    }
    ~Scratch() {
        std::error_code ignored;
        fs::remove_all(path, ignored);
    }
};

class NullBuffer : public std::streambuf {
protected:
    int overflow(int c) override { return c == traits_type::eof() ? 0 : c; }
    std::streamsize xsputn(const char*, std::streamsize n) override { return n; }
};

NullBuffer g_null;

/// One thread: the inputs are tiny, and idle OpenMP threads spinning between the kernels of a shared machine
/// make each input take seconds instead of milliseconds.
const bool g_one_thread = [] {
    setThreadCount(1);
    return true;
}();

} // namespace

const std::string& scratchDir() {
    static const Scratch scratch;
    return scratch.path;
}

void writeFile(const std::string& path, std::string_view bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (!out) {
        finding("support", "cannot write the scratch file " + path);
    }
}

std::vector<std::string> split(std::string_view text, std::string_view separator, std::size_t max_parts) {
    std::vector<std::string> parts;
    while (parts.size() + 1 < max_parts) {
        const std::size_t at = text.find(separator);
        if (at == std::string_view::npos) {
            break;
        }
        parts.emplace_back(text.substr(0, at));
        text.remove_prefix(at + separator.size());
    }
    parts.emplace_back(text);
    return parts;
}

QuietStreams::QuietStreams() : out_(std::cout.rdbuf(&g_null)), err_(std::cerr.rdbuf(&g_null)) {}

QuietStreams::~QuietStreams() {
    std::cout.rdbuf(out_);
    std::cerr.rdbuf(err_);
}

std::string sourceDir() { return VITRUM_SOURCE_DIR; }

} // namespace vitrum::fuzz
