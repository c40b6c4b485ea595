// A 4-ary min-heap of ids with keys that can be changed in place (the mutable priority queue of
// Frank & Lang): O(log n) per update, no allocation after construction. Keys live in the heap
// array itself, so a sift walks contiguous memory instead of chasing ids; four children per node
// halve the depth, and the four sit in one or two cache lines.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

namespace ddsimp::detail {

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

    bool empty() const { return heap_.empty(); }
    uint32_t top() const { return heap_.front().id; }
    HeapKey top_key() const { return heap_.front().key(); }
    bool contains(uint32_t id) const { return slot_[id] != kAbsent; }
    // The key of an id in the heap.
    HeapKey key(uint32_t id) const { return heap_[slot_[id]].key(); }

    // Inserts id, or moves it to its new key.
    void set(uint32_t id, const HeapKey& key) {
        uint32_t at = slot_[id];
        const Entry e = Entry::make(key, id);
        if (at == kAbsent) {
            at = uint32_t(heap_.size());
            heap_.push_back(e);
        } else {
            heap_[at] = e;
        }
        sift_down(sift_up(at));
    }
    void erase(uint32_t id) {
        const uint32_t at = slot_[id];
        if (at == kAbsent) return;
        const Entry last = heap_.back();
        heap_.pop_back();
        slot_[id] = kAbsent;
        if (last.id == id) return;
        if (at == 0) return pop_into_root(last);
        heap_[at] = last;
        slot_[last.id] = at;
        sift_down(sift_up(at));
    }

private:
    // A key packed into one integer that orders as HeapKey does: each float mapped to an
    // unsigned integer in the same order (-0 first made +0, as the float comparison equates
    // them), weight in the high half. One integer comparison instead of a chain of float ones.
    struct Entry {
        uint32_t tie_bits, weight_bits, id;

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
            return {bits(k.tie), bits(k.weight), id};
        }
        HeapKey key() const { return {value(weight_bits), value(tie_bits)}; }
        uint64_t order() const { return uint64_t(weight_bits) << 32 | tie_bits; }
        bool operator<(const Entry& o) const {
            const uint64_t a = order(), b = o.order();
            return a < b || (a == b && id < o.id);
        }
    };
    static constexpr uint32_t kAbsent = std::numeric_limits<uint32_t>::max();

    void place(uint32_t at, const Entry& e) {
        heap_[at] = e;
        slot_[e.id] = at;
    }
    // The lightest of the children of `at` (which has at least one). With all four there, two
    // independent pairs then their winners: the order is total, so the same child either way.
    uint32_t least_child(uint32_t at, uint32_t n) const {
        const uint32_t first = 4 * at + 1;
        if (first + 4 <= n) {
            const uint32_t l = heap_[first + 1] < heap_[first] ? first + 1 : first;
            const uint32_t r = heap_[first + 3] < heap_[first + 2] ? first + 3 : first + 2;
            return heap_[r] < heap_[l] ? r : l;
        }
        uint32_t child = first;
        for (uint32_t c = first + 1; c < n; ++c)
            if (heap_[c] < heap_[child]) child = c;
        return child;
    }
    uint32_t sift_up(uint32_t at) {
        const Entry e = heap_[at];
        while (at > 0) {
            const uint32_t parent = (at - 1) / 4;
            if (!(e < heap_[parent])) break;
            place(at, heap_[parent]);
            at = parent;
        }
        place(at, e);
        return at;
    }
    void sift_down(uint32_t at) {
        const Entry e = heap_[at];
        const uint32_t n = uint32_t(heap_.size());
        while (4 * at + 1 < n) {
            const uint32_t child = least_child(at, n);
            if (!(heap_[child] < e)) break;
            place(at, heap_[child]);
            at = child;
        }
        place(at, e);
    }
    // Removing the top: the last entry rarely belongs high up, so move the hole down to a leaf
    // along the lighter children, then let the last entry rise from there (fewer comparisons
    // than sifting it down from the root; the heap's top is the same either way).
    void pop_into_root(const Entry& last) {
        const uint32_t n = uint32_t(heap_.size());
        uint32_t at = 0;
        while (4 * at + 1 < n) {
            const uint32_t child = least_child(at, n);
            place(at, heap_[child]);
            at = child;
        }
        place(at, last);
        sift_up(at);
    }

    std::vector<Entry> heap_;
    std::vector<uint32_t> slot_;
};

} // namespace ddsimp::detail
