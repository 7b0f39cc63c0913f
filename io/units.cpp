#include "io/units.hpp"

#include <array>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace vitrum {

namespace {

struct UnitEntry {
    std::string_view name;
    double factor;
};

// Internal units: µm, GPa, mN, ns (kernels/views.hpp).
constexpr std::array<UnitEntry, 4> kLength{{{"m", 1e6}, {"mm", 1e3}, {"um", 1.0}, {"nm", 1e-3}}};
constexpr std::array<UnitEntry, 4> kStress{{{"Pa", 1e-9}, {"kPa", 1e-6}, {"MPa", 1e-3}, {"GPa", 1.0}}};
constexpr std::array<UnitEntry, 4> kForce{{{"N", 1e3}, {"mN", 1.0}, {"uN", 1e-3}, {"nN", 1e-6}}};
constexpr std::array<UnitEntry, 5> kTime{{{"s", 1e9}, {"ms", 1e6}, {"us", 1e3}, {"ns", 1.0}, {"ps", 1e-3}}};

std::pair<const UnitEntry*, const UnitEntry*> entries(Quantity quantity) {
    switch (quantity) {
    case Quantity::Length:
        return {kLength.data(), kLength.data() + kLength.size()};
    case Quantity::Stress:
        return {kStress.data(), kStress.data() + kStress.size()};
    case Quantity::Force:
        return {kForce.data(), kForce.data() + kForce.size()};
    case Quantity::Time:
        return {kTime.data(), kTime.data() + kTime.size()};
    }
    throw std::invalid_argument("unknown quantity");
}

const char* quantityName(Quantity quantity) {
    switch (quantity) {
    case Quantity::Length:
        return "length";
    case Quantity::Stress:
        return "stress";
    case Quantity::Force:
        return "force";
    case Quantity::Time:
        return "time";
    }
    return "?";
}

} // namespace

double unitFactor(Quantity quantity, std::string_view unit) {
    auto [first, last] = entries(quantity);
    for (const UnitEntry* e = first; e != last; ++e) {
        if (e->name == unit) {
            return e->factor;
        }
    }
    std::string known;
    for (const std::string& name : unitNames(quantity)) {
        known += (known.empty() ? "" : ", ") + name;
    }
    throw std::invalid_argument("unknown " + std::string(quantityName(quantity)) + " unit '" +
                                std::string(unit) + "' (known: " + known + ")");
}

std::vector<std::string> unitNames(Quantity quantity) {
    auto [first, last] = entries(quantity);
    std::vector<std::string> names;
    for (const UnitEntry* e = first; e != last; ++e) {
        names.emplace_back(e->name);
    }
    return names;
}

double toInternal(double value, double factor) {
    // Products and quotients of the table's factors (velocity = length/time) can be off by an ulp from the
    // power of ten they stand for; snapping to the exact integer restores it.
    return factor >= 1.0 ? value * std::round(factor) : value / std::round(1.0 / factor);
}

double fromInternal(double internal, double factor) {
    return factor >= 1.0 ? internal / std::round(factor) : internal * std::round(1.0 / factor);
}

} // namespace vitrum
