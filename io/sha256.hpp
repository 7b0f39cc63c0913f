// SHA-256 (FIPS 180-4), for provenance: hashes of scene files, golden data and checkpoints.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace vitrum {

/// Incremental SHA-256. hexDigest() finishes a copy of the state, so it may be called at any point and
/// update() may go on afterwards (the digest then covers everything fed so far).
class Sha256 {
public:
    Sha256();
    void update(const void* data, std::size_t bytes);
    void update(std::string_view text) { update(text.data(), text.size()); }
    /// 64 lowercase hex characters.
    std::string hexDigest() const;

private:
    void compress(const std::uint8_t* block);

    std::array<std::uint32_t, 8> state_;
    std::array<std::uint8_t, 64> buffer_{};
    std::size_t buffered_ = 0;
    std::uint64_t total_bytes_ = 0;
};

} // namespace vitrum
