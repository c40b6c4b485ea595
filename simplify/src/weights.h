// The data term of the vertex weight (the curvature term lives with the mesh, which knows angles).
#pragma once

#include "working_mesh.h"

#include <string>
#include <utility>
#include <vector>

namespace ddsimp::detail {

// grad(v) = max over neighbours v_i of ||f_i - f||_1 / ||x_i - x||_1 with every field component
// divided by its field's range and lengths by the bounding-box diagonal.
struct GradientTerms {
    std::vector<std::pair<uint32_t, float>> components; // (offset in a vertex's data, 1 / range)
    double inv_diagonal = 0;

    // Throws InputError for a field name the surface does not have.
    void setup(const Surface& surface, const std::vector<std::string>& fields);
    double at(const WorkingMesh& mesh, uint32_t v) const;
};

} // namespace ddsimp::detail
