// Determinism: the same input and options give the same bytes, run after run, whatever the
// thread count and wherever the input lives in memory.
#include "test_surfaces.h"

#include <oneapi/tbb/global_control.h>

namespace ddsimp::test {
namespace {

class Determinism : public ::testing::TestWithParam<Config> {};
INSTANTIATE_TEST_SUITE_P(All, Determinism, ::testing::ValuesIn(all_configs()), config_name);

// Large enough for threaded set-up stages to split work (20480 triangles), with data that makes
// many weights equal (a step: ties must be broken the same way every time).
Surface big_input() {
    Surface s = with_test_fields(icosphere(5));
    add_field(s, "step", 1,
              [](const Vec3& p) { return std::vector<double>{p[2] > 0.1 ? 1.0 : 0.0}; });
    return s;
}

// A flat grid with constant data: every interior vertex weighs exactly the same.
Surface tie_input() {
    Surface s = grid(40, 40);
    add_field(s, "c", 1, [](const Vec3&) { return std::vector<double>{1.0}; });
    return s;
}

void expect_same_result(const Result& a, const Result& b) {
    EXPECT_TRUE(same_bytes(a.surface, b.surface));
    EXPECT_EQ(a.operations, b.operations);
    EXPECT_EQ(a.triangles_out, b.triangles_out);
    EXPECT_EQ(a.stop, b.stop);
}

TEST_P(Determinism, TwoRunsGiveTheSameBytes) {
    for (const Surface& in : {big_input(), tie_input()}) {
        Options o = options_for(GetParam());
        o.keep_fraction = 0.1;
        expect_same_result(simplify(in, o), simplify(in, o));
    }
}

TEST_P(Determinism, ThreadCountDoesNotMatter) {
    // oneTBB gives an arena no more workers than the machine has cores unless allowed more: the
    // thread counts below then really run on that many threads, also on a two-core machine.
    oneapi::tbb::global_control allow(oneapi::tbb::global_control::max_allowed_parallelism, 17);
    for (const Surface& in : {big_input(), tie_input()}) {
        Options o = options_for(GetParam());
        o.keep_fraction = 0.1;
        o.threads = 1;
        Result one = simplify(in, o);
        for (int threads : {0, 2, 3, 4, 8, 16}) { // 0: every hardware thread
            o.threads = threads;
            expect_same_result(one, simplify(in, o));
        }
    }
}

// A copy of the input at another address (and the options rebuilt) gives the same bytes: nothing
// may depend on pointer values (hash maps keyed by address, sorting by address).
TEST_P(Determinism, InputAddressDoesNotMatter) {
    Surface in = big_input();
    Options o = options_for(GetParam());
    o.keep_fraction = 0.2;
    Result a = simplify(in, o);
    std::vector<Surface> elsewhere(3, in); // different heap blocks
    Options p = options_for(GetParam());
    p.keep_fraction = 0.2;
    expect_same_result(a, simplify(elsewhere[2], p));
}

// A progress callback only observes: with or without it, the same bytes.
TEST_P(Determinism, ProgressCallbackDoesNotChangeTheResult) {
    Surface in = tie_input();
    Options o = options_for(GetParam());
    Result plain = simplify(in, o);
    o.progress = [](double) { return true; };
    expect_same_result(plain, simplify(in, o));
}

TEST_P(Determinism, ProgressiveRecordThreadCountDoesNotMatter) {
    Surface in = big_input();
    Options o = options_for(GetParam());
    o.keep_fraction = 0.05;
    o.threads = 1;
    ProgressiveRecord one = ProgressiveRecord::build(in, o);
    oneapi::tbb::global_control allow(oneapi::tbb::global_control::max_allowed_parallelism, 8);
    o.threads = 7;
    ProgressiveRecord two = ProgressiveRecord::build(in, o);
    ASSERT_EQ(one.operations(), two.operations());
    for (size_t n : {size_t(15000), size_t(5000), size_t(1100)})
        EXPECT_TRUE(same_bytes(one.level(n), two.level(n))) << n;
}

} // namespace
} // namespace ddsimp::test
