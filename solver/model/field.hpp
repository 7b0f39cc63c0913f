// The one field descriptor (STYLE.md rule 9): a field's name, its components per element and its unit. The
// stores' field tables (forEachField in particles.hpp, bonds.hpp and the effects' headers) describe each
// member once with it; the checkpoint, the page placement and the maps all read the tables.
#pragma once

#include <string>

namespace vitrum {

struct Field {
    const char* name;  ///< as stored in the checkpoint and, with its unit, named in the maps
    int components;    ///< values per element (3: a vector, 4: a quaternion, 6: a symmetric tensor)
    const char* unit;  ///< in vitrum's internal units (kernels/views.hpp); "" for counts, flags and ratios
};

/// The name with its unit as outputs carry it: "velocity" in km/s → "velocity_km_per_s" ('/' → "_per_",
/// '*' → "_", "" → no suffix).
inline std::string labelWithUnit(const Field& field) {
    std::string unit;
    for (const char* c = field.unit; *c; ++c) {
        unit += *c == '/' ? std::string("_per_") : *c == '*' ? std::string("_") : std::string(1, *c);
    }
    return unit.empty() ? std::string(field.name) : std::string(field.name) + "_" + unit;
}

} // namespace vitrum
