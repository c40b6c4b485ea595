// ddsimp remote simplify FILE|--surface ID --alpha A --keep K1,K2 -o DIR: asks the server for
// levels and prints one JSON line per mesh that arrives (a preview the server sends at once, then
// the exact levels), writing only the exact levels into DIR.
#include "cli_support.h"
#include "command_remote.h"
#include "commands.h"
#include "ddsimp/io/surface_io.h"

#include <CLI/CLI.hpp>

#include <condition_variable>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>

namespace ddsimp::cli {

namespace {

struct RemoteSimplifyArgs {
    RemoteArgs remote;
    std::string input;
    std::string surface;
    double alpha = Options{}.alpha;
    std::vector<double> keep;
    std::string strategy = "edge";
    std::string placement = "least-error";
    std::string data = "least-error";
    std::string terms = "quadrics";
    std::vector<std::string> fields;
    double feature_angle = Options{}.feature_angle;
    bool progressive = false;
    bool raw = false;
    std::string output;
};

// Levels handed from the client's network thread to the command's, in arrival order.
class LevelQueue {
public:
    void push(Level level) {
        std::lock_guard lock(mutex_);
        levels_.push_back(std::move(level));
        ready_.notify_one();
    }
    std::optional<Level> pop_for(std::chrono::milliseconds timeout) {
        std::unique_lock lock(mutex_);
        if (!ready_.wait_for(lock, timeout, [&] { return !levels_.empty(); })) return {};
        Level level = std::move(levels_.front());
        levels_.pop_front();
        return level;
    }

private:
    std::mutex mutex_;
    std::condition_variable ready_;
    std::deque<Level> levels_;
};

std::string level_file(const std::string& dir, double keep) {
    char name[64];
    std::snprintf(name, sizeof name, "keep-%g.vtk", keep);
    return (std::filesystem::path(dir) / name).string();
}

// A progressive level holds every vertex received so far; a file holds only the level's own.
Surface without_unused_vertices(const Surface& s) {
    std::vector<uint32_t> map(s.vertex_count(), UINT32_MAX);
    for (uint32_t v : s.triangles) map[v] = 0;
    Surface out;
    for (const Field& f : s.fields) out.fields.push_back({f.name, f.components, {}, f.kind});
    uint32_t next = 0;
    for (size_t v = 0; v < map.size(); ++v) {
        if (map[v] == UINT32_MAX) continue;
        map[v] = next++;
        out.positions.insert(out.positions.end(), &s.positions[3 * v], &s.positions[3 * v + 3]);
        for (size_t f = 0; f < s.fields.size(); ++f) {
            const size_t nc = size_t(s.fields[f].components);
            const float* at = &s.fields[f].values[nc * v];
            out.fields[f].values.insert(out.fields[f].values.end(), at, at + nc);
        }
    }
    for (uint32_t v : s.triangles) out.triangles.push_back(map[v]);
    return out;
}

int run_remote_simplify(const RemoteSimplifyArgs& args) {
    if (args.input.empty() == args.surface.empty())
        throw UsageError("give either a FILE to upload or --surface ID");
    for (double k : args.keep)
        if (!(k > 0 && k <= 1))
            throw UsageError("--keep " + std::to_string(k) + " is outside (0, 1]");
    make_output_directory(args.output);
    io::check_output_path(level_file(args.output, args.keep.front()));
    Surface input;
    if (!args.input.empty()) input = io::read_surface(args.input);

    return with_server_errors(args.remote, [&] {
        Client client;
        connect_remote(client, args.remote);
        LevelRequest request;
        request.surface = args.surface;
        if (!args.input.empty())
            request.surface =
                client.upload(input, std::filesystem::path(args.input).filename().string()).surface;
        request.alpha = args.alpha;
        request.keep = args.keep;
        request.strategy =
            args.strategy == "vertex" ? Strategy::VertexRemoval : Strategy::EdgeCollapse;
        request.placement = args.placement == "volume"     ? Placement::VolumePreserving
                            : args.placement == "midpoint" ? Placement::Midpoint
                                                           : Placement::LeastError;
        request.data_placement =
            args.data == "interpolated" ? DataPlacement::Interpolated : DataPlacement::LeastError;
        request.terms = args.terms == "paper" ? Terms::AngleDeficitGradient : Terms::ErrorQuadrics;
        request.gradient_fields = args.fields;
        request.feature_angle = args.feature_angle;
        request.progressive = args.progressive;
        request.encoding = args.raw ? Encoding::Raw : Encoding::Meshopt;

        const auto start = std::chrono::steady_clock::now();
        LevelQueue arrived;
        PendingRequest pending =
            client.request(request, [&arrived](const Level& l) { arrived.push(l); });
        for (size_t n = 0; n < args.keep.size();) {
            std::optional<Level> level;
            while (!(level = arrived.pop_for(std::chrono::milliseconds(100)))) {
                if (pending.done.wait_for(std::chrono::seconds(0)) != std::future_status::ready)
                    continue;
                if (!(level = arrived.pop_for(std::chrono::milliseconds(0)))) {
                    pending.done.get();                     // throws if the request failed
                    for (auto& f : pending.levels) f.get(); // or for the level that is missing
                }
                break;
            }
            const double seconds = seconds_since(start);
            // As asked, not as the float the protocol carried back.
            const double keep =
                level->index < args.keep.size() ? args.keep[level->index] : level->keep;
            const Surface mesh = without_unused_vertices(level->mesh);
            nlohmann::json line = {
                {"keep", keep}, {"preview", level->preview}, {"triangles", mesh.triangle_count()}};
            add_level_error(line, level->error);
            line["vertices"] = mesh.vertex_count();
            if (!level->preview) {
                line["file"] = level_file(args.output, keep);
                io::write_surface(mesh, line["file"].get<std::string>());
                ++n;
            }
            line.update({{"seconds", seconds},
                         {"server_seconds", level->seconds},
                         {"cached", level->cached},
                         {"bytes", level->wire_bytes},
                         {"encoding", level->encoding == Encoding::Meshopt ? "meshopt" : "raw"},
                         {"target_reached", level->target_reached},
                         {"result", level->result}});
            print_json_line(line);
        }
        pending.done.get();
        return kExitOk;
    });
}

} // namespace

Command add_remote_simplify(CLI::App& remote) {
    auto args = std::make_shared<RemoteSimplifyArgs>();
    CLI::App* sub = remote.add_subcommand("simplify", "Levels of a reduction, from the server");
    auto* file = sub->add_option("input", args->input, "Surface file to upload first");
    sub->add_option("--surface", args->surface, "A stored surface's id (see remote list)")
        ->excludes(file);
    sub->add_option("--alpha", args->alpha, "Weight of curvature vs data gradient, in [0, 1]")
        ->check(CLI::Range(0.0, 1.0))
        ->capture_default_str();
    sub->add_option("--keep", args->keep, "Fractions of the triangles to keep, e.g. 0.5,0.1")
        ->delimiter(',')
        ->required();
    sub->add_option("--strategy", args->strategy, "edge (collapse) or vertex (removal)")
        ->check(CLI::IsMember({"edge", "vertex"}))
        ->capture_default_str();
    sub->add_option("--placement", args->placement,
                    "Edge collapse point: least-error (on the edge), midpoint or volume")
        ->check(CLI::IsMember({"least-error", "midpoint", "volume"}))
        ->capture_default_str();
    sub->add_option("--data", args->data,
                    "Edge collapse data at the new point: least-error (of the data error, "
                    "clamped to the two values it replaces) or interpolated (along the edge)")
        ->check(CLI::IsMember({"least-error", "interpolated"}))
        ->capture_default_str();
    sub->add_option("--terms", args->terms,
                    "What the weight measures: quadrics (error against the input) or paper "
                    "(angle deficit and data gradient)")
        ->check(CLI::IsMember({"quadrics", "paper"}))
        ->capture_default_str();
    sub->add_option("--feature-angle", args->feature_angle,
                    "Dihedral angle (degrees) above which an edge is a feature; 180: none")
        ->check(CLI::Range(0.0, 180.0))
        ->capture_default_str();
    sub->add_option("--fields", args->fields, "Fields that drive the data term (default: all)")
        ->delimiter(',');
    sub->add_flag("--progressive", args->progressive,
                  "Receive a base level, then refinements (the files hold each whole level)");
    sub->add_flag("--raw", args->raw, "Ask for raw arrays instead of meshoptimizer's codecs");
    sub->add_option("-o,--output", args->output, "Directory for the levels (keep-K.vtk)")
        ->required();
    add_remote_options(*sub, args->remote);
    return {sub, [args] { return run_remote_simplify(*args); }};
}

} // namespace ddsimp::cli
