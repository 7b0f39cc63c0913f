#include "app/pack_command.hpp"

#include <filesystem>
#include <iostream>
#include <stdexcept>

#include "io/atomic_file.hpp"
#include "io/packing_io.hpp"
#include "kernels/parallel.hpp"
#include "solver/errors.hpp"

namespace vitrum {

int packCommand(const PackOptions& o) {
    setThreadCount(o.threads);
    Packing packing;
    try {
        packing = packRandom(o.params);
    } catch (const std::invalid_argument& e) {
        throw InputError(std::string("vitrum pack: ") + e.what());
    }
    if (std::filesystem::path(o.output).has_parent_path()) {
        std::filesystem::create_directories(std::filesystem::path(o.output).parent_path());
    }
    savePacking(o.output, packing);
    std::cout << formatPackingReport(packing.report) << "wrote " << o.output << " (" << threadCount()
              << " threads)\n";
    if (!o.json.empty()) {
        nlohmann::ordered_json j;
        j["params"] = packingParamsJson(packing.params);
        j["report"] = packingReportJson(packing.report);
        writeFileAtomically(o.json, j.dump(2) + "\n");
    }
    return 0;
}

} // namespace vitrum
