// The one field descriptor every writer takes (STYLE.md rule 9): a name and a non-owning view.
#pragma once

#include <string>

namespace vitrum {

/// A named, read-only view of n x components doubles, component-interleaved (x0 y0 z0 x1 y1 z1 ...).
/// The name is what appears in the output file, so it should carry its unit where one applies
/// (e.g. "displacement_um"). The view never owns the data: writers read it and forget it.
struct FieldView {
    std::string name;
    int components;
    const double* data;
};

} // namespace vitrum
