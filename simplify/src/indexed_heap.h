// A 4-ary min-heap of ids with keys that can be changed in place (the mutable priority queue of
// Frank & Lang): O(log n) per update, no allocation after construction. Keys live in the heap
// array itself, so a sift walks contiguous memory instead of chasing ids; four children per node
// halve the depth, and the four sit in one or two cache lines.
#pragma once

#include <algorithm>
#include <cstdint>
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
    const HeapKey& top_key() const { return heap_.front().key; }
    bool contains(uint32_t id) const { return slot_[id] != kAbsent; }
    // The key of an id in the heap.
    const HeapKey& key(uint32_t id) const { return heap_[slot_[id]].key; }

    // Inserts id, or moves it to its new key.
    void set(uint32_t id, const HeapKey& key) {
        uint32_t at = slot_[id];
        if (at == kAbsent) {
            at = uint32_t(heap_.size());
            heap_.push_back({key, id});
        } else {
            heap_[at].key = key;
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
        heap_[at] = last;
        slot_[last.id] = at;
        sift_down(sift_up(at));
    }

private:
    struct Entry {
        HeapKey key;
        uint32_t id;
        bool operator<(const Entry& o) const {
            return key < o.key || (!(o.key < key) && id < o.id);
        }
    };
    static constexpr uint32_t kAbsent = std::numeric_limits<uint32_t>::max();

    void place(uint32_t at, const Entry& e) {
        heap_[at] = e;
        slot_[e.id] = at;
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
        for (;;) {
            const uint32_t first = 4 * at + 1;
            if (first >= n) break;
            uint32_t child = first;
            const uint32_t end = std::min(first + 4, n);
            for (uint32_t c = first + 1; c < end; ++c)
                if (heap_[c] < heap_[child]) child = c;
            if (!(heap_[child] < e)) break;
            place(at, heap_[child]);
            at = child;
        }
        place(at, e);
    }

    std::vector<Entry> heap_;
    std::vector<uint32_t> slot_;
};

} // namespace ddsimp::detail
