#include "config.h"

#include <CLI/CLI.hpp>

#include <cctype>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#ifndef DDSIMP_DEFAULT_SAMPLE
#define DDSIMP_DEFAULT_SAMPLE ""
#endif
#ifndef DDSIMP_DEFAULT_WEB_DIR
#define DDSIMP_DEFAULT_WEB_DIR ""
#endif

namespace ddsimp::server {
namespace {

// The environment variable of a flag or file key: --http-port / http-port → DDSIMP_HTTP_PORT.
std::string environment_name(const std::string& key) {
    std::string env = "DDSIMP_";
    for (char ch : key.substr(key.find_first_not_of('-')))
        env += ch == '-' ? '_' : char(std::toupper(static_cast<unsigned char>(ch)));
    return env;
}

// The configuration file (TOML/INI `key = value`) without the keys whose DDSIMP_* variable is
// set, so that the precedence is flag > environment > file > default. CLI11 reads the file before
// the environment and lets the first source win; a container's `-e` or a Kubernetes Secret must
// override a mounted file, as it does for most servers.
class FileBelowEnvironment : public CLI::ConfigTOML {
public:
    std::vector<CLI::ConfigItem> from_config(std::istream& input) const override {
        std::vector<CLI::ConfigItem> items = CLI::ConfigTOML::from_config(input);
        std::erase_if(items, [](const CLI::ConfigItem& item) {
            const char* value = std::getenv(environment_name(item.name).c_str());
            return item.parents.empty() && value != nullptr && *value != '\0';
        });
        return items;
    }
};

} // namespace

Config parse_config(int argc, char** argv) {
    Config c;
    c.sample = DDSIMP_DEFAULT_SAMPLE;
    c.web_dir = DDSIMP_DEFAULT_WEB_DIR;
    CLI::App app{"ddsimp-server: data-dependent surface simplification as a service"};
    app.set_version_flag("--version", "ddsimp-server 0.1.0");
    app.set_config("--config", "", "read options from an INI file (key = value)");
    app.config_formatter(std::make_shared<FileBelowEnvironment>());
    app.option_defaults()->always_capture_default();
    const auto opt = [&](const std::string& name, auto& value, const std::string& help) {
        return app.add_option(name, value, help)->envname(environment_name(name));
    };
    opt("--bind", c.bind, "address of the native port (0.0.0.0 for every interface)");
    opt("--http-bind", c.http_bind,
        "address of the HTTP port (unauthenticated /metrics, /healthz); \"\" for --bind's");
    opt("--port", c.port, "native protocol port");
    opt("--http-port", c.http_port, "HTTP port: /healthz, /metrics, WebSocket /ws, web renderer");
    opt("--data-dir", c.data_dir, "where uploaded surfaces are stored");
    opt("--token", c.token, "require this token from every client");
    opt("--tokens-file", c.tokens_file,
        "a file of tokens, one per user: lines \"NAME TOKEN\" (each with its own quotas)");
    opt("--tls-cert", c.tls_cert, "TLS certificate (PEM); with --tls-key, TLS on both ports");
    opt("--tls-key", c.tls_key, "TLS private key (PEM)");
    opt("--threads", c.threads, "simplification threads")->check(CLI::Range(1, 256));
    opt("--speculate", c.speculate,
        "after an upload, while no request waits, compute the records at alpha 0, 0.5 and 1, so "
        "that a near preview exists for any alpha (false: off)");
    opt("--cache-mb", c.cache_mb, "memory for cached results (MiB)");
    opt("--surfaces-mb", c.surfaces_mb,
        "memory for stored surfaces (MiB); the others stay on disk until a request needs them");
    opt("--web-dir", c.web_dir, "the browser renderer's built files, served at / (\"\" for none)");
    opt("--sample", c.sample, "a surface file loaded at start (\"\" for none)");
    opt("--max-frame-bytes", c.max_frame_bytes, "largest accepted frame");
    opt("--max-surface-triangles", c.max_surface_triangles, "largest accepted upload");
    opt("--max-surface-mb", c.max_surface_mb,
        "largest surface in memory (MiB, raw: 12 bytes a triangle, 12 + 4 per field component a "
        "vertex): larger uploads are refused, larger stored surfaces not read");
    opt("--max-clients", c.max_clients,
        "connections at once: native, HTTP, WebSocket and TLS handshakes together");
    opt("--max-clients-per-address", c.max_clients_per_address,
        "connections at once from one IP address");
    opt("--fd-reserve", c.fd_reserve,
        "descriptors kept for the server's own files; the client limits fit below the rest");
    opt("--max-sessions", c.max_sessions, "sessions at once");
    opt("--max-queue-mb", c.max_queue_mb,
        "per client: MiB waiting to be sent before it is dropped");
    opt("--max-queue-total-mb", c.max_queue_total_mb,
        "all clients together: MiB waiting to be sent; the client whose level would pass it is "
        "dropped");
    opt("--max-upload-mb", c.max_upload_mb,
        "all clients together: MiB of uploads received but not yet stored");
    opt("--max-download-mb", c.max_download_mb,
        "all clients together: MiB of HTTP downloads being built and sent, level.glb files (one "
        "counts four times its file while it is built) and web files; one that would pass it is "
        "refused");
    opt("--max-remembered-kb", c.max_remembered_kb,
        "KiB of result keys remembered after their requests (for resuming by key)");
    opt("--quota-surfaces", c.quota_surfaces,
        "per token and per session: stored surfaces (uploads in progress count)");
    opt("--quota-surfaces-mb", c.quota_surfaces_mb,
        "per token and per session: MiB of stored surfaces and uploads in progress");
    opt("--quota-upload-mb", c.quota_upload_mb,
        "per token and per session: MiB of uploads in progress");
    Timeouts& t = c.timeouts;
    const auto seconds = [&](const std::string& name, double& value, const std::string& help) {
        opt(name, value, help)->check(CLI::Range(0.001, 1e6));
    };
    seconds("--handshake-timeout", t.handshake,
            "seconds a new connection has for TLS, Hello and Auth (or its WebSocket upgrade)");
    seconds("--idle-timeout", t.idle, "seconds of silence before a connection is closed");
    seconds("--send-timeout", t.send,
            "seconds a stalled write is allowed before the client is dropped");
    seconds("--http-timeout", t.http,
            "seconds for an HTTP request to arrive, and between requests on a kept-alive one");
    seconds("--upload-timeout", t.upload,
            "seconds an upload in progress may wait for its next chunk before it is forgotten");
    seconds("--accept-backoff", t.accept_backoff,
            "the longest pause of a listener after accepting failed (e.g. out of descriptors)");
    seconds("--accept-log-interval", t.accept_log_interval,
            "seconds between two log lines about failed accepts");
    opt("--log-level", c.log_level, "trace, debug, info, warn, error")
        ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error"}));
    opt("--log-format", c.log_format, "text, or json: one JSON object per line")
        ->check(CLI::IsMember({"text", "json"}));
    try {
        app.parse(argc, argv);
        if (c.tls_cert.empty() != c.tls_key.empty())
            throw CLI::ValidationError("--tls-cert and --tls-key", "give both or neither");
        if (c.http_bind.empty()) c.http_bind = c.bind;
    } catch (const CLI::ParseError& e) {
        std::exit(app.exit(e));
    }
    return c;
}

} // namespace ddsimp::server
