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

// 32 surfaces of 2.1 MB into a server that keeps 5 MiB of them: the others are evicted (the least
// recently used first) and read back from the data directory when a request needs them, with the
// same bytes; the server's memory does not grow with what it stores. After a restart nothing but
// the index is in memory, and the lists say what they said before.
TEST(HostileStorage, SurfacesBeyondTheMemoryBoundAreReadBackWhenNeeded) {
    constexpr int kSurfaces = 32;
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
    const size_t allowance =
        with_sanitizer_memory(kBoundMiB * kMiB + 4 * surface_bytes + kAllocatorSlack);
    ASSERT_LT(allowance, stored) << "the check would not notice every surface kept";
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

} // namespace
} // namespace ddsimp::test
