// The order of one pass: every candidate (an edge or a vertex) with its key, sorted lightest
// first by a stable radix sort, so that equal keys keep the candidates' id order and the order is
// total and deterministic. A pass selects from the lightest part of this order (see
// Simplifier::run_pass).
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

// A candidate with its key packed into 48 bits that order as (weight, tie): each float mapped to
// an unsigned integer in the same order (-0 first made +0, as the float comparison equates
// them), the weight's 32 bits above the tie's top 16 (its sign, exponent and 7 bits of mantissa:
// ties closer than about 1% count as equal and go by id).
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
        return {uint64_t(bits(k.weight)) << 16 | bits(k.tie) >> 16, id};
    }
    float weight() const {
        uint32_t u = uint32_t(order >> 16);
        u = u & 0x80000000u ? u & 0x7fffffffu : ~u;
        float f;
        std::memcpy(&f, &u, sizeof f);
        return f;
    }
};

inline constexpr int kKeyDigits = 4, kDigitBits = 12; // 48 bits of key
inline constexpr size_t kDigitValues = size_t(1) << kDigitBits;
inline uint32_t digit(const Candidate& c, int d) {
    return uint32_t(c.order >> (kDigitBits * d)) & (kDigitValues - 1);
}

// Sorts `items`, which come in id order, by key, then by id: stable counting passes over the
// key's 12-bit digits, lowest first (a digit on which all items agree is skipped); a comparison
// sort for a few items. `scratch` is reused between calls.
template <class Vector> void sort_candidates(Vector& items, Vector& scratch) {
    const size_t n = items.size();
    if (n < kDigitValues) {
        std::sort(items.begin(), items.end(), [](const Candidate& a, const Candidate& b) {
            return a.order != b.order ? a.order < b.order : a.id < b.id;
        });
        return;
    }
    scratch.resize(n);
    std::vector<uint32_t> count(kKeyDigits * kDigitValues, 0);
    for (const Candidate& c : items)
        for (int d = 0; d < kKeyDigits; ++d) ++count[d * kDigitValues + digit(c, d)];
    for (int d = 0; d < kKeyDigits; ++d) {
        uint32_t* bucket = &count[d * kDigitValues];
        if (bucket[digit(items[0], d)] == n) continue; // one value: no change
        uint32_t sum = 0;
        for (size_t b = 0; b < kDigitValues; ++b) {
            const uint32_t c = bucket[b];
            bucket[b] = sum;
            sum += c;
        }
        for (const Candidate& c : items) scratch[bucket[digit(c, d)]++] = c;
        items.swap(scratch);
    }
}

// The `count` lightest of a pass's candidates without holding them all: add() counts each one's
// top key digit, bound(count) finds the highest top digit the lightest `count` need, and keeps()
// then says which to collect (in id order) and sort: the lightest `count` first, perhaps followed
// by more. The same first `count` as sorting all of them.
class LightestShare {
public:
    void add(const Candidate& c) { ++histogram_[digit(c, kKeyDigits - 1)], ++total_; }
    size_t total() const { return total_; }
    void bound(size_t count) {
        last_ = uint32_t(kDigitValues - 1);
        if (count >= total_ || total_ < kDigitValues) return; // all of them
        last_ = 0;
        for (size_t sum = 0; sum + histogram_[last_] < count;) sum += histogram_[last_++];
    }
    bool keeps(const Candidate& c) const { return digit(c, kKeyDigits - 1) <= last_; }

private:
    std::vector<uint32_t> histogram_ = std::vector<uint32_t>(kDigitValues, 0);
    size_t total_ = 0;
    uint32_t last_ = 0;
};

} // namespace ddsimp::detail
