// ddsimp-mpi: `ddsimp simplify` across Open MPI ranks, for surfaces beyond one node.
//
//     mpirun -np N ddsimp-mpi simplify IN -o OUT [the options of ddsimp simplify] [--json]
//     mpirun -np N ddsimp-mpi simplify part-{rank}.vtp --pieces -o OUT ...   (one file per rank)
//
// Rank 0 reads IN (with --pieces every rank its own file) and writes OUT; see
// distributed_simplify.h for what the ranks do. Exit status as for ddsimp: 0 success, 1 input or
// I/O error, 2 usage error; every error is one line on stderr from rank 0 starting with
// "ddsimp-mpi: ", and every rank stops (no rank is left waiting).
#include "cli_support.h"
#include "ddsimp/io/surface_io.h"
#include "distributed_simplify.h"
#include "simplify_args.h"

#include <CLI/CLI.hpp>
#include <mpi.h>

#include <cstdio>
#include <string>

namespace {

int rank_ = 0;

int fail(int status, const std::string& message) {
    if (rank_ != 0) return status;
    std::string line = message;
    for (char& c : line)
        if (c == '\n' || c == '\r') c = ' ';
    std::fprintf(stderr, "ddsimp-mpi: %s\n", line.c_str());
    return status;
}

int run(int argc, char** argv) {
    using namespace ddsimp::cli;
    CLI::App app{"ddsimp-mpi: data-dependent surface simplification across MPI ranks\n"
                 "Exit status: 0 success, 1 input or I/O error, 2 usage error."};
    app.require_subcommand(1);
    SimplifyArgs args;
    args.threads = 1; // one per rank: the ranks share a node's cores
    CLI::App* simplify = app.add_subcommand(
        "simplify",
        "Reduce a surface, keeping its topology: one piece per rank, then a final pass");
    add_simplify_options(*simplify, args);
    bool pieces = false;
    simplify->add_flag("--pieces", pieces,
                       "IN names one file per rank, with {rank} for the rank number (e.g. "
                       "part-{rank}.vtp): each rank reads its own; border vertices in several "
                       "files are welded where they coincide exactly");

    // The command line is the same on every rank, so every rank reaches the same verdict.
    if (argc > 1 && argv[1][0] != '-' && !simplify->check_name(argv[1]))
        return fail(kExitUsageError,
                    std::string("unknown command '") + argv[1] + "' (commands: simplify)");
    try {
        app.parse(argc, argv);
    } catch (const CLI::Success& e) { // --help
        return rank_ == 0 ? app.exit(e) : 0;
    } catch (const CLI::ParseError& e) {
        return fail(kExitUsageError, e.what() + std::string(" (see ddsimp-mpi simplify --help)"));
    }

    if (pieces && args.input.find(ddsimp::mpi::kRankPattern) == std::string::npos)
        return fail(kExitUsageError, "--pieces: the input '" + args.input +
                                         "' has no {rank} to replace by the rank number");
    try {
        return ddsimp::mpi::distributed_simplify(args, *simplify, pieces);
    } catch (const ddsimp::mpi::RankStopped&) {
        return kExitInputError; // rank 0 reports the error
    } catch (...) {
        const Failure f = failure_of(std::current_exception());
        return fail(f.status, f.message);
    }
}

} // namespace

int main(int argc, char** argv) {
    MPI_Init(&argc, &argv);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    const int status = run(argc, argv);
    MPI_Finalize();
    return status;
}
