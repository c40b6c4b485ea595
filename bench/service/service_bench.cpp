// ddsimp_bench_service: the service's loopback figures (issue 4), measured against a running
// ddsimp-server (bench/service/run.sh starts one):
//
//  1. latency from sending a Request to the last byte of a cached 10% level, raw and meshopt;
//  2. streaming throughput of a cached whole-surface level, against a plain loopback socket copy
//     of the same number of bytes measured in the same run (goal: at least 50% of it);
//  3. one level to every member of a session of 64, against a session of one (goal: at most 4×
//     the time of one).
//
// Every figure is the median (and 90th percentile) of --runs repetitions after a warm-up that
// fills the server's cache. Mesh payloads are skipped on arrival, not decoded: what is timed is
// the server and the loopback, not a client's decoding.
#include "ddsimp/io/surface_io.h" // io/, from the ddsimp_io target
#include "frame_socket.h"

#include "ddsimp/protocol/mesh_codec.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <mutex>
#include <sstream>
#include <thread>

#ifndef DDSIMP_BENCH_DEFAULT_SURFACE
#define DDSIMP_BENCH_DEFAULT_SURFACE "bench/data/carotid-1m.vtp"
#endif

namespace {

using namespace ddsimp;
using namespace ddsimp::bench;
using Clock = std::chrono::steady_clock;

double seconds_between(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double>(b - a).count();
}

struct Spread {
    double median = 0, p90 = 0;
};

Spread spread_of(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    if (v.empty()) return {};
    return {v[v.size() / 2], v[std::min(v.size() - 1, (v.size() * 9) / 10)]};
}

struct Settings {
    std::string host = "127.0.0.1";
    uint16_t port = 7420;
    std::string token;
    std::string surface_path = DDSIMP_BENCH_DEFAULT_SURFACE;
    int runs = 9;
    int members = 64;
    int fresh_runs = 3;
    double alpha = 0.5;
    double keep = 0.1;
    int server_pid = 0;
    std::string json_path;
};

std::vector<std::string> capabilities_for(v1::Encoding encoding) {
    if (encoding == v1::MESHOPT) return {"meshopt-codec", "sessions"};
    return {"sessions"};
}

const char* encoding_name(v1::Encoding encoding) {
    return encoding == v1::MESHOPT ? "meshopt" : "raw";
}

std::string upload(FrameSocket& socket, const Surface& surface) {
    const protocol::EncodedBlob blob = protocol::encode_mesh(surface, v1::RAW);
    v1::UploadBegin begin;
    begin.set_upload_id(1);
    begin.set_name("bench");
    begin.set_vertex_count(surface.vertex_count());
    begin.set_triangle_count(surface.triangle_count());
    for (const Field& f : surface.fields) {
        auto* info = begin.add_fields();
        info->set_name(f.name);
        info->set_components(uint32_t(f.components));
    }
    begin.set_total_bytes(blob.bytes.size());
    socket.send(begin);
    for (size_t at = 0; at < blob.bytes.size(); at += protocol::kDefaultChunkBytes) {
        v1::UploadChunk chunk;
        chunk.set_upload_id(1);
        chunk.set_offset(at);
        chunk.set_data(blob.bytes.substr(at, protocol::kDefaultChunkBytes));
        socket.send(chunk);
    }
    v1::UploadEnd end;
    end.set_upload_id(1);
    socket.send(end);
    return socket.expect<v1::UploadResult>().surface();
}

// One level of a request, timed from sending the request to the last byte of its MESH_END.
struct TimedLevel {
    double seconds = 0;
    uint64_t bytes = 0;
};

TimedLevel timed_level(FrameSocket& socket, uint64_t request_id, const std::string& surface,
                       double alpha, double keep, v1::Encoding encoding) {
    v1::Request request;
    request.set_request_id(request_id);
    request.set_surface(surface);
    request.set_alpha(float(alpha));
    request.add_keep(float(keep));
    request.set_encoding(encoding);
    const uint64_t bytes_before = socket.bytes_received();
    const auto start = Clock::now();
    socket.send(request);
    socket.skip_to_mesh_end();
    TimedLevel timed{seconds_between(start, Clock::now()), socket.bytes_received() - bytes_before};
    socket.expect<v1::RequestDone>();
    return timed;
}

// The same number of bytes through a plain loopback TCP connection: a writer sending in the
// server's chunk size, started by one byte from the reader (as a request starts a level), and a
// reader with the same buffer as FrameSocket.
double plain_copy_seconds(uint64_t total_bytes) {
    asio::io_context io;
    tcp::acceptor acceptor(io, tcp::endpoint(asio::ip::make_address("127.0.0.1"), 0));
    const tcp::endpoint endpoint = acceptor.local_endpoint();
    std::thread writer([endpoint, total_bytes] {
        asio::io_context writer_io;
        tcp::socket socket(writer_io);
        socket.connect(endpoint);
        socket.set_option(tcp::no_delay(true));
        const std::vector<char> chunk(protocol::kHeaderBytes + protocol::kDefaultChunkBytes, 'x');
        char go = 0;
        asio::read(socket, asio::buffer(&go, 1));
        for (uint64_t left = total_bytes; left > 0;) {
            const size_t n = size_t(std::min<uint64_t>(left, chunk.size()));
            asio::write(socket, asio::buffer(chunk.data(), n));
            left -= n;
        }
    });
    tcp::socket reader = acceptor.accept();
    reader.set_option(tcp::no_delay(true));
    std::vector<char> buffer(1u << 20);
    const auto start = Clock::now();
    asio::write(reader, asio::buffer("g", 1));
    for (uint64_t got = 0; got < total_bytes;) got += reader.read_some(asio::buffer(buffer));
    const double seconds = seconds_between(start, Clock::now());
    writer.join();
    return seconds;
}

// The reference for a session's fan-out of a cached level: the same bytes to `members` plain
// loopback connections, from one writer thread (as the server's network thread) in the server's
// chunk size, each connection read by its own thread; from the start to the last byte read.
double plain_fanout_seconds(uint64_t bytes_per_member, int members) {
    asio::io_context io;
    tcp::acceptor acceptor(io, tcp::endpoint(asio::ip::make_address("127.0.0.1"), 0));
    std::vector<tcp::socket> writers, readers;
    for (int m = 0; m < members; ++m) {
        writers.emplace_back(io);
        writers.back().connect(acceptor.local_endpoint());
        readers.push_back(acceptor.accept());
    }
    const std::vector<char> chunk(protocol::kHeaderBytes + protocol::kDefaultChunkBytes, 'x');
    const auto start = Clock::now();
    std::vector<std::thread> reading;
    for (auto& r : readers)
        reading.emplace_back([&r, bytes_per_member] {
            std::vector<char> buffer(1u << 20);
            for (uint64_t got = 0; got < bytes_per_member;)
                got += r.read_some(asio::buffer(buffer));
        });
    std::vector<uint64_t> left(members, bytes_per_member);
    for (bool more = true; more;) { // round robin, a chunk at a time, as a queue per client would
        more = false;
        for (int m = 0; m < members; ++m) {
            if (left[m] == 0) continue;
            const size_t n = size_t(std::min<uint64_t>(left[m], chunk.size()));
            asio::write(writers[m], asio::buffer(chunk.data(), n));
            left[m] -= n;
            more = more || left[m] > 0;
        }
    }
    for (auto& t : reading) t.join();
    return seconds_between(start, Clock::now());
}

// A session of `members` connections. The first changes the view; the time of one change is
// from sending it to the last member's MESH_END. Cached: the view alternates between two levels
// the warm-up computed, so what is timed is the fan-out of bytes. Fresh (`fresh_alpha` set): every
// change asks for a new α, so the level is computed once per change and shared by all members.
std::vector<double> session_fanout(const Settings& s, const std::string& surface, int members,
                                   v1::Encoding encoding, int warmups, int runs,
                                   float* fresh_alpha = nullptr,
                                   uint64_t* bytes_per_member = nullptr) {
    asio::io_context io;
    const std::string name = "bench-" + std::to_string(members) + "-" + encoding_name(encoding);
    std::vector<std::unique_ptr<FrameSocket>> sockets;
    for (int i = 0; i < members; ++i) {
        sockets.push_back(std::make_unique<FrameSocket>(io, s.host, s.port));
        sockets.back()->hello(capabilities_for(encoding), s.token);
        v1::JoinSession join;
        join.set_name(name);
        sockets.back()->send(join);
        sockets.back()->expect<v1::SessionState>();
    }

    const int changes = warmups + runs;
    std::vector<std::vector<Clock::time_point>> arrivals(changes,
                                                         std::vector<Clock::time_point>(members));
    std::mutex mutex;
    std::condition_variable arrived;
    std::vector<int> arrived_count(changes, 0);
    std::vector<std::thread> readers;
    for (int m = 1; m < members; ++m) {
        readers.emplace_back([&, m] {
            for (int c = 0; c < changes; ++c) {
                sockets[m]->skip_to_mesh_end();
                const auto now = Clock::now();
                std::lock_guard lock(mutex);
                arrivals[c][m] = now;
                ++arrived_count[c];
                arrived.notify_all();
            }
        });
    }

    std::vector<double> seconds;
    FrameSocket& leader = *sockets[0];
    for (int c = 0; c < changes; ++c) {
        v1::SetSessionState change;
        change.set_name(name);
        change.mutable_view()->set_surface(surface);
        if (fresh_alpha) {
            *fresh_alpha += 0.01f;
            change.mutable_view()->set_alpha(*fresh_alpha);
            change.mutable_view()->set_keep(float(s.keep));
        } else {
            change.mutable_view()->set_alpha(float(s.alpha));
            change.mutable_view()->set_keep(float(c % 2 == 0 ? s.keep : s.keep * 1.1));
        }
        change.set_set_alpha(true);
        const uint64_t bytes_before = leader.bytes_received();
        const auto start = Clock::now();
        leader.send(change);
        leader.skip_to_mesh_end();
        if (bytes_per_member) *bytes_per_member = leader.bytes_received() - bytes_before;
        arrivals[c][0] = Clock::now();
        std::unique_lock lock(mutex);
        arrived.wait(lock, [&] { return arrived_count[c] == members - 1; });
        const auto last = *std::max_element(arrivals[c].begin(), arrivals[c].end());
        if (c >= warmups) seconds.push_back(seconds_between(start, last));
    }
    for (auto& r : readers) r.join();
    return seconds;
}

std::string server_memory(int pid) {
    if (pid <= 0) return {};
    std::ifstream status("/proc/" + std::to_string(pid) + "/status");
    std::string line, out;
    while (std::getline(status, line))
        if (line.rfind("VmHWM:", 0) == 0 || line.rfind("VmRSS:", 0) == 0) out += line + "; ";
    return out;
}

std::string ms(double seconds) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f ms", seconds * 1e3);
    return buf;
}

} // namespace

int main(int argc, char** argv) {
    Settings s;
    CLI::App app{"ddsimp_bench_service: latency, throughput and session fan-out of a running "
                 "ddsimp-server on loopback"};
    app.add_option("--host", s.host, "server address");
    app.add_option("--port", s.port, "server's native port");
    app.add_option("--token", s.token, "token, if the server wants one");
    app.add_option("--surface", s.surface_path, "surface to upload (>= 1 M triangles for issue 4)");
    app.add_option("--runs", s.runs, "timed repetitions of each measure")
        ->check(CLI::Range(1, 1000));
    app.add_option("--members", s.members, "members of the large session")
        ->check(CLI::Range(2, 250));
    app.add_option("--fresh-runs", s.fresh_runs,
                   "repetitions of the session measure with a level computed per change")
        ->check(CLI::Range(0, 100));
    app.add_option("--alpha", s.alpha, "α of the requested levels");
    app.add_option("--keep", s.keep, "the level: fraction of the triangles")
        ->check(CLI::Range(0.001, 0.9));
    app.add_option("--server-pid", s.server_pid, "read the server's peak memory from /proc");
    app.add_option("--json", s.json_path, "also write the figures as JSON here");
    CLI11_PARSE(app, argc, argv);

    try {
        const Surface surface = io::read_surface(s.surface_path);
        std::cerr << "surface: " << s.surface_path << ", " << surface.triangle_count()
                  << " triangles\n";
        asio::io_context io;
        FrameSocket client(io, s.host, s.port);
        client.hello({"meshopt-codec"}, s.token);
        const std::string id = upload(client, surface);
        nlohmann::json json{{"surface", s.surface_path},
                            {"triangles", surface.triangle_count()},
                            {"runs", s.runs},
                            {"keep", s.keep},
                            {"alpha", s.alpha}};
        std::ostringstream table;
        table << "| measure | median | p90 | goal |\n|---|---|---|---|\n";
        uint64_t request_id = 1;

        // 1. Latency of a cached level. The first request computes and caches it.
        for (v1::Encoding encoding : {v1::RAW, v1::MESHOPT}) {
            const TimedLevel first =
                timed_level(client, request_id++, id, s.alpha, s.keep, encoding);
            std::cerr << encoding_name(encoding)
                      << " level, first request (computed): " << ms(first.seconds) << "\n";
            std::vector<double> t;
            uint64_t bytes = 0;
            for (int r = 0; r < s.runs; ++r) {
                const TimedLevel timed =
                    timed_level(client, request_id++, id, s.alpha, s.keep, encoding);
                t.push_back(timed.seconds);
                bytes = timed.bytes;
            }
            const Spread spread = spread_of(t);
            table << "| cached " << s.keep * 100 << "% level, request to last byte, "
                  << encoding_name(encoding) << " (" << bytes / 1000 << " kB) | "
                  << ms(spread.median) << " | " << ms(spread.p90) << " | — |\n";
            json["latency"][encoding_name(encoding)] = {{"median_s", spread.median},
                                                        {"p90_s", spread.p90},
                                                        {"bytes", bytes},
                                                        {"first_request_s", first.seconds}};
        }

        // 2. Throughput of the whole surface as a level, against a plain socket copy.
        timed_level(client, request_id++, id, s.alpha, 1.0, v1::RAW);
        std::vector<double> served, copied;
        uint64_t bytes = 0;
        for (int r = 0; r < s.runs; ++r) {
            const TimedLevel timed = timed_level(client, request_id++, id, s.alpha, 1.0, v1::RAW);
            bytes = timed.bytes;
            served.push_back(double(timed.bytes) / timed.seconds);
            copied.push_back(double(timed.bytes) / plain_copy_seconds(timed.bytes));
        }
        const Spread serve = spread_of(served), copy = spread_of(copied);
        const double ratio = serve.median / copy.median;
        char line[512];
        std::snprintf(line, sizeof line,
                      "| streaming throughput, whole surface raw (%.1f MB) | %.0f MB/s | %.0f MB/s "
                      "| — |\n| plain loopback socket copy of the same bytes | %.0f MB/s | %.0f "
                      "MB/s | — |\n| streaming / plain copy | %.0f%% | | ≥ 50%% %s |\n",
                      bytes / 1e6, serve.median / 1e6, serve.p90 / 1e6, copy.median / 1e6,
                      copy.p90 / 1e6, ratio * 100, ratio >= 0.5 ? "(met)" : "(missed)");
        table << line;
        json["throughput"] = {{"bytes", bytes},
                              {"server_bytes_per_s", serve.median},
                              {"plain_copy_bytes_per_s", copy.median},
                              {"ratio", ratio}};

        // 3. Session fan-out: one member against s.members, for a cached level (the fan-out of
        // bytes) and for a level computed per change (computed once, shared by every member).
        float fresh_alpha = float(s.alpha);
        const auto fanout_rows = [&](const char* what, v1::Encoding encoding, const Spread& one,
                                     const Spread& many, nlohmann::json& out) {
            const double fanout = many.median / one.median;
            table << "| session of 1, " << what << ", " << encoding_name(encoding) << " | "
                  << ms(one.median) << " | " << ms(one.p90) << " | — |\n";
            std::snprintf(line, sizeof line,
                          "| session of %d, same | %s | %s | ≤ 4× of one: %.2f× %s |\n", s.members,
                          ms(many.median).c_str(), ms(many.p90).c_str(), fanout,
                          fanout <= 4 ? "(met)" : "(missed)");
            table << line;
            out = {{"one_median_s", one.median},
                   {"many_median_s", many.median},
                   {"members", s.members},
                   {"ratio", fanout}};
        };
        for (v1::Encoding encoding : {v1::RAW, v1::MESHOPT}) {
            const std::string level = "cached " + std::to_string(int(s.keep * 100)) + "% level";
            uint64_t member_bytes = 0;
            const Spread many = spread_of(
                session_fanout(s, id, s.members, encoding, 2, s.runs, nullptr, &member_bytes));
            fanout_rows(level.c_str(), encoding,
                        spread_of(session_fanout(s, id, 1, encoding, 2, s.runs)), many,
                        json["session"]["cached"][encoding_name(encoding)]);
            std::vector<double> plain;
            for (int r = 0; r < s.runs; ++r)
                plain.push_back(plain_fanout_seconds(member_bytes, s.members));
            const Spread reference = spread_of(plain);
            std::snprintf(line, sizeof line,
                          "| the same bytes (%d × %.0f kB) to %d plain loopback sockets | %s | %s "
                          "| session at %.0f%% of its speed |\n",
                          s.members, member_bytes / 1e3, s.members, ms(reference.median).c_str(),
                          ms(reference.p90).c_str(), 100 * reference.median / many.median);
            table << line;
            json["session"]["cached"][encoding_name(encoding)]["plain_fanout_median_s"] =
                reference.median;
        }
        if (s.fresh_runs > 0) {
            const std::string level =
                std::to_string(int(s.keep * 100)) + "% level computed per change";
            fanout_rows(
                level.c_str(), v1::MESHOPT,
                spread_of(session_fanout(s, id, 1, v1::MESHOPT, 0, s.fresh_runs, &fresh_alpha)),
                spread_of(
                    session_fanout(s, id, s.members, v1::MESHOPT, 0, s.fresh_runs, &fresh_alpha)),
                json["session"]["computed"]["meshopt"]);
        }

        const std::string memory = server_memory(s.server_pid);
        if (!memory.empty()) {
            table << "\nServer memory at the end: " << memory << "\n";
            json["server_memory"] = memory;
        }
        std::cout << table.str();
        if (!s.json_path.empty()) std::ofstream(s.json_path) << json.dump(2) << "\n";
        return 0;
    } catch (const std::exception& e) {
        std::cerr << "ddsimp_bench_service: " << e.what() << "\n";
        return 1;
    }
}
