// `ddsimp-mpi simplify`: the surface is read on rank 0 (or one piece per rank with --pieces,
// welded on rank 0), validated, cut into one spatially coherent
// piece per rank (pieces.h) and sent out; every rank simplifies its piece with the piece borders
// locked; rank 0 gathers the pieces, welds them back into one surface, and a final pass over the
// whole surface (nothing locked) reaches the target. Each piece is taken further than the target
// fraction only by kPieceSlack, so that the final pass chooses the last operations globally.
#pragma once

#include "simplify_args.h"

#include <string_view>

namespace CLI {
class App;
}

namespace ddsimp::mpi {

// Pieces stop at kPieceSlack x their share of the target; the final pass does the rest. Pieces
// reduced further, with their borders locked, cannot spend their error where one process would,
// so the data error rises above one process's; 3 keeps it level where a smaller slack did not
// (bench/mpi/README.md). The price is a final pass over 3x the target on rank 0 alone.
inline constexpr double kPieceSlack = 3.0;

// With --pieces, IN names one file per rank with this in place of the rank number.
inline constexpr std::string_view kRankPattern = "{rank}";

// Thrown on ranks other than 0 when every rank has agreed to stop for an error (rank 0 reports it).
struct RankStopped {};

// Collective: every rank calls it with the same parsed command line. Returns the exit status;
// for an error on any rank, once every rank has agreed to stop, throws io::IoError or InputError
// on rank 0 and RankStopped on the others. `pieces`: see read_input in distributed_simplify.cpp.
int distributed_simplify(const cli::SimplifyArgs& args, const CLI::App& command, bool pieces);

} // namespace ddsimp::mpi
