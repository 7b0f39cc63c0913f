// Outputs are never half-written: text files are written to "<path>.tmp" and renamed over <path>, so a reader
// (or a crash) sees either the old file or the complete new one.
#pragma once

#include <string>
#include <string_view>

namespace vitrum {

/// Writes `text` to `path` atomically; throws RuntimeFailure naming the path on failure.
void writeFileAtomically(const std::string& path, std::string_view text);

} // namespace vitrum
