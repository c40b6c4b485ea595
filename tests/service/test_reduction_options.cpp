// protocol/reduction_options.h: the one mapping between a Request (or a session's View) and
// ddsimp::Options: the library's defaults for unset fields, floats read as their decimals, the
// library's check, and result keys derived from the options.
#include "ddsimp/protocol/reduction_options.h"

#include <gtest/gtest.h>

namespace ddsimp::protocol {
namespace {

TEST(ReductionOptions, AFloatIsReadAsTheDecimalItWasTypedAs) {
    EXPECT_EQ(from_wire(0.3f), 0.3);
    EXPECT_EQ(from_wire(0.7f), 0.7);
    EXPECT_EQ(from_wire(0.5f), 0.5);
    EXPECT_EQ(from_wire(0.0f), 0.0);
    EXPECT_EQ(from_wire(1.0f), 1.0);
    EXPECT_NE(double(0.3f), 0.3); // what a plain conversion would give
}

TEST(ReductionOptions, AnEmptyRequestHasTheLibrarysDefaults) {
    v1::Request r;
    r.set_alpha(float(Options{}.alpha));
    const Options o = options_from(r);
    const Options library;
    EXPECT_EQ(o.alpha, library.alpha);
    EXPECT_EQ(o.strategy, library.strategy);
    EXPECT_EQ(o.placement, library.placement);
    EXPECT_EQ(o.data_placement, library.data_placement);
    EXPECT_EQ(o.terms, library.terms);
    EXPECT_EQ(o.feature_angle, library.feature_angle); // the wire's 0 is "none", as 180 is
    EXPECT_EQ(o.keep_fraction, 0.0);                   // the levels come from keep

    v1::ReductionDefaults d;
    set_defaults(d);
    EXPECT_EQ(d.alpha(), library.alpha);
    EXPECT_EQ(from_wire(d.placement()), library.placement);
    EXPECT_EQ(from_wire(d.data_placement()), library.data_placement);
    EXPECT_EQ(d.feature_angle(), library.feature_angle);
}

TEST(ReductionOptions, OptionsSurviveTheWireExactly) {
    Options o;
    o.alpha = 0.123456789012345;
    o.strategy = Strategy::VertexRemoval;
    o.placement = Placement::VolumePreserving;
    o.data_placement = DataPlacement::Interpolated;
    o.terms = Terms::AngleDeficitGradient;
    o.gradient_fields = {"pressure", "velocity"};
    o.feature_angle = 45;
    v1::Request r;
    set_options(r, o);
    v1::Request parsed;
    ASSERT_TRUE(parsed.ParseFromString(r.SerializeAsString()));
    const Options back = options_from(parsed);
    EXPECT_EQ(back.alpha, o.alpha);
    EXPECT_EQ(back.strategy, o.strategy);
    EXPECT_EQ(back.placement, o.placement);
    EXPECT_EQ(back.data_placement, o.data_placement);
    EXPECT_EQ(back.terms, o.terms);
    EXPECT_EQ(back.gradient_fields, o.gradient_fields);
    EXPECT_EQ(back.feature_angle, 45.0);
    EXPECT_EQ(result_key("s", back), result_key("s", o));

    // A client that sends only the float alpha still means 0.3.
    v1::Request old;
    old.set_alpha(0.3f);
    EXPECT_EQ(options_from(old).alpha, 0.3);
}

TEST(ReductionOptions, OutOfRangeValuesAreRefusedByTheLibrarysCheck) {
    v1::Request r;
    r.set_alpha_exact(1.5);
    EXPECT_THROW(options_from(r), InputError);
    r.set_alpha_exact(0.5);
    r.set_feature_angle(-3);
    EXPECT_THROW(options_from(r), InputError);
    v1::View v;
    set_alpha(v, -0.1);
    EXPECT_THROW(options_from(v), InputError);
}

TEST(ReductionOptions, TheKeyChangesWithEveryOptionThatChangesTheOutput) {
    const Options base;
    const std::string key = result_key("surface", base);
    EXPECT_EQ(key, result_key("surface", Options{}));
    EXPECT_NE(key, result_key("other", base));
    auto differs = [&](auto change) {
        Options o = base;
        change(o);
        return result_key("surface", o) != key;
    };
    EXPECT_TRUE(differs([](Options& o) { o.alpha = double(0.5f) + 1e-12; }));
    EXPECT_TRUE(differs([](Options& o) { o.strategy = Strategy::VertexRemoval; }));
    EXPECT_TRUE(differs([](Options& o) { o.placement = Placement::Midpoint; }));
    EXPECT_TRUE(differs([](Options& o) { o.data_placement = DataPlacement::Interpolated; }));
    EXPECT_TRUE(differs([](Options& o) { o.terms = Terms::AngleDeficitGradient; }));
    EXPECT_TRUE(differs([](Options& o) { o.feature_angle = 60; }));
    EXPECT_TRUE(differs([](Options& o) { o.gradient_fields = {"f"}; }));
    // Not part of what is computed: the level's target and the thread count.
    EXPECT_FALSE(differs([](Options& o) { o.keep_fraction = 0.5; }));
    EXPECT_FALSE(differs([](Options& o) { o.threads = 4; }));
}

TEST(ReductionOptions, KeepCountsAsTheLibraryCounts) {
    Options o;
    o.keep_fraction = 0.3;
    EXPECT_EQ(target_for_keep(0.3f, 10), target_triangles(o, 10));
    o.keep_fraction = 0.1;
    EXPECT_EQ(target_for_keep(0.1f, 1180725), target_triangles(o, 1180725));
}

} // namespace
} // namespace ddsimp::protocol
