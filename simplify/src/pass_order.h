// The order of the passes: every candidate (an edge or a vertex) with its key, lightest first,
// equal keys in id order, so that the order is total and deterministic. A ranking sorts the
// candidates it ranked again (by a stable radix sort, or in place when they are many) and merges
// them into the order it keeps; a pass selects from the lightest part of it (see
// Simplifier::run_pass).
#pragma once

#include "parallel.h"

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

// A candidate with its key packed into 48 bits that order as (weight, tie): each float mapped to
// an unsigned integer in the same order (-0 first made +0, as the float comparison equates
// them), the weight's 32 bits above the tie's top 16 (its sign, exponent and 7 bits of mantissa:
// ties closer than about 1% count as equal and go by id). Twelve bytes: the kept order holds
// every candidate.
struct Candidate {
    uint32_t weight_bits, tie_bits; // the order's top 32 bits and its low 16
    uint32_t id;

    uint64_t order() const { return uint64_t(weight_bits) << 16 | tie_bits; }

    static uint32_t bits(float f) {
        f += 0.0f; // -0 -> +0
        uint32_t u;
        std::memcpy(&u, &f, sizeof u);
        return u & 0x80000000u ? ~u : u | 0x80000000u;
    }
    static Candidate make(const Key& k, uint32_t id) {
        return {bits(k.weight), bits(k.tie) >> 16, id};
    }
    bool operator==(const Candidate&) const = default;
    bool operator<(const Candidate& o) const {
        return weight_bits != o.weight_bits ? weight_bits < o.weight_bits
               : tie_bits != o.tie_bits     ? tie_bits < o.tie_bits
                                            : id < o.id;
    }
    float weight() const {
        uint32_t u = weight_bits;
        u = u & 0x80000000u ? u & 0x7fffffffu : ~u;
        float f;
        std::memcpy(&f, &u, sizeof f);
        return f;
    }
};

inline constexpr int kKeyDigits = 4, kDigitBits = 12; // 48 bits of key
inline constexpr size_t kDigitValues = size_t(1) << kDigitBits;
inline uint32_t digit(const Candidate& c, int d) {
    return uint32_t(c.order() >> (kDigitBits * d)) & (kDigitValues - 1);
}

// Sorts `items`, which come in id order, by key, then by id: stable counting passes over the
// key's 12-bit digits, lowest first (a digit on which all items agree is skipped); a comparison
// sort for a few items. Each piece of the items is counted and scattered on its own thread, into
// places that follow the pieces before it for every digit value, so the order is a serial sort's
// on any number of threads. `scratch` is reused between calls.
template <class Vector> void sort_candidates(Vector& items, Vector& scratch, Parallel& parallel) {
    const size_t n = items.size();
    if (n < kDigitValues) {
        std::sort(items.begin(), items.end());
        return;
    }
    scratch.resize(n);
    // A piece is worth a thread from as many items as there are digit values.
    const size_t pieces = parallel.pieces(n / kDigitValues);
    auto begin_of = [&](size_t p) { return p * n / pieces; };
    // count[p * kKeyDigits * kDigitValues + d * kDigitValues + value]: piece p's items with
    // digit d = value; for the digit being sorted, where piece p's next such item goes.
    std::vector<uint32_t> count(pieces * kKeyDigits * kDigitValues, 0);
    auto counts = [&](size_t p, int d) { return &count[(p * kKeyDigits + d) * kDigitValues]; };
    parallel.for_each(
        pieces,
        [&](size_t p) {
            for (size_t i = begin_of(p); i < begin_of(p + 1); ++i)
                for (int d = 0; d < kKeyDigits; ++d) ++counts(p, d)[digit(items[i], d)];
        },
        1);
    for (int d = 0; d < kKeyDigits; ++d) {
        const uint32_t first = digit(items[0], d);
        size_t same = 0;
        for (size_t p = 0; p < pieces; ++p) same += counts(p, d)[first];
        if (same == n) continue; // one value: no change
        if (d > 0 && pieces > 1) // the pieces hold other items since the last digit's pass
            parallel.for_each(
                pieces,
                [&](size_t p) {
                    uint32_t* c = counts(p, d);
                    std::fill(c, c + kDigitValues, 0);
                    for (size_t i = begin_of(p); i < begin_of(p + 1); ++i) ++c[digit(items[i], d)];
                },
                1);
        uint32_t sum = 0;
        for (size_t b = 0; b < kDigitValues; ++b)
            for (size_t p = 0; p < pieces; ++p) {
                const uint32_t c = counts(p, d)[b];
                counts(p, d)[b] = sum;
                sum += c;
            }
        parallel.for_each(
            pieces,
            [&](size_t p) {
                uint32_t* next = counts(p, d);
                for (size_t i = begin_of(p); i < begin_of(p + 1); ++i)
                    scratch[next[digit(items[i], d)]++] = items[i];
            },
            1);
        items.swap(scratch);
    }
}

namespace sort_detail {

inline constexpr int kPlaceBits = 8; // in-place digits: a bucket table that fits any stack
inline constexpr size_t kPlaceValues = size_t(1) << kPlaceBits;
inline constexpr size_t kFewToPlace = 64; // a comparison sort from here down

// Sorts [first, last), whose keys agree above bit `top` (exclusive), by the key's next
// kPlaceBits bits below `top`, in place (American flag sort), then each bucket on its own
// (`each(begin, end, next_top)`, which this calls back for buckets that need it).
template <class Each> void place_by_digit(Candidate* first, Candidate* last, int top, Each each) {
    const int shift = std::max(0, top - kPlaceBits);
    const uint64_t mask = (uint64_t(1) << (top - shift)) - 1;
    auto bucket = [&](const Candidate& c) { return size_t((c.order() >> shift) & mask); };
    size_t count[kPlaceValues] = {};
    for (Candidate* c = first; c != last; ++c) ++count[bucket(*c)];
    size_t head[kPlaceValues], tail[kPlaceValues], sum = 0;
    for (size_t b = 0; b < kPlaceValues; ++b) head[b] = sum, sum += count[b], tail[b] = sum;
    for (size_t b = 0; b < kPlaceValues; ++b)
        while (head[b] < tail[b]) {
            Candidate c = first[head[b]];
            size_t to = bucket(c);
            while (to != b) { // follow the cycle until an item for bucket b comes back
                std::swap(c, first[head[to]++]);
                to = bucket(c);
            }
            first[head[b]++] = c;
        }
    for (size_t b = 0, begin = 0; b < kPlaceValues; begin += count[b++])
        if (count[b] > 1) each(first + begin, first + begin + count[b], shift);
}

// Sorts [first, last), whose keys agree above bit `top`, serially.
inline void place_sort(Candidate* first, Candidate* last, int top) {
    if (size_t(last - first) <= kFewToPlace || top == 0) return std::sort(first, last);
    place_by_digit(first, last, top, place_sort);
}

} // namespace sort_detail

// Sorts `items` by key, then by id, in place: an MSD radix sort (American flag) over the key's
// bits from the highest on which two items differ, each bucket of a few items, or of one key,
// sorted by comparison. The buckets of the first digit are sorted on the threads. The result is
// the one total order, whatever the thread count. For many items: no second array of their size.
template <class Vector> void sort_candidates_in_place(Vector& items, Parallel& parallel) {
    if (items.size() <= sort_detail::kFewToPlace) return std::sort(items.begin(), items.end());
    uint64_t any = 0, all = ~uint64_t(0);
    for (const Candidate& c : items) any |= c.order(), all &= c.order();
    const uint64_t differ = any ^ all;
    const int top = differ == 0 ? 0 : 64 - __builtin_clzll(differ);
    Candidate* first = items.data();
    if (top == 0) return std::sort(first, first + items.size()); // one key: by id
    std::vector<std::pair<Candidate*, Candidate*>> buckets;
    sort_detail::place_by_digit(
        first, first + items.size(), top,
        [&](Candidate* b, Candidate* e, int) { buckets.emplace_back(b, e); });
    const int next = std::max(0, top - sort_detail::kPlaceBits);
    parallel.for_each(
        buckets.size(),
        [&](size_t k) { sort_detail::place_sort(buckets[k].first, buckets[k].second, next); }, 1);
}

// Merges `from` (sorted) into `into` (sorted), in place from the back: the one sorted order of
// both. `from` is usually much the shorter: the place of each of its items is found by a search
// galloping back from the last one's, and the items of `into` between moved as one block.
template <class Vector> void merge_candidates(Vector& into, const Vector& from) {
    size_t i = into.size(), j = from.size(), k = i + j;
    into.resize(k);
    while (j > 0) {
        const auto& item = from[--j];
        // The first of into[0, i) that goes after item: into[low, high) holds it.
        size_t high = i, step = 1;
        while (step <= high && item < into[high - step]) high -= step, step *= 2;
        size_t low = high >= step ? high - step : 0;
        high = std::upper_bound(into.begin() + low, into.begin() + high, item) - into.begin();
        std::move_backward(into.begin() + high, into.begin() + i, into.begin() + k);
        k -= i - high;
        i = high;
        into[--k] = item;
    }
}

} // namespace ddsimp::detail
