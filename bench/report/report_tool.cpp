// ddsimp_report: the measuring half of the fidelity report (bench/report/run.sh drives it).
//
//   ddsimp_report reduce IN --peer P --keep F [--alpha A] [--weight W] [-o OUT] [--no-compare]
//       One reduction in this process (so its peak memory is its own): reads IN, runs peer P
//       (see peers.h) to F of IN's triangles, and prints one JSON object: time, memory, triangles
//       reached, geometric and data error (io/compare.h, the same code for every peer) and the
//       topology before and after. The WebAssembly peers run in a node process: their time is
//       the call's as node measured it, their memory node's peak ("runtime": "wasm"). Exit
//       status 0 even when the peer fails (the JSON says so); 1 for an unreadable IN, 2 for bad
//       arguments.
//   ddsimp_report prepare IN [IN2...] -o OUT [--fields a,b] [--derive-heat]
//       Makes a report surface: IN's triangles with the fields of every IN (same points, e.g.
//       the two files of an OpenFOAM cutting plane), only `--fields` if given, plus a derived
//       scalar `heat` for surfaces without data, repaired by ddsimp::validate so that every
//       simplifier gets the same clean input.
//   ddsimp_report cut VOLUME [--q Q] [--function N] --axis x|y|z [--at T] [--fields a,b] -o OUT
//       A cutting plane through a volume (vtkCutter) at fraction T of its extent along the axis,
//       carrying the volume's point fields; repaired like `prepare`.
#include "peers.h"

#include "ddsimp/io/compare.h" // io/, from the ddsimp_io target
#include "ddsimp/io/surface_io.h"
#include "ddsimp/io/volume_reader.h"
#include "ddsimp/io/vtk_surface.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <vtkCleanPolyData.h>
#include <vtkCutter.h>
#include <vtkDataSet.h>
#include <vtkPlane.h>
#include <vtkPolyData.h>

#include <malloc.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <string>

namespace {

using ddsimp::Surface;
using nlohmann::json;

// ---------------------------------------------------------------------------------------------
// Memory and time of one call
// ---------------------------------------------------------------------------------------------

// A "Vm...:" line of /proc/self/status in bytes, or -1.
long long proc_status_bytes(const char* key) {
    std::ifstream status("/proc/self/status");
    std::string line;
    const std::string prefix = std::string(key) + ":";
    while (std::getline(status, line))
        if (line.rfind(prefix, 0) == 0) return std::stoll(line.substr(prefix.size())) * 1024;
    return -1;
}

double cpu_seconds() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return double(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
           1e-6 * double(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

long long max_rss_bytes() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return static_cast<long long>(usage.ru_maxrss) * 1024;
}

json topology_json(const ddsimp::Topology& t) {
    return {{"euler", t.euler_characteristic}, {"boundary_loops", t.boundary_loops},
            {"components", t.components},      {"nonmanifold_edges", t.nonmanifold_edges},
            {"vertices", t.vertices},          {"triangles", t.triangles}};
}

// ---------------------------------------------------------------------------------------------
// reduce
// ---------------------------------------------------------------------------------------------

struct ReduceArgs {
    std::string input, peer, output;
    double keep = 0.1, alpha = 0.5, weight = 1.0;
    bool compare = true;
};

// A reduction counts as having reached its target if it is within 2% of it (vtkQuadricDecimation
// aims at a fraction and lands a few triangles either side).
constexpr double kReachedSlack = 1.02;

int run_reduce(const ReduceArgs& args) {
    Surface input;
    try {
        input = ddsimp::io::read_surface(args.input);
        ddsimp::validate(input);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ddsimp_report: %s\n", e.what());
        return 1;
    }
    ddsimp::report::PeerRequest request;
    request.alpha = args.alpha;
    request.weight = args.weight;
    request.target_triangles =
        static_cast<size_t>(std::floor(double(input.triangle_count()) * args.keep));

    json out = {{"input", args.input},
                {"peer", args.peer},
                {"alpha", args.alpha},
                {"weight", args.weight},
                {"keep", args.keep},
                {"triangles_in", input.triangle_count()},
                {"target", request.target_triangles}};

    // Peak memory of the call alone: hand freed pages back, reset the kernel's high-water mark.
    malloc_trim(0);
    const long long rss_before = proc_status_bytes("VmRSS");
    bool hwm_reset = false;
    if (std::ofstream clear("/proc/self/clear_refs"); clear) hwm_reset = bool(clear << "5");
    const double cpu_start = cpu_seconds();
    const auto wall_start = std::chrono::steady_clock::now();
    ddsimp::report::PeerOutput result;
    std::string error;
    try {
        result = ddsimp::report::run_peer(args.peer, input, request);
    } catch (const std::invalid_argument& e) {
        std::fprintf(stderr, "ddsimp_report: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        error = e.what();
    }
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    const double cpu = cpu_seconds() - cpu_start;
    const long long hwm = proc_status_bytes("VmHWM");
    if (!result.runtime.empty()) {
        // Measured by the process that ran the call; spawning it and the exchange do not count.
        out["runtime"] = result.runtime;
        if (result.call_seconds) out["seconds"] = *result.call_seconds;
        if (result.call_cpu_seconds) out["cpu_seconds"] = *result.call_cpu_seconds;
        if (result.process_peak_rss_bytes > 0)
            out["peak_rss_bytes"] = result.process_peak_rss_bytes;
    } else {
        out["seconds"] = wall;
        out["cpu_seconds"] = cpu;
        out["peak_rss_bytes"] = max_rss_bytes();
        if (hwm_reset && hwm > 0 && rss_before > 0) out["call_rss_bytes"] = hwm - rss_before;
    }

    const size_t reached = result.surface.triangle_count();
    out["triangles_out"] = reached;
    out["triangles_seen"] = result.triangles_seen;
    if (!error.empty()) {
        out["status"] = "failed";
        out["message"] = error;
    } else if (result.failed) {
        out["status"] = "failed";
        out["message"] = result.message;
    } else if (reached == 0 || double(reached) > kReachedSlack * double(request.target_triangles)) {
        out["status"] = "not reached";
        out["message"] = result.message;
    } else {
        out["status"] = "ok";
        out["message"] = result.message;
    }

    if (reached > 0) {
        out["topology_in"] = topology_json(ddsimp::analyze_topology(input));
        try {
            Surface repaired = result.surface; // peers may leave degenerate or duplicate triangles
            const ddsimp::RepairReport repairs = ddsimp::validate(repaired);
            json t = topology_json(ddsimp::analyze_topology(repaired));
            t["degenerate_dropped"] = repairs.degenerate_triangles_dropped;
            t["duplicates_dropped"] = repairs.duplicate_triangles_dropped;
            out["topology_out"] = t;
            const json& a = out["topology_in"];
            out["topology_kept"] =
                a["euler"] == t["euler"] && a["boundary_loops"] == t["boundary_loops"] &&
                a["components"] == t["components"] &&
                t["nonmanifold_edges"].get<size_t>() <= a["nonmanifold_edges"].get<size_t>() &&
                repairs.degenerate_triangles_dropped == 0 &&
                repairs.duplicate_triangles_dropped == 0;
        } catch (const ddsimp::InputError& e) {
            out["topology_kept"] = false;
            out["topology_error"] = e.what();
        }
    }

    if (args.compare && reached > 0) {
        std::vector<std::string> common; // the input's fields the output still has
        std::vector<std::string> lost;
        for (const ddsimp::Field& f : input.fields) {
            const ddsimp::Field* g = result.surface.find_field(f.name);
            (g && g->components == f.components ? common : lost).push_back(f.name);
        }
        const ddsimp::tools::CompareReport cmp =
            ddsimp::tools::compare_surfaces(input, result.surface, common);
        out["geometric_rms"] = cmp.distance.symmetric.rms;
        out["geometric_hausdorff"] = cmp.distance.symmetric.max;
        // The data error of a surface is that of its worst field (all are range-normalised).
        double data_rms = 0, data_max = 0;
        json fields = json::object();
        for (const ddsimp::tools::FieldError& f : cmp.fields) {
            fields[f.name] = {{"rms", f.error.symmetric.rms}, {"max", f.error.symmetric.max}};
            data_rms = std::max(data_rms, f.error.symmetric.rms);
            data_max = std::max(data_max, f.error.symmetric.max);
        }
        if (!cmp.fields.empty()) {
            out["data_rms"] = data_rms;
            out["data_max"] = data_max;
        }
        out["fields"] = fields;
        if (!lost.empty()) out["fields_lost"] = lost;
    }

    if (!args.output.empty() && reached > 0) ddsimp::io::write_surface(result.surface, args.output);
    std::printf("%s\n", out.dump().c_str());
    return 0;
}

// ---------------------------------------------------------------------------------------------
// prepare and cut
// ---------------------------------------------------------------------------------------------

// Keeps only `names` (in that order); an unknown name is an error.
void keep_fields(Surface& surface, const std::vector<std::string>& names, const std::string& ctx) {
    if (names.empty()) return;
    std::vector<ddsimp::Field> kept;
    for (const std::string& name : names) {
        const ddsimp::Field* f = surface.find_field(name);
        if (!f) throw std::runtime_error(ctx + ": no field '" + name + "'");
        kept.push_back(*f);
    }
    surface.fields = std::move(kept);
}

// A smooth synthetic scalar for surfaces that carry no data (the scanned and CAD geometries): a
// hot spot (Gaussian, width 15% of the bounding-box diagonal) centred at 30/60/70% of the box,
// over a sine wave of 4 periods per diagonal along y. Deterministic, of order 1.
void derive_heat(Surface& surface) {
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t v = 0; v < surface.vertex_count(); ++v)
        for (int c = 0; c < 3; ++c) {
            lo[c] = std::min(lo[c], surface.positions[3 * v + c]);
            hi[c] = std::max(hi[c], surface.positions[3 * v + c]);
        }
    double diagonal = 0, centre[3];
    const double at[3] = {0.3, 0.6, 0.7};
    for (int c = 0; c < 3; ++c) {
        diagonal += double(hi[c] - lo[c]) * double(hi[c] - lo[c]);
        centre[c] = lo[c] + at[c] * double(hi[c] - lo[c]);
    }
    diagonal = std::sqrt(diagonal);
    const double width = 0.15 * diagonal;
    ddsimp::Field heat{"heat", 1, {}};
    heat.values.reserve(surface.vertex_count());
    for (size_t v = 0; v < surface.vertex_count(); ++v) {
        double d2 = 0;
        for (int c = 0; c < 3; ++c) {
            const double d = surface.positions[3 * v + c] - centre[c];
            d2 += d * d;
        }
        const double y = (surface.positions[3 * v + 1] - lo[1]) / diagonal;
        heat.values.push_back(static_cast<float>(std::exp(-d2 / (2 * width * width)) +
                                                 0.25 * std::sin(8 * std::numbers::pi * y)));
    }
    surface.fields.push_back(std::move(heat));
}

void repair_and_write(Surface& surface, const std::string& output) {
    const ddsimp::RepairReport r = ddsimp::validate(surface);
    ddsimp::io::write_surface(surface, output);
    std::printf("%s: %zu triangles, %zu fields (dropped %zu degenerate, %zu duplicate; %zu "
                "flipped)\n",
                output.c_str(), surface.triangle_count(), surface.fields.size(),
                r.degenerate_triangles_dropped, r.duplicate_triangles_dropped, r.triangles_flipped);
}

struct PrepareArgs {
    std::vector<std::string> inputs, fields;
    std::string output;
    bool derive_heat = false;
};

int run_prepare(const PrepareArgs& args) {
    Surface surface = ddsimp::io::read_surface(args.inputs.front());
    for (size_t i = 1; i < args.inputs.size(); ++i) {
        Surface more = ddsimp::io::read_surface(args.inputs[i]);
        if (more.positions != surface.positions)
            throw std::runtime_error(args.inputs[i] + ": not the same points as " +
                                     args.inputs.front());
        for (ddsimp::Field& f : more.fields)
            if (!surface.find_field(f.name)) surface.fields.push_back(std::move(f));
    }
    keep_fields(surface, args.fields, args.inputs.front());
    if (args.derive_heat) derive_heat(surface);
    repair_and_write(surface, args.output);
    return 0;
}

struct CutArgs {
    std::string volume, q_file, output, axis = "z";
    std::vector<int> functions;
    std::vector<std::string> fields;
    double at = 0.5;
};

int run_cut(const CutArgs& args) {
    ddsimp::io::VolumeSource source{args.volume, args.q_file, args.functions};
    vtkSmartPointer<vtkDataSet> volume = ddsimp::io::read_volume(source);
    double bounds[6];
    volume->GetBounds(bounds);
    const int axis = args.axis == "x" ? 0 : args.axis == "y" ? 1 : 2;
    double origin[3], normal[3] = {0, 0, 0};
    for (int c = 0; c < 3; ++c) origin[c] = 0.5 * (bounds[2 * c] + bounds[2 * c + 1]);
    origin[axis] = bounds[2 * axis] + args.at * (bounds[2 * axis + 1] - bounds[2 * axis]);
    normal[axis] = 1;
    auto plane = vtkSmartPointer<vtkPlane>::New();
    plane->SetOrigin(origin);
    plane->SetNormal(normal);
    auto cutter = vtkSmartPointer<vtkCutter>::New();
    cutter->SetInputData(volume);
    cutter->SetCutFunction(plane);
    cutter->GenerateTrianglesOn();
    // vtkCutter cuts an unstructured grid cell by cell: merge the points the cells share.
    auto merge = vtkSmartPointer<vtkCleanPolyData>::New();
    merge->SetInputConnection(cutter->GetOutputPort());
    merge->PointMergingOn();
    merge->SetTolerance(0.0);
    merge->Update();
    Surface surface =
        ddsimp::io::surface_from_dataset(merge->GetOutput(), args.volume + " cut", args.fields);
    repair_and_write(surface, args.output);
    return 0;
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"ddsimp_report: one measured reduction, or a report surface"};
    app.require_subcommand(1);

    ReduceArgs reduce;
    CLI::App* r = app.add_subcommand("reduce", "One reduction by one peer, measured (JSON)");
    r->add_option("input", reduce.input, "Surface")->required();
    r->add_option("--peer", reduce.peer,
                  "ddsimp-edge, ddsimp-vertex, meshopt, vtk-quadric, vtk-decimatepro, "
                  "openmesh, meshopt-attributes or meshopt-update")
        ->required();
    r->add_option("--keep", reduce.keep, "Fraction of the triangles to keep")
        ->check(CLI::Range(0.0, 1.0));
    r->add_option("--alpha", reduce.alpha, "ddsimp's alpha")->check(CLI::Range(0.0, 1.0));
    r->add_option("--weight", reduce.weight,
                  "meshoptimizer's attribute weight (meshopt-attributes, meshopt-update)")
        ->check(CLI::PositiveNumber);
    r->add_option("-o,--output", reduce.output, "Write the reduced surface here");
    r->add_flag("!--no-compare", reduce.compare, "Skip the error measurement (timing only)");

    PrepareArgs prepare;
    CLI::App* p = app.add_subcommand("prepare", "A repaired report surface from ready surfaces");
    p->add_option("inputs", prepare.inputs, "Surfaces with the same points")->required();
    p->add_option("-o,--output", prepare.output, "Output surface")->required();
    p->add_option("--fields", prepare.fields, "Fields to keep")->delimiter(',');
    p->add_flag("--derive-heat", prepare.derive_heat, "Add the synthetic scalar 'heat'");

    CutArgs cut;
    CLI::App* c = app.add_subcommand("cut", "A cutting plane through a volume");
    c->add_option("volume", cut.volume, "Volume or grid")->required();
    c->add_option("--q", cut.q_file, "PLOT3D solution file");
    c->add_option("--function", cut.functions, "PLOT3D function numbers")->delimiter(',');
    c->add_option("--axis", cut.axis, "Plane normal")->check(CLI::IsMember({"x", "y", "z"}));
    c->add_option("--at", cut.at, "Fraction of the extent")->check(CLI::Range(0.0, 1.0));
    c->add_option("--fields", cut.fields, "Fields to carry")->delimiter(',');
    c->add_option("-o,--output", cut.output, "Output surface")->required();

    CLI11_PARSE(app, argc, argv);
    try {
        if (r->parsed()) return run_reduce(reduce);
        if (p->parsed()) return run_prepare(prepare);
        return run_cut(cut);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ddsimp_report: %s\n", e.what());
        return 1;
    }
}
