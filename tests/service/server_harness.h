// Starting a real ddsimp-server on loopback for the integration tests, and a small blocking
// protocol client that speaks frames directly (so the tests do not depend on the client
// library they may be testing).
#pragma once

#include "ddsimp/protocol/frame.h"
#include "ddsimp/protocol/mesh_codec.h"

#include <boost/asio.hpp>
#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <regex>
#include <string>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>
#include <vector>

// Which sanitizer the tests are built with (DDSIMP_TEST_TSAN, DDSIMP_TEST_ASAN), if any.
#if defined(__SANITIZE_THREAD__)
#define DDSIMP_TEST_TSAN 1
#elif defined(__SANITIZE_ADDRESS__)
#define DDSIMP_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define DDSIMP_TEST_TSAN 1
#elif __has_feature(address_sanitizer)
#define DDSIMP_TEST_ASAN 1
#endif
#endif

namespace ddsimp::test {

// How long a test waits for the server's next answer before calling it lost. A sanitizer slows
// the server (ThreadSanitizer 5-15x, AddressSanitizer 2-3x) while other tests share the cores, and
// a lost answer would fail the test, so the wait grows with it (within ctest's 300 s per test); it
// bounds a hang and times nothing.
#if defined(DDSIMP_TEST_TSAN)
inline constexpr std::chrono::seconds kAnswerTimeout{240};
#elif defined(DDSIMP_TEST_ASAN)
inline constexpr std::chrono::seconds kAnswerTimeout{180};
#else
inline constexpr std::chrono::seconds kAnswerTimeout{60};
#endif

namespace asio = boost::asio;
using tcp = asio::ip::tcp;

inline uint16_t free_port() {
    asio::io_context io;
    tcp::acceptor a(io, tcp::endpoint(asio::ip::make_address("127.0.0.1"), 0));
    return a.local_endpoint().port();
}

inline std::filesystem::path temp_dir(const std::string& name) {
    auto dir = std::filesystem::temp_directory_path() /
               ("ddsimp-test-" + name + "-" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

// Given as `--sample` to ServerProcess: the server starts with its own built-in sample (the
// carotid isosurface) instead of the small plane the tests use.
inline const std::string kBuiltInSample = "(built-in)";

// A ddsimp-server child process. `before_exec` runs in the child just before the server starts
// (e.g. to drop a privilege or set a resource limit). Unless `extra` says otherwise with --sample,
// the server's sample is the 756-triangle plane data/SurfaceVectors.ddsurf, small and quick.
class ServerProcess {
public:
    ServerProcess(std::filesystem::path data_dir, std::vector<std::string> extra = {},
                  std::function<void()> before_exec = {})
        : data_dir_(std::move(data_dir)), extra_(std::move(extra)),
          before_exec_(std::move(before_exec)) {
        start();
    }
    ~ServerProcess() { stop(SIGKILL); }

    // Starts the server on two free ports. A port found free can be taken by another process
    // before the server binds it (tests run in parallel, and every client connection takes an
    // ephemeral port too): a server that exits before it listens is started again on new ports.
    void start() {
        for (int attempt = 0; attempt < 5; ++attempt)
            if (spawn()) return;
        ADD_FAILURE() << "ddsimp-server did not start listening";
    }

    // One try of start(): true once the server listens, false if it exited before.
    bool spawn() {
        port = free_port();
        http_port = free_port();
        std::vector<std::string> args{
            DDSIMP_SERVER_BINARY,      "--port",     std::to_string(port), "--http-port",
            std::to_string(http_port), "--data-dir", data_dir_.string()};
        if (flag("--log-level") == "127.0.0.1") args.insert(args.end(), {"--log-level", "warn"});
        // Speculation keeps the pool busy after every upload: only the tests of it turn it on.
        if (flag("--speculate") == "127.0.0.1") args.insert(args.end(), {"--speculate", "false"});
        if (flag("--sample") == "127.0.0.1")
            args.insert(args.end(), {"--sample", DDSIMP_SAMPLE_DATA "/SurfaceVectors.ddsurf"});
        for (size_t i = 0; i < extra_.size(); ++i) {
            if (extra_[i] == "--sample" && i + 1 < extra_.size() && extra_[i + 1] == kBuiltInSample)
                ++i; // neither the flag nor its value: the server's default
            else
                args.push_back(extra_[i]);
        }
        pid_ = ::fork();
        if (pid_ == 0) {
            ::prctl(PR_SET_PDEATHSIG, SIGKILL); // never outlive a test that crashed
            if (before_exec_) before_exec_();
            std::vector<char*> argv;
            for (auto& a : args) argv.push_back(a.data());
            argv.push_back(nullptr);
            ::execv(argv[0], argv.data());
            ::_exit(127);
        }
        // Ready when both ports accept; not starting if it exited first.
        for (int i = 0; i < 300; ++i) {
            if (accepts(port, flag("--bind")) && accepts(http_port, flag("--http-bind")))
                return true;
            int status = 0;
            if (::waitpid(pid_, &status, WNOHANG) == pid_) {
                pid_ = -1;
                return false;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
        }
        stop(SIGKILL); // neither listening nor gone after 15 s
        return false;
    }

    // Sends `signal` and waits; returns the exit status (or -signal).
    int stop(int signal = SIGTERM) {
        if (pid_ <= 0) return 0;
        ::kill(pid_, signal);
        int status = 0;
        ::waitpid(pid_, &status, 0);
        pid_ = -1;
        return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
    }

    static bool accepts(uint16_t p, const std::string& host = "127.0.0.1") {
        asio::io_context io;
        tcp::socket s(io);
        boost::system::error_code ec;
        s.connect({asio::ip::make_address(host), p}, ec);
        return !ec;
    }
    // The value of a flag given to the server ("127.0.0.1" when it is not given: the address a
    // --bind or --http-bind not given stands for).
    std::string flag(const std::string& name) const {
        for (size_t i = 0; i + 1 < extra_.size(); ++i)
            if (extra_[i] == name) return extra_[i + 1];
        return "127.0.0.1";
    }

    // A line of /proc/PID/status in bytes ("VmRSS", "VmHWM": resident now, at most so far).
    size_t status_bytes(const std::string& key) const {
        std::ifstream in("/proc/" + std::to_string(pid_) + "/status");
        for (std::string line; std::getline(in, line);)
            if (line.rfind(key + ":", 0) == 0)
                return size_t(std::stoull(line.substr(key.size() + 1))) << 10;
        ADD_FAILURE() << "no " << key << " in /proc/" << pid_ << "/status";
        return 0;
    }
    // Whether the process is still running (not exited or killed).
    bool running() const { return pid_ > 0 && ::waitpid(pid_, nullptr, WNOHANG) == 0; }
    pid_t pid() const { return pid_; }

    uint16_t port = 0, http_port = 0;

private:
    std::filesystem::path data_dir_;
    std::vector<std::string> extra_;
    std::function<void()> before_exec_;
    pid_t pid_ = -1;
};

// A plain HTTP GET; returns status line + headers + body.
inline std::string http_get(uint16_t port, const std::string& target) {
    asio::io_context io;
    tcp::socket s(io);
    s.connect({asio::ip::make_address("127.0.0.1"), port});
    const std::string req =
        "GET " + target + " HTTP/1.1\r\nHost: localhost\r\nConnection: close\r\n\r\n";
    asio::write(s, asio::buffer(req));
    std::string out;
    boost::system::error_code ec;
    char buf[4096];
    while (size_t n = s.read_some(asio::buffer(buf), ec)) out.append(buf, n);
    return out;
}

// One sample of /metrics (e.g. "ddsimp_connections"), or -1 if the server does not report it.
inline double metric(uint16_t http_port, const std::string& name) {
    const std::string text = http_get(http_port, "/metrics");
    std::smatch m;
    if (!std::regex_search(text, m, std::regex("\n" + name + " ([0-9.e+-]+)"))) return -1;
    return std::stod(m[1]);
}

// The frames that upload a surface: UploadBegin, 256 KiB UploadChunks, UploadEnd.
inline std::vector<std::string> upload_frames(const Surface& s, uint64_t id,
                                              const std::string& name = "test",
                                              const std::string& session = "") {
    const protocol::EncodedBlob blob = protocol::encode_mesh(s, v1::RAW);
    v1::UploadBegin b;
    b.set_upload_id(id);
    b.set_name(name);
    b.set_vertex_count(s.vertex_count());
    b.set_triangle_count(s.triangle_count());
    for (const Field& f : s.fields) {
        auto* info = b.add_fields();
        info->set_name(f.name);
        info->set_components(uint32_t(f.components));
    }
    b.set_total_bytes(blob.bytes.size());
    b.set_session(session);
    std::vector<std::string> frames{protocol::encode_frame(b)};
    for (size_t at = 0; at < blob.bytes.size(); at += 256 * 1024) {
        v1::UploadChunk c;
        c.set_upload_id(id);
        c.set_offset(at);
        c.set_data(blob.bytes.substr(at, 256 * 1024));
        frames.push_back(protocol::encode_frame(c));
    }
    v1::UploadEnd e;
    e.set_upload_id(id);
    frames.push_back(protocol::encode_frame(e));
    return frames;
}

// Blocking frames over a TCP socket, with a deadline on every read.
class RawClient {
public:
    explicit RawClient(uint16_t port) : socket_(io_) {
        socket_.connect({asio::ip::make_address("127.0.0.1"), port});
        // As the client library does: without it, Nagle's algorithm holds back a small frame sent
        // right after another until the server's delayed ACK, about 40 ms, so frames sent in a
        // row (a test's burst of requests) reach the server that much apart.
        socket_.set_option(asio::ip::tcp::no_delay(true));
    }

    void send_bytes(const std::string& bytes) {
        socket_.non_blocking(false); // next() reads without blocking
        asio::write(socket_, asio::buffer(bytes));
    }
    template <class M> void send(const M& m) { send_bytes(protocol::encode_frame(m)); }

    // The next frame, or nothing if the connection closed or nothing came within the timeout.
    std::optional<protocol::Frame> next(std::chrono::milliseconds timeout = kAnswerTimeout) {
        const auto deadline = std::chrono::steady_clock::now() + timeout;
        for (;;) {
            if (auto f = decoder_.next()) return f;
            if (closed_) return std::nullopt;
            char buf[65536];
            boost::system::error_code ec;
            socket_.non_blocking(true);
            const size_t n = socket_.read_some(asio::buffer(buf), ec);
            if (ec == asio::error::would_block) {
                if (std::chrono::steady_clock::now() > deadline) return std::nullopt;
                std::this_thread::sleep_for(std::chrono::milliseconds(2));
                continue;
            }
            if (ec) {
                closed_ = true;
                continue;
            }
            decoder_.feed(std::string_view(buf, n));
        }
    }

    // The next frame of type M, skipping others (pongs, session states) unless strict.
    template <class M> M expect(std::chrono::milliseconds timeout = kAnswerTimeout) {
        for (;;) {
            auto f = next(timeout);
            if (!f)
                throw std::runtime_error(
                    "connection closed or timed out waiting for " +
                    protocol::message_type_name(protocol::message_type_of<M>()));
            if (f->type == protocol::message_type_of<M>()) return protocol::parse_payload<M>(*f);
            if (f->type == v1::ERROR)
                throw std::runtime_error("server error: " +
                                         protocol::parse_payload<v1::Error>(*f).message());
        }
    }

    bool closed_by_server(std::chrono::milliseconds timeout = std::chrono::seconds(10)) {
        while (auto f = next(timeout)) {
        }
        return closed_;
    }

    v1::Welcome hello(const std::vector<std::string>& caps = {"meshopt-codec", "progressive",
                                                              "sessions"},
                      const std::string& token = "") {
        v1::Hello h;
        h.set_protocol_version(1);
        h.set_client_name("test");
        h.set_kind(v1::TOOL);
        for (const auto& c : caps) h.add_capabilities(c);
        send(h);
        v1::Welcome w = expect<v1::Welcome>();
        if (w.auth_required()) {
            v1::Auth a;
            a.set_token(token);
            send(a);
            expect<v1::AuthOk>();
        }
        return w;
    }

    // Uploads in 256 KiB chunks; returns the result.
    v1::UploadResult upload(const Surface& s, uint64_t id, const std::string& name = "test",
                            const std::string& session = "") {
        for (const std::string& frame : upload_frames(s, id, name, session)) send_bytes(frame);
        return expect<v1::UploadResult>();
    }

    struct Level {
        v1::MeshBegin begin;
        std::string bytes;
    };
    // Reads one MeshBegin, its chunks and MeshEnd (other frames in between are kept in `other`).
    Level level(std::vector<protocol::Frame>* other = nullptr) {
        Level l;
        for (;;) {
            auto f = next();
            if (!f) throw std::runtime_error("closed while waiting for a level");
            if (f->type == v1::MESH_BEGIN) {
                l.begin = protocol::parse_payload<v1::MeshBegin>(*f);
            } else if (f->type == v1::MESH_CHUNK) {
                auto c = protocol::parse_payload<v1::MeshChunk>(*f);
                EXPECT_EQ(c.offset(), l.bytes.size());
                l.bytes += c.data();
            } else if (f->type == v1::MESH_END) {
                return l;
            } else if (f->type == v1::ERROR) {
                throw std::runtime_error("server error: " +
                                         protocol::parse_payload<v1::Error>(*f).message());
            } else if (other) {
                other->push_back(*f);
            }
        }
    }

    tcp::socket& socket() { return socket_; }

private:
    asio::io_context io_;
    tcp::socket socket_;
    protocol::FrameDecoder decoder_{64u << 20};
    bool closed_ = false;
};

} // namespace ddsimp::test
