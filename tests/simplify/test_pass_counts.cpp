// The passes' counts (pass_counts.h), which the speed benchmark reports: consistent with the run
// they count, and the same on any number of threads, as the passes are.
#include "pass_counts.h"
#include "test_surfaces.h"

#include <oneapi/tbb/global_control.h>

namespace ddsimp::test {
namespace {

struct Counts {
    size_t passes, walked, taken, waited, refused;
    bool operator==(const Counts&) const = default;
};

Counts counted_run(const Surface& in, Options o) {
    detail::PassCounts& counts = detail::pass_counts();
    counts.reset();
    const Result r = simplify(in, o);
    EXPECT_LT(r.triangles_out, in.triangle_count());
    const Counts c{counts.passes.load(), counts.walked.load(), counts.taken.load(),
                   counts.waited.load(), counts.refused.load()};
    // A pass applies its taken operations up to the target: the last pass may take more.
    EXPECT_GE(c.taken, r.operations);
    EXPECT_LT(c.taken, r.operations + in.triangle_count());
    // Each check was of a candidate the walk selected; the walk also passes over candidates next
    // to selected ones, which are not checked.
    EXPECT_GT(c.walked, c.taken + c.waited + c.refused);
    return c;
}

class PassCounts : public ::testing::TestWithParam<Config> {};
INSTANTIATE_TEST_SUITE_P(All, PassCounts, ::testing::ValuesIn(all_configs()), config_name);

TEST_P(PassCounts, AreConsistentAndTheSameOnAnyThreadCount) {
    oneapi::tbb::global_control allow(oneapi::tbb::global_control::max_allowed_parallelism, 4);
    const Surface in = with_test_fields(torus(30, 12));
    Options o = options_for(GetParam());
    o.keep_fraction = 0.1;
    o.threads = 1;
    const Counts one = counted_run(in, o);
    EXPECT_GT(one.passes, 1u);
    // The torus's data makes some plans heavier than their keys, and its coarse end refuses.
    EXPECT_GT(one.waited + one.refused, 0u);
    o.threads = 4;
    EXPECT_EQ(counted_run(in, o), one);
}

} // namespace
} // namespace ddsimp::test
