// The server's own memory total (ddsimp_memory_bound_bytes, docs/operations.md#memory) against a
// real ddsimp-server: it is the documented formula of its flags, and under the attacks that fill
// its parts at once (frames held half-read, uploads stalled, computations on both threads, a
// surface over --max-surface-mb) its resident memory stays within its size at rest plus that total.
#include "hostile_support.h"

namespace ddsimp::test {
namespace {

constexpr size_t kFrameBytes = size_t(1) << 20;

std::string header(v1::MessageType type, uint32_t length) {
    unsigned char h[protocol::kHeaderBytes];
    protocol::write_header(h, type, length);
    return std::string(reinterpret_cast<char*>(h), sizeof h);
}

// docs/operations.md#memory, for the flags below, `clients` connections and two threads.
double documented_total(double clients) {
    constexpr double MiB = 1 << 20, KiB = 1 << 10, T = 2;
    const double X = 4 * MiB, N = 100'000;
    return 8 * MiB + (T + 1) * X                   // surfaces
           + clients * (kFrameBytes + 96 * KiB)    // connections
           + std::min(clients * 8 * MiB, 16 * MiB) // send queues
           + 16 * MiB + T * 2 * X                  // uploads
           + 16 * MiB + T * 300 * N                // results
           + clients * 16 * KiB                    // request jobs
           + 1024 * KiB;                           // remembered keys
}

TEST(MemoryBound, TheServerStatesItsTotalAndStaysWithinIt) {
    ServerProcess server(temp_dir("memory-bound"), {"--max-clients",
                                                    "48",
                                                    "--max-frame-bytes",
                                                    "1048576",
                                                    "--max-queue-mb",
                                                    "8",
                                                    "--max-queue-total-mb",
                                                    "16",
                                                    "--cache-mb",
                                                    "16",
                                                    "--surfaces-mb",
                                                    "8",
                                                    "--max-upload-mb",
                                                    "16",
                                                    "--max-surface-mb",
                                                    "4",
                                                    "--max-surface-triangles",
                                                    "100000",
                                                    "--max-remembered-kb",
                                                    "1024",
                                                    "--threads",
                                                    "2",
                                                    "--handshake-timeout",
                                                    "30",
                                                    "--idle-timeout",
                                                    "60"});
    const auto m = [&](const std::string& name) { return metric(server.http_port, name); };
    const double clients = m("ddsimp_sockets_limit");
    EXPECT_EQ(clients, 48);
    const double total = m("ddsimp_memory_bound_bytes");
    EXPECT_EQ(total, std::floor(documented_total(clients)));

    RawClient c(server.port);
    c.hello({});
    // Two surfaces of 81,920 triangles (about 2.1 MiB each) for the two threads to simplify.
    const Surface a = with_test_fields(icosphere(6));
    Surface b = a;
    for (float& x : b.positions) x *= 1.5f;
    const std::string ida = c.upload(a, 1).surface(), idb = c.upload(b, 2).surface();
    // One over --max-surface-mb (within the triangle limit) is refused before a byte of it is
    // held: 16 more components per vertex make it about 4.7 MiB.
    Surface big = a;
    big.fields.push_back({"wide", 16, std::vector<float>(a.vertex_count() * 16, 1.0f)});
    c.send_bytes(upload_frames(big, 3).front());
    const v1::Error over = next_error(c);
    EXPECT_EQ(over.code(), v1::Error::RESOURCE_EXHAUSTED);
    EXPECT_NE(over.message().find("--max-surface-mb"), std::string::npos) << over.message();
    const size_t at_rest = server.status_bytes("VmRSS");

    // Forty connections each holding all but the last byte of a frame of the maximum size.
    asio::io_context io;
    const std::string hello = protocol::encode_frame(hello_message());
    std::vector<std::unique_ptr<BareConnection>> held;
    for (int i = 0; i < 40; ++i) {
        held.push_back(std::make_unique<BareConnection>(io, server.port));
        held.back()->send_bytes(hello + header(v1::PING, uint32_t(kFrameBytes)) +
                                std::string(kFrameBytes - 1, 'x'));
    }
    // Uploads that hold most of the upload budget: every byte but the last chunk of six surfaces
    // (at most four per connection).
    RawClient uploader(server.port), uploader2(server.port);
    uploader.hello({});
    uploader2.hello({});
    for (int i = 0; i < 6; ++i) {
        Surface s = a;
        for (float& x : s.positions) x *= 2.0f + float(i);
        const std::vector<std::string> frames = upload_frames(s, uint64_t(10 + i));
        for (size_t f = 0; f + 2 < frames.size(); ++f)
            (i < 3 ? uploader : uploader2).send_bytes(frames[f]);
    }
    // Both threads simplifying, each a surface of its own, to the end.
    c.send(level_request(ida, {0.01f}, 4, 0.1f));
    c.send(level_request(idb, {0.01f}, 5, 0.9f));
    for (int done = 0; done < 2;) {
        const std::optional<protocol::Frame> f = c.next(std::chrono::seconds(120));
        ASSERT_TRUE(f) << "no answer";
        done += f->type == v1::REQUEST_DONE;
    }
    EXPECT_GT(m("ddsimp_upload_bytes"), 10.0 * kMiB);
    const size_t peak = server.status_bytes("VmHWM");
    const size_t allowance = with_sanitizer_memory(size_t(total) + kAllocatorSlack);
    EXPECT_LE(peak, at_rest + allowance)
        << "peak " << (peak >> 20) << " MiB, at rest " << (at_rest >> 20) << " MiB, total "
        << (size_t(total) >> 20) << " MiB";
    RecordProperty("memory_bound_kib", int(size_t(total) >> 10));
    RecordProperty("at_rest_kib", int(at_rest >> 10));
    RecordProperty("peak_growth_kib", int((peak - std::min(peak, at_rest)) >> 10));
}

} // namespace
} // namespace ddsimp::test
