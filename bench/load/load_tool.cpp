// ddsimp-load: N clients × M operations against a running ddsimp-server, through the client
// library (libddsimp-client), with a configurable mix of
//
//   upload   a new surface (a sphere scaled per operation, so nothing is deduplicated);
//   level    one level of the main surface at a keep drawn from --keeps (mostly cached);
//   session  join one of --sessions sessions, change its view (keep), leave.
//
// Reports per operation kind the latency percentiles (p50, p90, p99, max), the throughput, every
// error, and the server's peak memory (VmHWM of --server-pid) and its drop and error counters
// (/metrics on --http-port). The main surface's levels are computed once before the clock starts
// (--cold: not). The random choices are seeded: the same flags make the same load.
//
// --hostile runs every attack of the hostile-clients issue at once while normal clients ask for
// a cached level, and reports the goals (hostile_mode.h).
#include "hostile_mode.h"

#include "ddsimp/io/surface_io.h" // io/, from the ddsimp_io target

#include "ddsimp/client.h"

#include <CLI/CLI.hpp>
#include <boost/asio.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>
#include <random>
#include <regex>
#include <sstream>
#include <thread>

namespace {

using namespace ddsimp;
using Clock = std::chrono::steady_clock;

struct Settings {
    std::string server = "127.0.0.1:7420";
    std::string token;
    bool tls = false;    // connect with TLS, any certificate accepted (a bench's own)
    std::string surface; // uploaded once as the main surface; empty: the server's first listed
    int clients = 8;
    int requests = 50; // per client
    std::string mix = "upload=1,level=8,session=1";
    std::vector<double> keeps{0.01, 0.05, 0.1, 0.25, 0.5};
    double alpha = 0.5;
    int sessions = 4;
    int upload_rings = 64; // the uploaded sphere: 4·rings·(rings - 1) triangles (16128 at 64)
    int server_pid = 0;
    int http_port = 0;
    uint64_t seed = 1;
};

enum class Kind { Upload, Level, Session };
const char* kind_name(Kind k) {
    return k == Kind::Upload ? "upload" : k == Kind::Level ? "level" : "session";
}

// "upload=1,level=8,session=1" -> a weighted choice.
std::discrete_distribution<int> parse_mix(const std::string& text) {
    std::map<std::string, double> weights{{"upload", 0}, {"level", 0}, {"session", 0}};
    std::stringstream in(text);
    for (std::string part; std::getline(in, part, ',');) {
        const size_t eq = part.find('=');
        if (eq == std::string::npos || !weights.count(part.substr(0, eq)))
            throw CLI::ValidationError("--mix",
                                       "\"" + part + "\" is not upload=W, level=W or session=W");
        weights[part.substr(0, eq)] = std::stod(part.substr(eq + 1));
    }
    if (weights["upload"] + weights["level"] + weights["session"] <= 0)
        throw CLI::ValidationError("--mix", "every weight is 0");
    return {weights["upload"], weights["level"], weights["session"]};
}

// A closed UV sphere of radius `r` with a scalar field (its height): a valid surface of
// 4·rings·(rings - 1) triangles.
Surface sphere(int rings, float r) {
    Surface s;
    const int segments = 2 * rings;
    const auto add = [&](double theta, double phi) {
        s.positions.push_back(float(r * std::sin(theta) * std::cos(phi)));
        s.positions.push_back(float(r * std::sin(theta) * std::sin(phi)));
        s.positions.push_back(float(r * std::cos(theta)));
    };
    add(0, 0); // north pole: vertex 0
    for (int i = 1; i < rings; ++i)
        for (int j = 0; j < segments; ++j) add(M_PI * i / rings, 2 * M_PI * j / segments);
    add(M_PI, 0); // south pole
    const uint32_t south = uint32_t(s.positions.size() / 3 - 1);
    const auto ring = [&](int i, int j) {
        return uint32_t(1 + (i - 1) * segments + (j % segments));
    };
    const auto tri = [&](uint32_t a, uint32_t b, uint32_t c) {
        s.triangles.insert(s.triangles.end(), {a, b, c});
    };
    for (int j = 0; j < segments; ++j) {
        tri(0, ring(1, j), ring(1, j + 1));
        tri(south, ring(rings - 1, j + 1), ring(rings - 1, j));
        for (int i = 1; i + 1 < rings; ++i) {
            tri(ring(i, j), ring(i + 1, j), ring(i + 1, j + 1));
            tri(ring(i, j), ring(i + 1, j + 1), ring(i, j + 1));
        }
    }
    Field height{"height", 1, {}};
    for (size_t v = 2; v < s.positions.size(); v += 3) height.values.push_back(s.positions[v]);
    s.fields.push_back(std::move(height));
    return s;
}

struct Sample {
    Kind kind;
    double seconds;
};

struct Results {
    std::mutex mutex;
    std::vector<Sample> samples;
    std::vector<std::string> errors;
    void add(Kind k, double s) {
        std::lock_guard lock(mutex);
        samples.push_back({k, s});
    }
    void fail(Kind k, const std::string& what) {
        std::lock_guard lock(mutex);
        errors.push_back(std::string(kind_name(k)) + ": " + what);
    }
};

ConnectOptions connect_options(const Settings& s, int client) {
    ConnectOptions o;
    parse_server_address(s.server, o);
    o.token = s.token;
    o.tls = s.tls;
    o.tls_insecure = s.tls;
    o.client_name = "ddsimp-load " + std::to_string(client);
    o.timeout = std::chrono::minutes(5);
    return o;
}

void run_client(const Settings& s, int index, const std::string& main_surface, Results& out) {
    std::mt19937_64 random(s.seed * 1000003 + uint64_t(index));
    std::discrete_distribution<int> choose = parse_mix(s.mix);
    Client client;
    try {
        client.connect(connect_options(s, index));
    } catch (const ClientError& e) {
        return out.fail(Kind::Level, std::string("connect: ") + e.what());
    }
    client.on_session_event([](const SessionEvent&) {}); // meshes of joined sessions: not kept
    for (int op = 0; op < s.requests; ++op) {
        const Kind kind = Kind(choose(random));
        const auto start = Clock::now();
        try {
            if (kind == Kind::Upload) {
                const float scale = 1.0f + 1e-4f * float(index * s.requests + op + 1);
                client.upload(sphere(s.upload_rings, scale), "load-upload");
            } else if (kind == Kind::Level) {
                LevelRequest r;
                r.surface = main_surface;
                r.alpha = s.alpha;
                r.keep = {s.keeps[random() % s.keeps.size()]};
                client.request_levels(r);
            } else {
                const std::string name = "load-" + std::to_string(random() % s.sessions);
                client.join_session(name, "load-key");
                ViewChange change;
                change.surface = main_surface;
                change.alpha = s.alpha;
                change.keep = s.keeps[random() % s.keeps.size()];
                client.set_view(name, change);
                client.leave_session(name);
            }
            out.add(kind, std::chrono::duration<double>(Clock::now() - start).count());
        } catch (const std::exception& e) {
            out.fail(kind, e.what());
            if (!client.connected()) {
                try {
                    client.connect(connect_options(s, index));
                } catch (const ClientError& again) {
                    return out.fail(kind, std::string("reconnect: ") + again.what());
                }
            }
        }
    }
}

double percentile(std::vector<double> v, double p) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    const size_t i = size_t(std::ceil(p / 100.0 * double(v.size()))) - (p > 0 ? 1 : 0);
    return v[std::min(i, v.size() - 1)];
}

size_t vm_hwm_kib(int pid) {
    std::ifstream in("/proc/" + std::to_string(pid) + "/status");
    for (std::string line; std::getline(in, line);)
        if (line.rfind("VmHWM:", 0) == 0) return std::stoull(line.substr(6));
    return 0;
}

// Some counters of the server's /metrics.
std::map<std::string, double> server_metrics(const std::string& host, int port) {
    namespace asio = boost::asio;
    asio::io_context io;
    asio::ip::tcp::resolver resolver(io);
    asio::ip::tcp::socket socket(io);
    asio::connect(socket, resolver.resolve(host, std::to_string(port)));
    const std::string request =
        "GET /metrics HTTP/1.1\r\nHost: " + host + "\r\nConnection: close\r\n\r\n";
    asio::write(socket, asio::buffer(request));
    std::string text;
    boost::system::error_code ec;
    char buffer[8192];
    while (size_t n = socket.read_some(asio::buffer(buffer), ec)) text.append(buffer, n);
    std::map<std::string, double> out;
    for (const char* name :
         {"ddsimp_request_errors_total", "ddsimp_connections_dropped_total",
          "ddsimp_bad_frames_total", "ddsimp_client_queue_bytes_max", "ddsimp_cache_bytes"}) {
        std::smatch m;
        if (std::regex_search(text, m, std::regex(std::string("\n") + name + " ([0-9.e+-]+)")))
            out[name] = std::stod(m[1]);
    }
    return out;
}

} // namespace

int main(int argc, char** argv) {
    Settings s;
    CLI::App app{"ddsimp-load: N clients x M operations against a running ddsimp-server"};
    app.add_option("--server", s.server, "HOST:PORT of the server")->capture_default_str();
    app.add_option("--token", s.token, "the server's token")->envname("DDSIMP_TOKEN");
    app.add_flag("--tls", s.tls,
                 "connect with TLS, accepting any certificate (a test server's own); --hostile: "
                 "every attacker too, and some stop halfway through their TLS handshake");
    app.add_option("--surface", s.surface,
                   "main surface file, uploaded once (default: the server's first surface)")
        ->check(CLI::ExistingFile);
    app.add_option("--clients,-n", s.clients, "clients at once")
        ->capture_default_str()
        ->check(CLI::Range(1, 4096));
    app.add_option("--requests,-m", s.requests, "operations per client")
        ->capture_default_str()
        ->check(CLI::Range(1, 1000000));
    app.add_option("--mix", s.mix, "weights of the operations")->capture_default_str();
    app.add_option("--keeps", s.keeps, "keep fractions the level and session operations use")
        ->delimiter(',')
        ->check(CLI::Range(1e-6, 1.0));
    app.add_option("--alpha", s.alpha, "alpha of every level")->capture_default_str();
    app.add_option("--sessions", s.sessions, "sessions the session operations pick from")
        ->capture_default_str()
        ->check(CLI::Range(1, 1000));
    app.add_option("--upload-rings", s.upload_rings,
                   "size of the uploaded sphere (4·r·(r-1) triangles)")
        ->capture_default_str()
        ->check(CLI::Range(3, 2000));
    app.add_option("--server-pid", s.server_pid, "report this process's VmHWM (same machine)");
    app.add_option("--http-port", s.http_port, "report the server's /metrics counters");
    app.add_option("--seed", s.seed, "of the random choices")->capture_default_str();
    bool json = false, warm = true, hostile = false;
    app.add_flag("--json", json, "one JSON line instead of the table");
    app.add_flag("!--cold", warm,
                 "do not compute the main surface's levels before the clock starts");
    load::HostileSettings h;
    app.add_flag("--hostile", hostile,
                 "every attack at once while --clients normal clients ask for a cached level of "
                 "--surface (needs --server-pid and --http-port)");
    app.add_option("--attack-seconds", h.attack_seconds, "--hostile: how long the attack lasts")
        ->capture_default_str()
        ->check(CLI::Range(1.0, 3600.0));
    app.add_option("--server-log", h.server_log,
                   "--hostile: the server's log, checked for lines the logger did not write");
    CLI11_PARSE(app, argc, argv);
    try {
        if (hostile) {
            ConnectOptions o;
            parse_server_address(s.server, o);
            h.host = o.host;
            h.port = o.port;
            h.http_port = uint16_t(s.http_port);
            h.token = s.token;
            h.tls = s.tls;
            h.surface = s.surface;
            h.server_pid = s.server_pid;
            h.alpha = s.alpha;
            h.keeps = s.keeps;
            h.normal_clients = s.clients;
            h.json = json;
            return load::run_hostile(h);
        }
        parse_mix(s.mix);
        std::string main_surface;
        double warm_up = 0;
        {
            Client setup;
            setup.connect(connect_options(s, -1));
            if (!s.surface.empty()) {
                main_surface = setup.upload(io::read_surface(s.surface), s.surface).surface;
            } else {
                const std::vector<SurfaceInfo> list = setup.list_surfaces();
                if (list.empty())
                    throw std::runtime_error("the server has no surface; give --surface");
                main_surface = list.front().surface;
            }
            // The main surface's simplification is computed once, before the clock starts: the
            // load measures serving, not that one computation (reported on its own).
            if (warm) {
                LevelRequest r;
                r.surface = main_surface;
                r.alpha = s.alpha;
                r.keep = s.keeps;
                const auto start = Clock::now();
                setup.request_levels(r);
                warm_up = std::chrono::duration<double>(Clock::now() - start).count();
            }
        }
        Results results;
        const auto start = Clock::now();
        std::vector<std::thread> threads;
        for (int i = 0; i < s.clients; ++i)
            threads.emplace_back([&, i] { run_client(s, i, main_surface, results); });
        for (auto& t : threads) t.join();
        const double wall = std::chrono::duration<double>(Clock::now() - start).count();

        nlohmann::json report{{"clients", s.clients},
                              {"requests_per_client", s.requests},
                              {"mix", s.mix},
                              {"seconds", wall},
                              {"warm_up_seconds", warm_up},
                              {"operations", results.samples.size()},
                              {"throughput_per_second", double(results.samples.size()) / wall},
                              {"errors", results.errors.size()}};
        for (Kind k : {Kind::Upload, Kind::Level, Kind::Session}) {
            std::vector<double> t;
            for (const Sample& x : results.samples)
                if (x.kind == k) t.push_back(x.seconds);
            report["latency"][kind_name(k)] = {{"count", t.size()},
                                               {"p50", percentile(t, 50)},
                                               {"p90", percentile(t, 90)},
                                               {"p99", percentile(t, 99)},
                                               {"max", percentile(t, 100)}};
        }
        if (s.server_pid > 0) report["server_vm_hwm_mib"] = double(vm_hwm_kib(s.server_pid)) / 1024;
        if (s.http_port > 0) {
            ConnectOptions o;
            parse_server_address(s.server, o);
            report["server_metrics"] = server_metrics(o.host, s.http_port);
        }
        for (size_t i = 0; i < std::min<size_t>(results.errors.size(), 10); ++i)
            report["first_errors"].push_back(results.errors[i]);

        if (json) {
            std::cout << report.dump() << "\n";
        } else {
            if (warm)
                std::printf("warm-up (the main surface's levels computed once): %.2f s\n", warm_up);
            std::printf("%d clients x %d operations (%s): %zu done in %.2f s, %.1f/s, %zu errors\n",
                        s.clients, s.requests, s.mix.c_str(), results.samples.size(), wall,
                        double(results.samples.size()) / wall, results.errors.size());
            std::printf("%-8s %7s %9s %9s %9s %9s  (ms)\n", "op", "count", "p50", "p90", "p99",
                        "max");
            for (Kind k : {Kind::Upload, Kind::Level, Kind::Session}) {
                const auto& l = report["latency"][kind_name(k)];
                std::printf("%-8s %7zu %9.1f %9.1f %9.1f %9.1f\n", kind_name(k),
                            l["count"].get<size_t>(), 1e3 * l["p50"].get<double>(),
                            1e3 * l["p90"].get<double>(), 1e3 * l["p99"].get<double>(),
                            1e3 * l["max"].get<double>());
            }
            if (report.contains("server_vm_hwm_mib"))
                std::printf("server peak memory (VmHWM): %.0f MiB\n",
                            report["server_vm_hwm_mib"].get<double>());
            if (report.contains("server_metrics"))
                for (const auto& [name, value] : report["server_metrics"].items())
                    std::printf("%s %.0f\n", name.c_str(), value.get<double>());
            for (const std::string& e : results.errors) std::printf("error: %s\n", e.c_str());
        }
        return results.errors.empty() ? 0 : 1;
    } catch (const std::exception& e) {
        std::cerr << "ddsimp-load: " << e.what() << "\n";
        return 1;
    }
}
