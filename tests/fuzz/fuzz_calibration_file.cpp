// libFuzzer target for the calibration file reader (io/calibration_io.hpp readCalibration, which takes a path:
// the bytes are written to a scratch file) and for withCommandSection, the edit `vitrum calibrate
// densification` makes to such a file (the result, when the edit is accepted, is read again). Each must accept
// or raise InputError.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_support.hpp"
#include "io/calibration_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace vitrum;
    static const std::string path = fuzz::scratchDir() + "/calibration.toml";
    const std::string text(reinterpret_cast<const char*>(data), size);
    fuzz::writeFile(path, text);
    fuzz::expectAcceptedOrInputError("calibration_file", [&] { (void)readCalibration(path); });
    fuzz::expectAcceptedOrInputError("calibration_file", [&] {
        const std::string section = std::string(kDensificationSectionMarker) +
                                    "\n[densification]\nyield_stress = 7.13\ntangent_modulus = 98.82\n"
                                    "max_permanent_strain = 0.067\n";
        fuzz::writeFile(path, withCommandSection(text, section, path));
        (void)readCalibration(path);
    });
    return 0;
}
