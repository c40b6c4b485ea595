// The integers of a legacy (before format 5) cell array: a count and that many point ids for each
// cell, walked to check that the array holds its cells exactly.
#pragma once

#include <array>
#include <cstdint>
#include <istream>
#include <optional>
#include <string>
#include <vector>

namespace ddsimp::io::legacy_vtk {

// The integers of one cell array, read one at a time (ASCII tokens or big-endian int32).
class IntReader {
public:
    IntReader(std::istream& in, bool binary) : in_(in), binary_(binary) {}

    std::optional<int64_t> next() {
        if (!binary_) {
            long long v = 0;
            if (!(in_ >> v)) return std::nullopt;
            return v;
        }
        std::array<unsigned char, 4> b{};
        if (!in_.read(reinterpret_cast<char*>(b.data()), 4)) return std::nullopt;
        return int32_t(uint32_t(b[0]) << 24 | uint32_t(b[1]) << 16 | uint32_t(b[2]) << 8 |
                       uint32_t(b[3]));
    }

private:
    std::istream& in_;
    bool binary_;
};

// The integers of a cell array VTK has read, one at a time, for walk_cells.
struct VectorInts {
    const std::vector<int>& values;
    size_t at = 0;
    std::optional<int64_t> next() {
        if (at == values.size()) return std::nullopt;
        return values[at++];
    }
};

// Walks the `size` integers of an array of `cells` cells, taken one at a time from `ints` (an
// IntReader or anything with next()); "" if they hold them exactly.
template <class Ints>
std::string walk_cells(Ints& ints, const std::string& keyword, int64_t cells, int64_t size) {
    const std::string what = keyword + " " + std::to_string(cells) + " " + std::to_string(size);
    int64_t at = 0;
    for (int64_t c = 0; c < cells; ++c) {
        if (at >= size) return what + ": the array ends before cell " + std::to_string(c);
        const std::optional<int64_t> count = ints.next();
        if (!count) return what + ": the file ends in cell " + std::to_string(c);
        if (*count < 0 || *count > size - at - 1)
            return what + ": cell " + std::to_string(c) + " has " + std::to_string(*count) +
                   " points, more than the array holds";
        for (int64_t i = 0; i < *count; ++i)
            if (!ints.next()) return what + ": the file ends in cell " + std::to_string(c);
        at += 1 + *count;
    }
    if (at != size)
        return what + ": the cells take " + std::to_string(at) + " of the " + std::to_string(size) +
               " numbers";
    return "";
}

} // namespace ddsimp::io::legacy_vtk
