// Hostile clients against the server's listeners and log: silent sockets on the HTTP port from
// many addresses (every connection counted, within the descriptor limit), a server out of
// descriptors (accepting pauses and logs once per interval), client-chosen strings that try to
// forge log lines, and the HTTP port bound apart from the native one.
#include "hostile_support.h"

#include <nlohmann/json.hpp>

#include <fcntl.h>
#include <sys/resource.h>

namespace ddsimp::test {
namespace {

// Runs in the server's child process: the descriptor limit (soft and hard) and stderr to `log`.
std::function<void()> limited(size_t descriptors, std::string log = "") {
    return [descriptors, log] {
        const rlimit limit{descriptors, descriptors};
        ::setrlimit(RLIMIT_NOFILE, &limit);
        if (!log.empty()) {
            const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
            ::dup2(fd, 2);
            ::close(fd);
        }
    };
}

// Waits (up to a minute) until the monitor reads the value; returns the last it read.
double await_value(HttpKeepAlive& monitor, const std::string& name, double value) {
    double now = -1;
    for (int i = 0; i < 600 && (now = monitor.metric(name)) != value; ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
    return now;
}

std::vector<std::string> lines_of(const std::filesystem::path& file) {
    std::ifstream in(file);
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
}

// Silent sockets on the HTTP port, as the 1,100 that once took every descriptor of a server
// limited to 1,024: each is counted, no address gets more than its share, and the total stays
// below the descriptor limit less the reserve, so the server never runs out of descriptors and
// keeps serving the clients it has. Those past a limit are told why and closed at once.
TEST(HostileConnections, SilentHttpSocketsFromManyAddressesAreCountedAndBounded) {
    constexpr size_t kDescriptors = 256, kReserve = 64, kPerAddress = 32, kAttempts = 40;
    constexpr size_t kLimit = kDescriptors - kReserve; // --max-clients 1000 is lowered to this
    ServerProcess server(temp_dir("silent-http"),
                         {"--max-clients", "1000", "--max-clients-per-address",
                          std::to_string(kPerAddress), "--fd-reserve", std::to_string(kReserve),
                          "--http-timeout", "300"},
                         limited(kDescriptors));
    WellBehavedClient good(server.port);
    HttpKeepAlive monitor(server.http_port);
    EXPECT_EQ(monitor.metric("ddsimp_sockets_limit"), kLimit);
    EXPECT_EQ(monitor.metric("ddsimp_sockets"), 2);

    // Five addresses, each trying for more than its share: each gets its share.
    asio::io_context io;
    std::vector<std::unique_ptr<BareConnection>> held;
    const auto attack_from = [&](const std::string& address) {
        for (size_t i = 0; i < kAttempts; ++i)
            held.push_back(std::make_unique<BareConnection>(io, server.http_port, address));
    };
    for (int a = 2; a <= 6; ++a) {
        attack_from("127.0.0." + std::to_string(a));
        // Some refusals may not have reached the socket yet: the server's count says.
        const double sockets =
            await_value(monitor, "ddsimp_sockets", double(2 + (a - 1) * kPerAddress));
        EXPECT_EQ(sockets, 2 + (a - 1) * kPerAddress) << "after 127.0.0." << a;
    }
    EXPECT_EQ(
        await_value(monitor, "ddsimp_connections_refused_total", 5 * (kAttempts - kPerAddress)),
        5 * (kAttempts - kPerAddress));
    // The clients of other addresses are served.
    EXPECT_NE(http_get(server.http_port, "/healthz").find("ok"), std::string::npos);
    good.check_level();

    // Three more addresses fill the total: past it, every new connection is refused with the
    // reason, the HTTP port's included, and the clients inside are served.
    for (int a = 7; a <= 9; ++a) attack_from("127.0.0." + std::to_string(a));
    EXPECT_EQ(await_value(monitor, "ddsimp_sockets", kLimit), kLimit);
    const std::string full = http_get(server.http_port, "/healthz");
    EXPECT_NE(full.find("503 Service Unavailable"), std::string::npos) << full;
    EXPECT_NE(full.find("maximum of " + std::to_string(kLimit) + " clients"), std::string::npos)
        << full;
    BareConnection newcomer(io, server.port);
    newcomer.send(hello_message());
    const std::optional<v1::Error> e = newcomer.until_closed();
    ASSERT_TRUE(e);
    EXPECT_EQ(e->code(), v1::Error::RESOURCE_EXHAUSTED);
    good.check_level();
    EXPECT_EQ(monitor.metric("ddsimp_accept_errors_total"), 0) << "never out of descriptors";

    held.clear(); // they go: the places come back
    EXPECT_EQ(await_value(monitor, "ddsimp_sockets", 2), 2);
    EXPECT_NE(http_get(server.http_port, "/healthz").find("ok"), std::string::npos);
    good.check_level();
}

// A server left without descriptors (no reserve: --fd-reserve 0) cannot accept: it pauses,
// doubling the pause up to --accept-backoff, instead of trying again at once, and logs it once
// per --accept-log-interval, where it once wrote the same line millions of times.
TEST(HostileConnections, AcceptErrorsPauseAndAreLoggedOncePerInterval) {
    constexpr size_t kDescriptors = 48;
    constexpr double kLogInterval = 2;
    const auto dir = temp_dir("accept-errors");
    const auto log = dir / "server.log";
    ServerProcess server(dir / "data",
                         {"--fd-reserve", "0", "--accept-backoff", "0.5", "--accept-log-interval",
                          std::to_string(kLogInterval), "--log-level", "info"},
                         limited(kDescriptors, log.string()));
    WellBehavedClient good(server.port);
    // Everything the good client asks for is answered once before the flood: under UBSan, the
    // first call through each new dynamic type opens a pipe to check the memory, which a process
    // out of descriptors cannot.
    good.ping();
    good.check_level();
    asio::io_context io;
    std::vector<std::unique_ptr<BareConnection>> flood;
    const auto start = std::chrono::steady_clock::now();
    for (size_t i = 0; i < kDescriptors + 20; ++i) // the kernel completes them; the server cannot
        flood.push_back(
            std::make_unique<BareConnection>(io, i % 2 ? server.port : server.http_port));
    // Hold them while the server keeps failing: the good client (already in) is served.
    for (int i = 0; i < 10; ++i) {
        good.ping();
        std::this_thread::sleep_for(std::chrono::milliseconds(300));
    }
    good.check_level();
    flood.clear();
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    // Room again: served.
    const double errors = metric(server.http_port, "ddsimp_accept_errors_total");
    EXPECT_GT(errors, 0) << "the flood must have run the server out of descriptors";
    // Each listener tries again after 10, 20, 40 ... ms, then every 0.5 s: a bounded number of
    // times for the attack's length, not as often as it can.
    EXPECT_LE(errors, 2 * (7 + seconds / 0.5)) << seconds << " s";
    good.check_level();
    size_t logged = 0;
    for (const std::string& line : lines_of(log))
        if (line.find("accepting failed") != std::string::npos) ++logged;
    EXPECT_GE(logged, 1u);
    EXPECT_LE(logged, 2 * (1 + seconds / kLogInterval)) << seconds << " s";
}

// Strings a client chooses (its name before any token is checked, an upload's label, a session's
// name) with newlines, a forged log line, terminal escape sequences and a right-to-left mark: in
// the text log every line is one of the server's, and in the JSON log every line is one JSON
// object.
TEST(HostileConnections, ClientStringsCannotForgeLogLines) {
    const std::string forged = "me\n2026-11-27T10:00:00.000 info client 7 (10.0.0.1:1) is "
                               "\"admin\" (TOOL)\r\x1b[2J\x1b]0;owned\x07\xc2\x9b"
                               "31m\xe2\x80\xae" +
                               std::string(5000, 'x');
    for (const std::string format : {"text", "json"}) {
        const auto dir = temp_dir("forged-log-" + format);
        const auto log = dir / "server.log";
        {
            ServerProcess server(dir / "data", {"--log-level", "info", "--log-format", format},
                                 limited(1024, log.string()));
            RawClient c(server.port);
            v1::Hello h = hello_message();
            h.set_client_name(forged);
            c.send(h);
            c.expect<v1::Welcome>();
            c.upload(small_surface(), 1, forged.substr(0, 190));
            v1::JoinSession join;
            join.set_name(forged.substr(0, 190));
            c.send(join);
            c.expect<v1::SessionState>();
            server.stop();
        }
        const std::vector<std::string> lines = lines_of(log);
        ASSERT_GT(lines.size(), 3u);
        size_t named = 0;
        for (const std::string& line : lines) {
            for (char ch : line)
                EXPECT_TRUE(ch >= 0x20 && ch != 0x7f) << "a control character in: " << line;
            EXPECT_LT(line.size(), 1000u) << "not capped: " << line.substr(0, 200);
            if (format == "text") {
                EXPECT_TRUE(std::regex_search(
                    line, std::regex(R"(^\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\.\d{3} \w+ )")))
                    << line;
            } else {
                const nlohmann::json j = nlohmann::json::parse(line);
                EXPECT_TRUE(j.contains("time") && j.contains("level") && j.contains("message"));
            }
            if (line.find("me\\\\x0a2026-11-27T10:00:00.000") != std::string::npos ||
                line.find("me\\x0a2026-11-27T10:00:00.000") != std::string::npos)
                ++named;
        }
        EXPECT_GE(named, 1u) << "the client's name is logged, escaped";
        for (const std::string& line : lines)
            EXPECT_FALSE(line.rfind("2026-11-27T10:00:00.000", 0) == 0) << "forged: " << line;
    }
}

// --http-bind apart from --bind: the unauthenticated HTTP port on one address, the native port
// on another, each listening there only.
TEST(HostileConnections, HttpBindIsApartFromBind) {
    ServerProcess server(temp_dir("http-bind"),
                         {"--bind", "127.0.0.1", "--http-bind", "127.0.0.2"});
    EXPECT_TRUE(ServerProcess::accepts(server.port, "127.0.0.1"));
    EXPECT_FALSE(ServerProcess::accepts(server.port, "127.0.0.2"));
    EXPECT_TRUE(ServerProcess::accepts(server.http_port, "127.0.0.2"));
    EXPECT_FALSE(ServerProcess::accepts(server.http_port, "127.0.0.1"));
}

} // namespace
} // namespace ddsimp::test
