// Rows of the stores as they travel between ranks and are cut out of the whole sample: every field of a
// store's table (forEachField) at once, so a new field travels without new code. Internal to solver/parallel.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <vector>

#include "solver/model/field.hpp"

namespace vitrum::rows {

/// Pointers to every field of a store, in its table's order.
template <class Store>
std::vector<const void*> fieldAddresses(const Store& s) {
    std::vector<const void*> out;
    forEachField(s, [&](const Field&, const auto& member) { out.push_back(&member); });
    return out;
}

/// The rows `rows` of a field of `components` values per row (an empty field stays empty: an effect that is
/// not there).
template <class V>
void copyRows(const V& from, V& to, const std::vector<std::int64_t>& rows, std::size_t components) {
    to.clear();
    if (from.empty()) {
        return;
    }
    to.resize(rows.size() * components);
    for (std::size_t r = 0; r < rows.size(); ++r) {
        const auto g = static_cast<std::size_t>(rows[r]);
        std::copy(from.begin() + static_cast<long>(g * components), from.begin() + static_cast<long>((g + 1) * components),
                  to.begin() + static_cast<long>(r * components));
    }
}

/// Every field of `to` = the rows of `from`'s (the same store type, so the same table).
template <class Store>
void copyStoreRows(const Store& from, Store& to, const std::vector<std::int64_t>& rows) {
    const std::vector<const void*> source = fieldAddresses(from);
    std::size_t k = 0;
    forEachField(to, [&](const Field& f, auto& member) {
        using V = std::remove_reference_t<decltype(member)>;
        copyRows(*static_cast<const V*>(source[k++]), member, rows, static_cast<std::size_t>(f.components));
    });
}

/// Appends every field of `rows` rows of a store to `bytes`: per field its value count, then the values.
template <class Store>
void packRows(const Store& store, std::size_t first, std::size_t count, std::vector<std::byte>& bytes) {
    forEachField(store, [&](const Field& f, const auto& member) {
        using T = typename std::remove_reference_t<decltype(member)>::value_type;
        const std::size_t c = static_cast<std::size_t>(f.components);
        const std::int64_t values = member.empty() ? 0 : static_cast<std::int64_t>(count * c);
        const std::size_t at = bytes.size();
        bytes.resize(at + sizeof(values) + static_cast<std::size_t>(values) * sizeof(T));
        std::memcpy(bytes.data() + at, &values, sizeof(values));
        if (values > 0) {
            std::memcpy(bytes.data() + at + sizeof(values), member.data() + first * c,
                        static_cast<std::size_t>(values) * sizeof(T));
        }
    });
}

/// Reads one rank's packRows record from `at`, appending each field's values.
template <class Store>
const std::byte* unpackRows(Store& store, const std::byte* at) {
    forEachField(store, [&](const Field&, auto& member) {
        using T = typename std::remove_reference_t<decltype(member)>::value_type;
        std::int64_t values = 0;
        std::memcpy(&values, at, sizeof(values));
        at += sizeof(values);
        const std::size_t old = member.size();
        member.resize(old + static_cast<std::size_t>(values));
        if (values > 0) {
            std::memcpy(member.data() + old, at, static_cast<std::size_t>(values) * sizeof(T));
        }
        at += static_cast<std::size_t>(values) * sizeof(T);
    });
    return at;
}

/// Appends the fields of the rows `rows` (any order) of a store to `bytes`, in packRows' format.
template <class Store>
void packSelectedRows(const Store& store, const std::vector<std::int32_t>& rows, std::vector<std::byte>& bytes) {
    forEachField(store, [&](const Field& f, const auto& member) {
        using T = typename std::remove_reference_t<decltype(member)>::value_type;
        const std::size_t c = static_cast<std::size_t>(f.components);
        const std::int64_t values = member.empty() ? 0 : static_cast<std::int64_t>(rows.size() * c);
        const std::size_t at = bytes.size();
        bytes.resize(at + sizeof(values) + static_cast<std::size_t>(values) * sizeof(T));
        std::memcpy(bytes.data() + at, &values, sizeof(values));
        if (values > 0) {
            std::byte* w = bytes.data() + at + sizeof(values);
            for (std::int32_t r : rows) {
                std::memcpy(w, member.data() + static_cast<std::size_t>(r) * c, c * sizeof(T));
                w += c * sizeof(T);
            }
        }
    });
}

} // namespace vitrum::rows
