// A 4-ary min-heap of ids with keys that can be changed in place (the mutable priority queue of
// Frank & Lang): O(log n) per update, no allocation after construction. Keys live in the heap
// array itself, so a sift walks contiguous memory instead of chasing ids; four children per node
// halve the depth, and the four share one cache line: entries are 16 bytes and the array is
// stored in 64-byte groups, shifted by three so that every node's children start a group.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <new>
#include <vector>

namespace ddsimp::detail {

// Storage on 64-byte boundaries (the heap's groups of four siblings are then one cache line each).
template <class T> struct CacheLineAllocator {
    using value_type = T;
    CacheLineAllocator() = default;
    template <class U> CacheLineAllocator(const CacheLineAllocator<U>&) {}
    T* allocate(size_t n) {
        return static_cast<T*>(::operator new(n * sizeof(T), std::align_val_t(64)));
    }
    void deallocate(T* p, size_t) { ::operator delete(p, std::align_val_t(64)); }
    template <class U> bool operator==(const CacheLineAllocator<U>&) const { return true; }
};

// Weight first, then a geometric tie-break (shorter first); the heap breaks remaining ties by
// id, so the order is total and the run deterministic.
struct HeapKey {
    float weight = std::numeric_limits<float>::infinity();
    float tie = 0;
    bool operator<(const HeapKey& o) const {
        return weight != o.weight ? weight < o.weight : tie < o.tie;
    }
};

class IndexedHeap {
public:
    explicit IndexedHeap(size_t capacity) : slot_(capacity, kAbsent) {}

    bool empty() const { return size_ == 0; }
    uint32_t top() const { return entry(0).id; }
    HeapKey top_key() const { return entry(0).key(); }
    bool contains(uint32_t id) const { return slot_[id] != kAbsent; }
    // The key of an id in the heap.
    HeapKey key(uint32_t id) const { return entry(slot_[id]).key(); }

    // Inserts id, or moves it to its new key.
    void set(uint32_t id, const HeapKey& key) {
        uint32_t at = slot_[id];
        const Entry e = Entry::make(key, id);
        if (at == kAbsent) {
            at = size_++;
            if (size_ + kShift > heap_.size()) heap_.resize(heap_.size() + kGroup);
        }
        entry(at) = e;
        sift_down(sift_up(at));
    }
    void erase(uint32_t id) {
        const uint32_t i = slot_[id];
        if (i == kAbsent) return;
        const Entry last = entry(--size_);
        slot_[id] = kAbsent;
        if (last.id == id) return;
        if (i == 0) return pop_into_root(last);
        entry(i) = last;
        slot_[last.id] = i;
        sift_down(sift_up(i));
    }

private:
    // A key packed into one integer that orders as HeapKey does: each float mapped to an
    // unsigned integer in the same order (-0 first made +0, as the float comparison equates
    // them), weight in the high half. One integer comparison instead of a chain of float ones.
    struct Entry {
        uint32_t tie_bits, weight_bits, id, unused = 0;

        static uint32_t bits(float f) {
            f += 0.0f; // -0 -> +0
            uint32_t u;
            std::memcpy(&u, &f, sizeof u);
            return u & 0x80000000u ? ~u : u | 0x80000000u;
        }
        static float value(uint32_t u) {
            u = u & 0x80000000u ? u & 0x7fffffffu : ~u;
            float f;
            std::memcpy(&f, &u, sizeof f);
            return f;
        }
        static Entry make(const HeapKey& k, uint32_t id) {
            return {bits(k.tie), bits(k.weight), id, 0};
        }
        HeapKey key() const { return {value(weight_bits), value(tie_bits)}; }
        uint64_t order() const { return uint64_t(weight_bits) << 32 | tie_bits; }
        bool operator<(const Entry& o) const {
            const uint64_t a = order(), b = o.order();
            return a < b || (a == b && id < o.id);
        }
    };
    static constexpr uint32_t kAbsent = std::numeric_limits<uint32_t>::max();
    static constexpr uint32_t kGroup = 4, kShift = kGroup - 1; // node i at storage index i + 3

    Entry& entry(uint32_t i) { return heap_[i + kShift]; }
    const Entry& entry(uint32_t i) const { return heap_[i + kShift]; }
    void place(uint32_t i, const Entry& e) {
        entry(i) = e;
        slot_[e.id] = i;
    }
    // The lightest of the children of `at` (which has at least one). With all four there, two
    // independent pairs then their winners: the order is total, so the same child either way.
    uint32_t least_child(uint32_t at, uint32_t n) const {
        const uint32_t first = 4 * at + 1;
        if (first + 4 <= n) {
            const uint32_t l = entry(first + 1) < entry(first) ? first + 1 : first;
            const uint32_t r = entry(first + 3) < entry(first + 2) ? first + 3 : first + 2;
            return entry(r) < entry(l) ? r : l;
        }
        uint32_t child = first;
        for (uint32_t c = first + 1; c < n; ++c)
            if (entry(c) < entry(child)) child = c;
        return child;
    }
    uint32_t sift_up(uint32_t at) {
        const Entry e = entry(at);
        while (at > 0) {
            const uint32_t parent = (at - 1) / 4;
            if (!(e < entry(parent))) break;
            place(at, entry(parent));
            at = parent;
        }
        place(at, e);
        return at;
    }
    void sift_down(uint32_t at) {
        const Entry e = entry(at);
        const uint32_t n = size_;
        while (4 * at + 1 < n) {
            const uint32_t child = least_child(at, n);
            if (!(entry(child) < e)) break;
            place(at, entry(child));
            at = child;
        }
        place(at, e);
    }
    // Removing the top: the last entry rarely belongs high up, so move the hole down to a leaf
    // along the lighter children, then let the last entry rise from there (fewer comparisons
    // than sifting it down from the root; the heap's top is the same either way).
    void pop_into_root(const Entry& last) {
        const uint32_t n = size_;
        uint32_t at = 0;
        while (4 * at + 1 < n) {
            const uint32_t child = least_child(at, n);
            place(at, entry(child));
            at = child;
        }
        place(at, last);
        sift_up(at);
    }

    std::vector<Entry, CacheLineAllocator<Entry>> heap_ =
        std::vector<Entry, CacheLineAllocator<Entry>>(kShift);
    uint32_t size_ = 0;
    std::vector<uint32_t> slot_;
};

} // namespace ddsimp::detail
