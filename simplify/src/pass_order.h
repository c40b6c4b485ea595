// The order of one pass: every candidate (an edge or a vertex) with its key, sorted lightest
// first by a stable radix sort, so that equal keys keep the candidates' id order and the order is
// total and deterministic. A pass takes the lightest part of this order (see Simplifier::run).
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

namespace ddsimp::detail {

// Weight first, then a geometric tie-break (shorter first), then the candidate's id.
struct Key {
    float weight = std::numeric_limits<float>::infinity();
    float tie = 0;
};

// A candidate with its key packed into one integer that orders as (weight, tie): each float
// mapped to an unsigned integer in the same order (-0 first made +0, as the float comparison
// equates them), weight in the high half.
struct Candidate {
    uint64_t order;
    uint32_t id;

    static uint32_t bits(float f) {
        f += 0.0f; // -0 -> +0
        uint32_t u;
        std::memcpy(&u, &f, sizeof u);
        return u & 0x80000000u ? ~u : u | 0x80000000u;
    }
    static Candidate make(const Key& k, uint32_t id) {
        return {uint64_t(bits(k.weight)) << 32 | bits(k.tie), id};
    }
    float weight() const {
        uint32_t u = uint32_t(order >> 32);
        u = u & 0x80000000u ? u & 0x7fffffffu : ~u;
        float f;
        std::memcpy(&f, &u, sizeof f);
        return f;
    }
};

// Sorts `items`, which come in id order, by their packed key, then by id: four stable counting
// passes over 16-bit digits, lowest first (digits on which all items agree are skipped); a
// comparison sort for a few items. `scratch` is reused between calls.
inline void sort_candidates(std::vector<Candidate>& items, std::vector<Candidate>& scratch) {
    constexpr int kDigits = 4, kBits = 16;
    constexpr size_t kBuckets = size_t(1) << kBits;
    const size_t n = items.size();
    if (n < 2 * kBuckets) {
        std::sort(items.begin(), items.end(), [](const Candidate& a, const Candidate& b) {
            return a.order != b.order ? a.order < b.order : a.id < b.id;
        });
        return;
    }
    scratch.resize(n);
    std::vector<uint32_t> count(kDigits * kBuckets, 0);
    for (const Candidate& c : items)
        for (int d = 0; d < kDigits; ++d) ++count[d * kBuckets + (c.order >> (kBits * d) & 0xffff)];
    for (int d = 0; d < kDigits; ++d) {
        uint32_t* bucket = &count[d * kBuckets];
        if (bucket[items[0].order >> (kBits * d) & 0xffff] == n) continue; // one value: no change
        uint32_t sum = 0;
        for (size_t b = 0; b < kBuckets; ++b) {
            const uint32_t c = bucket[b];
            bucket[b] = sum;
            sum += c;
        }
        for (const Candidate& c : items) scratch[bucket[c.order >> (kBits * d) & 0xffff]++] = c;
        items.swap(scratch);
    }
}

// The `count` lightest of `items` (in id order), sorted, into `out`, perhaps followed by more:
// the items whose top 16 key bits are at most those of the count-th lightest, sorted. The same
// first `count` as sorting all of them, for less work. `items` is left in an unspecified state.
inline void lightest_sorted(std::vector<Candidate>& items, size_t count,
                            std::vector<Candidate>& out) {
    constexpr size_t kBuckets = size_t(1) << 16;
    out.clear();
    if (count < items.size() && items.size() >= 4 * kBuckets) {
        std::vector<uint32_t> histogram(kBuckets, 0);
        for (const Candidate& c : items) ++histogram[c.order >> 48];
        size_t last = 0, sum = 0;
        while (sum + histogram[last] < count) sum += histogram[last++];
        for (const Candidate& c : items)
            if ((c.order >> 48) <= last) out.push_back(c);
    } else {
        out.swap(items);
    }
    sort_candidates(out, items);
}

} // namespace ddsimp::detail
