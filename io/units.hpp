// Unit names a scene may declare and their factors into vitrum's internal units (kernels/views.hpp: µm, GPa,
// mN, ns; velocity µm/ns = km/s). Shared by the scene reader and the writers that label outputs.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace vitrum {

enum class Quantity { Length, Stress, Force, Time };

/// Internal value = file value × factor. Throws std::invalid_argument naming the accepted units.
double unitFactor(Quantity quantity, std::string_view unit);
/// The accepted unit names, in the order messages list them ("m, mm, um, nm").
std::vector<std::string> unitNames(Quantity quantity);

/// Factors into µm, GPa, mN and ns.
inline double lengthFactor(const std::string& unit) {
    return unitFactor(Quantity::Length, unit);
}
inline double stressFactor(const std::string& unit) {
    return unitFactor(Quantity::Stress, unit);
}
inline double forceFactor(const std::string& unit) {
    return unitFactor(Quantity::Force, unit);
}
inline double timeFactor(const std::string& unit) {
    return unitFactor(Quantity::Time, unit);
}
/// Velocity is length/time (→ µm/ns = km/s).
inline double velocityFactor(const std::string& length_unit, const std::string& time_unit) {
    return lengthFactor(length_unit) / timeFactor(time_unit);
}

/// value × factor, rounded once: every factor is a power of ten, so one below 1 is applied as a division by
/// its exact integer reciprocal (100 nm → exactly 0.1 µm, not 100 × 1.0000000000000000208e-3).
double toInternal(double value, double factor);
/// Inverse of toInternal, also rounded once. toInternal(fromInternal(x, f), f) == x for every x that came
/// from toInternal (checked on 10⁶ random values per factor) and for round numbers such as the scene
/// defaults; an arbitrary double may be an ulp off, as not every double is (file value) × factor.
double fromInternal(double internal, double factor);

} // namespace vitrum
