// Splitting and stitching for ddsimp-mpi (tools/mpi/pieces.h), without MPI: the pieces of a few
// small surfaces are simplified with their locks, one after another, and stitched.
#include "pieces.h"
#include "test_surfaces.h"

namespace ddsimp::test {
namespace {

using mpi::kNoId;

std::vector<size_t> piece_sizes(const std::vector<uint32_t>& piece_of, uint32_t parts) {
    std::vector<size_t> sizes(parts, 0);
    for (uint32_t p : piece_of) ++sizes.at(p);
    return sizes;
}

// 3200 triangles: halves of 1600, then quarters of 800.
TEST(Bisection, FourEqualPieces) {
    EXPECT_EQ(piece_sizes(mpi::bisect_triangles(grid(40, 40), 4), 4),
              (std::vector<size_t>{800, 800, 800, 800}));
}

// Three pieces: 3200 * 1/3 = 1066 on the left, the other 2134 halved.
TEST(Bisection, ThreePiecesInProportion) {
    EXPECT_EQ(piece_sizes(mpi::bisect_triangles(grid(40, 40), 3), 3),
              (std::vector<size_t>{1066, 1067, 1067}));
}

// On a strip four times longer in x than in y, two pieces are cut across x: every centroid of
// piece 0 lies left of every centroid of piece 1.
TEST(Bisection, CutsTheLongestSide) {
    const Surface s = grid(80, 20);
    const std::vector<uint32_t> piece_of = mpi::bisect_triangles(s, 2);
    double right_of_0 = -INFINITY, left_of_1 = INFINITY;
    for (size_t t = 0; t < s.triangle_count(); ++t) {
        const double x = triangle_centroid(s, t)[0];
        if (piece_of[t] == 0)
            right_of_0 = std::max(right_of_0, x);
        else
            left_of_1 = std::min(left_of_1, x);
    }
    EXPECT_LT(right_of_0, left_of_1);
}

// Grid of 4 x 2 cells: the two left columns of cells (8 triangles: centroids x < 0.5) are piece
// 0. The vertex column i = 2 is the border; piece 0 has columns 0..2 (9 vertices) and locks
// columns 1 and 2 (every triangle of cell column 1 touches column 2).
TEST(Split, BorderAndLocksOfTwoPieces) {
    const Surface s = grid(4, 2);
    const std::vector<uint32_t> piece_of = mpi::bisect_triangles(s, 2);
    const std::vector<mpi::Piece> pieces = mpi::split_surface(s, piece_of, 2);
    ASSERT_EQ(pieces.size(), 2u);
    const mpi::Piece& left = pieces[0];
    EXPECT_EQ(left.surface.triangle_count(), 8u);
    ASSERT_EQ(left.surface.vertex_count(), 9u);
    for (size_t v = 0; v < 9; ++v) {
        const double x = left.surface.positions[3 * v]; // i / 4
        const int column = int(std::lround(4 * x));
        EXPECT_EQ(left.locked[v], column >= 1) << "vertex at x = " << x;
        if (column == 2) {
            ASSERT_NE(left.border[v], kNoId);
            // The global id names the input vertex at the same place.
            EXPECT_EQ(position(s, left.border[v]), position(left.surface, v));
        } else {
            EXPECT_EQ(left.border[v], kNoId);
        }
    }
}

// The pieces of a surface, untouched, stitch back into the same triangles.
TEST(Stitch, UntouchedPiecesGiveTheInputBack) {
    const Surface s = with_test_fields(torus(24, 12));
    const auto pieces = mpi::split_surface(s, mpi::bisect_triangles(s, 3), 3);
    std::vector<mpi::ReducedPiece> reduced;
    for (const mpi::Piece& p : pieces) reduced.push_back({p.surface, p.border});
    const Surface stitched = mpi::stitch(reduced);
    EXPECT_EQ(stitched.vertex_count(), s.vertex_count());
    EXPECT_EQ(canonical_triangles(stitched), canonical_triangles(s));
}

// Pieces written one file per rank (each with its copy of the border vertices) weld back into
// the surface they were cut from.
TEST(Weld, FilesPerRankGiveTheSurfaceBack) {
    const Surface s = with_test_fields(torus(24, 12));
    std::vector<Surface> files;
    for (const mpi::Piece& p : mpi::split_surface(s, mpi::bisect_triangles(s, 4), 4))
        files.push_back(p.surface);
    const Surface welded = mpi::weld_pieces(files);
    EXPECT_EQ(welded.vertex_count(), s.vertex_count());
    EXPECT_EQ(canonical_triangles(welded), canonical_triangles(s));
    EXPECT_TRUE(topology_kept(analyze_topology(s), analyze_topology(welded)));
}

// Only boundary vertices weld: two coincident vertices inside one piece stay apart, and so do an
// interior vertex of one piece and a boundary vertex of another at the same place.
TEST(Weld, InteriorVerticesStayApart) {
    Surface a = fan(6); // centre (0,0,0) inside, rim on the boundary
    Surface b = fan(6); // the same place: every rim vertex welds, the centre does not
    const Surface welded = mpi::weld_pieces({a, b});
    EXPECT_EQ(welded.vertex_count(), 7u + 1u); // 6 shared rim vertices, 2 centres
    EXPECT_EQ(welded.triangle_count(), 12u);
}

TEST(Weld, DifferentFieldsAreAnError) {
    Surface a = with_test_fields(square()), b = square();
    EXPECT_THROW(mpi::weld_pieces({a, b}), std::runtime_error);
}

struct PieceCase {
    const char* name;
    Surface (*make)();
    uint32_t parts;
};
void PrintTo(const PieceCase& c, std::ostream* os) {
    *os << c.name << "/" << c.parts;
}

class SimplifiedPieces : public ::testing::TestWithParam<std::tuple<Config, PieceCase>> {};

Surface torus_surface() {
    return with_test_fields(torus(48, 24));
}
Surface sphere_surface() {
    return with_test_fields(icosphere(4));
}
Surface annulus_surface() {
    return with_test_fields(grid_with_hole(40, 12, 28));
}
Surface two_grids() {
    return with_test_fields(two_components(30));
}
// Two 30 x 30 grids, [0,1]^2 and [1,2]x[0,1], touching along x = 1 with a vertex of each at every
// point of that line (not welded): 2 components, 2 loops, Euler 2. The coincident vertices tell
// nothing apart by position, and some are border vertices.
Surface touching_grids() {
    Surface s = grid(30, 30), right = grid(30, 30);
    for (size_t v = 0; v < right.vertex_count(); ++v) right.positions[3 * v] += 1.0f;
    append(s, right);
    return with_test_fields(s);
}

INSTANTIATE_TEST_SUITE_P(
    All, SimplifiedPieces,
    ::testing::Combine(::testing::ValuesIn(all_configs()),
                       ::testing::Values(PieceCase{"torus", torus_surface, 4},
                                         PieceCase{"sphere", sphere_surface, 3},
                                         PieceCase{"annulus", annulus_surface, 4},
                                         PieceCase{"two_grids", two_grids, 3},
                                         PieceCase{"touching_grids", touching_grids, 6})),
    [](const auto& info) {
        return std::string(std::get<0>(info.param).name) + "_" + std::get<1>(info.param).name +
               "_" + std::to_string(std::get<1>(info.param).parts);
    });

// Each piece simplified as far as it goes with its locks, then stitched: every border vertex is
// still there, in its place, and the stitched surface has the input's topology, with no new
// non-manifold edge where pieces meet; so does a final pass over it.
TEST_P(SimplifiedPieces, StitchKeepsTheTopology) {
    const auto& [config, c] = GetParam();
    const Surface s = c.make();
    const Topology before = analyze_topology(s);
    const auto pieces = mpi::split_surface(s, mpi::bisect_triangles(s, c.parts), c.parts);
    std::vector<mpi::ReducedPiece> reduced;
    size_t borders = 0;
    for (const mpi::Piece& p : pieces) {
        Options o = options_for(config);
        o.keep_fraction = 0;
        o.locked = p.locked;
        const ProgressiveRecord record = ProgressiveRecord::build(p.surface, o);
        mpi::ReducedPiece r = mpi::reduce_piece(p, record);
        EXPECT_LT(r.surface.triangle_count(), p.surface.triangle_count()); // it did shrink
        EXPECT_TRUE(same_bytes(r.surface, record.after(record.operations())));
        for (size_t v = 0; v < r.border.size(); ++v)
            if (r.border[v] != kNoId) {
                EXPECT_EQ(position(r.surface, v), position(s, r.border[v]));
                ++borders;
            }
        reduced.push_back(std::move(r));
    }
    size_t expected = 0; // each piece's border vertices, found again after simplifying
    for (const mpi::Piece& p : pieces)
        expected += size_t(std::count_if(p.border.begin(), p.border.end(),
                                         [](uint32_t id) { return id != kNoId; }));
    EXPECT_GT(expected, 0u);
    EXPECT_EQ(borders, expected);
    const Surface stitched = mpi::stitch(reduced);
    EXPECT_TRUE(well_formed(stitched));
    EXPECT_TRUE(fields_carried(s, stitched));
    EXPECT_TRUE(topology_kept(before, analyze_topology(stitched)));

    Options o = options_for(config);
    o.keep_fraction = 0.05;
    const Result final = simplify(stitched, o);
    EXPECT_TRUE(topology_kept(before, analyze_topology(final.surface)));
}

} // namespace
} // namespace ddsimp::test
