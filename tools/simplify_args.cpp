// The options and reports of `ddsimp simplify`, shared with ddsimp-mpi (see simplify_args.h).
#include "simplify_args.h"

#include "cli_support.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <string>

namespace ddsimp::cli {

void add_simplify_options(CLI::App& command, SimplifyArgs& args) {
    command.add_option("input", args.input, "Input surface (.vtk .vtp .ply .obj .off .stl)")
        ->required();
    command
        .add_option("-o,--output", args.output, "Output surface (.vtk .vtp .ply .obj .off .glb)")
        ->required();
    command.add_option("--colour-by", args.colour_by,
                       ".glb: the field shown as vertex colours (default: the first continuous "
                       "scalar that varies)");
    command.add_flag("--meshopt", args.meshopt, ".glb: compress with EXT_meshopt_compression");
    command.add_option("--alpha", args.alpha, "Weight of curvature vs data gradient, in [0, 1]")
        ->check(CLI::Range(0.0, 1.0))
        ->capture_default_str();
    auto* keep = command.add_option("--keep", args.keep, "Keep this fraction of the triangles")
                     ->check(CLI::Range(0.0, 1.0))
                     ->capture_default_str();
    command.add_option("--triangles", args.triangles, "Stop at or below this many triangles")
        ->excludes(keep);
    command
        .add_option("--max-weight", args.max_weight,
                    "Also stop when the lightest element weighs more than this")
        ->check(CLI::Validator(
            [](std::string& text) {
                try {
                    if (std::stod(text) >= 0) return std::string();
                } catch (const std::exception&) {
                }
                return "'" + text + "' is not a number >= 0";
            },
            "W>=0"));
    command.add_option("--strategy", args.strategy, "edge (collapse) or vertex (removal)")
        ->check(CLI::IsMember({"edge", "vertex"}))
        ->capture_default_str();
    command
        .add_option("--placement", args.placement,
                    "Edge collapse point: least-error (on the edge), midpoint or volume")
        ->check(CLI::IsMember({"least-error", "midpoint", "volume"}))
        ->capture_default_str();
    command
        .add_option("--data", args.data,
                    "Edge collapse data at the new point: least-error (of the data error, "
                    "clamped to the two values it replaces, then fitted over the whole level) or "
                    "interpolated (along the edge)")
        ->check(CLI::IsMember({"least-error", "interpolated"}))
        ->capture_default_str();
    command
        .add_option("--terms", args.terms,
                    "What the weight measures: quadrics (error against the input) or paper "
                    "(angle deficit and data gradient)")
        ->check(CLI::IsMember({"quadrics", "paper"}))
        ->capture_default_str();
    command.add_option("--fields", args.fields, "Fields that drive the data term (default: all)")
        ->delimiter(',');
    command
        .add_option("--feature-angle", args.feature_angle,
                    "Dihedral angle (degrees) above which an edge is a feature; 180: none")
        ->check(CLI::Range(0.0, 180.0))
        ->capture_default_str();
    command
        .add_option("--line-tolerance", args.line_tolerance,
                    "Boundary/feature vertices go only where the line turns less (degrees) "
                    "or zigzags within half an edge; doubled up to 80 once nothing else is "
                    "removable (0: every turning vertex stays)")
        ->check(CLI::Range(0.0, 180.0))
        ->capture_default_str();
    command
        .add_option("--max-normal-turn", args.max_normal_turn,
                    "Refuse operations that turn a normal more (degrees)")
        ->check(CLI::Range(0.0, 180.0))
        ->capture_default_str();
    command
        .add_option("--threads", args.threads,
                    "Threads that simplify, 0 for every hardware thread (the output is the same)")
        ->check(CLI::Range(0, 1024))
        ->capture_default_str();
    command.add_flag("--json", args.json, "Print one JSON object instead of a summary");
}

Options simplify_options(const SimplifyArgs& args, const CLI::App& command) {
    Options options;
    options.alpha = args.alpha;
    options.strategy = args.strategy == "vertex" ? Strategy::VertexRemoval : Strategy::EdgeCollapse;
    options.placement = args.placement == "volume"     ? Placement::VolumePreserving
                        : args.placement == "midpoint" ? Placement::Midpoint
                                                       : Placement::LeastError;
    options.data_placement =
        args.data == "interpolated" ? DataPlacement::Interpolated : DataPlacement::LeastError;
    options.terms = args.terms == "paper" ? Terms::AngleDeficitGradient : Terms::ErrorQuadrics;
    options.keep_fraction = args.keep;
    options.target_triangles = command.count("--triangles") ? args.triangles : 0;
    options.max_weight = args.max_weight;
    options.gradient_fields = args.fields;
    options.feature_angle = args.feature_angle;
    options.line_tolerance = args.line_tolerance;
    options.max_normal_turn = args.max_normal_turn;
    options.threads = args.threads;
    if (command.count("--triangles") && args.triangles == 0)
        throw UsageError("--triangles must be at least 1");
    return options;
}

nlohmann::json simplify_json(const SimplifyArgs& args, const Options& options, const Result& result,
                             double seconds) {
    return {
        {"input", args.input},
        {"output", args.output},
        {"triangles_in", result.triangles_in},
        {"triangles_out", result.triangles_out},
        {"vertices_out", result.surface.vertex_count()},
        {"operations", result.operations},
        {"seconds", seconds},
        {"strategy", args.strategy},
        {"placement", args.placement},
        {"data", args.data},
        {"alpha", args.alpha},
        {"target_triangles", options.target_triangles},
        {"keep_fraction", options.target_triangles ? nlohmann::json(nullptr)
                                                   : nlohmann::json(options.keep_fraction)},
        {"target_reached", result.target_reached},
        {"stop_reason", describe(result.stop)},
        {"repairs", repairs_json(result.repairs)},
    };
}

void print_simplify_summary(const SimplifyArgs& args, const Options& options, const Result& result,
                            double seconds) {
    const double percent = result.triangles_in
                               ? 100.0 * double(result.triangles_out) / double(result.triangles_in)
                               : 0;
    std::printf("%s: %zu -> %zu triangles (%.1f%%), %zu vertices, %s, alpha %g, %.3f s\n",
                args.output.c_str(), result.triangles_in, result.triangles_out, percent,
                result.surface.vertex_count(),
                options.strategy == Strategy::EdgeCollapse ? "edge collapse" : "vertex removal",
                args.alpha, seconds);
    std::printf("%s%s\n", result.target_reached ? "target reached" : "target not reached: ",
                result.target_reached ? "" : describe(result.stop));
    const RepairReport& r = result.repairs;
    if (r.degenerate_triangles_dropped || r.duplicate_triangles_dropped || r.unused_vertices ||
        r.triangles_flipped)
        std::printf("repaired input: %zu degenerate and %zu duplicate triangles dropped, %zu "
                    "flipped to agree with their neighbours, %zu unused vertices\n",
                    r.degenerate_triangles_dropped, r.duplicate_triangles_dropped,
                    r.triangles_flipped, r.unused_vertices);
}

} // namespace ddsimp::cli
