// A binary min-heap of vertex ids with keys that can be changed in place (the mutable priority
// queue of Frank & Lang): O(log n) per update, no allocation after construction.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

namespace ddsimp::detail {

// Weight first, then a geometric tie-break (shorter first), then the id: a total order, so the
// run is deterministic.
struct HeapKey {
    double weight = std::numeric_limits<double>::infinity();
    double tie = 0;
    bool operator<(const HeapKey& o) const {
        return weight != o.weight ? weight < o.weight : tie < o.tie;
    }
};

class IndexedHeap {
public:
    explicit IndexedHeap(size_t capacity) : slot_(capacity, kAbsent), key_(capacity) {}

    bool empty() const { return heap_.empty(); }
    uint32_t top() const { return heap_.front(); }
    const HeapKey& key(uint32_t id) const { return key_[id]; }
    bool contains(uint32_t id) const { return slot_[id] != kAbsent; }

    // Inserts id, or moves it to its new key.
    void set(uint32_t id, const HeapKey& key) {
        key_[id] = key;
        if (slot_[id] == kAbsent) {
            slot_[id] = uint32_t(heap_.size());
            heap_.push_back(id);
        }
        sift_down(sift_up(slot_[id]));
    }
    void erase(uint32_t id) {
        const uint32_t at = slot_[id];
        if (at == kAbsent) return;
        const uint32_t last = heap_.back();
        heap_.pop_back();
        slot_[id] = kAbsent;
        if (last == id) return;
        heap_[at] = last;
        slot_[last] = at;
        sift_down(sift_up(at));
    }

private:
    static constexpr uint32_t kAbsent = std::numeric_limits<uint32_t>::max();
    bool less(uint32_t a, uint32_t b) const {
        return key_[a] < key_[b] || (!(key_[b] < key_[a]) && a < b);
    }
    void place(uint32_t at, uint32_t id) {
        heap_[at] = id;
        slot_[id] = at;
    }
    uint32_t sift_up(uint32_t at) {
        const uint32_t id = heap_[at];
        while (at > 0) {
            const uint32_t parent = (at - 1) / 2;
            if (!less(id, heap_[parent])) break;
            place(at, heap_[parent]);
            at = parent;
        }
        place(at, id);
        return at;
    }
    void sift_down(uint32_t at) {
        const uint32_t id = heap_[at], n = uint32_t(heap_.size());
        for (;;) {
            uint32_t child = 2 * at + 1;
            if (child >= n) break;
            if (child + 1 < n && less(heap_[child + 1], heap_[child])) ++child;
            if (!less(heap_[child], id)) break;
            place(at, heap_[child]);
            at = child;
        }
        place(at, id);
    }

    std::vector<uint32_t> heap_, slot_;
    std::vector<HeapKey> key_;
};

} // namespace ddsimp::detail
