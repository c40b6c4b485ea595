// ddsimp compare ORIGINAL REDUCED: geometric and data error of a reduced surface.
#include "cli_support.h"
#include "commands.h"
#include "ddsimp/io/compare.h"
#include "ddsimp/io/surface_io.h"
#include "text_table.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace ddsimp::cli {

namespace {

struct CompareArgs {
    std::string original, reduced;
    std::vector<std::string> fields;
    bool json = false;
};

nlohmann::json to_json(const tools::ErrorStats& s) {
    return {{"rms", s.rms}, {"max", s.max}};
}

nlohmann::json to_json(const tools::TwoWayError& e) {
    return {{"original_to_reduced", to_json(e.original_to_reduced)},
            {"reduced_to_original", to_json(e.reduced_to_original)},
            {"symmetric", to_json(e.symmetric)}};
}

// rms and max of each direction, in the table's column order.
std::vector<std::string> error_cells(const std::string& label, const tools::TwoWayError& e) {
    std::vector<std::string> cells{label};
    for (const tools::ErrorStats* s :
         {&e.original_to_reduced, &e.reduced_to_original, &e.symmetric})
        for (double x : {s->rms, s->max}) {
            char buffer[32];
            std::snprintf(buffer, sizeof buffer, "%.4e", x);
            cells.emplace_back(buffer);
        }
    return cells;
}

int run_compare(const CompareArgs& args) {
    const Surface original = read_input(args.original);
    const Surface reduced = read_input(args.reduced);
    require_fields(original, args.fields, args.original);
    require_fields(reduced, args.fields, args.reduced);

    const auto start = std::chrono::steady_clock::now();
    tools::CompareReport report;
    try {
        report = tools::compare_surfaces(original, reduced, args.fields);
    } catch (const InputError& e) {
        throw io::IoError("comparing " + args.original + " with " + args.reduced + ": " + e.what());
    }
    const double seconds = seconds_since(start);

    if (args.json) {
        nlohmann::json fields = nlohmann::json::array();
        for (const tools::FieldError& f : report.fields)
            fields.push_back({{"name", f.name},
                              {"components", f.components},
                              {"range", f.range},
                              {"error", to_json(f.error)}});
        nlohmann::json out = {{"original", args.original},
                              {"reduced", args.reduced},
                              {"diagonal", report.diagonal},
                              {"original_samples", report.original_samples},
                              {"reduced_samples", report.reduced_samples},
                              {"distance", to_json(report.distance)},
                              {"fields", fields},
                              {"seconds", seconds}};
        std::printf("%s\n", out.dump().c_str());
        return kExitOk;
    }
    std::printf("%s vs %s (%zu and %zu sample vertices, %.3f s)\n", args.original.c_str(),
                args.reduced.c_str(), report.original_samples, report.reduced_samples, seconds);
    std::printf("  errors relative to the original's bounding-box diagonal (%g) or field range\n",
                report.diagonal);
    using Align = TextTable::Align;
    TextTable table({{"error of"},
                     {"rms orig->red", Align::Right},
                     {"max orig->red", Align::Right},
                     {"rms red->orig", Align::Right},
                     {"max red->orig", Align::Right},
                     {"rms symmetric", Align::Right},
                     {"max symmetric", Align::Right}});
    table.add_row(error_cells("distance", report.distance));
    for (const tools::FieldError& f : report.fields) table.add_row(error_cells(f.name, f.error));
    std::printf("%s", table.render("  ").c_str());
    return kExitOk;
}

} // namespace

Command add_compare_command(CLI::App& app) {
    auto args = std::make_shared<CompareArgs>();
    CLI::App* sub = app.add_subcommand(
        "compare", "Geometric distance and data error between a surface and its reduction");
    sub->add_option("original", args->original, "The original surface")->required();
    sub->add_option("reduced", args->reduced, "The reduced surface")->required();
    sub->add_option("--field", args->fields,
                    "Field(s) to compare (repeatable or comma-separated; default: all shared)")
        ->delimiter(',');
    sub->add_flag("--json", args->json, "Print one JSON object");
    return {sub, [args] { return run_compare(*args); }};
}

} // namespace ddsimp::cli
