#include "weights.h"

#include "validate.h"

#include <algorithm>
#include <cmath>
#include <set>

namespace ddsimp::detail {

void GradientTerms::setup(const Surface& s, const std::vector<std::string>& fields) {
    for (const std::string& name : fields)
        if (!s.find_field(name)) {
            std::string known;
            for (const Field& f : s.fields) known += (known.empty() ? "" : ", ") + f.name;
            throw InputError("unknown field '" + name +
                             "' (the surface has: " + (known.empty() ? "no fields" : known) + ")");
        }
    const std::vector<std::string> names = fields.empty() ? default_gradient_fields(s) : fields;
    const std::set<std::string> chosen(names.begin(), names.end());

    std::vector<uint8_t> used(s.vertex_count(), 0);
    for (uint32_t v : s.triangles) used[v] = 1;

    components.clear();
    uint32_t offset = 0;
    for (const Field& f : s.fields) {
        const size_t nc = size_t(f.components);
        if (chosen.count(f.name)) {
            double range = 0;
            for (size_t c = 0; c < nc; ++c) {
                double lo = INFINITY, hi = -INFINITY;
                for (size_t v = 0; v < used.size(); ++v)
                    if (used[v])
                        lo = std::min(lo, double(f.values[v * nc + c])),
                        hi = std::max(hi, double(f.values[v * nc + c]));
                range = std::max(range, hi - lo);
            }
            if (range > 0)
                for (size_t c = 0; c < nc; ++c)
                    components.push_back({uint32_t(offset + c), float(1.0 / range)});
        }
        offset += uint32_t(nc);
    }

    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t v = 0; v < used.size(); ++v)
        if (used[v])
            for (int a = 0; a < 3; ++a)
                lo[a] = std::min(lo[a], double(s.positions[3 * v + a])),
                hi[a] = std::max(hi[a], double(s.positions[3 * v + a]));
    const double diagonal =
        std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                  (hi[2] - lo[2]) * (hi[2] - lo[2]));
    inv_diagonal = diagonal > 0 ? 1.0 / diagonal : 0.0;
}

double GradientTerms::at(const WorkingMesh& mesh, uint32_t v) const {
    if (components.empty() || inv_diagonal == 0) return 0;
    if (mesh.kind[v] == VertexKind::Complex || mesh.kind[v] == VertexKind::Dead) return 0;
    Steepest steepest(*this, mesh, v);
    mesh.for_each_edge(v, [&](uint32_t, uint32_t other, bool) { steepest.consider(other); });
    return steepest.value();
}

} // namespace ddsimp::detail

namespace ddsimp {

namespace {
// The mesh of a repaired copy (consistent orientation), with the input's vertex numbering.
detail::WorkingMesh analysed(const Surface& input) {
    RepairReport repairs;
    Surface repaired;
    detail::Parallel one(1);
    const Surface& surface = detail::validated(input, repaired, repairs, one);
    detail::WorkingMesh mesh;
    detail::Limits limits; // features do not matter for the weights
    mesh.build(surface, surface.vertex_count(), limits);
    return mesh;
}
} // namespace

std::vector<float> vertex_curvature(const Surface& surface) {
    const detail::WorkingMesh mesh = analysed(surface);
    std::vector<float> result(surface.vertex_count());
    for (uint32_t v = 0; v < result.size(); ++v) result[v] = float(mesh.curvature(v));
    return result;
}

std::vector<float> vertex_gradient(const Surface& surface, const std::vector<std::string>& fields) {
    detail::GradientTerms terms;
    terms.setup(surface, fields);
    const detail::WorkingMesh mesh = analysed(surface);
    std::vector<float> result(surface.vertex_count());
    for (uint32_t v = 0; v < result.size(); ++v) result[v] = float(terms.at(mesh, v));
    return result;
}

} // namespace ddsimp
