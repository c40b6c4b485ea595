// Splitting a surface into spatially coherent pieces for ddsimp-mpi, and stitching the simplified
// pieces back into one surface. No MPI here: the pipeline (distributed_simplify.cpp) moves the
// pieces between ranks.
//
// A piece locks its border vertices (those shared with another piece) and every vertex of its
// triangles at such a border vertex. With that one-ring locked too, no operation in the piece can
// touch a border vertex's star: the border stays exactly as in the input, so welding the pieces
// back gives a surface with the input's topology (no edge can appear in two pieces, no edge can
// gain a third triangle across a border).
#pragma once

#include "ddsimp/ddsimp.h"

#include <cstdint>
#include <vector>

namespace ddsimp::mpi {

inline constexpr uint32_t kNoId = 0xffffffffu;

// The piece (0 .. parts-1) of each triangle, by recursive coordinate bisection of the triangle
// centroids: the longest side of the centroids' bounding box is cut where the triangle counts
// are in proportion to the piece counts on each side (any number of parts, not only powers of
// two). Ties are broken by triangle index, so the split is deterministic.
std::vector<uint32_t> bisect_triangles(const Surface& surface, uint32_t parts);

struct Piece {
    Surface surface;              // its triangles over its own vertices, in global id order
    std::vector<uint8_t> locked;  // per vertex: a border vertex or a neighbour of one
    std::vector<uint32_t> border; // per vertex: its global id if shared with another piece,
                                  // else kNoId
};

// The pieces of `surface` (validated: indices in range) for the given triangle assignment.
std::vector<Piece> split_surface(const Surface& surface, const std::vector<uint32_t>& piece_of,
                                 uint32_t parts);

// A simplified piece and the global ids of its border vertices (kNoId for the others).
struct ReducedPiece {
    Surface surface;
    std::vector<uint32_t> border;
};

// The piece after all the operations of `record` (built from piece.surface with piece.locked):
// ProgressiveRecord::after, whose vertices are in the order of their record ids. A border vertex's
// neighbours are all locked, so no operation touches it and it keeps its id: it is found by that,
// not by its coordinates (which need not be unique). Throws std::runtime_error if one is gone.
ReducedPiece reduce_piece(const Piece& piece, const ProgressiveRecord& record);

// One surface from pieces that a simulation wrote one per rank, with their shared border vertices
// in each file: a vertex on a piece's open boundary that lies exactly (bit for bit) where a
// boundary vertex of an earlier piece lies becomes that vertex (with the earlier piece's data).
// Other coincident vertices within one piece stay apart. Throws std::runtime_error if the pieces'
// fields differ in name or components.
Surface weld_pieces(const std::vector<Surface>& pieces);

// One surface from the pieces, in piece order: every vertex once, a border vertex shared by
// several pieces welded into one (the first piece's copy). Every piece must have the same fields.
Surface stitch(const std::vector<ReducedPiece>& pieces);

} // namespace ddsimp::mpi
