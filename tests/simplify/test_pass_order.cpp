// pass_order.h (internal): a pass's candidates sorted by key, then id, by counting passes; the
// lightest share must be what a comparison sort of all candidates gives.
#include "pass_order.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

namespace ddsimp::detail {
namespace {

// `n` candidates in id order with keys drawn from `distinct` values (many ties when few).
std::vector<Candidate> random_candidates(size_t n, uint32_t distinct, uint32_t seed) {
    std::mt19937 random(seed);
    std::uniform_int_distribution<uint32_t> pick(0, distinct - 1);
    std::vector<Candidate> c(n);
    for (size_t i = 0; i < n; ++i) {
        const float weight = float(pick(random)) * 0.37f, tie = float(pick(random) % 7);
        c[i] = Candidate::make({weight, tie}, uint32_t(i));
    }
    return c;
}

bool lighter(const Candidate& a, const Candidate& b) {
    return a.order != b.order ? a.order < b.order : a.id < b.id;
}

TEST(PassOrder, LightestShareSortedEqualsAComparisonSort) {
    // Few candidates (comparison sort), many (counting passes), few and many distinct keys,
    // shares from one candidate to all of them, and the counting passes in one piece or in
    // several on threads.
    for (int threads : {1, 3})
        for (size_t n : {100u, 5000u, 200000u})
            for (uint32_t distinct : {3u, 1000u, 1u << 30})
                for (double share : {0.0, 0.25, 1.0}) {
                    const std::vector<Candidate> input =
                        random_candidates(n, distinct, uint32_t(n));
                    std::vector<Candidate> want = input;
                    std::sort(want.begin(), want.end(), lighter);
                    const size_t count = std::max<size_t>(1, size_t(share * double(n)));
                    LightestShare lightest;
                    for (const Candidate& c : input) lightest.add(c);
                    lightest.bound(count);
                    std::vector<Candidate> got, scratch;
                    for (const Candidate& c : input)
                        if (lightest.keeps(c)) got.push_back(c);
                    Parallel parallel(threads);
                    sort_candidates(got, scratch, parallel);
                    ASSERT_GE(got.size(), count);
                    for (size_t i = 0; i < count; ++i) {
                        ASSERT_EQ(got[i].id, want[i].id)
                            << threads << " threads, n " << n << ", at " << i;
                        ASSERT_EQ(got[i].order, want[i].order) << "n " << n << ", at " << i;
                    }
                }
}

TEST(PassOrder, TheShareOfKeysIsTheShareOfTheirCandidates) {
    // The ranking counts and keeps keys by their weight alone: the same as their candidates.
    std::mt19937 random(7);
    std::uniform_real_distribution<float> weight(-2.0f, 1e6f), tie(0.0f, 10.0f);
    std::vector<Key> keys(50000);
    for (Key& k : keys) k = {random() % 5 == 0 ? 0.0f : weight(random), tie(random)};
    LightestShare by_key, by_candidate;
    for (const Key& k : keys) by_key.add(k), by_candidate.add(Candidate::make(k, 0));
    by_key.bound(keys.size() / 4), by_candidate.bound(keys.size() / 4);
    size_t kept = 0;
    for (const Key& k : keys) {
        ASSERT_EQ(by_key.keeps(k), by_candidate.keeps(Candidate::make(k, 0)));
        kept += by_key.keeps(k);
    }
    EXPECT_GE(kept, keys.size() / 4);
    EXPECT_LT(kept, keys.size());
}

TEST(PassOrder, NegativeZeroAndZeroAreEqualKeys) {
    EXPECT_EQ(Candidate::make({-0.0f, 1}, 0).order, Candidate::make({0.0f, 1}, 0).order);
    EXPECT_LT(Candidate::make({-1.0f, 0}, 0).order, Candidate::make({0.0f, 0}, 0).order);
    EXPECT_EQ(Candidate::make({2.5f, 0}, 0).weight(), 2.5f);
}

} // namespace
} // namespace ddsimp::detail
