// simplify(), for every strategy/placement: targets, stop reasons, topology on every builder,
// fields carried, alpha, boundary, feature edges, orientation, cancellation, bad options.
// Behaviour specific to one strategy is in test_edge_collapse.cpp and test_vertex_removal.cpp.
#include "test_surfaces.h"

#include <thread>

namespace ddsimp::test {
namespace {

class Simplify : public ::testing::TestWithParam<Config> {
protected:
    Options options() const { return options_for(GetParam()); }
};

INSTANTIATE_TEST_SUITE_P(All, Simplify, ::testing::ValuesIn(all_configs()), config_name);

// --- targets -------------------------------------------------------------------------------------

// Each operation removes at most 2 triangles on a manifold surface (an interior edge collapse
// removes its 2 triangles; removing an interior vertex of degree d removes d and adds d - 2, a
// boundary one removes d and adds d - 1). So a run that stops as soon as it is at or below the
// target ends within 2 triangles below it.
void expect_target(const Surface& in, const Options& o, size_t target) {
    Result r = simplify(in, o);
    EXPECT_EQ(r.stop, StopReason::TargetReached) << describe(r.stop);
    EXPECT_TRUE(r.target_reached);
    EXPECT_EQ(r.triangles_in, in.triangle_count());
    EXPECT_EQ(r.triangles_out, r.surface.triangle_count());
    EXPECT_LE(r.triangles_out, target);
    EXPECT_GE(r.triangles_out + 2, target);
    EXPECT_GE(2 * r.operations, r.triangles_in - r.triangles_out);
    EXPECT_TRUE(well_formed(r.surface));
    EXPECT_TRUE(fields_carried(in, r.surface));
    EXPECT_TRUE(topology_kept(analyze_topology(in), analyze_topology(r.surface)));
}

// 40x40 grid: 3200 triangles; 10% = 320.
TEST_P(Simplify, KeepFractionOnAFineGrid) {
    Options o = options();
    o.keep_fraction = 0.1;
    expect_target(with_test_fields(grid(40, 40)), o, 320);
}

// Icosphere level 4: 5120 triangles; 10% = 512.
TEST_P(Simplify, KeepFractionOnASphere) {
    Options o = options();
    o.keep_fraction = 0.1;
    expect_target(with_test_fields(icosphere(4)), o, 512);
}

TEST_P(Simplify, TriangleCountOnASphere) {
    Options o = options();
    o.target_triangles = 1001;
    expect_target(with_test_fields(icosphere(4)), o, 1001);
}

// "the first that is set wins: target_triangles, then keep_fraction"
TEST_P(Simplify, TriangleCountWinsOverKeepFraction) {
    Options o = options();
    o.target_triangles = 2000;
    o.keep_fraction = 0.1;
    expect_target(with_test_fields(grid(40, 40)), o, 2000);
}

// A target at or above the input is met without any operation: the output is the input.
TEST_P(Simplify, TargetAlreadyMet) {
    Surface in = with_test_fields(grid(6, 6)); // 72 triangles
    for (size_t target : {size_t(72), size_t(1000)}) {
        Options o = options();
        o.target_triangles = target;
        Result r = simplify(in, o);
        EXPECT_EQ(r.stop, StopReason::TargetReached);
        EXPECT_TRUE(r.target_reached);
        EXPECT_EQ(r.operations, 0u);
        EXPECT_EQ(r.triangles_out, 72u);
        EXPECT_EQ(canonical_triangles(r.surface), canonical_triangles(in));
    }
    Options o = options();
    o.keep_fraction = 1.0;
    Result r = simplify(in, o);
    EXPECT_EQ(r.operations, 0u);
    EXPECT_TRUE(r.target_reached);
}

// --- stop reasons --------------------------------------------------------------------------------

// A tetrahedron is the smallest closed genus-0 surface: any collapse breaks the link condition
// (the edge's endpoints share two neighbours that are themselves adjacent, the result would be
// two triangles on the same three vertices); removing a vertex leaves a triangle hole bounded by
// the other three, re-triangulated as a duplicate of the opposite face. Nothing is removable.
TEST_P(Simplify, TetrahedronCannotBeReduced) {
    Surface in = with_test_fields(tetrahedron());
    Options o = options();
    o.keep_fraction = 0.0;
    Result r = simplify(in, o);
    EXPECT_EQ(r.stop, StopReason::NothingRemovable);
    EXPECT_FALSE(r.target_reached);
    EXPECT_EQ(r.triangles_out, 4u);
    EXPECT_EQ(r.operations, 0u);
    EXPECT_EQ(canonical_triangles(r.surface), canonical_triangles(in));
}

// A single triangle: its three vertices are boundary corners (turns of 90 and 135 degrees, more
// than the 20-degree line tolerance). A square: four 90-degree corners. Nothing is removable.
TEST_P(Simplify, SingleTriangleAndSquareCannotBeReduced) {
    for (const Surface& in : {with_test_fields(single_triangle()), with_test_fields(square())}) {
        Options o = options();
        o.target_triangles = 1;
        Result r = simplify(in, o);
        EXPECT_EQ(r.triangles_out, in.triangle_count());
        EXPECT_EQ(r.operations, 0u);
        if (in.triangle_count() == 1) {
            EXPECT_EQ(r.stop, StopReason::TargetReached); // 1 <= 1: already met
        } else {
            EXPECT_EQ(r.stop, StopReason::NothingRemovable);
            EXPECT_FALSE(r.target_reached);
        }
        EXPECT_EQ(canonical_triangles(r.surface), canonical_triangles(in));
    }
}

// max_weight with the paper's terms (Terms::AngleDeficitGradient): alpha = 0 (weights from data
// only) on a 40x40 grid with f = max(0, x - 0.5).
// Vertices with x < 0.5 see f = 0 at all neighbours: gradient 0. Vertices with x >= 0.5 (columns
// 20..40, 21 * 41 = 861 of 1681) have a horizontal neighbour with |df| = h (f's range 0.5): all
// the same gradient g > 0. Normalised to a mean of 1: 1681/861 = 1.95 for them, 0 for the rest.
// With max_weight 0.5 every element touching x >= 0.5 weighs > 0.5 (a vertex 1.95, an edge at
// least 1.95), the left half weighs 0: the left half is reduced, then the run stops at the
// bound. Cells with i >= 20 (1600 triangles) have only heavy vertices and stay; the 19 columns of
// cells left of x = 0.475 (1520 triangles) are weightless. 10% (320) cannot be reached.
Surface ramp_grid() {
    Surface s = grid(40, 40);
    add_field(s, "ramp", 1,
              [](const Vec3& p) { return std::vector<double>{std::max(0.0, p[0] - 0.5)}; });
    return s;
}

TEST_P(Simplify, WeightBoundStopsTheRun) {
    Surface in = ramp_grid();
    Options o = options();
    o.terms = Terms::AngleDeficitGradient;
    o.alpha = 0.0;
    o.max_weight = 0.5;
    o.keep_fraction = 0.1;
    Result r = simplify(in, o);
    EXPECT_EQ(r.stop, StopReason::WeightBound) << describe(r.stop);
    EXPECT_FALSE(r.target_reached);
    EXPECT_LT(r.triangles_out, 3200u - 1000u); // most of the left half's 1520 are gone
    EXPECT_GE(r.triangles_out, 1600u);         // the right half's 1600 are untouched
    // every vertex with x >= 0.5 is still there, exactly
    for (int j = 0; j <= 40; ++j)
        for (int i = 20; i <= 40; ++i)
            EXPECT_TRUE(has_vertex_at(r.surface, {double(i) / 40, double(j) / 40, 0}))
                << i << "," << j;
    EXPECT_TRUE(topology_kept(analyze_topology(in), analyze_topology(r.surface)));
}

// The bound is one of several stops: a target met first wins.
TEST_P(Simplify, TargetBeforeWeightBound) {
    Options o = options();
    o.terms = Terms::AngleDeficitGradient;
    o.alpha = 0.0;
    o.max_weight = 0.5;
    o.keep_fraction = 0.9; // 2880: reachable within the weightless left half
    Result r = simplify(ramp_grid(), o);
    EXPECT_EQ(r.stop, StopReason::TargetReached);
    EXPECT_TRUE(r.target_reached);
    EXPECT_LE(r.triangles_out, 2880u);
}

// max_weight 0 on a surface where every vertex weighs more than 0: nothing is done.
// f = x on a flat grid with alpha = 0: all gradients equal (sqrt 2, see test_weights), all
// weights 1 after normalisation.
TEST_P(Simplify, WeightBoundBeforeAnyOperation) {
    Surface in = grid(10, 10);
    add_field(in, "f", 1, [](const Vec3& p) { return std::vector<double>{p[0]}; });
    Options o = options();
    o.terms = Terms::AngleDeficitGradient;
    o.alpha = 0.0;
    o.max_weight = 0.5;
    Result r = simplify(in, o);
    EXPECT_EQ(r.stop, StopReason::WeightBound);
    EXPECT_FALSE(r.target_reached);
    EXPECT_EQ(r.operations, 0u);
    EXPECT_EQ(r.triangles_out, 200u);
}

// With the error quadrics (the default terms) the same ramp costs nothing where the data is
// linear: a collapse or removal within x <= 0.5 or within x >= 0.5 puts a vertex where the input's
// linear interpolation already has its (interpolated) value, so every such operation weighs 0 and
// a bound of 1e-9 stops nothing there. What stays is the kink x = 0.5: no output triangle may
// span it (its interpolation would differ from max(0, x - 0.5) inside), and every output vertex
// keeps data equal to max(0, x - 0.5) at its position. Edge collapse's data is interpolated:
// the operations are what is tested, not the level's fit afterwards, which lands each input
// sample on the stars near the point it went into and on a level this coarse (regions of
// hundreds of input triangles) can miss the triangle that covers it.
TEST_P(Simplify, ErrorQuadricsSimplifyLinearDataForFree) {
    Options o = options();
    o.data_placement = DataPlacement::Interpolated;
    o.alpha = 0.0;
    o.max_weight = 1e-9;
    o.keep_fraction = 0.05; // 160: each side needs ~2 x 41 triangles to keep the kink's vertices
    Result r = simplify(ramp_grid(), o);
    EXPECT_LT(r.triangles_out, 3200u / 4) << describe(r.stop);
    const Field& f = *r.surface.find_field("ramp");
    for (size_t v = 0; v < r.surface.vertex_count(); ++v) {
        const double x = r.surface.positions[3 * v];
        EXPECT_NEAR(f.values[v], std::max(0.0, x - 0.5), 1e-6) << "vertex " << v << " x " << x;
    }
    for (size_t t = 0; t < r.surface.triangle_count(); ++t) {
        double lo = 1, hi = 0;
        for (int c = 0; c < 3; ++c) {
            const double x = r.surface.positions[3 * r.surface.triangles[3 * t + c]];
            lo = std::min(lo, x), hi = std::max(hi, x);
        }
        EXPECT_FALSE(lo < 0.5 - 1e-6 && hi > 0.5 + 1e-6) << "triangle " << t << " spans the kink";
    }
    EXPECT_TRUE(topology_kept(analyze_topology(ramp_grid()), analyze_topology(r.surface)));
}

// A roof: the 40x40 grid folded along x = 0.5, z = 0.5 - |x - 0.5| (two planes at 45 degrees).
// The crease vertices have no angle deficit (the paper's curvature is blind to it), but moving one
// off the crease, or re-triangulating across it, leaves the two planes: with the error quadrics
// and alpha = 1 the operations that keep each plane exact weigh 0 and come first, and 10%
// (320 triangles, more than the ~2 x 41 each half needs to keep the crease's 41 vertices) is
// reached without any output triangle leaving the roof: every triangle's centroid is on it.
TEST_P(Simplify, ErrorQuadricsKeepACrease) {
    Surface in = grid(40, 40);
    for (size_t v = 0; v < in.vertex_count(); ++v)
        in.positions[3 * v + 2] = float(0.5 - std::abs(in.positions[3 * v] - 0.5));
    Options o = options();
    o.alpha = 1.0;
    o.keep_fraction = 0.1;
    Result r = simplify(in, o);
    EXPECT_TRUE(r.target_reached) << describe(r.stop);
    for (size_t t = 0; t < r.surface.triangle_count(); ++t) {
        double c[3] = {0, 0, 0};
        for (int k = 0; k < 3; ++k)
            for (int a = 0; a < 3; ++a)
                c[a] += r.surface.positions[3 * r.surface.triangles[3 * t + k] + a] / 3;
        EXPECT_NEAR(c[2], 0.5 - std::abs(c[0] - 0.5), 1e-5) << "triangle " << t;
    }
    EXPECT_TRUE(topology_kept(analyze_topology(in), analyze_topology(r.surface)));
}

// --- cancellation and progress -------------------------------------------------------------------

TEST_P(Simplify, ProgressIsReportedInOrder) {
    std::vector<double> seen;
    Options o = options();
    o.progress = [&](double f) {
        seen.push_back(f);
        return true;
    };
    Result r = simplify(with_test_fields(grid(60, 60)), o);
    EXPECT_TRUE(r.target_reached);
    ASSERT_FALSE(seen.empty()) << "progress was never called on 7200 triangles";
    EXPECT_TRUE(progress_in_order(seen));
}

// The service relies on this: progress is called on the calling thread only, whatever the threads.
TEST_P(Simplify, ProgressIsCalledOnTheCallingThread) {
    const std::thread::id caller = std::this_thread::get_id();
    size_t calls = 0, elsewhere = 0;
    Options o = options();
    o.threads = 4;
    o.progress = [&](double) {
        ++calls;
        elsewhere += std::this_thread::get_id() != caller;
        return true;
    };
    simplify(with_test_fields(grid(120, 120)), o);
    EXPECT_GT(calls, 3u);
    EXPECT_EQ(elsewhere, 0u);
}

TEST_P(Simplify, CancelledAtTheFirstCall) {
    Surface in = with_test_fields(grid(60, 60));
    Options o = options();
    o.progress = [](double) { return false; };
    Result r = simplify(in, o);
    EXPECT_EQ(r.stop, StopReason::Cancelled);
    EXPECT_FALSE(r.target_reached);
    EXPECT_LE(r.triangles_out, in.triangle_count());
    // what was done so far is still a sound surface
    EXPECT_TRUE(well_formed(r.surface));
    EXPECT_TRUE(fields_carried(in, r.surface));
    EXPECT_TRUE(topology_kept(analyze_topology(in), analyze_topology(r.surface)));
}

TEST_P(Simplify, CancelledLater) {
    Surface in = with_test_fields(grid(60, 60));
    int calls = 0;
    Options o = options();
    o.progress = [&](double) { return ++calls < 3; };
    Result r = simplify(in, o);
    EXPECT_EQ(r.stop, StopReason::Cancelled);
    EXPECT_FALSE(r.target_reached);
    EXPECT_TRUE(well_formed(r.surface));
    EXPECT_TRUE(topology_kept(analyze_topology(in), analyze_topology(r.surface)));
}

// Once the callback has said stop, it is not called again: a last call (e.g. progress(1.0))
// would tell a progress bar that the work completed when it was abandoned.
TEST_P(Simplify, NoProgressCallAfterCancelling) {
    Surface in = with_test_fields(grid(60, 60));
    std::vector<double> seen;
    Options o = options();
    o.progress = [&](double f) {
        seen.push_back(f);
        return seen.size() < 2;
    };
    Result r = simplify(in, o);
    EXPECT_EQ(r.stop, StopReason::Cancelled);
    EXPECT_EQ(seen.size(), 2u) << "last call: progress(" << seen.back() << ")";
}

// The set-up reports progress too: with nothing to remove, every call but the last comes from it,
// and it can be cancelled there.
TEST_P(Simplify, TheSetUpReportsProgressAndCanBeCancelled) {
    const Surface in = with_test_fields(grid(120, 120));
    Options o = options();
    o.keep_fraction = 1.0; // the target is met: no pass runs
    std::vector<double> seen;
    o.progress = [&](double f) {
        seen.push_back(f);
        return true;
    };
    const Result done = simplify(in, o);
    EXPECT_EQ(done.stop, StopReason::TargetReached);
    ASSERT_GT(seen.size(), 2u) << "the set-up never reported";
    EXPECT_EQ(seen.front(), 0.0);
    seen.clear();
    o.progress = [&](double f) {
        seen.push_back(f);
        return false;
    };
    const Result cancelled = simplify(in, o);
    EXPECT_EQ(cancelled.stop, StopReason::Cancelled);
    EXPECT_EQ(seen.size(), 1u);
    EXPECT_EQ(cancelled.operations, 0u);
    EXPECT_TRUE(well_formed(cancelled.surface));
    EXPECT_TRUE(topology_kept(analyze_topology(in), analyze_topology(cancelled.surface)));
}

// simplify() reports the level's fit after the run: more calls than the run alone makes (the
// record's build, which runs the same set-up and passes), and a cancel there ends it with the
// level as the run reached it, not fitted, and no call after.
TEST_P(Simplify, TheLevelFitReportsProgressAndCanBeCancelled) {
    const Surface in = with_test_fields(grid(120, 120));
    Options o = options();
    // One thread: the calls of the run are then the same in every run. On more, the checks beside
    // the selection walk report from the calling thread only, and how many of them it does varies.
    o.threads = 1;
    size_t run_calls = 0;
    o.progress = [&](double) {
        ++run_calls;
        return true;
    };
    const ProgressiveRecord record = ProgressiveRecord::build(in, o);
    const Surface as_run = record.after_as_recorded(record.operations());
    ASSERT_FALSE(same_bytes(record.after(record.operations()), as_run))
        << "the level is not fitted: nothing to watch";
    size_t calls = 0;
    o.progress = [&](double) {
        ++calls;
        return true;
    };
    EXPECT_EQ(simplify(in, o).stop, StopReason::TargetReached);
    EXPECT_GT(calls, run_calls + 1) << "the fit never reported";
    calls = 0;
    o.progress = [&](double) { return ++calls <= run_calls; }; // stop at the fit's first call
    const Result r = simplify(in, o);
    EXPECT_EQ(r.stop, StopReason::Cancelled);
    EXPECT_FALSE(r.target_reached);
    EXPECT_EQ(calls, run_calls + 1);
    EXPECT_EQ(r.operations, record.operations());
    EXPECT_TRUE(same_bytes(r.surface, as_run));
}

// --- options ---------------------------------------------------------------------------------

TEST_P(Simplify, RejectsInvalidOptions) {
    Surface in = with_test_fields(grid(4, 4));
    for (double alpha : {-0.1, 1.1, std::nan("")}) {
        Options o = options();
        o.alpha = alpha;
        EXPECT_THROW(simplify(in, o), InputError) << "alpha " << alpha;
    }
    for (double keep : {-0.5, std::nan("")}) {
        Options o = options();
        o.keep_fraction = keep;
        EXPECT_THROW(simplify(in, o), InputError) << "keep_fraction " << keep;
    }
    Options o = options();
    o.gradient_fields = {"no_such_field"};
    EXPECT_THROW(simplify(in, o), InputError);
}

// The public check names the option that is wrong and accepts the defaults.
TEST(CheckOptions, NamesTheOptionAndAcceptsDefaults) {
    EXPECT_NO_THROW(check_options(Options{}));
    const auto message = [](Options o) {
        try {
            check_options(o);
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    Options o;
    o.alpha = 1.5;
    EXPECT_NE(message(o).find("alpha"), std::string::npos) << message(o);
    o = Options{};
    o.feature_angle = 181;
    EXPECT_NE(message(o).find("feature angle"), std::string::npos) << message(o);
    o = Options{};
    o.threads = -1; // 0 is every hardware thread
    EXPECT_NE(message(o).find("threads"), std::string::npos) << message(o);
}

// The triangle target: a count wins over a fraction; a fraction counts as the library's run does.
TEST(CheckOptions, TargetTriangles) {
    Options o;
    o.keep_fraction = 0.1;
    EXPECT_EQ(target_triangles(o, 1000), 100u);
    EXPECT_EQ(target_triangles(o, 1009), 100u);
    o.keep_fraction = 0.3;
    EXPECT_EQ(target_triangles(o, 10), 3u); // 0.3 x 10 is 2.9999999999999996 in doubles
    o.target_triangles = 7;
    EXPECT_EQ(target_triangles(o, 1000), 7u);
}

TEST(Simplify, DescribeNamesEveryStopReason) {
    std::set<std::string> texts;
    for (StopReason r : {StopReason::TargetReached, StopReason::WeightBound,
                         StopReason::NothingRemovable, StopReason::Cancelled}) {
        std::string t = describe(r);
        EXPECT_FALSE(t.empty());
        texts.insert(t);
    }
    EXPECT_EQ(texts.size(), 4u);
}

// --- topology on every builder -------------------------------------------------------------------

struct Builder {
    const char* name;
    std::function<Surface()> build;
    bool reducible; // some operation is possible for every strategy (fine meshes)
    bool closed;    // closed and outward: the signed volume keeps its sign
};

std::vector<Builder> builders() {
    return {
        {"SingleTriangle", single_triangle, false, false},
        {"Square", square, false, false},
        {"Octagon", [] { return fan(8); }, false, false},
        {"Tetrahedron", tetrahedron, false, true},
        {"Octahedron", octahedron, false, true},
        {"Icosphere", [] { return icosphere(3); }, true, true},
        {"Grid", [] { return grid(16, 16); }, true, false},
        {"Cube", [] { return cube(5); }, true, true},
        {"Torus", [] { return torus(24, 12); }, true, true},
        {"TwoComponents", [] { return two_components(8); }, true, false},
        {"GridWithHole", [] { return grid_with_hole(16, 5, 11); }, true, false},
        {"Bowtie", bowtie, false, false},
        {"Fin", fin, false, false},
        {"CornerTouchingGrids", [] { return corner_touching_grids(8); }, true, false},
        {"FinOnGrid", [] { return fin_on_grid(12); }, true, false},
        {"TetrahedronOnGrid", [] { return tetrahedron_on_grid(12); }, true, false},
        {"Moebius", [] { return moebius(40); }, false, false},
    };
}

class SimplifyBuilder : public ::testing::TestWithParam<std::tuple<Config, int>> {};

// Run every builder as far as it goes (keep_fraction 0): the topology of the repaired input is
// kept, the output is well-formed, every field carried within range, complex vertices survive,
// and closed surfaces keep the sign of their volume.
TEST_P(SimplifyBuilder, KeepsTopology) {
    const Config& c = std::get<0>(GetParam());
    const Builder b = builders()[size_t(std::get<1>(GetParam()))];
    Surface in = with_test_fields(b.build());
    Surface repaired = in;
    validate(repaired);
    Options o = options_for(c);
    o.keep_fraction = 0.0;
    Result r = simplify(in, o);
    EXPECT_EQ(r.stop, StopReason::NothingRemovable) << describe(r.stop);
    EXPECT_FALSE(r.target_reached);
    EXPECT_EQ(r.triangles_out, r.surface.triangle_count());
    EXPECT_TRUE(well_formed(r.surface));
    EXPECT_TRUE(topology_kept(analyze_topology(repaired), analyze_topology(r.surface)));
    EXPECT_TRUE(fields_carried(repaired, r.surface));
    if (b.reducible) {
        EXPECT_LT(r.triangles_out, repaired.triangle_count());
    }
    for (const Vec3& p : nonmanifold_vertex_positions(repaired))
        EXPECT_TRUE(has_vertex_at(r.surface, p))
            << "complex vertex (" << p[0] << ", " << p[1] << ", " << p[2] << ") was removed";
    if (b.closed) {
        EXPECT_GT(signed_volume(r.surface), 0.0);
    }
}

INSTANTIATE_TEST_SUITE_P(All, SimplifyBuilder,
                         ::testing::Combine(::testing::ValuesIn(all_configs()),
                                            ::testing::Range(0, int(builders().size()))),
                         [](const ::testing::TestParamInfo<std::tuple<Config, int>>& i) {
                             return std::string(std::get<0>(i.param).name) + "_" +
                                    builders()[size_t(std::get<1>(i.param))].name;
                         });

// --- alpha ------------------------------------------------------------------------------------

size_t count_near(const Surface& s, const std::function<bool(const Vec3&)>& near) {
    size_t n = 0;
    for (size_t v = 0; v < s.vertex_count(); ++v) n += near(position(s, v));
    return n;
}

// A flat 40x40 grid with a data step between columns 19 (x = 0.475, f = 0) and 20 (x = 0.5,
// f = 1). Flat: curvature is 0 except at the 4 corners. With alpha = 1 the data is ignored; with
// alpha = 0 only the two step columns weigh anything, so they are removed last. At 10% the
// alpha = 0 result keeps more vertices within 0.0625 of the step than the alpha = 1 result.
TEST_P(Simplify, AlphaZeroKeepsTheDataStep) {
    Surface in = grid(40, 40);
    add_field(in, "step", 1,
              [](const Vec3& p) { return std::vector<double>{p[0] < 0.49 ? 0.0 : 1.0}; });
    auto near_step = [](const Vec3& p) { return std::abs(p[0] - 0.4875) <= 0.0625; };
    Options o = options();
    o.keep_fraction = 0.1;
    o.alpha = 0.0;
    Result data = simplify(in, o);
    o.alpha = 1.0;
    Result geometry = simplify(in, o);
    EXPECT_TRUE(data.target_reached);
    EXPECT_TRUE(geometry.target_reached);
    EXPECT_GT(count_near(data.surface, near_step), count_near(geometry.surface, near_step));
}

// A roof (two planes meeting at a ridge along x = 0.5, 0.3 high) carrying smooth data. With
// alpha = 0 the geometry still weighs its floor (0.2), so the reduction keeps the ridge, where the
// data is read from: every input vertex within 2% of the ridge's height of the result. (With the
// data's error alone, 0.008 to 0.015 off: the ridge was cut.)
TEST_P(Simplify, AlphaZeroKeepsTheRidgeUnderTheData) {
    constexpr double kHeight = 0.3;
    Surface in = grid(40, 40);
    for (size_t v = 0; v < in.vertex_count(); ++v)
        in.positions[3 * v + 2] = float(2 * kHeight * (0.5 - std::abs(in.positions[3 * v] - 0.5)));
    add_field(in, "heat", 1,
              [](const Vec3& p) { return std::vector<double>{std::sin(4 * p[0]) + p[1] * p[1]}; });
    EXPECT_LT(farthest_after_reduction(in, options(), 0, 0.1), 0.02 * kHeight);
}

// The mirror image: a smooth bump (curvature) at (0.75, 0.5) and a data step along a circle
// around (0.25, 0.5) far from it, reduced to so few triangles (2%) that the two compete for them:
// alpha = 1 follows the bump more closely than alpha = 0, alpha = 0 keeps more vertices near the
// step than alpha = 1. (With more to spare, alpha = 0 follows the bump as well: where the data is
// flat, the geometric term's floor of 0.2 decides. A straight step along the grid's lines would
// not compete: vertex removal keeps it exactly with the four corners of its two columns.)
TEST_P(Simplify, AlphaOneKeepsTheBump) {
    Surface in = grid(40, 40);
    for (size_t v = 0; v < in.vertex_count(); ++v) {
        double dx = in.positions[3 * v] - 0.75, dy = in.positions[3 * v + 1] - 0.5;
        in.positions[3 * v + 2] = float(0.08 * std::exp(-(dx * dx + dy * dy) / 0.01));
    }
    auto from_centre = [](const Vec3& p) { return std::hypot(p[0] - 0.25, p[1] - 0.5); };
    add_field(in, "step", 1, [&](const Vec3& p) {
        return std::vector<double>{from_centre(p) < 0.15 ? 1.0 : 0.0};
    });
    auto near_step = [&](const Vec3& p) { return std::abs(from_centre(p) - 0.15) <= 0.0625; };
    Options o = options();
    o.keep_fraction = 0.02;
    o.alpha = 0.0;
    Result data = simplify(in, o);
    o.alpha = 1.0;
    Result geometry = simplify(in, o);
    EXPECT_LT(farthest_input_vertex(in, geometry.surface), farthest_input_vertex(in, data.surface));
    EXPECT_GT(count_near(data.surface, near_step), count_near(geometry.surface, near_step));
}

// Only the named gradient fields drive the weights: with alpha = 0, gradient_fields = {"step"}
// behaves like the step-only surface, gradient_fields = {"other"} (smooth in y) does not keep the
// step.
TEST_P(Simplify, GradientFieldsSelectTheData) {
    Surface in = grid(40, 40);
    add_field(in, "step", 1,
              [](const Vec3& p) { return std::vector<double>{p[0] < 0.49 ? 0.0 : 1.0}; });
    add_field(in, "other", 1, [](const Vec3& p) { return std::vector<double>{p[1] * p[1]}; });
    auto near_step = [](const Vec3& p) { return std::abs(p[0] - 0.4875) <= 0.0625; };
    Options o = options();
    o.keep_fraction = 0.1;
    o.alpha = 0.0;
    o.gradient_fields = {"step"};
    Result step = simplify(in, o);
    o.gradient_fields = {"other"};
    Result other = simplify(in, o);
    EXPECT_GT(count_near(step.surface, near_step), count_near(other.surface, near_step));
    // both carry both fields
    EXPECT_TRUE(fields_carried(in, step.surface));
    EXPECT_TRUE(fields_carried(in, other.surface));
}

// --- boundary --------------------------------------------------------------------------------

// A flat square grid reduced as far as it goes: the 4 corners stay exactly; every boundary edge
// of the output lies on one side of the square (both ends on x = 0, x = 1, y = 0 or y = 1); the
// surface stays in z = 0, covers the whole square (area 1) and faces +z everywhere.
TEST_P(Simplify, SquareGridKeepsItsOutline) {
    Surface in = with_test_fields(grid(24, 24));
    Options o = options();
    o.keep_fraction = 0.0;
    Result r = simplify(in, o);
    const Surface& s = r.surface;
    ASSERT_TRUE(well_formed(s));
    for (Vec3 corner : {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{1, 1, 0}, Vec3{0, 1, 0}})
        EXPECT_TRUE(has_vertex_at(s, corner)) << corner[0] << "," << corner[1];
    std::map<std::pair<uint32_t, uint32_t>, int> edges;
    for (size_t t = 0; t < s.triangle_count(); ++t) {
        auto c = corners(s, t);
        for (int k = 0; k < 3; ++k) edges[std::minmax(c[k], c[(k + 1) % 3])]++;
        EXPECT_GT(triangle_normal(s, t)[2], 0) << "triangle " << t << " faces down";
    }
    auto on = [](double x, double side) { return std::abs(x - side) < 1e-6; };
    for (auto& [e, n] : edges) {
        if (n != 1) continue;
        Vec3 a = position(s, e.first), b = position(s, e.second);
        bool same_side = (on(a[0], 0) && on(b[0], 0)) || (on(a[0], 1) && on(b[0], 1)) ||
                         (on(a[1], 0) && on(b[1], 0)) || (on(a[1], 1) && on(b[1], 1));
        EXPECT_TRUE(same_side) << "boundary edge (" << a[0] << "," << a[1] << ")-(" << b[0] << ","
                               << b[1] << ") leaves the outline";
    }
    for (size_t v = 0; v < s.vertex_count(); ++v) EXPECT_NEAR(s.positions[3 * v + 2], 0.0, 1e-6);
    EXPECT_NEAR(total_area(s), 1.0, 1e-5);
    EXPECT_LT(r.triangles_out, in.triangle_count() / 4);
}

// Line tolerance: the rim of a 24-gon fan turns by 15 degrees at each vertex, and its centre
// rises 0.5 above the rim, so that removing the centre costs far more than thinning the rim.
// Reduced by one triangle: with the default 20 degrees the rim gives way (an edge collapse along
// it may move both its ends); with 10 degrees it may not, and the centre goes instead (the
// tolerance is the only thing that differs).
TEST_P(Simplify, LineToleranceGuardsTheBoundary) {
    const Surface in = with_test_fields(fan(24, 0.5));
    auto rim_left = [&](const Surface& out) {
        size_t left = 0;
        for (size_t v = 1; v <= 24; ++v) left += has_vertex_at(out, position(in, v));
        return left;
    };
    Options o = options();
    o.target_triangles = 23;
    o.line_tolerance = 10.0;
    const Result strict = simplify(in, o);
    EXPECT_EQ(rim_left(strict.surface), 24u);
    EXPECT_FALSE(has_vertex_at(strict.surface, position(in, 0)));
    EXPECT_TRUE(topology_kept(analyze_topology(in), analyze_topology(strict.surface)));
    o.line_tolerance = 20.0;
    const Result loose = simplify(in, o);
    EXPECT_LT(rim_left(loose.surface), 24u);
    EXPECT_TRUE(has_vertex_at(loose.surface, position(in, 0)));
    EXPECT_TRUE(topology_kept(analyze_topology(in), analyze_topology(loose.surface)));
}

// Once nothing else is removable, lines may bend more where a vertex goes: a flat 24-gon fan
// with a tolerance of 10 degrees (its rim turns by 15) loses its centre, and then its rim thins
// out: what is left of it turns by more than the widest tolerance, 80 degrees, at every vertex,
// so at most 4 vertices (the turns add up to 360). A tolerance of 0 never widens: the whole rim
// stays. (A right angle always stays: VertexRemoval.SquareGridEndsAsTwoTriangles.)
TEST_P(Simplify, LinesWidenOnceNothingElseIsRemovable) {
    const Surface in = with_test_fields(fan(24));
    Options o = options();
    o.keep_fraction = 0.0;
    o.line_tolerance = 10.0;
    const Result widened = simplify(in, o);
    EXPECT_EQ(widened.stop, StopReason::NothingRemovable) << describe(widened.stop);
    size_t rim_left = 0;
    for (size_t v = 1; v <= 24; ++v) rim_left += has_vertex_at(widened.surface, position(in, v));
    EXPECT_LE(rim_left, 4u);
    EXPECT_TRUE(topology_kept(analyze_topology(in), analyze_topology(widened.surface)));
    for (size_t t = 0; t < widened.surface.triangle_count(); ++t)
        EXPECT_GT(triangle_normal(widened.surface, t)[2], 0);
    o.line_tolerance = 0.0;
    const Result kept = simplify(in, o);
    EXPECT_EQ(kept.stop, StopReason::NothingRemovable) << describe(kept.stop);
    EXPECT_EQ(kept.triangles_out, 22u);
    for (size_t v = 1; v <= 24; ++v) EXPECT_TRUE(has_vertex_at(kept.surface, position(in, v))) << v;
}

// --- feature edges -------------------------------------------------------------------------------

// A cube with 6x6 faces (dihedral turn 90 degrees > feature angle 60): reduced as far as it
// goes, the 8 corners survive exactly, every triangle stays on one face with that face's outward
// normal (nothing cuts across a feature edge), and the volume stays 8.
TEST_P(Simplify, CubeKeepsCornersAndFeatureEdges) {
    Surface in = with_test_fields(cube(6));
    Options o = options();
    o.keep_fraction = 0.0;
    o.feature_angle = 45; // features are off by default; the cube's edges turn normals by 90
    Result r = simplify(in, o);
    const Surface& s = r.surface;
    ASSERT_TRUE(well_formed(s));
    for (double x : {-1.0, 1.0})
        for (double y : {-1.0, 1.0})
            for (double z : {-1.0, 1.0}) EXPECT_TRUE(has_vertex_at(s, {x, y, z})) << x << y << z;
    for (size_t t = 0; t < s.triangle_count(); ++t) {
        Vec3 n = triangle_normal(s, t);
        n = (1.0 / norm(n)) * n;
        int k = 0;
        for (int a = 1; a < 3; ++a)
            if (std::abs(n[a]) > std::abs(n[k])) k = a;
        EXPECT_GT(std::abs(n[k]), 0.9999) << "triangle " << t << " is not on a face";
        for (uint32_t v : corners(s, t))
            EXPECT_NEAR(s.positions[3 * v + k], n[k] > 0 ? 1.0 : -1.0, 1e-6)
                << "triangle " << t << " is not on the face its normal points out of";
    }
    EXPECT_NEAR(signed_volume(s), 8.0, 1e-4);
    EXPECT_LT(r.triangles_out, in.triangle_count() / 2);
}

// --- orientation ---------------------------------------------------------------------------------

// A sphere whose triangles disagree about their orientation (every other one flipped, as in the
// shared earth.vtp) is repaired by validate and then reduced like the original.
TEST_P(Simplify, InconsistentOrientationIsRepairedThenReduced) {
    Surface in = with_test_fields(flipped(icosphere(3), [](size_t t) { return t % 2 == 1; }));
    Options o = options();
    o.keep_fraction = 0.1;
    Result r = simplify(in, o);
    EXPECT_EQ(r.repairs.triangles_flipped, 640u);
    EXPECT_TRUE(r.target_reached) << describe(r.stop);
    EXPECT_LE(r.triangles_out, 128u);
    EXPECT_TRUE(well_formed(r.surface));
    EXPECT_GT(signed_volume(r.surface), 0);
}

// No flipped triangles: on a sphere every output triangle faces away from the centre.
TEST_P(Simplify, SphereTrianglesFaceOutward) {
    Surface in = with_test_fields(icosphere(3));
    Options o = options();
    o.keep_fraction = 0.1;
    Result r = simplify(in, o);
    ASSERT_TRUE(well_formed(r.surface));
    for (size_t t = 0; t < r.surface.triangle_count(); ++t)
        EXPECT_GT(dot(triangle_normal(r.surface, t), triangle_centroid(r.surface, t)), 0) << t;
    EXPECT_GT(signed_volume(r.surface), 0);
}

// ... and on a torus every triangle faces away from the tube's centre line (the circle of radius
// R = 2 in z = 0), the original surface's normal nearby.
TEST_P(Simplify, TorusTrianglesFaceOutward) {
    Surface in = with_test_fields(torus(40, 16));
    Options o = options();
    o.keep_fraction = 0.2;
    Result r = simplify(in, o);
    ASSERT_TRUE(well_formed(r.surface));
    for (size_t t = 0; t < r.surface.triangle_count(); ++t) {
        Vec3 c = triangle_centroid(r.surface, t);
        double rho = std::hypot(c[0], c[1]);
        Vec3 ring{2.0 * c[0] / rho, 2.0 * c[1] / rho, 0};
        EXPECT_GT(dot(triangle_normal(r.surface, t), c - ring), 0) << t;
    }
    EXPECT_GT(signed_volume(r.surface), 0);
    EXPECT_TRUE(topology_kept(analyze_topology(in), analyze_topology(r.surface)));
}

} // namespace
} // namespace ddsimp::test
