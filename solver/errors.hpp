// The two failure kinds the CLI maps to exit codes: bad input (2) and runtime failure (1).
#pragma once

#include <stdexcept>
#include <string>

namespace vitrum {

/// The user's input is wrong (scene file, override, CLI). The message names the file, line, key and what
/// was expected. Exit code 2.
struct InputError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// The run failed (numerical instability, I/O failure). Exit code 1.
struct RuntimeFailure : std::runtime_error {
    using std::runtime_error::runtime_error;
};

} // namespace vitrum
