#include "previews.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <cstdint>

namespace ddsimp::server {

Surface clustered_preview(const Surface& surface, size_t target) {
    std::vector<uint32_t> kept(surface.triangles.size());
    const size_t indices = meshopt_simplifySloppy(
        kept.data(), surface.triangles.data(), surface.triangles.size(), surface.positions.data(),
        surface.vertex_count(), 3 * sizeof(float), std::max<size_t>(target, 1) * 3, 1.0f, nullptr);
    kept.resize(indices);

    Surface out;
    std::vector<uint32_t> map(surface.vertex_count(), UINT32_MAX);
    for (uint32_t v : kept) {
        if (map[v] == UINT32_MAX) {
            map[v] = uint32_t(out.positions.size() / 3);
            out.positions.insert(out.positions.end(), &surface.positions[3 * size_t(v)],
                                 &surface.positions[3 * size_t(v) + 3]);
        }
    }
    for (const Field& f : surface.fields) {
        const size_t nc = size_t(f.components);
        Field g{f.name, f.components, std::vector<float>(out.vertex_count() * nc), f.kind};
        for (size_t v = 0; v < map.size(); ++v)
            if (map[v] != UINT32_MAX)
                std::copy_n(&f.values[v * nc], nc, &g.values[size_t(map[v]) * nc]);
        out.fields.push_back(std::move(g));
    }
    out.triangles.reserve(kept.size());
    for (uint32_t v : kept) out.triangles.push_back(map[v]);
    return out;
}

} // namespace ddsimp::server
