#include "pieces.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace ddsimp::mpi {

namespace {

using Centroid = std::array<double, 3>;

// Cuts `ids` (triangles) into `parts` pieces, numbered from `first`.
void bisect(std::vector<uint32_t>::iterator begin, std::vector<uint32_t>::iterator end,
            uint32_t first, uint32_t parts, const std::vector<Centroid>& centroid,
            std::vector<uint32_t>& piece_of) {
    if (parts == 1 || end - begin <= 1) {
        for (auto it = begin; it != end; ++it) piece_of[*it] = first;
        return;
    }
    Centroid lo = centroid[*begin], hi = lo;
    for (auto it = begin; it != end; ++it)
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::min(lo[k], centroid[*it][k]);
            hi[k] = std::max(hi[k], centroid[*it][k]);
        }
    int axis = 0;
    for (int k = 1; k < 3; ++k)
        if (hi[k] - lo[k] > hi[axis] - lo[axis]) axis = k;
    const uint32_t left = parts / 2;
    const auto count = size_t(end - begin);
    const auto middle = begin + std::ptrdiff_t(count * left / parts);
    std::nth_element(begin, middle, end, [&](uint32_t a, uint32_t b) {
        const double ca = centroid[a][size_t(axis)], cb = centroid[b][size_t(axis)];
        return ca < cb || (ca == cb && a < b);
    });
    bisect(begin, middle, first, left, centroid, piece_of);
    bisect(middle, end, first + left, parts - left, centroid, piece_of);
}

} // namespace

std::vector<uint32_t> bisect_triangles(const Surface& s, uint32_t parts) {
    const size_t n = s.triangle_count();
    std::vector<Centroid> centroid(n);
    for (size_t t = 0; t < n; ++t) {
        Centroid c{0, 0, 0};
        for (int i = 0; i < 3; ++i)
            for (int k = 0; k < 3; ++k) c[size_t(k)] += s.positions[3 * s.triangles[3 * t + i] + k];
        centroid[t] = c;
    }
    std::vector<uint32_t> ids(n), piece_of(n, 0);
    for (uint32_t t = 0; t < n; ++t) ids[t] = t;
    if (parts > 0) bisect(ids.begin(), ids.end(), 0, parts, centroid, piece_of);
    return piece_of;
}

std::vector<Piece> split_surface(const Surface& s, const std::vector<uint32_t>& piece_of,
                                 uint32_t parts) {
    const size_t nv = s.vertex_count(), nt = s.triangle_count();
    // The first piece that uses each vertex, and whether a second one does.
    std::vector<uint32_t> owner(nv, kNoId);
    std::vector<uint8_t> shared(nv, 0);
    for (size_t t = 0; t < nt; ++t)
        for (int i = 0; i < 3; ++i) {
            const uint32_t v = s.triangles[3 * t + i];
            if (owner[v] == kNoId)
                owner[v] = piece_of[t];
            else if (owner[v] != piece_of[t])
                shared[v] = 1;
        }

    std::vector<Piece> pieces(parts);
    std::vector<uint32_t> local(nv);
    std::vector<uint8_t> used(nv), near(nv);
    for (uint32_t p = 0; p < parts; ++p) {
        Piece& piece = pieces[p];
        std::fill(used.begin(), used.end(), 0);
        std::fill(near.begin(), near.end(), 0);
        for (size_t t = 0; t < nt; ++t) {
            if (piece_of[t] != p) continue;
            const uint32_t* c = &s.triangles[3 * t];
            const bool at_border = shared[c[0]] || shared[c[1]] || shared[c[2]];
            for (int i = 0; i < 3; ++i) used[c[i]] = 1, near[c[i]] |= uint8_t(at_border);
        }
        uint32_t count = 0;
        for (size_t v = 0; v < nv; ++v) {
            if (!used[v]) continue;
            local[v] = count++;
            piece.surface.positions.insert(piece.surface.positions.end(), &s.positions[3 * v],
                                           &s.positions[3 * v] + 3);
            piece.locked.push_back(near[v]);
            piece.border.push_back(shared[v] ? uint32_t(v) : kNoId);
        }
        for (size_t t = 0; t < nt; ++t)
            if (piece_of[t] == p)
                for (int i = 0; i < 3; ++i)
                    piece.surface.triangles.push_back(local[s.triangles[3 * t + i]]);
        for (const Field& f : s.fields) {
            Field g{f.name, f.components, {}, f.kind};
            const size_t nc = size_t(f.components);
            g.values.reserve(count * nc);
            for (size_t v = 0; v < nv; ++v)
                if (used[v])
                    g.values.insert(g.values.end(), &f.values[v * nc], &f.values[v * nc] + nc);
            piece.surface.fields.push_back(std::move(g));
        }
    }
    return pieces;
}

ReducedPiece reduce_piece(const Piece& piece, const ProgressiveRecord& record) {
    // after() keeps the vertices in the order of their ids: the kept ids, in order, say which
    // output vertex each border vertex became.
    const std::vector<uint32_t> triangles = record.indexed_triangles(record.operations());
    std::vector<uint8_t> kept(record.vertices().vertex_count(), 0);
    for (uint32_t v : triangles) kept[v] = 1;
    ReducedPiece out;
    out.surface = record.after(record.operations());
    for (size_t v = 0; v < kept.size(); ++v)
        if (kept[v]) out.border.push_back(v < piece.border.size() ? piece.border[v] : kNoId);
    for (size_t v = 0; v < piece.border.size(); ++v)
        if (piece.border[v] != kNoId && !kept[v])
            throw std::runtime_error("border vertex " + std::to_string(piece.border[v]) +
                                     " was lost in its piece");
    return out;
}

Surface weld_pieces(const std::vector<Surface>& pieces) {
    Surface out;
    if (pieces.empty()) return out;
    for (const Field& f : pieces.front().fields)
        out.fields.push_back({f.name, f.components, {}, f.kind});
    using Key = std::array<uint32_t, 3>; // a position's bits
    struct KeyHash {
        size_t operator()(const Key& k) const {
            return (size_t(k[0]) * 0x9e3779b97f4a7c15ull) ^ (size_t(k[1]) * 0xc2b2ae3d27d4eb4full) ^
                   size_t(k[2]);
        }
    };
    std::unordered_map<Key, uint32_t, KeyHash> boundary; // earlier pieces' boundary vertices
    for (size_t p = 0; p < pieces.size(); ++p) {
        const Surface& s = pieces[p];
        if (s.fields.size() != out.fields.size())
            throw std::runtime_error("piece " + std::to_string(p) + " has " +
                                     std::to_string(s.fields.size()) + " fields, piece 0 has " +
                                     std::to_string(out.fields.size()));
        for (size_t i = 0; i < s.fields.size(); ++i)
            if (s.fields[i].name != out.fields[i].name ||
                s.fields[i].components != out.fields[i].components)
                throw std::runtime_error("piece " + std::to_string(p) + " has field '" +
                                         s.fields[i].name + "' where piece 0 has '" +
                                         out.fields[i].name + "'");
        // Open-boundary vertices: on an edge that only one triangle of the piece uses.
        std::vector<uint64_t> edges;
        edges.reserve(s.triangles.size());
        for (size_t t = 0; t < s.triangles.size(); t += 3)
            for (int c = 0; c < 3; ++c) {
                const uint64_t a = s.triangles[t + size_t(c)],
                               b = s.triangles[t + size_t(c + 1) % 3];
                edges.push_back(std::min(a, b) << 32 | std::max(a, b));
            }
        std::sort(edges.begin(), edges.end());
        std::vector<uint8_t> on_boundary(s.vertex_count(), 0);
        for (size_t i = 0; i < edges.size();) {
            size_t j = i;
            while (j < edges.size() && edges[j] == edges[i]) ++j;
            if (j - i == 1) on_boundary[edges[i] >> 32] = on_boundary[edges[i] & 0xffffffffu] = 1;
            i = j;
        }
        std::vector<uint32_t> index(s.vertex_count());
        std::vector<std::pair<Key, uint32_t>> mine; // this piece's boundary, for later pieces
        for (size_t v = 0; v < s.vertex_count(); ++v) {
            Key key;
            std::memcpy(key.data(), &s.positions[3 * v], sizeof key);
            if (on_boundary[v]) {
                const auto it = boundary.find(key);
                if (it != boundary.end()) {
                    index[v] = it->second;
                    continue;
                }
            }
            index[v] = uint32_t(out.vertex_count());
            if (on_boundary[v]) mine.emplace_back(key, index[v]);
            out.positions.insert(out.positions.end(), &s.positions[3 * v], &s.positions[3 * v] + 3);
            for (size_t i = 0; i < s.fields.size(); ++i) {
                const size_t nc = size_t(s.fields[i].components);
                out.fields[i].values.insert(out.fields[i].values.end(), &s.fields[i].values[v * nc],
                                            &s.fields[i].values[v * nc] + nc);
            }
        }
        for (uint32_t c : s.triangles) out.triangles.push_back(index[c]);
        boundary.insert(mine.begin(), mine.end()); // the first copy of a position wins
    }
    return out;
}

Surface stitch(const std::vector<ReducedPiece>& pieces) {
    Surface out;
    if (pieces.empty()) return out;
    for (const Field& f : pieces.front().surface.fields)
        out.fields.push_back({f.name, f.components, {}, f.kind});
    std::unordered_map<uint32_t, uint32_t> welded; // global id -> vertex of `out`
    for (const ReducedPiece& piece : pieces) {
        const Surface& s = piece.surface;
        if (s.fields.size() != out.fields.size())
            throw std::runtime_error("pieces with different fields cannot be stitched");
        std::vector<uint32_t> index(s.vertex_count());
        for (size_t v = 0; v < s.vertex_count(); ++v) {
            if (piece.border[v] != kNoId) {
                const auto [it, fresh] =
                    welded.emplace(piece.border[v], uint32_t(out.vertex_count()));
                index[v] = it->second;
                if (!fresh) continue;
            } else {
                index[v] = uint32_t(out.vertex_count());
            }
            out.positions.insert(out.positions.end(), &s.positions[3 * v], &s.positions[3 * v] + 3);
            for (size_t i = 0; i < s.fields.size(); ++i) {
                const Field& f = s.fields[i];
                const size_t nc = size_t(f.components);
                if (f.name != out.fields[i].name || f.components != out.fields[i].components)
                    throw std::runtime_error("pieces with different fields cannot be stitched");
                out.fields[i].values.insert(out.fields[i].values.end(), &f.values[v * nc],
                                            &f.values[v * nc] + nc);
            }
        }
        for (uint32_t c : s.triangles) out.triangles.push_back(index[c]);
    }
    return out;
}

} // namespace ddsimp::mpi
