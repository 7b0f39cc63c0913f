// Named particle sets defined by geometry. Selector grammar (lengths in the scene's length unit):
//   selector := clause ( "and" clause )*
//   clause   := "all" | "surface" | "dome" | "top layer" | "bottom layer" | coord op number
//   coord    := x | y | z | r (distance from the z axis) | d (distance from the origin)
//   op       := < | <= | > | >=
// "surface": centre within 1.5 radii of the shape's boundary; "top layer" / "bottom layer": centres within
// half a radius of the highest / lowest centre in z; "dome": surface particles within 1.5 radii of the
// sphere about the origin that bounds the sample (for a hemisphere, its curved face, which the paper clamps;
// the particles under the flat face are not in it).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace vitrum {

struct Particles;
struct SampleParams;

struct SelectorClause {
    enum class Kind { All, Surface, Dome, TopLayer, BottomLayer, Compare } kind = Kind::All;
    char coord = 'z';     ///< x y z r d
    std::string op = "<"; ///< < <= > >=
    double value = 0.0;   ///< in the scene's length unit
};

/// Parses a selector; throws std::invalid_argument with what was expected.
std::vector<SelectorClause> parseSelector(const std::string& text);

/// Indices of the particles matching every clause, ascending. length_factor converts clause values to µm.
std::vector<std::int32_t> selectParticles(const std::vector<SelectorClause>& clauses, const Particles& particles,
                                          double length_factor);

} // namespace vitrum
