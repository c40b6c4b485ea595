// ddsimp simplify IN -o OUT: reads, simplifies with ddsimp::simplify, writes, reports.
#include "cli_support.h"
#include "commands.h"
#include "surface_io.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <memory>

namespace ddsimp::cli {

namespace {

struct SimplifyArgs {
    std::string input, output;
    double alpha = Options{}.alpha;
    double keep = Options{}.keep_fraction;
    size_t triangles = 0;
    double max_weight = Options{}.max_weight;
    std::string strategy = "edge";
    std::string placement = "midpoint";
    std::vector<std::string> fields;
    double feature_angle = Options{}.feature_angle;
    double line_tolerance = Options{}.line_tolerance;
    double max_normal_turn = Options{}.max_normal_turn;
    int threads = 1;
    bool json = false;
};

int run_simplify(const SimplifyArgs& args, const CLI::App& app) {
    Options options;
    options.alpha = args.alpha;
    options.strategy = args.strategy == "vertex" ? Strategy::VertexRemoval : Strategy::EdgeCollapse;
    options.placement =
        args.placement == "volume" ? Placement::VolumePreserving : Placement::Midpoint;
    options.keep_fraction = args.keep;
    options.target_triangles = app.count("--triangles") ? args.triangles : 0;
    options.max_weight = args.max_weight;
    options.gradient_fields = args.fields;
    options.feature_angle = args.feature_angle;
    options.line_tolerance = args.line_tolerance;
    options.max_normal_turn = args.max_normal_turn;
    options.threads = args.threads;
    if (app.count("--triangles") && args.triangles == 0)
        throw UsageError("--triangles must be at least 1");

    io::check_output_path(args.output);
    const Surface input = io::read_surface(args.input);
    require_fields(input, args.fields, args.input);

    Result result;
    double seconds = 0;
    {
        TerminalProgress progress("simplifying " + args.input);
        options.progress = progress.callback();
        const auto start = std::chrono::steady_clock::now();
        try {
            result = simplify(input, options);
        } catch (const InputError& e) {
            throw io::IoError(args.input + ": " + e.what());
        }
        seconds = seconds_since(start);
    }
    io::write_surface(result.surface, args.output);

    if (args.json) {
        nlohmann::json out = {
            {"input", args.input},
            {"output", args.output},
            {"triangles_in", result.triangles_in},
            {"triangles_out", result.triangles_out},
            {"vertices_out", result.surface.vertex_count()},
            {"operations", result.operations},
            {"seconds", seconds},
            {"strategy", args.strategy},
            {"placement", args.placement},
            {"alpha", args.alpha},
            {"target_triangles", options.target_triangles},
            {"keep_fraction", options.target_triangles ? nlohmann::json(nullptr)
                                                       : nlohmann::json(options.keep_fraction)},
            {"target_reached", result.target_reached},
            {"stop_reason", describe(result.stop)},
            {"repairs", repairs_json(result.repairs)},
        };
        std::printf("%s\n", out.dump().c_str());
        return kExitOk;
    }
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
    return kExitOk;
}

} // namespace

Command add_simplify_command(CLI::App& app) {
    auto args = std::make_shared<SimplifyArgs>();
    CLI::App* sub = app.add_subcommand("simplify", "Reduce a surface, keeping its topology");
    sub->add_option("input", args->input, "Input surface (.vtk .vtp .ply .obj .off .stl)")
        ->required();
    sub->add_option("-o,--output", args->output, "Output surface (.vtk .vtp .ply .obj .off)")
        ->required();
    sub->add_option("--alpha", args->alpha, "Weight of curvature vs data gradient, in [0, 1]")
        ->check(CLI::Range(0.0, 1.0))
        ->capture_default_str();
    auto* keep = sub->add_option("--keep", args->keep, "Keep this fraction of the triangles")
                     ->check(CLI::Range(0.0, 1.0))
                     ->capture_default_str();
    sub->add_option("--triangles", args->triangles, "Stop at or below this many triangles")
        ->excludes(keep);
    sub->add_option("--max-weight", args->max_weight,
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
    sub->add_option("--strategy", args->strategy, "edge (collapse) or vertex (removal)")
        ->check(CLI::IsMember({"edge", "vertex"}))
        ->capture_default_str();
    sub->add_option("--placement", args->placement, "Edge collapse point: midpoint or volume")
        ->check(CLI::IsMember({"midpoint", "volume"}))
        ->capture_default_str();
    sub->add_option("--fields", args->fields, "Fields that drive the data term (default: all)")
        ->delimiter(',');
    sub->add_option("--feature-angle", args->feature_angle,
                    "Dihedral angle (degrees) above which an edge is a feature; 180: none")
        ->check(CLI::Range(0.0, 180.0))
        ->capture_default_str();
    sub->add_option("--line-tolerance", args->line_tolerance,
                    "Boundary/feature vertices go only where the line turns less (degrees)")
        ->check(CLI::Range(0.0, 180.0))
        ->capture_default_str();
    sub->add_option("--max-normal-turn", args->max_normal_turn,
                    "Refuse operations that turn a normal more (degrees)")
        ->check(CLI::Range(0.0, 180.0))
        ->capture_default_str();
    sub->add_option("--threads", args->threads, "Threads for the set-up stages")
        ->check(CLI::Range(1, 1024))
        ->capture_default_str();
    sub->add_flag("--json", args->json, "Print one JSON object instead of a summary");
    return {sub, [args, sub] { return run_simplify(*args, *sub); }};
}

} // namespace ddsimp::cli
