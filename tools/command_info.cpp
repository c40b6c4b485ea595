// ddsimp info IN: sizes, fields with their ranges, and the topology simplification keeps.
#include "cli_support.h"
#include "commands.h"
#include "ddsimp/io/surface_io.h"
#include "text_table.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

namespace ddsimp::cli {

namespace {

struct InfoArgs {
    std::string input;
    bool json = false;
};

struct FieldRange {
    std::vector<double> min, max; // per component
};

FieldRange range_of(const Field& f, size_t vertices) {
    FieldRange r;
    r.min.assign(size_t(f.components), INFINITY);
    r.max.assign(size_t(f.components), -INFINITY);
    for (size_t v = 0; v < vertices; ++v)
        for (int c = 0; c < f.components; ++c) {
            const double x = f.values[v * f.components + c];
            r.min[c] = std::min(r.min[c], x);
            r.max[c] = std::max(r.max[c], x);
        }
    return r;
}

int run_info(const InfoArgs& args) {
    io::Notes notes;
    const Surface surface = io::read_surface(args.input, &notes);
    const std::vector<std::string> driving = default_gradient_fields(surface);
    auto drives = [&](const Field& f) {
        return std::find(driving.begin(), driving.end(), f.name) != driving.end();
    };
    Surface repaired = surface;
    RepairReport repairs;
    Topology topology;
    try {
        repairs = validate(repaired);
        topology = analyze_topology(repaired);
    } catch (const InputError& e) {
        throw io::IoError(args.input + ": " + e.what());
    }

    if (args.json) {
        nlohmann::json fields = nlohmann::json::array();
        for (const Field& f : surface.fields) {
            const FieldRange r = range_of(f, surface.vertex_count());
            fields.push_back({{"name", f.name},
                              {"components", f.components},
                              {"kind", io::describe(f.kind)},
                              {"drives_by_default", drives(f)},
                              {"min", r.min},
                              {"max", r.max}});
        }
        nlohmann::json out = {
            {"input", args.input},
            {"vertices", surface.vertex_count()},
            {"triangles", surface.triangle_count()},
            {"fields", fields},
            {"topology",
             {{"vertices", topology.vertices},
              {"triangles", topology.triangles},
              {"edges", topology.edges},
              {"boundary_edges", topology.boundary_edges},
              {"boundary_loops", topology.boundary_loops},
              {"components", topology.components},
              {"euler_characteristic", topology.euler_characteristic},
              {"nonmanifold_edges", topology.nonmanifold_edges},
              {"nonmanifold_vertices", topology.nonmanifold_vertices}}},
            {"repairs", repairs_json(repairs)},
            {"notes", notes},
        };
        std::printf("%s\n", out.dump().c_str());
        return kExitOk;
    }

    std::printf("%s\n", args.input.c_str());
    std::printf("  %-22s %zu (%zu used by triangles)\n", "vertices", surface.vertex_count(),
                topology.vertices);
    std::printf("  %-22s %zu", "triangles", surface.triangle_count());
    if (repairs.degenerate_triangles_dropped || repairs.duplicate_triangles_dropped)
        std::printf(" (%zu degenerate and %zu duplicate; the rest is analysed)",
                    repairs.degenerate_triangles_dropped, repairs.duplicate_triangles_dropped);
    std::printf("  %-22s %zu (driving the data term by default: %s)\n", "fields",
                surface.fields.size(), driving.empty() ? "none" : join(driving).c_str());
    for (const std::string& note : notes) std::printf("  note: %s\n", note.c_str());
    if (surface.fields.empty()) return kExitOk;
    // One row per component: a vector's as NAME[0], NAME[1], ...
    using Align = TextTable::Align;
    TextTable table(
        {{"field"}, {"kind"}, {"data term"}, {"min", Align::Right}, {"max", Align::Right}});
    for (const Field& f : surface.fields) {
        const FieldRange r = range_of(f, surface.vertex_count());
        for (int c = 0; c < f.components; ++c)
            table.add_row({f.components == 1 ? f.name : f.name + "[" + std::to_string(c) + "]",
                           io::describe(f.kind), drives(f) ? "drives" : "carried",
                           table_number(r.min[c]), table_number(r.max[c])});
    }
    std::printf("\n%s", table.render("  ").c_str());
    return kExitOk;
}

} // namespace

Command add_info_command(CLI::App& app) {
    auto args = std::make_shared<InfoArgs>();
    CLI::App* sub = app.add_subcommand("info", "Describe a surface: sizes, fields, topology");
    sub->add_option("input", args->input, "Surface file (.vtk .vtp .ply .obj .off .stl)")
        ->required();
    sub->add_flag("--json", args->json, "Print one JSON object");
    return {sub, [args] { return run_info(*args); }};
}

} // namespace ddsimp::cli
