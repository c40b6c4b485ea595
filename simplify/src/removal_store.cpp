// A pass's taken removals, packed. Each takes a header and its arrays at their ring's length,
// one after the other in one reserved block: a check claims its words with one atomic add, so
// checks on any thread store side by side. Where a removal lies in the block depends on the
// order the checks ran in; what it holds does not.
#include "huge_pages.h"
#include "simplifier.h"

#include <cstring>

namespace ddsimp {

namespace {

using Words = detail::HugePageAllocator<uint32_t>;

// Bytes packed into words, rounded up.
constexpr size_t words_of_bytes(size_t bytes) {
    return (bytes + sizeof(uint32_t) - 1) / sizeof(uint32_t);
}

} // namespace

Simplifier::RemovalStore::~RemovalStore() {
    if (words_) Words().deallocate(words_, capacity_);
}

size_t Simplifier::RemovalStore::words_for(size_t ring_size, size_t new_count) {
    // ring, star and outer_twin words; outer_line and the new triangles' corners bytes.
    return kHeader + 3 * ring_size + words_of_bytes(ring_size + 3 * new_count);
}

void Simplifier::RemovalStore::reset(size_t slots) {
    at_.clear();
    at_.reserve(slots);
    used_.store(0, std::memory_order_relaxed);
    const size_t needed = slots * words_for(kMaxValence, kMaxValence);
    if (needed <= capacity_) return;
    if (words_) Words().deallocate(words_, capacity_);
    // Never written until a removal is stored: only the words used become resident.
    words_ = Words().allocate(needed);
    capacity_ = needed;
}

void Simplifier::RemovalStore::release() {
    detail::release_pages(words_, words_ + used_.load(std::memory_order_relaxed));
    at_.clear();
    used_.store(0, std::memory_order_relaxed);
}

void Simplifier::RemovalStore::put(size_t slot, const Removal& r) {
    const size_t n = r.ring_size, fan = r.slots();
    const size_t begin = used_.fetch_add(words_for(n, r.new_count), std::memory_order_relaxed);
    uint32_t* w = words_ + begin;
    w[0] = r.vertex;
    w[1] = uint32_t(n) | uint32_t(r.new_count) << 8 | uint32_t(r.boundary) << 16 |
           uint32_t(r.cover.count) << 17;
    w[2] = uint32_t(uint8_t(r.feature_a + 1)) | uint32_t(uint8_t(r.feature_b + 1)) << 8;
    w[3] = uint32_t(r.cover.corner[0]) | uint32_t(r.cover.corner[1]) << 8 |
           uint32_t(r.cover.corner[2]) << 16;
    std::memcpy(w + 4, r.cover.weight, r.cover.count * sizeof(double));
    w += kHeader;
    std::memcpy(w, r.ring, n * sizeof(uint32_t));
    std::memcpy(w + n, r.star, fan * sizeof(uint32_t));
    std::memcpy(w + 2 * n, r.outer_twin, fan * sizeof(uint32_t));
    auto* bytes = reinterpret_cast<uint8_t*>(w + 3 * n);
    std::memcpy(bytes, r.outer_line, fan);
    std::memcpy(bytes + n, r.triangles, 3 * r.new_count);
    at_[slot] = begin;
}

Simplifier::RemovalStore::Shape Simplifier::RemovalStore::shape(size_t slot) const {
    const uint32_t w = words_[at_[slot] + 1];
    return {w & 0xff, w >> 8 & 0xff, w >> 17 & 3, (w >> 16 & 1) != 0};
}

void Simplifier::RemovalStore::get(size_t slot, Removal& r) const {
    const uint32_t* w = words_ + at_[slot];
    const Shape s = shape(slot);
    const size_t n = s.ring_size;
    r.vertex = w[0];
    r.ring_size = n;
    r.new_count = s.new_count;
    r.boundary = s.boundary;
    r.cover.count = s.cover_count;
    r.feature_a = int(w[2] & 0xff) - 1;
    r.feature_b = int(w[2] >> 8 & 0xff) - 1;
    for (int k = 0; k < 3; ++k) r.cover.corner[k] = uint8_t(w[3] >> (8 * k));
    std::memcpy(r.cover.weight, w + 4, r.cover.count * sizeof(double));
    const size_t fan = r.slots();
    w += kHeader;
    std::memcpy(r.ring, w, n * sizeof(uint32_t));
    std::memcpy(r.star, w + n, fan * sizeof(uint32_t));
    std::memcpy(r.outer_twin, w + 2 * n, fan * sizeof(uint32_t));
    const auto* bytes = reinterpret_cast<const uint8_t*>(w + 3 * n);
    std::memcpy(r.outer_line, bytes, fan);
    std::memcpy(r.triangles, bytes + n, 3 * r.new_count);
}

size_t Simplifier::RemovalStore::slots_of(size_t slot) const {
    const Shape s = shape(slot);
    return s.boundary ? s.ring_size - 1 : s.ring_size;
}

size_t Simplifier::RemovalStore::new_count_of(size_t slot) const {
    return shape(slot).new_count;
}

} // namespace ddsimp
