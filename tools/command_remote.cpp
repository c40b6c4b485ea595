// ddsimp remote ...: the commands that talk to ddsimp-server through libddsimp-client. This file
// holds what they share (connection options, errors) and the small ones: upload, list, delete.
#include "command_remote.h"

#include "cli_support.h"
#include "commands.h"
#include "ddsimp/io/surface_io.h"
#include "text_table.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace ddsimp::cli {

void add_remote_options(CLI::App& app, RemoteArgs& args) {
    app.add_option("--server", args.server, "The server as HOST:PORT")->capture_default_str();
    app.add_option("--token", args.token, "The server's access token");
    app.add_flag("--tls", args.tls, "Connect with TLS");
    app.add_option("--tls-ca", args.tls_ca, "CA certificate file (PEM) to check the server's by")
        ->check(CLI::ExistingFile);
    app.add_flag("--tls-insecure", args.tls_insecure,
                 "With --tls: accept any certificate (self-signed test servers only)");
    app.add_option("--session-key", args.session_key,
                   "With --session: the session's key; only those who give it join the session "
                   "and see its surfaces")
        ->envname("DDSIMP_SESSION_KEY");
}

void connect_remote(Client& client, const RemoteArgs& args) {
    ConnectOptions options;
    try {
        parse_server_address(args.server, options);
    } catch (const std::invalid_argument& e) {
        throw UsageError(std::string("--server: ") + e.what());
    }
    options.token = args.token;
    options.tls = args.tls || args.tls_insecure || !args.tls_ca.empty();
    options.ca_file = args.tls_ca;
    options.tls_insecure = args.tls_insecure;
    options.client_name = "ddsimp remote";
    options.kind = ClientKind::Tool;
    client.connect(options);
}

std::string describe_client_error(const ClientError& error, const RemoteArgs& args) {
    if (error.code() == ErrorCode::Connection || error.code() == ErrorCode::Protocol)
        return error.what();
    return args.server + " refused: " + error.what() + " (" + error_code_name(error.code()) + ")";
}

void make_output_directory(const std::string& dir) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (!std::filesystem::is_directory(dir))
        throw io::IoError("cannot create the output directory " + dir +
                          (ec ? ": " + ec.message() : ""));
}

void print_json_line(const nlohmann::json& line) {
    std::printf("%s\n", line.dump().c_str());
    std::fflush(stdout);
}

double float_decimal(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.7g", value);
    return std::strtod(text, nullptr);
}

void add_level_error(nlohmann::json& line, const std::optional<LevelError>& error) {
    if (!error) return;
    line["geometric_error"] = float_decimal(error->geometric);
    if (error->data_components > 0) line["data_error"] = float_decimal(error->data);
}

const char* strategy_name(Strategy strategy) {
    return strategy == Strategy::VertexRemoval ? "vertex" : "edge";
}

namespace {

struct UploadArgs {
    RemoteArgs remote;
    std::string input;
    std::string session;
};

int run_upload(const UploadArgs& args) {
    const Surface surface = io::read_surface(args.input);
    return with_server_errors(args.remote, [&] {
        Client client;
        connect_remote(client, args.remote);
        const std::string name = std::filesystem::path(args.input).filename().string();
        // A surface uploaded into a session is visible to its members only; members upload.
        if (!args.session.empty()) client.join_session(args.session, args.remote.session_key);
        const UploadResult r = client.upload(surface, name, args.session);
        print_json_line({{"surface", r.surface},
                         {"triangles", r.triangles},
                         {"vertices", r.vertices},
                         {"already_stored", r.already_stored},
                         {"repairs", r.repairs}});
        return kExitOk;
    });
}

int run_list(const RemoteArgs& args, bool json) {
    return with_server_errors(args, [&] {
        Client client;
        connect_remote(client, args);
        using Align = TextTable::Align;
        TextTable table({{"surface"},
                         {"name"},
                         {"triangles", Align::Right},
                         {"vertices", Align::Right},
                         {"fields"}});
        for (const SurfaceInfo& s : client.list_surfaces()) {
            nlohmann::json fields = nlohmann::json::array();
            std::vector<std::string> names;
            for (const FieldInfo& f : s.fields) {
                fields.push_back({{"name", f.name}, {"components", f.components}});
                names.push_back(
                    f.components == 1 ? f.name : f.name + "(" + std::to_string(f.components) + ")");
            }
            if (json)
                print_json_line({{"surface", s.surface},
                                 {"name", s.name},
                                 {"triangles", s.triangles},
                                 {"vertices", s.vertices},
                                 {"fields", fields}});
            else
                table.add_row({s.surface, s.name, std::to_string(s.triangles),
                               std::to_string(s.vertices), join(names)});
        }
        if (!json) std::printf("%s", table.render().c_str());
        return kExitOk;
    });
}

int run_delete(const RemoteArgs& args, const std::string& surface) {
    return with_server_errors(args, [&] {
        Client client;
        connect_remote(client, args);
        const bool removed = client.delete_surface(surface);
        print_json_line({{"surface", surface}, {"removed", removed}});
        return kExitOk;
    });
}

} // namespace

Command add_remote_upload(CLI::App& remote) {
    auto args = std::make_shared<UploadArgs>();
    CLI::App* sub = remote.add_subcommand("upload", "Send a surface to the server");
    sub->add_option("input", args->input, "Surface file (.vtk .vtp .ply .obj .off .stl)")
        ->required();
    sub->add_option("--session", args->session,
                    "Show it in this session, and to its members only (joins it)");
    add_remote_options(*sub, args->remote);
    return {sub, [args] { return run_upload(*args); }};
}

Command add_remote_list(CLI::App& remote) {
    auto args = std::make_shared<RemoteArgs>();
    auto json = std::make_shared<bool>(false);
    CLI::App* sub = remote.add_subcommand("list", "The surfaces the server has stored");
    add_remote_options(*sub, *args);
    sub->add_flag("--json", *json, "Print one JSON object per surface, a line each");
    return {sub, [args, json] { return run_list(*args, *json); }};
}

Command add_remote_delete(CLI::App& remote) {
    auto args = std::make_shared<RemoteArgs>();
    auto surface = std::make_shared<std::string>();
    CLI::App* sub = remote.add_subcommand(
        "delete",
        "Delete a surface your token uploaded (removed: false if another token keeps it)");
    sub->add_option("surface", *surface, "The surface's id (see ddsimp remote list)")->required();
    add_remote_options(*sub, *args);
    return {sub, [args, surface] { return run_delete(*args, *surface); }};
}

Command add_remote_command(CLI::App& app) {
    CLI::App* remote = app.add_subcommand(
        "remote", "Talk to ddsimp-server: upload, list, delete, simplify, watch, set");
    remote->require_subcommand(1);
    auto commands = std::make_shared<std::vector<Command>>(std::vector<Command>{
        add_remote_upload(*remote), add_remote_list(*remote), add_remote_delete(*remote),
        add_remote_simplify(*remote), add_remote_watch(*remote), add_remote_set(*remote)});
    return {remote, [commands] {
                for (const Command& c : *commands)
                    if (c.app->parsed()) return c.run();
                throw UsageError("no remote command given (see ddsimp remote --help)");
            }};
}

} // namespace ddsimp::cli
