// The command line of `ddsimp simplify`, shared with `ddsimp-mpi simplify`: its options, the
// library options they ask for, and the report of a run (one line of JSON or a short summary).
#pragma once

#include "ddsimp/ddsimp.h"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace ddsimp::cli {

struct SimplifyArgs {
    std::string input, output;
    double alpha = Options{}.alpha;
    double keep = Options{}.keep_fraction;
    size_t triangles = 0;
    double max_weight = Options{}.max_weight;
    std::string strategy = "edge";
    std::string placement = "least-error";
    std::string data = "least-error";
    std::string terms = "quadrics";
    std::vector<std::string> fields;
    double feature_angle = Options{}.feature_angle;
    double line_tolerance = Options{}.line_tolerance;
    double max_normal_turn = Options{}.max_normal_turn;
    int threads = Options{}.threads; // 0: every hardware thread
    bool json = false;
    std::string colour_by; // .glb output: the field shown as colours
    bool meshopt = false;  // .glb output: EXT_meshopt_compression
};

// Adds IN, -o OUT and every simplify option (with its checks) to `command`, writing into `args`,
// which must outlive the parse.
void add_simplify_options(CLI::App& command, SimplifyArgs& args);

// The library options the parsed command line asks for (no progress callback). Throws UsageError
// for what CLI11 cannot check ("--triangles 0").
Options simplify_options(const SimplifyArgs& args, const CLI::App& command);

// The --json object of a run that took `seconds`.
nlohmann::json simplify_json(const SimplifyArgs& args, const Options& options, const Result& result,
                             double seconds);

// The human-readable summary of a run on stdout: sizes, target, repairs.
void print_simplify_summary(const SimplifyArgs& args, const Options& options, const Result& result,
                            double seconds);

} // namespace ddsimp::cli
