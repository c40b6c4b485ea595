// Hostile clients against a real ddsimp-server: garbage bytes, absurd length headers, truncated
// frames, hundreds of idle connections and the client limit, a client that stops reading in the
// middle of a large mesh. In each case a well-behaved client keeps getting levels equal to the
// offline library's, and the server's peak memory (VmHWM) stays within what its configured
// limits allow on top of what it held before the attack.
#include "hostile_support.h"

#include <fcntl.h>
#include <unistd.h>

#include <random>

namespace ddsimp::test {
namespace {

constexpr size_t kMaxFrameBytes = kMiB; // --max-frame-bytes in these tests

class HostileClients : public ::testing::Test {
protected:
    void start(std::vector<std::string> flags) {
        flags.insert(flags.end(), {"--max-frame-bytes", std::to_string(kMaxFrameBytes)});
        server_ = std::make_unique<ServerProcess>(temp_dir(name()), flags);
        good_ = std::make_unique<WellBehavedClient>(server_->port);
        good_->check_level();
        baseline_ = server_->status_bytes("VmHWM");
    }
    static std::string name() {
        return ::testing::UnitTest::GetInstance()->current_test_info()->name();
    }
    // The peak since the attack began, beyond the peak before it.
    void expect_peak_within(size_t release_allowance) {
        const size_t allowance = with_sanitizer_memory(release_allowance);
        const size_t peak = server_->status_bytes("VmHWM");
        EXPECT_LE(peak, baseline_ + allowance)
            << "peak " << (peak >> 10) << " KiB, before the attack " << (baseline_ >> 10)
            << " KiB, allowed " << (allowance >> 10) << " KiB more";
    }
    std::unique_ptr<ServerProcess> server_;
    std::unique_ptr<WellBehavedClient> good_;
    size_t baseline_ = 0;
};

// Random bytes (seeded: the same every run), never starting like a frame.
TEST_F(HostileClients, GarbageBytesEndOnlyTheirOwnConnection) {
    start({});
    std::mt19937 random(20261121);
    asio::io_context io;
    constexpr int kClients = 40;
    for (int i = 0; i < kClients; ++i) {
        BareConnection c(io, server_->port);
        if (i % 2) c.send(hello_message()); // half of them after a valid Hello
        std::string garbage(size_t(12 + random() % (64u << 10)), '\0');
        for (char& ch : garbage) ch = char(random());
        garbage[0] = 'X';
        c.send_bytes(garbage);
        const std::optional<v1::Error> e = c.until_closed();
        ASSERT_TRUE(e) << "client " << i;
        EXPECT_EQ(e->code(), v1::Error::BAD_FRAME);
        EXPECT_NE(e->message().find("not a ddsimp frame"), std::string::npos) << e->message();
        if (i % 10 == 0) good_->check_level();
    }
    good_->check_level();
    EXPECT_EQ(metric(server_->http_port, "ddsimp_bad_frames_total"), kClients);
    EXPECT_EQ(await_metric(server_->http_port, "ddsimp_connections", 1), 1);
    // A garbage frame is read 12 bytes at a time and refused on its header: nothing is kept.
    expect_peak_within(kAllocatorSlack);
}

// Lengths over the limit, up to 4 GiB, for several types, before and after Hello: refused on the
// header, before a byte of payload is allocated. A frame of exactly the limit is accepted.
TEST_F(HostileClients, AbsurdLengthHeadersAreRefusedBeforeAllocating) {
    start({});
    asio::io_context io;
    int refused = 0;
    for (uint32_t length : {uint32_t(kMaxFrameBytes + 1), 0x7fffffffu, 0xffffffffu})
        for (v1::MessageType type : {v1::HELLO, v1::UPLOAD_CHUNK, v1::REQUEST})
            for (bool after_hello : {false, true}) {
                BareConnection c(io, server_->port);
                if (after_hello) c.send(hello_message());
                c.send_bytes(header(type, length));
                const std::optional<v1::Error> e = c.until_closed();
                ASSERT_TRUE(e);
                EXPECT_EQ(e->code(), v1::Error::BAD_FRAME);
                EXPECT_NE(e->message().find("over the limit of " + std::to_string(kMaxFrameBytes)),
                          std::string::npos)
                    << e->message();
                ++refused;
            }
    good_->check_level();
    EXPECT_EQ(metric(server_->http_port, "ddsimp_bad_frames_total"), refused);

    // Exactly the limit: an UploadChunk padded to kMaxFrameBytes is read and answered (for an
    // upload never begun), so the limit is the largest accepted payload, not one byte less.
    BareConnection exact(io, server_->port);
    exact.send(hello_message());
    ASSERT_EQ(exact.next()->type, v1::WELCOME);
    v1::UploadChunk chunk;
    chunk.set_upload_id(5);
    chunk.set_data(std::string(kMaxFrameBytes - 16, 'x'));
    const size_t overhead = chunk.ByteSizeLong() - chunk.data().size();
    chunk.set_data(std::string(kMaxFrameBytes - overhead, 'x'));
    ASSERT_EQ(chunk.ByteSizeLong(), kMaxFrameBytes);
    exact.send(chunk);
    const std::optional<protocol::Frame> answer = exact.next();
    ASSERT_TRUE(answer);
    const v1::Error e = protocol::parse_payload<v1::Error>(*answer);
    EXPECT_EQ(e.code(), v1::Error::INVALID_ARGUMENT);
    EXPECT_NE(e.message().find("upload 5 was not begun"), std::string::npos) << e.message();

    // 18 headers announced up to 4 GiB each; only the exact frame's MiB may have been allocated.
    expect_peak_within(kMaxFrameBytes + kAllocatorSlack);
}

// Frames cut short: half a header before Hello (the handshake timeout closes it), a header and
// part of its payload after Hello (the idle timeout closes it), and cuts followed by a close.
// Forty clients each stalled in a frame of the maximum size hold at most that frame each.
TEST_F(HostileClients, TruncatedFramesAreClosedByTheTimeoutsAndHoldOneFrameEach) {
    start({"--handshake-timeout", "1", "--idle-timeout", "3"});
    asio::io_context io;
    const std::string hello = protocol::encode_frame(hello_message());
    std::vector<std::unique_ptr<BareConnection>> stalled;
    for (int i = 0; i < 10; ++i) { // half a header, before Hello
        stalled.push_back(std::make_unique<BareConnection>(io, server_->port));
        stalled.back()->send_bytes(header(v1::HELLO, 40).substr(0, 6));
    }
    for (int i = 0; i < 10; ++i) { // half of a Hello frame
        stalled.push_back(std::make_unique<BareConnection>(io, server_->port));
        stalled.back()->send_bytes(hello.substr(0, hello.size() - 3));
    }
    constexpr int kFullFrames = 40;
    for (int i = 0; i < kFullFrames; ++i) { // Hello, then a frame of the maximum size cut in half
        stalled.push_back(std::make_unique<BareConnection>(io, server_->port));
        stalled.back()->send_bytes(hello + header(v1::UPLOAD_CHUNK, uint32_t(kMaxFrameBytes)) +
                                   std::string(kMaxFrameBytes / 2, 'x'));
    }
    for (int i = 0; i < 10; ++i) { // cut, then closed by the client
        BareConnection c(io, server_->port);
        c.send_bytes(hello + header(v1::PING, 100) + "abc");
        c.close();
    }
    good_->check_level();
    // Every stalled connection is closed by the server, without a word; the good client is
    // served meanwhile (and its pings keep it from idling out itself).
    std::atomic<bool> all_closed = false;
    std::thread waiter([&] {
        for (auto& c : stalled) EXPECT_FALSE(c->until_closed());
        all_closed = true;
    });
    while (!all_closed) {
        good_->ping();
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
    waiter.join();
    good_->check_level();
    EXPECT_EQ(await_metric(server_->http_port, "ddsimp_connections", 1), 1);
    // Each stalled full frame holds its payload buffer (the maximum frame) until it is closed.
    expect_peak_within(kFullFrames * (kMaxFrameBytes + kConnectionOverhead) + kAllocatorSlack);
}

// Hundreds of connections that say Hello and nothing more fill the client limit: those past it
// are refused with RESOURCE_EXHAUSTED, the good client (already in) keeps being served, and once
// the idle ones leave there is room again. Silent connections are closed by the handshake timeout.
// Every connection holds a place, the HTTP one that reads /metrics too.
TEST_F(HostileClients, HundredsOfIdleConnectionsMeetTheClientLimit) {
    constexpr size_t kMaxClients = 256, kIdle = 300;
    start({"--max-clients", std::to_string(kMaxClients), "--max-clients-per-address", "1000",
           "--handshake-timeout", "2"});
    HttpKeepAlive monitor(server_->http_port);
    EXPECT_EQ(monitor.metric("ddsimp_sockets"), 2); // the good client and the monitor
    asio::io_context io;
    std::vector<std::unique_ptr<BareConnection>> idle;
    size_t welcomed = 0, refused = 0;
    for (size_t i = 0; i < kIdle; ++i) {
        auto c = std::make_unique<BareConnection>(io, server_->port);
        c->send(hello_message());
        const std::optional<protocol::Frame> f = c->next();
        ASSERT_TRUE(f);
        if (f->type == v1::WELCOME) {
            ++welcomed;
            idle.push_back(std::move(c));
            continue;
        }
        const v1::Error e = protocol::parse_payload<v1::Error>(*f);
        EXPECT_EQ(e.code(), v1::Error::RESOURCE_EXHAUSTED);
        EXPECT_NE(e.message().find("maximum of 256 clients"), std::string::npos) << e.message();
        EXPECT_FALSE(c->until_closed());
        ++refused;
    }
    // The good client and the monitor hold two places; the idle ones fill the rest, and only it.
    EXPECT_EQ(welcomed, kMaxClients - 2);
    EXPECT_EQ(refused, kIdle - (kMaxClients - 2));
    EXPECT_EQ(monitor.metric("ddsimp_sockets"), kMaxClients);
    EXPECT_EQ(monitor.metric("ddsimp_connections"), kMaxClients - 1);
    EXPECT_EQ(monitor.metric("ddsimp_connections_refused_total"), refused);
    // The HTTP port is full too: a new request is told so.
    const std::string full = http_get(server_->http_port, "/healthz");
    EXPECT_NE(full.find("503"), std::string::npos) << full;
    EXPECT_NE(full.find("maximum of 256 clients"), std::string::npos) << full;
    good_->check_level();
    expect_peak_within(kMaxClients * kConnectionOverhead + kAllocatorSlack);

    idle.clear(); // they leave: there is room again
    EXPECT_EQ(await_metric(server_->http_port, "ddsimp_connections", 1), 1);
    RawClient newcomer(server_->port);
    EXPECT_NO_THROW(newcomer.hello({}));

    // Connections that never say anything are closed after the handshake timeout.
    std::vector<std::unique_ptr<BareConnection>> silent;
    for (int i = 0; i < 200; ++i)
        silent.push_back(std::make_unique<BareConnection>(io, server_->port));
    for (auto& c : silent) EXPECT_FALSE(c->until_closed()); // closed without a word
    good_->check_level();
    EXPECT_EQ(await_metric(server_->http_port, "ddsimp_connections", 2), 2);
}

// A client that stops reading in the middle of a large mesh: its queue never grows past the
// configured bound, it is dropped when its writes stall for the send timeout, what it had
// queued is released, and the good client is served throughout.
TEST_F(HostileClients, AReaderThatStopsMidMeshIsDroppedWithinItsQueueBound) {
    constexpr size_t kQueueMiB = 64, kCacheMiB = 64;
    start({"--send-timeout", "2", "--max-queue-mb", std::to_string(kQueueMiB), "--cache-mb",
           std::to_string(kCacheMiB)});
    const Surface big = with_test_fields(icosphere(7)); // 327680 triangles, ~12 MB raw
    const std::string id = good_->raw().upload(big, 7).surface();
    // The good client computes the record first, so the attack adds only levels and queues.
    good_->raw().send(level_request(id, {0.01f}, 70));
    good_->raw().level();
    good_->raw().expect<v1::RequestDone>();
    baseline_ = server_->status_bytes("VmHWM");

    RawClient slow(server_->port);
    slow.hello({});
    slow.socket().set_option(boost::asio::socket_base::receive_buffer_size(4096));
    // Four near-full levels, ~34 MB: more than loopback's socket buffers hold.
    slow.send(level_request(id, {1.0f, 0.99f, 0.98f, 0.97f}, 1));
    ASSERT_TRUE(slow.next()); // it reads the beginning of the first level, then nothing
    for (int i = 0; i < 600 && metric(server_->http_port, "ddsimp_connections_dropped_total") < 1;
         ++i) {
        good_->ping();
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    EXPECT_EQ(metric(server_->http_port, "ddsimp_connections_dropped_total"), 1);
    good_->check_level();
    EXPECT_LE(metric(server_->http_port, "ddsimp_client_queue_bytes_max"), kQueueMiB * kMiB);
    // Nothing stays queued for the dropped client.
    EXPECT_EQ(await_metric(server_->http_port, "ddsimp_queue_bytes", 0), 0);
    // The levels live in the result cache (bounded) and, beyond it, only in the client's queue.
    expect_peak_within((kCacheMiB + kQueueMiB) * kMiB + kAllocatorSlack);
}

// The server's log (its stderr) into `path`, for ServerProcess's `before_exec`.
std::function<void()> stderr_to(const std::string& path) {
    return [path] {
        const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        ::dup2(fd, 2);
        ::close(fd);
    };
}

std::string file_text(const std::filesystem::path& file) {
    std::ifstream in(file);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

// --max-queue-total-mb: what all clients together may have waiting to be sent. A client that
// stops reading holds most of it within its own --max-queue-mb; the client whose level would then
// pass the total is dropped, with the documented reason in the log, and only that one: the reader
// that stopped keeps its place (the send timeout is its bound) and a third client is served.
TEST(HostileQueues, TheClientWhoseLevelWouldPassTheTotalQueueIsDropped) {
    constexpr size_t kTotalMiB = 26;
    const auto dir = temp_dir("queue-total");
    const auto log = dir / "server.log";
    ServerProcess server(dir / "data",
                         {"--max-queue-total-mb", std::to_string(kTotalMiB), "--max-queue-mb",
                          std::to_string(kTotalMiB), "--send-timeout", "300"},
                         stderr_to(log.string()));
    WellBehavedClient good(server.port);
    // 327,680 triangles, 163,842 vertices with 4 field components: a whole level is 12 bytes a
    // triangle and 28 a vertex raw, about 8.1 MiB.
    const Surface big = with_test_fields(icosphere(7));
    const size_t level_bytes = 12 * big.triangle_count() + 28 * big.vertex_count();
    const std::string id = good.raw().upload(big, 7).surface();

    // Three near-whole levels (about 24 MiB, within both limits) for a client that reads nothing.
    RawClient stalled(server.port);
    stalled.socket().set_option(boost::asio::socket_base::receive_buffer_size(4096));
    stalled.hello({});
    stalled.send(level_request(id, {1.0f, 0.99f, 0.98f}, 1));
    // All three are queued once its job has ended (seen after its first level was queued); what
    // loopback's buffers took is not queued.
    double held = 0;
    for (int i = 0; i < 1200; ++i) {
        if (metric(server.http_port, "ddsimp_queue_bytes") > 0 &&
            metric(server.http_port, "ddsimp_request_jobs") == 0) {
            held = metric(server.http_port, "ddsimp_queue_bytes");
            break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    EXPECT_EQ(metric(server.http_port, "ddsimp_request_jobs"), 0);
    ASSERT_GT(held + double(level_bytes), double(kTotalMiB * kMiB))
        << "the stalled client holds only " << held << " bytes: one more level must pass the total";
    ASSERT_LE(held, double(kTotalMiB * kMiB));

    // One whole level fits this client's own queue, but not beside what the stalled one holds.
    RawClient passing(server.port);
    passing.hello({});
    const uint16_t passing_port = passing.socket().local_endpoint().port();
    passing.send(level_request(id, {1.0f}, 2));
    EXPECT_TRUE(passing.closed_by_server(std::chrono::seconds(60)));
    EXPECT_EQ(metric(server.http_port, "ddsimp_connections_dropped_total"), 1);
    // The stalled client and the good one are still connected, and the good one is served.
    EXPECT_EQ(await_metric(server.http_port, "ddsimp_connections", 2), 2);
    good.check_level();
    good.ping();
    EXPECT_LE(metric(server.http_port, "ddsimp_queue_bytes"), double(kTotalMiB * kMiB));

    const std::string text = file_text(log);
    const std::string reason = "its level would pass the " + std::to_string(kTotalMiB) +
                               " MiB all clients may have waiting to be sent "
                               "(--max-queue-total-mb)";
    const size_t at = text.find(reason);
    ASSERT_NE(at, std::string::npos) << text;
    const size_t line = text.rfind('\n', at) + 1;
    EXPECT_NE(text.substr(line, at - line).find("127.0.0.1:" + std::to_string(passing_port)),
              std::string::npos)
        << "the client dropped is the one whose level passed: " << text.substr(line, at - line);
    EXPECT_EQ(text.find(reason, at + 1), std::string::npos) << "one client dropped: " << text;
}

// af17e1f: a client waiting for its own request is not idle. Nothing is sent while a level is
// computed, and a computation longer than --idle-timeout used to end the connection of the
// client that asked for it. The timeout here is a quarter of what the same simplification (the
// first level of a surface computes its whole record: vertex removal down to keep 0.001) takes
// in this process, so the request outlasts it on any machine and under any sanitizer. The client
// gets its level; a client that only said Hello is still dropped, and so is the first one once
// it has what it asked for.
TEST(IdleTimeout, AClientWaitingForItsOwnRequestIsNotIdle) {
    constexpr float kKeep = 0.001f;
    Options options;
    options.alpha = 0.3; // what the request's 0.3f means to the server
    options.keep_fraction = kKeep;
    options.strategy = Strategy::VertexRemoval;
    // A surface whose simplification takes long enough that a quarter of it is no shorter than
    // the pauses a loaded machine makes between the client's frames (81,920 triangles, or four
    // times as many on a fast machine).
    Surface input, expected;
    double seconds = 0;
    for (int level = 6; level <= 7 && seconds < 2; ++level) {
        input = with_test_fields(icosphere(level));
        const auto start = std::chrono::steady_clock::now();
        expected = simplify(input, options).surface;
        seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }

    ServerProcess server(temp_dir("idle-timeout"), {"--idle-timeout", std::to_string(seconds / 4)});
    RawClient asking(server.port);
    asking.hello({});
    const std::string surface = asking.upload(input, 1).surface();
    v1::Request request = level_request(surface, {kKeep}, 7);
    request.set_strategy(v1::VERTEX_REMOVAL);
    asking.send(request);
    RawClient idle(server.port);
    idle.hello({});

    const RawClient::Level level = asking.level();
    EXPECT_EQ(level.begin.request_id(), 7u);
    const Surface got = protocol::decode_mesh(level.bytes, protocol::layout_of(level.begin));
    EXPECT_TRUE(same_bytes(got, expected));
    EXPECT_EQ(asking.expect<v1::RequestDone>().request_id(), 7u);
    EXPECT_TRUE(idle.closed_by_server(std::chrono::seconds(60)));
    EXPECT_TRUE(asking.closed_by_server(std::chrono::seconds(60)));
}

} // namespace
} // namespace ddsimp::test
