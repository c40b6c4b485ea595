#include "distributed_simplify.h"

#include "cli_support.h"
#include "ddsimp/io/surface_io.h"
#include "mpi_transfer.h"
#include "pieces.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <new>

namespace ddsimp::mpi {

namespace {

using Clock = std::chrono::steady_clock;

// What one rank did with its piece.
struct PieceReport {
    uint64_t triangles_in = 0, triangles_out = 0, locked = 0, operations = 0;
    double seconds = 0;
};

// The triangle target `options` sets for a surface of `triangles` triangles (as simplify counts
// it); 0 means "as far as it goes".
size_t target_for(const Options& options, size_t triangles) {
    if (options.target_triangles > 0) return options.target_triangles;
    return size_t(std::floor(options.keep_fraction * double(triangles) + 1e-9));
}

// `options` with an absolute triangle target (0: as far as it goes).
Options with_target(Options options, size_t target) {
    options.target_triangles = target;
    if (target == 0) options.keep_fraction = 0;
    return options;
}

// The message of the exception being handled, with the input file named for library errors.
std::string current_error(const std::string& input) {
    try {
        throw;
    } catch (const InputError& e) {
        return input + ": " + e.what();
    } catch (const std::bad_alloc&) {
        return "out of memory";
    } catch (const std::exception& e) {
        return e.what();
    }
}

// Rank 0's part of the set-up: the validated surface and its pieces.
struct Plan {
    Surface whole;
    RepairReport repairs;
    size_t target = 0;
    bool split = false;
    std::string why_whole; // why the surface is not split (one rank, too small, ...)
    std::vector<Piece> pieces;
};

Plan make_plan(Surface whole, const Options& options, int ranks) {
    Plan plan;
    plan.whole = std::move(whole);
    plan.repairs = validate(plan.whole);
    plan.target = target_for(options, plan.whole.triangle_count());
    if (ranks == 1) {
        plan.why_whole = "one rank";
        return plan;
    }
    // Pieces of a few triangles would be mostly border: not worth the traffic.
    if (plan.whole.triangle_count() < 64 * size_t(ranks)) {
        plan.why_whole = "fewer than 64 triangles per rank";
        return plan;
    }
    plan.pieces =
        split_surface(plan.whole, bisect_triangles(plan.whole, uint32_t(ranks)), uint32_t(ranks));
    plan.split = true;
    return plan;
}

// Collective: what was read, on rank 0 (nothing elsewhere): IN, or with `pieces` every rank's own
// file (IN with "{rank}" replaced by its rank), in rank order, to be welded. Throws io::IoError on
// rank 0 for an error on any rank, after every rank has agreed to stop; the others throw
// RankStopped.
std::vector<Surface> read_input(const cli::SimplifyArgs& args, bool pieces, int rank, int ranks) {
    std::string message;
    bool ok = true;
    Surface surface;
    std::string path = args.input;
    if (pieces) path.replace(path.find(kRankPattern), kRankPattern.size(), std::to_string(rank));
    if (pieces || rank == 0) try {
            if (rank == 0) io::check_output_path(args.output);
            surface = io::read_surface(path);
            cli::require_fields(surface, args.fields, path);
        } catch (...) {
            ok = false, message = current_error(path);
        }
    if (!all_ok(ok, message)) {
        if (rank == 0) throw io::IoError(message);
        throw RankStopped();
    }
    if (rank != 0) {
        if (pieces) send_surface(surface, 0);
        return {};
    }
    std::vector<Surface> read(pieces ? static_cast<size_t>(ranks) : 1);
    read[0] = std::move(surface);
    for (int r = 1; r < int(read.size()); ++r) read[size_t(r)] = recv_surface(r);
    return read;
}

// Rank 0: the surface to simplify, from what read_input read.
Surface whole_input(const cli::SimplifyArgs& args, bool pieces, std::vector<Surface>& read) {
    if (!pieces) return std::move(read[0]);
    try {
        return weld_pieces(read);
    } catch (const std::runtime_error& e) {
        throw io::IoError(args.input + ": " + e.what());
    }
}

// The piece's triangle target: its share of the global target, times the slack.
size_t piece_target(const Plan& plan, const Piece& piece) {
    const double share = double(plan.target) * double(piece.surface.triangle_count()) /
                         double(plan.whole.triangle_count());
    return std::min(piece.surface.triangle_count(), size_t(std::ceil(kPieceSlack * share)));
}

ReducedPiece simplify_piece(const Piece& piece, size_t target, const Options& options,
                            PieceReport& report) {
    const auto start = Clock::now();
    Options o = with_target(options, target);
    o.locked = piece.locked;
    const ProgressiveRecord record = ProgressiveRecord::build(piece.surface, o);
    ReducedPiece reduced = reduce_piece(piece, record);
    report.triangles_in = piece.surface.triangle_count();
    report.triangles_out = reduced.surface.triangle_count();
    report.locked = uint64_t(std::count(piece.locked.begin(), piece.locked.end(), 1));
    report.operations = record.operations();
    report.seconds = cli::seconds_since(start);
    return reduced;
}

void report_run(const cli::SimplifyArgs& args, const Options& options, const Result& result,
                double seconds, int ranks, const Plan& plan, const std::vector<PieceReport>& pieces,
                size_t stitched, double final_seconds) {
    if (args.json) {
        nlohmann::json out = cli::simplify_json(args, options, result, seconds);
        out["ranks"] = ranks;
        out["split"] = plan.split;
        if (!plan.split) out["why_not_split"] = plan.why_whole;
        nlohmann::json list = nlohmann::json::array();
        for (const PieceReport& p : pieces)
            list.push_back({{"triangles_in", p.triangles_in},
                            {"triangles_out", p.triangles_out},
                            {"locked_vertices", p.locked},
                            {"operations", p.operations},
                            {"seconds", p.seconds}});
        out["pieces"] = list;
        out["stitched_triangles"] = stitched;
        out["final_pass_seconds"] = final_seconds;
        std::printf("%s\n", out.dump().c_str());
        return;
    }
    cli::print_simplify_summary(args, options, result, seconds);
    if (plan.split) {
        double slowest = 0;
        for (const PieceReport& p : pieces) slowest = std::max(slowest, p.seconds);
        std::printf("%d pieces (slowest %.3f s), stitched %zu triangles, final pass %.3f s\n",
                    ranks, slowest, stitched, final_seconds);
    } else {
        std::printf("not split: %s\n", plan.why_whole.c_str());
    }
}

} // namespace

int distributed_simplify(const cli::SimplifyArgs& args, const CLI::App& command, bool pieces) {
    int rank = 0, ranks = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &ranks);
    const Options options = cli::simplify_options(args, command); // same on every rank

    const auto start = Clock::now();
    std::vector<Surface> read = read_input(args, pieces, rank, ranks);
    const double read_seconds = cli::seconds_since(start);
    Plan plan;
    std::string message;
    bool ok = true;
    if (rank == 0) try {
            plan = make_plan(whole_input(args, pieces, read), options, ranks);
        } catch (...) {
            ok = false, message = current_error(args.input);
        }
    read = {};
    if (!all_ok(ok, message)) {
        if (rank == 0) throw io::IoError(message);
        return cli::kExitInputError;
    }
    int split = plan.split;
    MPI_Bcast(&split, 1, MPI_INT, 0, MPI_COMM_WORLD);

    Result result;
    std::vector<PieceReport> reports(split ? size_t(ranks) : 0);
    size_t stitched = 0;
    double final_seconds = 0;
    if (!split) {
        if (rank != 0) return cli::kExitOk;
        try {
            result = simplify(plan.whole, options);
        } catch (const InputError& e) {
            throw io::IoError(args.input + ": " + e.what());
        }
        result.repairs = plan.repairs;
    } else {
        // Out: each rank's piece and target.
        Piece mine;
        uint64_t target = 0;
        if (rank == 0) {
            for (int r = 1; r < ranks; ++r) {
                const Piece& piece = plan.pieces[size_t(r)];
                send_surface(piece.surface, r);
                send_vector(piece.locked, r);
                send_vector(piece.border, r);
                target = piece_target(plan, piece);
                send_bytes(&target, sizeof target, r);
                plan.pieces[size_t(r)] = Piece{}; // its memory is no longer needed here
            }
            mine = std::move(plan.pieces[0]);
            target = piece_target(plan, mine);
        } else {
            mine.surface = recv_surface(0);
            mine.locked = recv_vector<uint8_t>(0);
            mine.border = recv_vector<uint32_t>(0);
            recv_bytes(&target, sizeof target, 0);
        }

        ReducedPiece reduced;
        PieceReport report;
        try {
            reduced = simplify_piece(mine, target, options, report);
        } catch (...) {
            ok = false, message = current_error(args.input);
        }
        if (!all_ok(ok, message)) {
            if (rank == 0) throw io::IoError(message);
            return cli::kExitInputError;
        }

        // Back: every piece to rank 0.
        if (rank != 0) {
            send_surface(reduced.surface, 0);
            send_vector(reduced.border, 0);
            send_bytes(&report, sizeof report, 0);
            return cli::kExitOk;
        }
        std::vector<ReducedPiece> pieces(static_cast<size_t>(ranks));
        pieces[0] = std::move(reduced);
        reports[0] = report;
        for (int r = 1; r < ranks; ++r) {
            pieces[size_t(r)].surface = recv_surface(r);
            pieces[size_t(r)].border = recv_vector<uint32_t>(r);
            recv_bytes(&reports[size_t(r)], sizeof(PieceReport), r);
        }
        const Surface whole = stitch(pieces);
        pieces.clear();
        stitched = whole.triangle_count();

        const auto final_start = Clock::now();
        try {
            cli::TerminalProgress progress("final pass over " + args.input);
            Options o = with_target(options, plan.target);
            o.progress = progress.callback();
            result = simplify(whole, o);
        } catch (const InputError& e) {
            throw io::IoError(args.input + ": stitched surface: " + e.what());
        }
        final_seconds = cli::seconds_since(final_start);
        result.triangles_in = plan.whole.triangle_count();
        result.repairs = plan.repairs;
        for (const PieceReport& p : reports) result.operations += p.operations;
    }
    const double seconds = cli::seconds_since(start) - read_seconds; // as ddsimp counts
    io::write_surface(result.surface, args.output);
    report_run(args, options, result, seconds, ranks, plan, reports, stitched, final_seconds);
    return cli::kExitOk;
}

} // namespace ddsimp::mpi
