#include "ddsimp/protocol/refinement.h"

#include <algorithm>
#include <array>

namespace ddsimp::protocol {
namespace {

using Triangle = std::array<uint32_t, 3>;

// The same triangle in the same orientation, whichever corner it starts at.
Triangle canonical(uint32_t a, uint32_t b, uint32_t c) {
    if (a <= b && a <= c) return {a, b, c};
    if (b <= a && b <= c) return {b, c, a};
    return {c, a, b};
}

void copy_vertex(const Surface& from, size_t v, Surface& to) {
    to.positions.insert(to.positions.end(), &from.positions[3 * v], &from.positions[3 * v + 3]);
    for (size_t f = 0; f < from.fields.size(); ++f) {
        const size_t nc = size_t(from.fields[f].components);
        const float* at = &from.fields[f].values[nc * v];
        to.fields[f].values.insert(to.fields[f].values.end(), at, at + nc);
    }
}

Surface empty_like(const Surface& s) {
    Surface out;
    for (const Field& f : s.fields) out.fields.push_back({f.name, f.components, {}, f.kind});
    return out;
}

bool is_dead(const uint32_t* t) {
    return t[0] == t[1] && t[1] == t[2];
}

} // namespace

uint32_t RefinementStream::local_id(uint32_t global, Surface& new_vertices) {
    const auto [it, inserted] = local_.try_emplace(global, uint32_t(local_.size()));
    if (inserted) copy_vertex(all_, global, new_vertices);
    return it->second;
}

Surface RefinementStream::base(const std::vector<uint32_t>& triangles) {
    local_.clear();
    Surface out = empty_like(all_);
    for (uint32_t v : triangles) out.triangles.push_back(local_id(v, out));
    slots_ = triangles;
    return out;
}

Refinement RefinementStream::refine(const std::vector<uint32_t>& triangles) {
    // The next level's triangles, sorted, each used at most once to keep a slot.
    std::vector<Triangle> next;
    next.reserve(triangles.size() / 3);
    for (size_t t = 0; t < triangles.size(); t += 3)
        next.push_back(canonical(triangles[t], triangles[t + 1], triangles[t + 2]));
    std::vector<Triangle> sorted = next;
    std::sort(sorted.begin(), sorted.end());
    std::vector<uint8_t> kept(sorted.size(), 0);

    // Slots whose triangle survives stay; the others are freed, in slot order.
    std::vector<uint32_t> freed;
    for (size_t s = 0; s < slots_.size(); s += 3) {
        if (slots_[s] == kDeadSlot) {
            freed.push_back(uint32_t(s / 3));
            continue;
        }
        const Triangle key = canonical(slots_[s], slots_[s + 1], slots_[s + 2]);
        auto at = std::lower_bound(sorted.begin(), sorted.end(), key);
        while (at != sorted.end() && *at == key && kept[size_t(at - sorted.begin())]) ++at;
        if (at != sorted.end() && *at == key)
            kept[size_t(at - sorted.begin())] = 1;
        else
            freed.push_back(uint32_t(s / 3));
    }

    // New triangles, in the next level's order, fill freed slots first, then append.
    Refinement r;
    r.new_vertices = empty_like(all_);
    std::vector<uint8_t> placed(sorted.size(), 0);
    size_t next_freed = 0;
    for (const Triangle& t : next) {
        size_t i = size_t(std::lower_bound(sorted.begin(), sorted.end(), t) - sorted.begin());
        while (i < sorted.size() && sorted[i] == t && (kept[i] || placed[i])) ++i;
        if (i == sorted.size() || sorted[i] != t) continue; // it kept its slot
        placed[i] = 1;
        uint32_t slot = 0;
        if (next_freed < freed.size()) {
            slot = freed[next_freed++];
        } else {
            slot = uint32_t(slots_.size() / 3);
            slots_.insert(slots_.end(), 3, kDeadSlot);
        }
        std::copy(t.begin(), t.end(), &slots_[3 * size_t(slot)]);
        r.writes.insert(r.writes.end(),
                        {slot, local_id(t[0], r.new_vertices), local_id(t[1], r.new_vertices),
                         local_id(t[2], r.new_vertices)});
    }
    for (; next_freed < freed.size(); ++next_freed) {
        const uint32_t slot = freed[next_freed];
        if (slots_[3 * size_t(slot)] == kDeadSlot) continue; // already empty
        std::fill_n(&slots_[3 * size_t(slot)], 3, kDeadSlot);
        r.writes.insert(r.writes.end(), {slot, kDeadSlot, kDeadSlot, kDeadSlot});
    }
    return r;
}

void SlotMesh::apply(const Refinement& r) {
    const Surface& add = r.new_vertices;
    if (add.fields.size() != mesh_.fields.size())
        throw BlobError("a refinement with " + std::to_string(add.fields.size()) +
                        " fields for a mesh with " + std::to_string(mesh_.fields.size()));
    for (size_t f = 0; f < add.fields.size(); ++f)
        if (add.fields[f].components != mesh_.fields[f].components)
            throw BlobError("field \"" + add.fields[f].name + "\" changes its components");
    if (r.writes.size() % 4 != 0) throw BlobError("slot writes are not groups of four");
    // Check everything before changing anything.
    const size_t vertices = mesh_.vertex_count() + add.vertex_count();
    size_t slot_count = mesh_.triangle_count();
    for (size_t w = 0; w < r.writes.size(); w += 4) {
        const uint32_t slot = r.writes[w];
        if (slot > slot_count)
            throw BlobError("a write to triangle slot " + std::to_string(slot) + " of " +
                            std::to_string(slot_count));
        if (slot == slot_count) ++slot_count;
        if (r.writes[w + 1] == kDeadSlot) continue;
        for (int c = 1; c < 4; ++c)
            if (r.writes[w + c] >= vertices)
                throw BlobError("a write refers to vertex " + std::to_string(r.writes[w + c]) +
                                " of " + std::to_string(vertices));
    }
    mesh_.positions.insert(mesh_.positions.end(), add.positions.begin(), add.positions.end());
    for (size_t f = 0; f < add.fields.size(); ++f)
        mesh_.fields[f].values.insert(mesh_.fields[f].values.end(), add.fields[f].values.begin(),
                                      add.fields[f].values.end());
    mesh_.triangles.resize(3 * slot_count, 0);
    for (size_t w = 0; w < r.writes.size(); w += 4) {
        uint32_t* t = &mesh_.triangles[3 * size_t(r.writes[w])];
        if (r.writes[w + 1] == kDeadSlot)
            t[0] = t[1] = t[2] = 0;
        else
            std::copy_n(&r.writes[w + 1], 3, t);
    }
}

size_t SlotMesh::live_triangles() const {
    size_t n = 0;
    for (size_t t = 0; t < mesh_.triangles.size(); t += 3) n += !is_dead(&mesh_.triangles[t]);
    return n;
}

Surface SlotMesh::live() const {
    Surface out = mesh_;
    out.triangles.clear();
    for (size_t t = 0; t < mesh_.triangles.size(); t += 3)
        if (!is_dead(&mesh_.triangles[t]))
            out.triangles.insert(out.triangles.end(), &mesh_.triangles[t], &mesh_.triangles[t + 3]);
    return out;
}

} // namespace ddsimp::protocol
