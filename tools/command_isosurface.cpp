// ddsimp isosurface VOLUME --field F --value V -o OUT: a surface with data, from a volume.
#include "cli_support.h"
#include "commands.h"
#include "ddsimp/io/isosurface.h"
#include "ddsimp/io/surface_io.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <memory>

namespace ddsimp::cli {

namespace {

struct IsosurfaceArgs {
    std::string volume, output;
    io::IsosurfaceOptions options;
    bool json = false;
};

int run_isosurface(const IsosurfaceArgs& args) {
    io::check_output_path(args.output);
    const auto start = std::chrono::steady_clock::now();
    const Surface surface = io::extract_isosurface(args.volume, args.options);
    const double seconds = seconds_since(start);
    write_output(surface, args.output);
    if (args.json) {
        std::vector<std::string> names;
        for (const Field& f : surface.fields) names.push_back(f.name);
        nlohmann::json out = {{"volume", args.volume},
                              {"output", args.output},
                              {"field", args.options.field},
                              {"value", args.options.value},
                              {"resample", args.options.resample},
                              {"vertices", surface.vertex_count()},
                              {"triangles", surface.triangle_count()},
                              {"fields", names},
                              {"seconds", seconds}};
        std::printf("%s\n", out.dump().c_str());
        return kExitOk;
    }
    std::printf("%s: %zu triangles, %zu vertices, fields: %s (%.2f s)\n", args.output.c_str(),
                surface.triangle_count(), surface.vertex_count(), describe_fields(surface).c_str(),
                seconds);
    return kExitOk;
}

} // namespace

Command add_isosurface_command(CLI::App& app) {
    auto args = std::make_shared<IsosurfaceArgs>();
    CLI::App* sub = app.add_subcommand(
        "isosurface", "Extract an isosurface from a volume, carrying other fields onto it");
    sub->add_option("volume", args->volume,
                    "Volume or grid (.vtk .vti .vts .vtr .vtu .ex2 .exo, PLOT3D grid with --q)")
        ->required();
    sub->add_option("--field", args->options.field, "Scalar field to contour")->required();
    sub->add_option("--value", args->options.value, "Isovalue")->required();
    sub->add_option("-o,--output", args->output, "Output surface (.vtk .vtp .ply .obj .off)")
        ->required();
    sub->add_option("--carry", args->options.carry,
                    "Fields to carry onto the surface (default: all point fields)")
        ->delimiter(',');
    sub->add_option("--resample", args->options.resample,
                    "Resample the volume to K times its resolution per axis first")
        ->check(CLI::Range(1, 64))
        ->capture_default_str();
    sub->add_option("--q", args->options.q_file, "PLOT3D solution (Q) file for a grid file");
    sub->add_option("--function", args->options.plot3d_functions,
                    "PLOT3D: extra function numbers to compute (e.g. 110 pressure)")
        ->delimiter(',');
    sub->add_flag("--json", args->json, "Print one JSON object");
    return {sub, [args] { return run_isosurface(*args); }};
}

} // namespace ddsimp::cli
