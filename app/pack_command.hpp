// `vitrum pack`: build a dense random packing, save it (HDF5) for scenes to reuse, print its report.
#pragma once

#include <string>

#include "solver/model/packing.hpp"

namespace vitrum {

struct PackOptions {
    PackingParams params;
    std::string output;    ///< .h5 file
    std::string json;      ///< optional report as JSON
    int threads = 0;
};

int packCommand(const PackOptions& options);

} // namespace vitrum
