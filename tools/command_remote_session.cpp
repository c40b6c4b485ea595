// ddsimp remote watch --session S -o DIR: one JSON line per session event, meshes written to DIR.
// ddsimp remote set --session S [--alpha A] [--keep K] [--field F]: steer a session's view.
#include "cli_support.h"
#include "command_remote.h"
#include "commands.h"
#include "ddsimp/io/surface_io.h"

#include <CLI/CLI.hpp>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <memory>

namespace ddsimp::cli {

namespace {

std::atomic<bool> g_interrupted{false};

extern "C" void on_interrupt(int) {
    g_interrupted = true;
}

nlohmann::json state_json(const SessionState& s) {
    nlohmann::json members = nlohmann::json::array();
    for (const Member& m : s.members)
        members.push_back({{"client_id", m.client_id}, {"name", m.name}});
    return {{"event", "state"},
            {"session", s.name},
            {"version", s.version},
            {"cause", s.cause},
            {"leader", s.leader},
            {"members", members},
            {"view",
             {{"surface", s.view.surface},
              {"alpha", float_decimal(s.view.alpha)},
              {"keep", float_decimal(s.view.keep)},
              {"field", s.view.field},
              {"strategy", strategy_name(s.view.strategy)}}}};
}

struct WatchArgs {
    RemoteArgs remote;
    std::string session;
    std::string output;
    size_t count = 0;
};

int run_watch(const WatchArgs& args) {
    make_output_directory(args.output);
    return with_server_errors(args.remote, [&] {
        Client client;
        connect_remote(client, args.remote);
        g_interrupted = false;
        std::signal(SIGINT, on_interrupt);
        std::signal(SIGTERM, on_interrupt);
        client.join_session(args.session, args.remote.session_key); // its state is the first event
        size_t events = 0, meshes = 0;
        while (!g_interrupted && (args.count == 0 || events < args.count)) {
            std::optional<SessionEvent> e =
                client.next_session_event(std::chrono::milliseconds(200));
            if (!e) continue;
            ++events;
            switch (e->kind) {
            case SessionEvent::Kind::State:
                print_json_line(state_json(e->state));
                break;
            case SessionEvent::Kind::Mesh: {
                char name[96];
                std::snprintf(name, sizeof name, "mesh-%04zu.vtk", ++meshes);
                const std::string file = (std::filesystem::path(args.output) / name).string();
                io::write_surface(e->mesh.mesh, file);
                nlohmann::json line = {{"event", "mesh"},
                                       {"session", e->mesh.session},
                                       {"keep", float_decimal(e->mesh.keep)},
                                       {"triangles", e->mesh.mesh.triangle_count()}};
                add_level_error(line, e->mesh.error);
                line.update({{"vertices", e->mesh.mesh.vertex_count()},
                             {"file", file},
                             {"result", e->mesh.result}});
                print_json_line(line);
                break;
            }
            case SessionEvent::Kind::Error:
                print_json_line({{"event", "error"},
                                 {"code", error_code_name(e->error_code)},
                                 {"message", e->error}});
                if (e->error_code == ErrorCode::Connection)
                    throw ClientError(e->error_code, e->error);
                break;
            }
        }
        std::signal(SIGINT, SIG_DFL);
        std::signal(SIGTERM, SIG_DFL);
        return kExitOk;
    });
}

struct SetArgs {
    RemoteArgs remote;
    std::string session;
    std::optional<double> alpha, keep;
    std::optional<std::string> field, surface, strategy;
};

int run_set(const SetArgs& args) {
    ViewChange change;
    change.alpha = args.alpha;
    change.keep = args.keep;
    change.field = args.field;
    change.surface = args.surface;
    if (args.strategy)
        change.strategy =
            *args.strategy == "vertex" ? Strategy::VertexRemoval : Strategy::EdgeCollapse;
    if (change.keep && !(*change.keep > 0)) throw UsageError("--keep must be above 0");
    if (!change.alpha && !change.keep && !change.field && !change.surface && !change.strategy)
        throw UsageError("nothing to set: give --alpha, --keep, --field, --surface or --strategy");
    return with_server_errors(args.remote, [&] {
        Client client;
        connect_remote(client, args.remote);
        client.join_session(args.session, args.remote.session_key); // only members steer
        print_json_line(state_json(client.set_view(args.session, change)));
        client.leave_session(args.session);
        return kExitOk;
    });
}

} // namespace

Command add_remote_watch(CLI::App& remote) {
    auto args = std::make_shared<WatchArgs>();
    CLI::App* sub =
        remote.add_subcommand("watch", "Join a session and report its events until interrupted");
    sub->add_option("--session", args->session, "The session's name")->required();
    sub->add_option("-o,--output", args->output, "Directory for the meshes received")->required();
    sub->add_option("--count", args->count, "Stop after this many events (0: never)")
        ->check(CLI::NonNegativeNumber);
    add_remote_options(*sub, args->remote);
    return {sub, [args] { return run_watch(*args); }};
}

Command add_remote_set(CLI::App& remote) {
    auto args = std::make_shared<SetArgs>();
    CLI::App* sub = remote.add_subcommand("set", "Change a session's view (and lead it)");
    sub->add_option("--session", args->session, "The session's name")->required();
    sub->add_option("--alpha", args->alpha, "Weight of curvature vs data gradient, in [0, 1]")
        ->check(CLI::Range(0.0, 1.0));
    sub->add_option("--keep", args->keep, "Fraction of the triangles to show, in (0, 1]")
        ->check(CLI::Range(0.0, 1.0));
    sub->add_option("--field", args->field, "The field to colour by");
    sub->add_option("--surface", args->surface, "A stored surface's id");
    sub->add_option("--strategy", args->strategy, "edge (collapse) or vertex (removal)")
        ->check(CLI::IsMember({"edge", "vertex"}));
    add_remote_options(*sub, args->remote);
    return {sub, [args] { return run_set(*args); }};
}

} // namespace ddsimp::cli
