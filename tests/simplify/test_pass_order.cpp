// pass_order.h (internal): candidates sorted by key, then id, by counting passes or in place, and
// merged into a sorted order; each must give what a comparison sort of all candidates gives.
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

// Sorts `got` with counting passes (in_place false) or in place, on `threads` threads, and
// expects the comparison sort's order of it.
void expect_sorted_as_compared(std::vector<Candidate> got, bool in_place, int threads) {
    std::vector<Candidate> want = got;
    std::sort(want.begin(), want.end(), lighter);
    std::vector<Candidate> scratch;
    Parallel parallel(threads);
    if (in_place)
        sort_candidates_in_place(got, parallel);
    else
        sort_candidates(got, scratch, parallel);
    ASSERT_EQ(got.size(), want.size());
    for (size_t i = 0; i < got.size(); ++i) {
        ASSERT_EQ(got[i].id, want[i].id) << (in_place ? "in place, " : "") << threads
                                         << " threads, n " << got.size() << ", at " << i;
        ASSERT_EQ(got[i].order(), want[i].order()) << "n " << got.size() << ", at " << i;
    }
}

TEST(PassOrder, CountingSortEqualsAComparisonSort) {
    // Few candidates (comparison sort), many (counting passes), few and many distinct keys, and
    // the counting passes in one piece or in several on threads.
    for (int threads : {1, 3})
        for (size_t n : {100u, 5000u, 200000u})
            for (uint32_t distinct : {3u, 1000u, 1u << 30})
                expect_sorted_as_compared(random_candidates(n, distinct, uint32_t(n)), false,
                                          threads);
}

TEST(PassOrder, InPlaceSortEqualsAComparisonSort) {
    // Few candidates (comparison sort), many (buckets by digit, then by comparison), one key
    // for all (by id alone), few and many distinct keys, in id order or shuffled, the first
    // digit's buckets sorted on one thread or on several.
    std::mt19937 random(5);
    for (int threads : {1, 3})
        for (size_t n : {50u, 5000u, 200000u})
            for (uint32_t distinct : {1u, 3u, 1000u, 1u << 30}) {
                std::vector<Candidate> c = random_candidates(n, distinct, uint32_t(n) + distinct);
                expect_sorted_as_compared(c, true, threads);
                std::shuffle(c.begin(), c.end(), random);
                expect_sorted_as_compared(c, true, threads);
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
