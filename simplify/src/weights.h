// The data term of the vertex weight (the curvature term lives with the mesh, which knows angles).
#pragma once

#include "working_mesh.h"

#include <cmath>
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

    // The steepest neighbour of one vertex, fed one neighbour at a time (by a fan walk that
    // does other work too). Compares df / dx without dividing: keeps the best pair (df, dx).
    class Steepest {
    public:
        Steepest(const GradientTerms& terms, const WorkingMesh& mesh, uint32_t v)
            : terms_(terms), mesh_(mesh), f_(mesh.data_of(v)), x_(mesh.position_of(v)),
              active_(!terms.components.empty() && terms.inv_diagonal != 0) {}
        void consider(uint32_t u) {
            if (!active_) return;
            const float* fu = mesh_.data_of(u);
            const float* xu = mesh_.position_of(u);
            const float dx =
                std::abs(xu[0] - x_[0]) + std::abs(xu[1] - x_[1]) + std::abs(xu[2] - x_[2]);
            if (dx <= 0) return; // coincident points: no direction to take a gradient along
            float df = 0;
            for (const auto& [c, s] : terms_.components) df += std::abs(fu[c] - f_[c]) * s;
            if (df * best_dx_ > best_df_ * dx) best_df_ = df, best_dx_ = dx;
        }
        // The gradient term of v (the caller knows whether v is complex or dead: then 0).
        double value() const {
            return active_ ? double(best_df_) / (double(best_dx_) * terms_.inv_diagonal) : 0;
        }

    private:
        const GradientTerms& terms_;
        const WorkingMesh& mesh_;
        const float* f_;
        const float* x_;
        bool active_;
        float best_df_ = 0, best_dx_ = 1;
    };
};

} // namespace ddsimp::detail
