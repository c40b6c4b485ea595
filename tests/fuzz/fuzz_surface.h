// Surfaces for fuzz targets: compared bit for bit (NaN equals itself), and built from fuzz bytes.
#pragma once

#include "fuzz_input.h"

#include "ddsimp/ddsimp.h"

#include <cstring>

namespace ddsimp::fuzz {

template <class T> bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() &&
           (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

inline bool same_bits(const Surface& a, const Surface& b) {
    if (!same_bits(a.positions, b.positions) || !same_bits(a.triangles, b.triangles) ||
        a.fields.size() != b.fields.size())
        return false;
    for (size_t f = 0; f < a.fields.size(); ++f)
        if (a.fields[f].name != b.fields[f].name ||
            a.fields[f].components != b.fields[f].components ||
            !same_bits(a.fields[f].values, b.fields[f].values))
            return false;
    return true;
}

// A surface of at most a few hundred vertices: counts, then indices (mostly in range, so that
// the checks after the index check are reached), positions and fields from the bytes. Shapes
// validate must reject (ragged arrays, wrong field lengths) are made on purpose now and then.
inline Surface surface_from(FuzzInput& in) {
    Surface s;
    const uint8_t shape = in.take<uint8_t>();
    const size_t vertices = in.take_below(257);
    const size_t triangles = in.take_below(513);
    const size_t fields = in.take_below(4);
    const uint8_t index_bound = in.take<uint8_t>(); // 0: any index at all
    s.triangles.resize(3 * triangles + (shape & 1));
    for (uint32_t& i : s.triangles)
        i = index_bound == 0 ? in.take<uint32_t>()
                             : uint32_t(in.take<uint8_t>() % (vertices ? vertices : index_bound));
    s.positions.resize(3 * vertices + ((shape >> 1) & 1));
    for (float& p : s.positions) {
        // Small integers mostly (coincident and collinear points), raw bits sometimes.
        const int8_t small = in.take<int8_t>();
        p = small == -128 ? in.take<float>() : float(small) / 8;
    }
    for (size_t f = 0; f < fields; ++f) {
        Field field;
        field.name = std::string(in.take_bytes(in.take_below(4)));
        field.components = int(in.take<int8_t>()) % 5;
        const size_t count =
            vertices * size_t(std::max(field.components, 0)) + ((shape >> 2) & 1) * (f == 0);
        field.values.resize(count);
        for (float& v : field.values) {
            const int8_t small = in.take<int8_t>();
            v = small == -128 ? in.take<float>() : float(small);
        }
        s.fields.push_back(std::move(field));
    }
    return s;
}

} // namespace ddsimp::fuzz
