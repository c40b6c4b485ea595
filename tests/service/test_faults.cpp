// Faults around a real ddsimp-server: clients that vanish mid-upload and mid-stream, the server
// killed (SIGKILL) while uploads are being stored, a data directory it may not write and one that
// is full, and surfaces over the size limits. Acknowledged surfaces are never lost, a partial
// file is never loaded, every refusal is clear (to the client and in the log), and the server
// goes on serving.
#include "hostile_support.h"

#include "ddsimp/protocol/content_hash.h"

#include <fcntl.h>
#include <linux/capability.h>
#include <sys/resource.h>
#include <sys/stat.h>

#include <map>
#include <mutex>
#include <set>
#include <thread>

namespace ddsimp::test {
namespace {

namespace fs = std::filesystem;

std::string read_file(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

// Files of the data directory with an extension (".ddsurf", ".tmp").
size_t files_with(const fs::path& dir, const std::string& extension) {
    size_t n = 0;
    for (const auto& e : fs::directory_iterator(dir)) n += e.path().extension() == extension;
    return n;
}

// In the server's child process: its log (stderr) to a file.
std::function<void()> log_to(const fs::path& log) {
    return [log] {
        const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        ::dup2(fd, 2);
        ::close(fd);
    };
}

// A surface of its own for every i (the icosphere scaled), so no two are deduplicated.
Surface distinct_surface(int i, int level = 5) {
    Surface s = with_test_fields(icosphere(level));
    for (float& x : s.positions) x *= 1.0f + 0.01f * float(i);
    return s;
}

TEST(Faults, AClientVanishingMidUploadLeavesNothingBehind) {
    const fs::path dir = temp_dir("vanish-upload");
    ServerProcess server(dir / "data");
    WellBehavedClient good(server.port);
    const size_t stored = files_with(dir / "data", ".ddsurf");
    for (int i = 0; i < 5; ++i) {
        RawClient c(server.port);
        c.hello({});
        const std::vector<std::string> frames = upload_frames(distinct_surface(i), 1);
        for (size_t f = 0; f < frames.size() / 2; ++f) c.send_bytes(frames[f]);
        if (i % 2) c.send_bytes(frames[frames.size() / 2].substr(0, 1000)); // and mid-frame
    }                                                                       // gone
    good.check_level();
    EXPECT_EQ(await_metric(server.http_port, "ddsimp_connections", 1), 1);
    // Its bytes are given back and nothing of it is stored or listed.
    EXPECT_EQ(metric(server.http_port, "ddsimp_upload_bytes"), 0);
    EXPECT_EQ(files_with(dir / "data", ".ddsurf"), stored);
    EXPECT_EQ(files_with(dir / "data", ".tmp"), 0u);
    EXPECT_EQ(listed(good.raw()).size(), 2u); // the sample and the good client's
}

TEST(Faults, AClientVanishingMidStreamIsForgotten) {
    ServerProcess server(temp_dir("vanish-stream"));
    WellBehavedClient good(server.port);
    const std::string big = good.raw().upload(with_test_fields(icosphere(7)), 2).surface();
    for (int i = 0; i < 3; ++i) {
        RawClient c(server.port);
        c.hello({});
        c.send(level_request(big, {1.0f, 0.9f, 0.8f}, 1));
        ASSERT_TRUE(c.next()); // MeshBegin of the first level; then it goes
        good.check_level();
    }
    good.check_level();
    EXPECT_EQ(await_metric(server.http_port, "ddsimp_connections", 1), 1);
    EXPECT_EQ(await_metric(server.http_port, "ddsimp_queue_bytes", 0), 0);
    // The levels it did not take are still served to whoever asks.
    good.raw().send(level_request(big, {0.8f}, 50));
    EXPECT_EQ(good.raw().level().begin.total_triangles(),
              offline_level(with_test_fields(icosphere(7)), 0.3f, 0.8f).triangle_count());
}

// Three clients upload distinct surfaces until the server is killed. After a restart every
// surface it acknowledged is listed and serves levels; nothing unacknowledged or torn is loaded.
TEST(Faults, SigkillDuringUploadsLosesNoAcknowledgedSurface) {
    const fs::path dir = temp_dir("kill-upload");
    ServerProcess server(dir);
    std::mutex mutex;
    std::set<std::string> acknowledged;
    std::map<std::string, int> index_of; // id -> i of distinct_surface
    std::atomic<int> next = 0;
    std::vector<std::thread> uploaders;
    for (int t = 0; t < 3; ++t)
        uploaders.emplace_back([&] {
            try {
                RawClient c(server.port);
                c.hello({});
                for (;;) {
                    const int i = next++;
                    const std::string id = c.upload(distinct_surface(i, 6), uint64_t(i)).surface();
                    std::lock_guard lock(mutex);
                    acknowledged.insert(id);
                    index_of[id] = i;
                }
            } catch (const std::exception&) { // the server is gone
            }
        });
    for (;;) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        std::lock_guard lock(mutex);
        if (acknowledged.size() >= 6) break;
    }
    EXPECT_EQ(server.stop(SIGKILL), -SIGKILL);
    for (auto& t : uploaders) t.join();
    const std::set<std::string> before_restart = acknowledged;

    // A torn surface file (half of a real one, under its own name) must be skipped, not loaded.
    const fs::path some = dir / (*before_restart.begin() + ".ddsurf");
    const std::string bytes = read_file(some);
    const Surface torn_surface = distinct_surface(1000, 6);
    const std::string torn_id = protocol::surface_hash(torn_surface);
    {
        std::ofstream torn(dir / (torn_id + ".ddsurf"), std::ios::binary);
        torn << bytes.substr(0, bytes.size() / 2);
    }
    server.start();
    RawClient c(server.port);
    c.hello({});
    const std::set<std::string> ids = listed(c);
    for (const std::string& id : before_restart) EXPECT_TRUE(ids.count(id)) << id;
    EXPECT_FALSE(ids.count(torn_id));
    EXPECT_EQ(files_with(dir, ".tmp"), 0u); // an interrupted write is removed
    // Every file but the torn one is a surface it lists (the sample is in memory only).
    EXPECT_EQ(files_with(dir, ".ddsurf"), (ids.size() - 1) + 1);
    // An acknowledged surface serves levels equal to the offline result.
    const std::string id = *before_restart.rbegin();
    c.send(level_request(id, {0.2f}, 1));
    const RawClient::Level l = c.level();
    EXPECT_TRUE(same_bytes(protocol::decode_mesh(l.bytes, protocol::layout_of(l.begin)),
                           offline_level(distinct_surface(index_of[id], 6), 0.3f, 0.2f)));
}

// Runs the server without the privilege to ignore file permissions (root in CI has it), so a
// directory it may not write is one it cannot write.
void drop_file_permission_overrides() {
    for (int cap : {CAP_DAC_OVERRIDE, CAP_DAC_READ_SEARCH, CAP_FOWNER})
        ::prctl(PR_CAPBSET_DROP, cap, 0, 0, 0); // fails harmlessly when not root
}

TEST(Faults, AnUnwritableDataDirectoryIsAClearErrorAndTheServerGoesOn) {
    const fs::path dir = temp_dir("unwritable");
    const fs::path log = dir / "server.log";
    ServerProcess server(dir / "data", {}, [&] {
        drop_file_permission_overrides();
        log_to(log)();
    });
    RawClient c(server.port);
    c.hello({});
    fs::permissions(dir / "data", fs::perms::owner_read | fs::perms::owner_exec);
    const std::vector<std::string> frames = upload_frames(small_surface(), 1);
    for (const std::string& f : frames) c.send_bytes(f);
    const v1::Error e = next_error(c);
    EXPECT_EQ(e.code(), v1::Error::UNAVAILABLE);
    EXPECT_EQ(e.request_id(), 1u);
    EXPECT_NE(e.message().find("the server cannot store it: cannot create"), std::string::npos)
        << e.message();
    EXPECT_NE(e.message().find("Permission denied"), std::string::npos) << e.message();
    EXPECT_NE(read_file(log).find("cannot store an upload: cannot create"), std::string::npos)
        << read_file(log);

    // Writable again: the same connection stores the same surface.
    fs::permissions(dir / "data", fs::perms::owner_all);
    c.send(level_request("nothing", {0.5f}, 2)); // the connection is still open
    EXPECT_EQ(next_error(c).code(), v1::Error::NOT_FOUND);
    EXPECT_FALSE(c.upload(small_surface(), 3).surface().empty());
    EXPECT_EQ(files_with(dir / "data", ".ddsurf"), 1u);
}

// A full disk, as a file size limit on the server (ulimit -f): the write that would pass it
// fails (EFBIG) instead of killing the server, the upload gets UNAVAILABLE, no partial file is
// left, and smaller surfaces are still stored.
TEST(Faults, AFullDataDirectoryIsAClearErrorAndTheServerGoesOn) {
    const fs::path dir = temp_dir("full");
    const fs::path log = dir / "server.log";
    constexpr rlim_t kFileLimit = 2 * kMiB; // the small surface's file is ~0.2 MB, the big one ~8
    ServerProcess server(dir / "data", {}, [&] {
        const rlimit limit{kFileLimit, kFileLimit};
        ::setrlimit(RLIMIT_FSIZE, &limit);
        log_to(log)();
    });
    WellBehavedClient good(server.port);
    RawClient c(server.port);
    c.hello({});
    for (const std::string& f : upload_frames(with_test_fields(icosphere(7)), 1)) c.send_bytes(f);
    const v1::Error e = next_error(c);
    EXPECT_EQ(e.code(), v1::Error::UNAVAILABLE);
    EXPECT_NE(e.message().find("cannot write"), std::string::npos) << e.message();
    EXPECT_NE(e.message().find("File too large"), std::string::npos) << e.message();
    EXPECT_NE(read_file(log).find("cannot store an upload: cannot write"), std::string::npos)
        << read_file(log);
    EXPECT_TRUE(server.running());
    EXPECT_EQ(files_with(dir / "data", ".tmp"), 0u);
    EXPECT_EQ(files_with(dir / "data", ".ddsurf"), 1u); // the good client's only
    good.check_level();
    EXPECT_FALSE(c.upload(distinct_surface(3, 4), 2).surface().empty());
}

// Uploads over the limits are refused on their UploadBegin, before a byte is allocated for them:
// too many triangles, a blob larger than the largest surface (here 64 fields of 256 components on
// a surface within the triangle limit: 3.9 TB), too many fields, and a second upload that would
// overrun the budget while the first is in progress.
TEST(Faults, SurfacesOverTheLimitsAreRefusedBeforeTheyAreAllocated) {
    constexpr size_t kTriangles = 20'000'000, kBudgetMiB = 64;
    ServerProcess server(temp_dir("over-limit"),
                         {"--max-surface-triangles", std::to_string(kTriangles), "--max-upload-mb",
                          std::to_string(kBudgetMiB), "--max-surface-mb", "48"});
    WellBehavedClient good(server.port);
    const size_t baseline = server.status_bytes("VmHWM");
    RawClient c(server.port);
    c.hello({});
    const auto begin = [](uint64_t id, uint64_t vertices, uint64_t triangles, int fields,
                          uint32_t components) {
        v1::UploadBegin b;
        b.set_upload_id(id);
        b.set_vertex_count(vertices);
        b.set_triangle_count(triangles);
        uint64_t total = 12 * vertices + 12 * triangles;
        for (int f = 0; f < fields; ++f) {
            auto* info = b.add_fields();
            info->set_name("f" + std::to_string(f));
            info->set_components(components);
            total += 4ull * components * vertices;
        }
        b.set_total_bytes(total);
        return b;
    };
    const auto refusal = [&](const v1::UploadBegin& b) {
        c.send(b);
        const v1::Error e = next_error(c);
        EXPECT_EQ(e.request_id(), b.upload_id());
        return e;
    };
    v1::Error e = refusal(begin(1, kTriangles / 2, kTriangles + 1, 0, 1));
    EXPECT_EQ(e.code(), v1::Error::RESOURCE_EXHAUSTED);
    EXPECT_NE(e.message().find("20000001 triangles, over the server's limit of 20000000"),
              std::string::npos)
        << e.message();
    e = refusal(begin(2, 3 * kTriangles, kTriangles, 64, 256));
    EXPECT_EQ(e.code(), v1::Error::RESOURCE_EXHAUSTED);
    EXPECT_NE(e.message().find("over the server's largest surface of 48 MiB (--max-surface-mb)"),
              std::string::npos)
        << e.message();
    e = refusal(begin(3, 100, 100, 65, 1));
    EXPECT_EQ(e.code(), v1::Error::RESOURCE_EXHAUSTED);
    EXPECT_NE(e.message().find("65 fields (at most 64)"), std::string::npos) << e.message();

    // 40 MiB fits the budget; a second 40 MiB does not while the first is in progress.
    const uint64_t vertices = (40 * kMiB) / 24, triangles = vertices; // 12 + 12 bytes each
    c.send(begin(4, vertices, triangles, 0, 1));
    RawClient other(server.port);
    other.hello({});
    other.send(begin(5, vertices, triangles, 0, 1));
    e = next_error(other);
    EXPECT_EQ(e.code(), v1::Error::RESOURCE_EXHAUSTED);
    EXPECT_NE(e.message().find("do not fit in the server's 64 MiB for uploads in progress; try "
                               "again later"),
              std::string::npos)
        << e.message();
    EXPECT_EQ(metric(server.http_port, "ddsimp_upload_bytes"), double(24 * vertices));
    good.check_level();
    EXPECT_TRUE(server.running());
    // Announced, not sent: nothing of the 40 MiB is resident, let alone the 3.9 TB.
    EXPECT_LE(server.status_bytes("VmHWM"), baseline + with_sanitizer_memory(kAllocatorSlack));

    c.socket().close(); // the first upload's client goes: its budget is free again
    EXPECT_EQ(await_metric(server.http_port, "ddsimp_upload_bytes", 0), 0);
    other.send(begin(6, vertices, triangles, 0, 1));
    other.send(v1::ListSurfaces{}); // answered after the UploadBegin: so that was accepted
    EXPECT_EQ(other.expect<v1::SurfaceList>().surfaces_size(), 2);
    EXPECT_EQ(metric(server.http_port, "ddsimp_upload_bytes"), double(24 * vertices));
}

} // namespace
} // namespace ddsimp::test
