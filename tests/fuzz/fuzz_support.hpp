// What every fuzz target shares (tests/fuzz/README.md): the contract check, the fuzz bytes read as a recipe,
// and scratch files. The contract of a reader: any input is either accepted or refused with vitrum's InputError
// carrying a message; anything else (another exception, a crash, a hang, a sanitizer report, an HDF5 object left
// open) is a finding. A finding prints "FUZZ FINDING" with the target and the reason and aborts, so libFuzzer
// saves the input and the replay driver (replay_main.cpp) fails its ctest.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <string>
#include <string_view>
#include <vector>

namespace vitrum {

struct Scene;

namespace fuzz {

/// Prints "FUZZ FINDING [target]: what" to stderr and aborts.
[[noreturn]] void finding(std::string_view target, const std::string& what);

/// Runs `body` under the reader contract: returns normally when it returns or throws an InputError with a
/// non-empty message; anything else is a finding of `target`. With VITRUM_FUZZ_VERBOSE set in the environment it
/// prints what each input got (accepted, or the refusal's message).
void expectAcceptedOrInputError(std::string_view target, const std::function<void()>& body);

/// A scene the reader accepted must write a resolved scene that reads back, to the same resolved text (what a
/// restart and `vitrum measure` rely on: they read resolved_scene.toml and compare its hash); `source` is the
/// source name to read it under. Anything else is a finding of `target`.
void expectResolvedRoundTrip(std::string_view target, const Scene& scene, const std::string& source);

/// The fuzz bytes consumed front to back; past the end every read gives 0 (so any byte string is a recipe).
class FuzzBytes {
public:
    FuzzBytes(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
    bool empty() const { return at_ >= size_; }
    std::size_t left() const { return empty() ? 0 : size_ - at_; }
    std::uint8_t u8() { return empty() ? 0 : data_[at_++]; }
    std::uint16_t u16() { return static_cast<std::uint16_t>(u8() | (u8() << 8)); }
    std::uint32_t u32() { return static_cast<std::uint32_t>(u16() | (static_cast<std::uint32_t>(u16()) << 16)); }
    std::uint64_t u64() { return u32() | (static_cast<std::uint64_t>(u32()) << 32); }
    /// The rest of the bytes as text.
    std::string rest() {
        std::string out;
        if (!empty()) out.assign(reinterpret_cast<const char*>(data_ + at_), size_ - at_);
        at_ = size_;
        return out;
    }

private:
    const std::uint8_t* data_;
    std::size_t size_;
    std::size_t at_ = 0;
};

/// A scratch directory for this process, made once (under /dev/shm when it exists: tmpfs, so forged files
/// cost no disk writes), removed at exit.
const std::string& scratchDir();

/// Writes `bytes` to `path` (replacing it); a failure is a finding (the scratch directory is ours).
void writeFile(const std::string& path, std::string_view bytes);

/// Splits `text` at `separator` into at most `max_parts` parts (the last one keeps the rest).
std::vector<std::string> split(std::string_view text, std::string_view separator, std::size_t max_parts);

/// Redirects std::cout and std::cerr to nothing for its scope (the commands print their tables and logs).
class QuietStreams {
public:
    QuietStreams();
    ~QuietStreams();
    QuietStreams(const QuietStreams&) = delete;
    QuietStreams& operator=(const QuietStreams&) = delete;

private:
    std::streambuf* out_;
    std::streambuf* err_;
};

/// The source tree (examples, the committed corpora), compiled in.
std::string sourceDir();

} // namespace fuzz
} // namespace vitrum
