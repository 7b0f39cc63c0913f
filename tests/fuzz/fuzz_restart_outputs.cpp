// libFuzzer target for the two files a restarted run reads back from its output directory before it appends to
// them: series.csv (io/series_writer.hpp SeriesWriter::continuing: the rows before the checkpoint's step kept,
// the header checked against the run's columns) and maps.pvd (io/vtk_writer.hpp PvdCollection::continuing: the
// entries up to the checkpoint's time kept). The fuzz bytes are the two files separated by "\n--8<--\n". Each
// must be accepted (and then appended to and rewritten) or refused with InputError.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "fuzz_support.hpp"
#include "io/series_writer.hpp"
#include "io/vtk_writer.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace vitrum;
    constexpr const char* kTarget = "restart_outputs";
    static const std::string series_path = fuzz::scratchDir() + "/series.csv";
    static const std::string pvd_path = fuzz::scratchDir() + "/maps.pvd";
    const std::vector<std::string> parts =
        fuzz::split(std::string_view(reinterpret_cast<const char*>(data), size), "\n--8<--\n", 2);
    fuzz::writeFile(series_path, parts[0]);
    fuzz::writeFile(pvd_path, parts.size() > 1 ? parts[1] : std::string());
    fuzz::expectAcceptedOrInputError(kTarget, [&] {
        SeriesWriter series = SeriesWriter::continuing(series_path, {"step", "time_ns", "force_N"}, 5);
        const double row[] = {5.0, 0.5, 1e-3};
        series.row(row);
        series.flush();
    });
    fuzz::expectAcceptedOrInputError(kTarget, [&] {
        PvdCollection pvd = PvdCollection::continuing(pvd_path, 0.5);
        pvd.add(0.5, "maps/step_5.vtu");
        pvd.write();
    });
    return 0;
}
