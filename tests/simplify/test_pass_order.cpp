// pass_order.h (internal): candidates sorted by key, then id, by counting passes, and merged into
// a sorted order; both must give what a comparison sort of all candidates gives.
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
    return a.order() != b.order() ? a.order() < b.order() : a.id < b.id;
}

TEST(PassOrder, CountingSortEqualsAComparisonSort) {
    // Few candidates (comparison sort), many (counting passes), few and many distinct keys, and
    // the counting passes in one piece or in several on threads.
    for (int threads : {1, 3})
        for (size_t n : {100u, 5000u, 200000u})
            for (uint32_t distinct : {3u, 1000u, 1u << 30}) {
                const std::vector<Candidate> input = random_candidates(n, distinct, uint32_t(n));
                std::vector<Candidate> want = input;
                std::sort(want.begin(), want.end(), lighter);
                std::vector<Candidate> got = input, scratch;
                Parallel parallel(threads);
                sort_candidates(got, scratch, parallel);
                ASSERT_EQ(got.size(), n);
                for (size_t i = 0; i < n; ++i) {
                    ASSERT_EQ(got[i].id, want[i].id)
                        << threads << " threads, n " << n << ", at " << i;
                    ASSERT_EQ(got[i].order(), want[i].order()) << "n " << n << ", at " << i;
                }
            }
}

TEST(PassOrder, MergingEqualsSortingAll) {
    // The candidates split into a kept order and the ones ranked again (none, a few, about as
    // many, all), each sorted, merged: the order of all of them sorted, ties in id order.
    std::mt19937 random(11);
    for (uint32_t distinct : {2u, 50u, 1u << 30})
        for (size_t fresh_every : {0u, 1u, 2u, 37u, 1000u}) {
            const std::vector<Candidate> all = random_candidates(20000, distinct, distinct);
            std::vector<Candidate> kept, fresh;
            for (const Candidate& c : all)
                (fresh_every > 0 && random() % fresh_every == 0 ? fresh : kept).push_back(c);
            std::sort(kept.begin(), kept.end(), lighter);
            std::sort(fresh.begin(), fresh.end(), lighter);
            merge_candidates(kept, fresh);
            std::vector<Candidate> want = all;
            std::sort(want.begin(), want.end(), lighter);
            ASSERT_EQ(kept.size(), want.size());
            for (size_t i = 0; i < want.size(); ++i) {
                ASSERT_EQ(kept[i].id, want[i].id) << distinct << " keys, at " << i;
                ASSERT_EQ(kept[i].order(), want[i].order()) << distinct << " keys, at " << i;
            }
        }
}

TEST(PassOrder, NegativeZeroAndZeroAreEqualKeys) {
    EXPECT_EQ(Candidate::make({-0.0f, 1}, 0).order(), Candidate::make({0.0f, 1}, 0).order());
    EXPECT_LT(Candidate::make({-1.0f, 0}, 0).order(), Candidate::make({0.0f, 0}, 0).order());
    EXPECT_EQ(Candidate::make({2.5f, 0}, 0).weight(), 2.5f);
}

} // namespace
} // namespace ddsimp::detail
