// The order of the candidates kept between passes: after every ranking of a run it must be the
// order that ranking every id afresh gives (order_audit.h), whatever the strategy, placement,
// terms and thread count, on surfaces with boundaries, holes, feature lines and thin parts.
#include "order_audit.h"
#include "test_surfaces.h"

#include <oneapi/tbb/global_control.h>

namespace ddsimp::test {
namespace {

class KeptOrder : public ::testing::TestWithParam<Config> {
protected:
    void SetUp() override {
        audit().rankings = 0, audit().mismatches = 0;
        audit().on = true;
    }
    void TearDown() override { audit().on = false; }
    static detail::OrderAudit& audit() { return detail::order_audit(); }

    // Runs `in` down to `keep` and expects every ranking of the run to be audited and to match.
    void expect_fresh_order(const Surface& in, Options o, double keep) {
        o.keep_fraction = keep;
        const size_t before = audit().rankings;
        const Result r = simplify(in, o);
        EXPECT_LT(r.triangles_out, in.triangle_count());
        EXPECT_GT(audit().rankings.load(), before + 1) << "more than one pass was ranked";
        EXPECT_EQ(audit().mismatches.load(), 0u);
    }
};
INSTANTIATE_TEST_SUITE_P(All, KeptOrder, ::testing::ValuesIn(all_configs()), config_name);

// Surfaces whose operations change kinds, lines and boundaries, with data that drives keys.
std::vector<Surface> audited_surfaces() {
    std::vector<Surface> s;
    s.push_back(with_test_fields(icosphere(3)));
    s.push_back(with_test_fields(grid_with_hole(24, 8, 14)));
    s.push_back(with_test_fields(fin_on_grid(20)));
    s.push_back(with_test_fields(thin_blade()));
    s.push_back(with_test_fields(torus(30, 12)));
    // Complex vertices: stars of several fans, whose refusals are found otherwise.
    s.push_back(with_test_fields(corner_touching_grids(12)));
    s.push_back(with_test_fields(tetrahedron_on_grid(16)));
    return s;
}

TEST_P(KeptOrder, EqualsRankingAfreshWithErrorQuadrics) {
    for (const Surface& in : audited_surfaces())
        for (double alpha : {0.0, 1.0}) {
            Options o = options_for(GetParam());
            o.alpha = alpha;
            o.threads = 1;
            expect_fresh_order(in, o, 0.05);
        }
}

TEST_P(KeptOrder, EqualsRankingAfreshWithThePapersTerms) {
    for (const Surface& in : audited_surfaces()) {
        Options o = options_for(GetParam());
        o.terms = Terms::AngleDeficitGradient;
        o.threads = 1;
        expect_fresh_order(in, o, 0.05);
    }
}

TEST_P(KeptOrder, EqualsRankingAfreshWithFeatureLinesAndInterpolatedData) {
    for (const Surface& in : audited_surfaces()) {
        Options o = options_for(GetParam());
        o.feature_angle = 40;
        o.data_placement = DataPlacement::Interpolated;
        o.threads = 1;
        expect_fresh_order(in, o, 0.05);
    }
}

// Operations applied side by side mark the same ids from several threads.
TEST_P(KeptOrder, EqualsRankingAfreshOnSeveralThreads) {
    oneapi::tbb::global_control allow(oneapi::tbb::global_control::max_allowed_parallelism, 4);
    for (const Surface& in : audited_surfaces()) {
        Options o = options_for(GetParam());
        o.threads = 4;
        expect_fresh_order(in, o, 0.05);
    }
}

} // namespace
} // namespace ddsimp::test
