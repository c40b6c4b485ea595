// Faces with more than three corners, split into triangles as VTK and viewers do, and counted so
// that the reader can say what it changed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace ddsimp::io {

class PolygonSplitter {
public:
    // Appends the triangles of the face `corners[0..n)` (indices into `positions`, 3 floats per
    // point) to `triangles`, in the face's orientation: a triangle as it is, a quad along the
    // diagonal that keeps both halves facing the quad's way (the shorter one if both do), a larger
    // polygon by VTK's ear cutting (a fan where that fails). Faces with fewer than three corners
    // add nothing and are counted as dropped.
    void split(const std::vector<float>& positions, const uint32_t* corners, size_t n,
               std::vector<uint32_t>& triangles);

    // "12 quads and 3 polygons (5 to 8 corners) triangulated into 30 triangles; 2 faces with
    // fewer than 3 corners dropped", or "" when every face was a triangle.
    std::string note() const;

private:
    size_t quads_ = 0, polygons_ = 0, made_ = 0, dropped_ = 0;
    size_t most_corners_ = 0, fewest_corners_ = 0;
};

} // namespace ddsimp::io
