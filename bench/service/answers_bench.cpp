// ddsimp_bench_answers: how soon the service answers (issue 28), against a running ddsimp-server
// (bench/service/answers.sh starts one), on the 1.18 M-triangle carotid by default:
//
//  1. an alpha change: the first picture (a preview) and the exact 10% level, against the
//     library's own time to 10% (ddsimp::simplify in this process, measured before);
//  2. a slider: 20 alpha values in 2 s (each request superseding the one before), then released:
//     the exact last level against one request alone, and the records still being computed
//     50 ms after the release (ddsimp_reductions_running from /metrics);
//  3. two clients, one sending 100 requests: the other's one request against its time alone.
//
// Prints one Markdown table (and JSON with --json). One run of each: the figures are seconds on
// a shared machine; compare each with its peer measured in the same run.
#include "ddsimp/io/surface_io.h" // io/, from the ddsimp_io target

#include "ddsimp/client.h"

#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/read.hpp>
#include <boost/asio/write.hpp>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <fstream>
#include <iostream>
#include <regex>
#include <sstream>
#include <thread>

#ifndef DDSIMP_BENCH_DEFAULT_SURFACE
#define DDSIMP_BENCH_DEFAULT_SURFACE "bench/data/carotid-1m.vtp"
#endif

namespace {

using namespace ddsimp;
using Clock = std::chrono::steady_clock;

double since(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

// One sample of /metrics, by a plain HTTP/1.0 GET.
double metric(uint16_t http_port, const std::string& name) {
    namespace asio = boost::asio;
    asio::io_context io;
    asio::ip::tcp::socket socket(io);
    asio::connect(socket,
                  asio::ip::tcp::resolver(io).resolve("127.0.0.1", std::to_string(http_port)));
    const std::string get = "GET /metrics HTTP/1.0\r\nHost: localhost\r\n\r\n";
    asio::write(socket, asio::buffer(get));
    std::string text;
    boost::system::error_code ec;
    char buffer[4096];
    for (size_t n; (n = socket.read_some(asio::buffer(buffer), ec)) > 0 || !ec;)
        text.append(buffer, n);
    std::smatch m;
    if (!std::regex_search(text, m, std::regex("\n" + name + " ([0-9.e+-]+)"))) return -1;
    return std::stod(m[1]);
}

struct Timed {
    double first = 0; // the first mesh (a preview, or the exact level)
    double exact = 0; // the exact level
    bool preview = false;
};

// One request of a level at `alpha`, timed from sending it.
Timed timed(Client& client, const std::string& surface, double alpha, double keep) {
    LevelRequest request;
    request.surface = surface;
    request.alpha = alpha;
    request.keep = {keep};
    request.encoding = Encoding::Raw;
    request.supersede = true;
    Timed out;
    const auto start = Clock::now();
    bool first = true;
    PendingRequest pending = client.request(request, [&](const Level& level) {
        if (first) out.first = since(start), out.preview = level.preview, first = false;
    });
    pending.levels[0].get();
    out.exact = since(start);
    return out;
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"How soon ddsimp-server answers: previews, cancellation, fair compute"};
    uint16_t port = 7420, http_port = 7421;
    std::string surface_path = DDSIMP_BENCH_DEFAULT_SURFACE, json_path;
    double keep = 0.1;
    app.add_option("--port", port, "the server's native port");
    app.add_option("--http-port", http_port, "the server's HTTP port (/metrics)");
    app.add_option("--surface", surface_path, "surface to upload");
    app.add_option("--keep", keep, "the level: fraction of the triangles");
    app.add_option("--json", json_path, "also write the figures as JSON here");
    CLI11_PARSE(app, argc, argv);

    const Surface input = io::read_surface(surface_path);
    nlohmann::json figures;
    {
        Options o;
        o.keep_fraction = keep;
        const auto start = Clock::now();
        simplify(input, o);
        figures["library_seconds"] = since(start);
    }

    ConnectOptions connect;
    connect.host = "127.0.0.1";
    connect.port = port;
    connect.timeout = std::chrono::minutes(10);
    Client client;
    client.connect(connect);
    const std::string surface = client.upload(input, "bench").surface;
    // The records the server makes while idle after an upload (--speculate): at alpha 0, 0.5, 1.
    {
        const auto start = Clock::now();
        while (metric(http_port, "ddsimp_speculations_pending") > 0)
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
        figures["speculation_seconds"] = since(start);
    }

    // 1. An alpha change, with the records of speculation (or earlier views) ready.
    timed(client, surface, 0.5, keep);
    const Timed change = timed(client, surface, 0.3, keep);
    figures["alpha_change_first_seconds"] = change.first;
    figures["alpha_change_first_is_preview"] = change.preview;
    figures["alpha_change_exact_seconds"] = change.exact;
    const Timed alone = timed(client, surface, 0.45, keep);
    figures["alone_exact_seconds"] = alone.exact;

    // 2. The slider: 20 values in 2 s, then released.
    {
        std::vector<PendingRequest> dragged;
        for (int i = 0; i < 20; ++i) {
            LevelRequest request;
            request.surface = surface;
            request.alpha = 0.6 + 0.01 * i;
            request.keep = {keep};
            request.encoding = Encoding::Raw;
            request.supersede = true;
            const auto sent = Clock::now();
            dragged.push_back(client.request(request));
            std::this_thread::sleep_until(sent + std::chrono::milliseconds(100));
        }
        const auto released = Clock::now();
        std::this_thread::sleep_until(released + std::chrono::milliseconds(50));
        // The last value's own record runs; any other is a superseded one still running.
        figures["slider_running_after_50ms"] = metric(http_port, "ddsimp_reductions_running");
        dragged.back().levels[0].get();
        figures["slider_last_exact_seconds"] = since(released);
        for (size_t i = 0; i + 1 < dragged.size(); ++i) try {
                dragged[i].levels[0].get();
            } catch (const ClientError&) {
            }
    }

    // 3. Two clients: one sends 100 requests, the other one request.
    {
        Client busy, other;
        busy.connect(connect);
        other.connect(connect);
        std::vector<PendingRequest> burst;
        for (int i = 0; i < 100; ++i) {
            LevelRequest request;
            request.surface = surface;
            request.alpha = 0.001 * i;
            request.keep = {keep};
            burst.push_back(busy.request(request));
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
        const Timed mine = timed(other, surface, 0.99, keep);
        figures["two_clients_other_exact_seconds"] = mine.exact;
        size_t refused = 0;
        for (PendingRequest& p : burst)
            if (p.levels[0].wait_for(std::chrono::seconds(0)) == std::future_status::ready) try {
                    p.levels[0].get();
                } catch (const ClientError& e) {
                    refused += e.code() == ErrorCode::ResourceExhausted;
                }
        figures["two_clients_busy_refused"] = refused;
        busy.close(); // its remaining computations are cancelled
    }
    const Timed alone_again = timed(client, surface, 0.98, keep);
    figures["alone_again_exact_seconds"] = alone_again.exact;

    const double library = figures["library_seconds"];
    std::ostringstream table;
    table << "| measure | seconds | goal |\n|---|---|---|\n"
          << "| library alone to " << keep * 100 << "% | " << library << " | |\n"
          << "| after the upload: speculative records at alpha 0, 0.5, 1 | "
          << figures["speculation_seconds"] << " | (in the background) |\n"
          << "| alpha change: first picture" << (change.preview ? " (preview)" : "") << " | "
          << change.first << " | <= 0.3 |\n"
          << "| alpha change: exact level | " << change.exact << " | <= " << library + 0.3
          << " (library + 0.3) |\n"
          << "| one request alone | " << alone.exact << " | |\n"
          << "| slider released: exact last level | " << figures["slider_last_exact_seconds"]
          << " | <= " << 1.5 * alone.exact << " (1.5x alone) |\n"
          << "| slider released + 50 ms: records computing | "
          << figures["slider_running_after_50ms"] << " | <= 2 (the last + one superseded) |\n"
          << "| two clients: the other's request | " << figures["two_clients_other_exact_seconds"]
          << " | <= " << 2 * alone.exact << " (2x alone) |\n";
    std::cout << table.str();
    if (!json_path.empty()) std::ofstream(json_path) << figures.dump(2) << '\n';
    return 0;
}
