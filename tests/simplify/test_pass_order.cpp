// pass_order.h (internal): runs_in_id_order cuts the lightest share into runs and puts each run in
// id order by counting passes; the result must be what a comparison sort of each run gives.
#include "pass_order.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

namespace ddsimp::detail {
namespace {

// `n` candidates with distinct ids below `id_limit`, in a shuffled (key) order.
std::vector<Candidate> shuffled_candidates(size_t n, uint32_t id_limit, uint32_t seed) {
    std::mt19937 random(seed);
    std::vector<uint32_t> ids(id_limit);
    for (uint32_t i = 0; i < id_limit; ++i) ids[i] = i;
    std::shuffle(ids.begin(), ids.end(), random);
    std::vector<Candidate> c(n);
    for (size_t i = 0; i < n; ++i) c[i] = {uint64_t(i), ids[i]};
    return c;
}

TEST(PassOrder, RunsInIdOrderEqualsSortingEachRun) {
    // Short runs (comparison sort), long runs (counting passes), ids needing one, two and three
    // 11-bit digits, and a share that leaves a tail untouched.
    for (size_t n : {100u, 5000u, 100000u})
        for (uint32_t id_limit : {uint32_t(2000), uint32_t(1) << 20, uint32_t(5000000)}) {
            if (id_limit < n) continue;
            const std::vector<Candidate> input = shuffled_candidates(n, id_limit, uint32_t(n));
            const size_t share = n - n / 7, runs = 8;
            std::vector<Candidate> want = input, got = input, scratch;
            for (size_t r = 0; r < runs; ++r)
                std::sort(want.begin() + std::ptrdiff_t(share * r / runs),
                          want.begin() + std::ptrdiff_t(share * (r + 1) / runs),
                          [](const Candidate& a, const Candidate& b) { return a.id < b.id; });
            runs_in_id_order(got, share, runs, scratch);
            ASSERT_EQ(got.size(), want.size());
            for (size_t i = 0; i < n; ++i) {
                ASSERT_EQ(got[i].id, want[i].id)
                    << "n " << n << ", ids < " << id_limit << ", at " << i;
                ASSERT_EQ(got[i].order, want[i].order) << "n " << n << ", at " << i;
            }
        }
}

} // namespace
} // namespace ddsimp::detail
