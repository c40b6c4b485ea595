// Hostile storage against a real ddsimp-server: more uploaded surfaces than the memory meant for
// them (--surfaces-mb), checked with the server's own accounting (/metrics) and its resident set.
#include "hostile_support.h"

namespace ddsimp::test {
namespace {

namespace fs = std::filesystem;

// A surface of its own for every i (the icosphere scaled), so no two are deduplicated: 81,920
// triangles with a scalar and a vector field, about 2.1 MB in memory.
Surface numbered_surface(int i) {
    Surface s = with_test_fields(icosphere(6));
    for (float& x : s.positions) x *= 1.0f + 0.01f * float(i);
    return s;
}

// The level a request with keep 1 gets: the surface as the server holds it, whole. The preview
// that may come first is skipped.
Surface whole_surface(RawClient& c, const std::string& surface, uint64_t id) {
    c.send(level_request(surface, {1.0f}, id));
    for (;;) {
        const RawClient::Level l = c.level();
        if (l.begin.preview()) continue;
        EXPECT_EQ(c.expect<v1::RequestDone>().request_id(), id);
        return protocol::decode_mesh(l.bytes, protocol::layout_of(l.begin));
    }
}

// 32 surfaces (12 under a sanitizer) of 2.1 MB into a server that keeps 5 MiB of them: the others
// are evicted (the least recently used first) and read back from the data directory when a request
// needs them, with the same bytes; the server's memory does not grow with what it stores. After a
// restart nothing but the index is in memory, and the lists say what they said before.
TEST(HostileStorage, SurfacesBeyondTheMemoryBoundAreReadBackWhenNeeded) {
#if defined(DDSIMP_TEST_ASAN) || defined(DDSIMP_TEST_TSAN)
    // A sanitizer's allowance is larger than what any number of these uploads would store, so
    // the memory check means something in release builds only: fewer uploads keep the run short
    // (and ASan's quarantine of freed buffers within its allowance).
    constexpr int kSurfaces = 12;
    constexpr bool kCheckable = false;
#else
    constexpr int kSurfaces = 32;
    constexpr bool kCheckable = true;
#endif
    constexpr size_t kBoundMiB = 5;
    const fs::path dir = temp_dir("surfaces-bound");
    const std::vector<std::string> flags{"--surfaces-mb", std::to_string(kBoundMiB),
                                         "--cache-mb",    "8",
                                         "--threads",     "1",
                                         "--sample",      ""};
    auto server = std::make_unique<ServerProcess>(dir, flags);
    const auto m = [&](const std::string& name) { return metric(server->http_port, name); };
    EXPECT_EQ(m("ddsimp_surface_limit_bytes"), double(kBoundMiB * kMiB));

    RawClient c(server->port);
    c.hello({});
    std::vector<std::string> ids;
    const Surface first = numbered_surface(0);
    ids.push_back(c.upload(first, 1).surface());
    const size_t surface_bytes = size_t(m("ddsimp_surface_bytes"));
    EXPECT_GT(surface_bytes, 2 * kMiB);
    const size_t peak_before = server->status_bytes("VmHWM");

    for (int i = 1; i < kSurfaces; ++i)
        ids.push_back(c.upload(numbered_surface(i), uint64_t(i + 1)).surface());
    EXPECT_EQ(m("ddsimp_surfaces"), kSurfaces);
    // Within the bound, the newest kept: what fits of 5 MiB, the rest evicted.
    EXPECT_LE(m("ddsimp_surface_bytes"), double(kBoundMiB * kMiB));
    EXPECT_EQ(m("ddsimp_surfaces_resident"), double(kBoundMiB * kMiB / surface_bytes));
    EXPECT_EQ(m("ddsimp_surface_evictions_total"),
              double(kSurfaces - kBoundMiB * kMiB / surface_bytes));
    EXPECT_EQ(m("ddsimp_surface_loads_total"), 0);
    // 67 MB stored; the peak may grow by the bound and one upload being received, decoded,
    // validated and written (four copies of a surface), never by what is stored.
    const size_t stored = size_t(kSurfaces) * surface_bytes;
    const size_t bound = kBoundMiB * kMiB + 4 * surface_bytes + kAllocatorSlack;
    if (kCheckable) {
        ASSERT_LT(bound, stored) << "the check would not notice every surface kept";
    }
    const size_t allowance = with_sanitizer_memory(bound);
    const size_t growth = server->status_bytes("VmHWM") - peak_before;
    EXPECT_LE(growth, allowance);
    RecordProperty("stored_kib", int(stored >> 10));
    RecordProperty("peak_growth_kib", int(growth >> 10));
    RecordProperty("allowance_kib", int(allowance >> 10));

    // The first surface was evicted long ago: read back, it is the same bytes.
    EXPECT_TRUE(same_bytes(whole_surface(c, ids[0], 100), first));
    EXPECT_GE(m("ddsimp_surface_loads_total"), 1);
    EXPECT_LE(m("ddsimp_surface_bytes"), double(kBoundMiB * kMiB));

    // After a restart: the index only, the same list (names, sizes, field ranges).
    c.send(v1::ListSurfaces{});
    const v1::SurfaceList before = c.expect<v1::SurfaceList>();
    server = std::make_unique<ServerProcess>(dir, flags);
    RawClient again(server->port);
    again.hello({});
    again.send(v1::ListSurfaces{});
    const v1::SurfaceList after = again.expect<v1::SurfaceList>();
    EXPECT_EQ(after.SerializeAsString(), before.SerializeAsString());
    EXPECT_EQ(m("ddsimp_surfaces"), kSurfaces);
    EXPECT_EQ(m("ddsimp_surfaces_resident"), 0);
    EXPECT_EQ(m("ddsimp_surface_bytes"), 0);
    const size_t at_rest = server->status_bytes("VmRSS");
    EXPECT_LT(at_rest, peak_before) << "the surfaces were read at start";
    RecordProperty("rss_kib_after_restart", int(at_rest >> 10));
    RecordProperty("hwm_kib_after_one_upload", int(peak_before >> 10));
    const Surface last = numbered_surface(kSurfaces - 1);
    EXPECT_TRUE(same_bytes(whole_surface(again, ids.back(), 101), last));
    EXPECT_GE(m("ddsimp_surface_loads_total"), 1);
    EXPECT_EQ(m("ddsimp_surfaces_resident"), 1);
}

// A small surface of its own for every i: 5,120 triangles, about 130 KB.
Surface small_numbered(int i) {
    Surface s = small_surface();
    for (float& x : s.positions) x *= 1.0f + 0.01f * float(i);
    return s;
}

// The UploadBegin of `s` (what upload_frames sends first).
std::string upload_begin_frame(const Surface& s, uint64_t id, const std::string& session = "") {
    return upload_frames(s, id, "test", session).front();
}

v1::SessionState join(RawClient& c, const std::string& name, const std::string& key) {
    v1::JoinSession j;
    j.set_name(name);
    j.set_key(key);
    c.send(j);
    return c.expect<v1::SessionState>();
}

// The error an upload gets instead of its result. `whole`: the bytes are sent too (a quota of
// stored surfaces refuses once they are known); otherwise UploadBegin alone (refused on it).
v1::Error refused_upload(RawClient& c, const Surface& s, uint64_t id,
                         const std::string& session = "", bool whole = true) {
    if (whole)
        for (const std::string& frame : upload_frames(s, id, "test", session)) c.send_bytes(frame);
    else
        c.send_bytes(upload_begin_frame(s, id, session));
    const v1::Error e = next_error(c);
    EXPECT_EQ(e.request_id(), id);
    EXPECT_EQ(e.code(), v1::Error::RESOURCE_EXHAUSTED) << e.message();
    return e;
}

// Every token (one per user, --tokens-file) and every session has its quota of stored surfaces
// and of uploads in progress: what passes it is refused on its UploadBegin with a message that
// says which quota, while the other users go on: uploads in progress on their UploadBegin, stored
// surfaces once the bytes are known. The quotas hold after a restart.
TEST(HostileStorage, QuotasPerTokenAndSessionRefuseWithAClearError) {
    const fs::path dir = temp_dir("quotas");
    fs::create_directories(dir);
    std::ofstream(dir / "tokens") << "# users\nalice a-secret\nbob b-secret\ncarol c-secret\n";
    const std::vector<std::string> flags{"--tokens-file",     (dir / "tokens").string(),
                                         "--quota-surfaces",  "2",
                                         "--quota-upload-mb", "1",
                                         "--sample",          ""};
    auto server = std::make_unique<ServerProcess>(dir / "data", flags);
    const auto m = [&](const std::string& name) { return metric(server->http_port, name); };

    RawClient alice(server->port), bob(server->port), carol(server->port);
    alice.hello({"sessions"}, "a-secret");
    bob.hello({"sessions"}, "b-secret");
    carol.hello({"sessions"}, "c-secret");
    join(alice, "lab", "k");
    join(bob, "lab", "k");

    // Alice's token: two surfaces (one public, one into the session), not three.
    alice.upload(small_numbered(1), 1);
    alice.upload(small_numbered(2), 2, "test", "lab");
    const v1::Error third = refused_upload(alice, small_numbered(3), 3);
    EXPECT_TRUE(says(third, "your token has 2 stored surfaces")) << third.message();
    EXPECT_TRUE(says(third, "--quota-surfaces")) << third.message();

    // The session holds Alice's surface and one of Bob's, not two of his.
    bob.upload(small_numbered(5), 5, "test", "lab");
    const v1::Error full = refused_upload(bob, small_numbered(6), 6, "lab");
    EXPECT_TRUE(says(full, "session \"lab\" has 2 stored surfaces")) << full.message();
    bob.upload(small_numbered(6), 7); // public: only his token counts

    // Uploads in progress: one of 1 MiB's worth, not two, for Carol; the others are not held up.
    const Surface medium = with_test_fields(icosphere(5)); // about 0.5 MiB
    carol.send_bytes(upload_begin_frame(medium, 1));
    const v1::Error second = refused_upload(carol, medium, 2, "", false);
    EXPECT_TRUE(says(second, "your token has 0.5 MiB of uploads in progress")) << second.message();
    EXPECT_TRUE(says(second, "--quota-upload-mb")) << second.message();
    EXPECT_EQ(m("ddsimp_upload_bytes"),
              double(protocol::encode_mesh(medium, v1::RAW).bytes.size()));
    EXPECT_EQ(m("ddsimp_quota_refusals_total"), 3);

    // After a restart every token's surfaces are still its own.
    server = std::make_unique<ServerProcess>(dir / "data", flags);
    RawClient again(server->port);
    again.hello({}, "a-secret");
    EXPECT_TRUE(says(refused_upload(again, small_numbered(9), 1), "your token has 2 stored"));
}

// An upload that receives no chunk for --upload-timeout expires, however often its client pings,
// and gives back what it reserved: the budget it held is another client's again.
TEST(HostileStorage, AnIdleUploadExpiresWhilePingsContinue) {
    ServerProcess server(temp_dir("idle-upload"),
                         {"--upload-timeout", "0.5", "--max-upload-mb", "1", "--sample", ""});
    const Surface medium = with_test_fields(icosphere(5)); // about 0.5 MiB: one fits, not two
    RawClient holder(server.port), other(server.port);
    holder.hello({});
    other.hello({});
    const std::vector<std::string> frames = upload_frames(medium, 1);
    holder.send_bytes(frames[0] + frames[1]); // UploadBegin and one chunk, then only pings

    const v1::Error busy = refused_upload(other, medium, 1, "", false);
    EXPECT_TRUE(says(busy, "for uploads in progress")) << busy.message();

    const auto start = std::chrono::steady_clock::now();
    std::optional<v1::Error> expired;
    size_t pongs = 0;
    for (uint64_t nonce = 1;
         !expired && std::chrono::steady_clock::now() - start < std::chrono::seconds(30); ++nonce) {
        v1::Ping ping;
        ping.set_nonce(nonce);
        holder.send(ping);
        for (;;) {
            const std::optional<protocol::Frame> f = holder.next();
            ASSERT_TRUE(f) << "closed while pinging";
            if (f->type == v1::ERROR) expired = protocol::parse_payload<v1::Error>(*f);
            if (f->type == v1::PONG) break;
        }
        if (!expired) ++pongs, std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    ASSERT_TRUE(expired) << "the upload never expired";
    EXPECT_GE(pongs, 3u); // it pinged all along
    EXPECT_EQ(expired->code(), v1::Error::CANCELLED);
    EXPECT_EQ(expired->request_id(), 1u);
    EXPECT_TRUE(says(*expired, "no chunk for 0.5 s (--upload-timeout)")) << expired->message();
    EXPECT_EQ(metric(server.http_port, "ddsimp_upload_bytes"), 0);
    // The other client's upload fits now; the expired one's chunks are refused.
    EXPECT_EQ(other.upload(medium, 2).triangles(), medium.triangle_count());
    holder.send_bytes(frames[2]);
    EXPECT_TRUE(says(next_error(holder), "was not begun"));
}

} // namespace
} // namespace ddsimp::test
