// Shared by the `ddsimp remote ...` commands: the connection options every one takes, the
// connected client, and how a server's refusal becomes the command's one error line.
#pragma once

#include "commands.h"
#include "ddsimp/client.h"

#include <nlohmann/json.hpp>

#include <string>

namespace CLI {
class App;
}

namespace ddsimp::cli {

struct RemoteArgs {
    std::string server = "localhost:7420";
    std::string token;
    bool tls = false;
    std::string tls_ca;
    bool tls_insecure = false;
    std::string session_key; // with --session: the session's key (see Client::join_session)
};

// Adds --server, --token, --tls, --tls-ca, --tls-insecure and --session-key to `app`.
void add_remote_options(CLI::App& app, RemoteArgs& args);

// A client connected as `args` say; throws UsageError for a bad --server, io::IoError for a
// server that cannot be reached or refuses (the message says which and why).
void connect_remote(Client& client, const RemoteArgs& args);

// Runs `body`, turning a ClientError into the io::IoError the command line reports (exit 1).
template <class F> int with_server_errors(const RemoteArgs& args, F&& body);

// Creates `dir` (and its parents) unless it exists; throws io::IoError if it cannot.
void make_output_directory(const std::string& dir);

// Prints one JSON object as one line on stdout, flushed (readers follow it as it happens).
void print_json_line(const nlohmann::json& line);

// A value the protocol carried as a float (alpha, keep), as the decimal it was meant to be
// (0.2f prints as 0.2, not 0.20000000298023224).
double float_decimal(double value);

// The level's error, if the server sent one, as fields of its JSON line: geometric_error (in
// bounding-box diagonals) and, when data was measured, data_error (in field ranges).
void add_level_error(nlohmann::json& line, const std::optional<LevelError>& error);

// Strategy names as the command line spells them ("edge", "vertex").
const char* strategy_name(Strategy strategy);

// The message of a ClientError as one line: local failures as they are, the server's refusals
// with its code and address ("localhost:7420 refused: no surface \"x\" (NOT_FOUND)").
std::string describe_client_error(const ClientError& error, const RemoteArgs& args);

// The subcommands of `ddsimp remote`, each with the options above.
Command add_remote_upload(CLI::App& remote);
Command add_remote_list(CLI::App& remote);
Command add_remote_simplify(CLI::App& remote);
Command add_remote_watch(CLI::App& remote);
Command add_remote_set(CLI::App& remote);

} // namespace ddsimp::cli

#include "ddsimp/io/surface_io.h"

template <class F> int ddsimp::cli::with_server_errors(const RemoteArgs& args, F&& body) {
    try {
        return body();
    } catch (const ClientError& e) {
        throw io::IoError(describe_client_error(e, args));
    }
}
