// Deleting stored surfaces against a real ddsimp-server: only a token that uploaded a surface
// deletes it; the quota, the data directory, the cached results and /metrics follow; a job that
// holds the surface finishes with it, even after giving its worker up. And a re-upload of stored
// bytes at quota is answered with the stored surface, charged to nobody again.
#include "hostile_support.h"

namespace ddsimp::test {
namespace {

namespace fs = std::filesystem;

// A small surface of its own for every i: 5,120 triangles.
Surface numbered(int i) {
    Surface s = small_surface();
    for (float& x : s.positions) x *= 1.0f + 0.01f * float(i);
    return s;
}

v1::DeleteSurface delete_message(const std::string& surface, uint64_t id) {
    v1::DeleteSurface d;
    d.set_delete_id(id);
    d.set_surface(surface);
    return d;
}

// An upload refused by a quota once its bytes are known (the whole upload is sent).
v1::Error refused_after_bytes(RawClient& c, const Surface& s, uint64_t id) {
    for (const std::string& frame : upload_frames(s, id)) c.send_bytes(frame);
    const v1::Error e = next_error(c);
    EXPECT_EQ(e.request_id(), id);
    EXPECT_EQ(e.code(), v1::Error::RESOURCE_EXHAUSTED) << e.message();
    return e;
}

struct Users {
    fs::path dir;
    std::vector<std::string> flags;
};

Users two_users(const std::string& name, const std::string& quota_surfaces) {
    Users u{temp_dir(name), {}};
    fs::create_directories(u.dir);
    std::ofstream(u.dir / "tokens") << "alice a-secret\nbob b-secret\n";
    u.flags = {"--tokens-file",    (u.dir / "tokens").string(),
               "--quota-surfaces", quota_surfaces,
               "--sample",         ""};
    return u;
}

// A full quota is freed by deleting: the upload refused before is stored after. The surface's
// files, its cached levels and its remembered keys go; /metrics counts it; after a restart it is
// still gone.
TEST(SurfaceDeletion, FreesTheQuotaAndIsGoneAfterARestart) {
    const Users users = two_users("delete-quota", "2");
    auto server = std::make_unique<ServerProcess>(users.dir / "data", users.flags);
    const auto m = [&](const std::string& name) { return metric(server->http_port, name); };
    RawClient alice(server->port);
    alice.hello({}, "a-secret");
    const std::string first = alice.upload(numbered(1), 1).surface();
    alice.upload(numbered(2), 2);
    // A level of the first, so that the cache holds some of it.
    alice.send(level_request(first, {0.5f}, 3));
    while (alice.level().begin.preview()) {
    }
    alice.expect<v1::RequestDone>();
    const double cached = m("ddsimp_cache_entries");
    EXPECT_GE(cached, 2); // its record and its level
    EXPECT_TRUE(says(refused_after_bytes(alice, numbered(3), 4), "--quota-surfaces"));

    alice.send(delete_message(first, 5));
    const v1::SurfaceDeleted deleted = alice.expect<v1::SurfaceDeleted>();
    EXPECT_EQ(deleted.delete_id(), 5u);
    EXPECT_EQ(deleted.surface(), first);
    EXPECT_TRUE(deleted.removed());
    EXPECT_FALSE(fs::exists(users.dir / "data" / (first + ".ddsurf")));
    EXPECT_FALSE(fs::exists(users.dir / "data" / (first + ".scopes")));
    EXPECT_EQ(m("ddsimp_surfaces"), 1);
    EXPECT_EQ(m("ddsimp_surfaces_deleted_total"), 1);
    EXPECT_LE(m("ddsimp_cache_entries"), cached - 2);
    EXPECT_EQ(m("ddsimp_remembered_results"), 0);
    EXPECT_EQ(listed(alice).count(first), 0u);

    const std::string third = alice.upload(numbered(3), 6).surface();
    EXPECT_EQ(m("ddsimp_surfaces"), 2);

    // Its levels are gone with it, from the cache too.
    alice.send(level_request(first, {0.5f}, 7));
    EXPECT_EQ(next_error(alice).code(), v1::Error::NOT_FOUND);
    // A second delete finds nothing.
    alice.send(delete_message(first, 8));
    const v1::Error again = next_error(alice);
    EXPECT_EQ(again.code(), v1::Error::NOT_FOUND);
    EXPECT_EQ(again.request_id(), 8u);

    server = std::make_unique<ServerProcess>(users.dir / "data", users.flags);
    RawClient later(server->port);
    later.hello({}, "a-secret");
    const std::set<std::string> ids = listed(later);
    EXPECT_EQ(ids.count(first), 0u);
    EXPECT_EQ(ids.count(third), 1u);
    EXPECT_EQ(ids.size(), 2u);
    // The quota after the restart: two stored, so a new one is refused, and one delete frees it.
    EXPECT_TRUE(says(refused_after_bytes(later, numbered(4), 1), "--quota-surfaces"));
    later.send(delete_message(third, 2));
    EXPECT_TRUE(later.expect<v1::SurfaceDeleted>().removed());
    later.upload(numbered(4), 3);
}

// Deleting a surface another token uploaded is refused with an error that says why; a surface the
// client does not see is NOT_FOUND, the same answer as an unknown id; the sample stays.
TEST(SurfaceDeletion, AnotherTokensSurfaceIsRefused) {
    Users users = two_users("delete-refused", "10");
    users.flags.pop_back(), users.flags.pop_back(); // the built-in sample
    ServerProcess server(users.dir / "data", users.flags);
    RawClient alice(server.port), bob(server.port);
    alice.hello({"sessions"}, "a-secret");
    bob.hello({"sessions"}, "b-secret");
    const std::string hers = alice.upload(numbered(1), 1).surface();
    v1::JoinSession j;
    j.set_name("private");
    j.set_key("k");
    alice.send(j);
    alice.expect<v1::SessionState>();
    const std::string hidden = alice.upload(numbered(2), 2, "test", "private").surface();

    bob.send(delete_message(hers, 1));
    const v1::Error refused = next_error(bob);
    EXPECT_EQ(refused.code(), v1::Error::PERMISSION_DENIED);
    EXPECT_EQ(refused.request_id(), 1u);
    EXPECT_TRUE(says(refused, "was not uploaded with your token")) << refused.message();
    bob.send(delete_message(hidden, 2));
    const v1::Error unseen = next_error(bob);
    EXPECT_EQ(unseen.code(), v1::Error::NOT_FOUND);
    bob.send(delete_message(std::string(64, 'a'), 3));
    EXPECT_EQ(next_error(bob).message(), "no surface " + std::string(64, 'a'));
    EXPECT_EQ(unseen.message(), "no surface " + hidden);

    const std::set<std::string> seen = listed(bob);
    ASSERT_EQ(seen.size(), 2u); // hers and the sample
    for (const std::string& id : seen) {
        if (id == hers) continue;
        alice.send(delete_message(id, 9));
        const v1::Error sample = next_error(alice);
        EXPECT_EQ(sample.code(), v1::Error::PERMISSION_DENIED);
        EXPECT_TRUE(says(sample, "built-in sample")) << sample.message();
    }
    EXPECT_EQ(metric(server.http_port, "ddsimp_surfaces"), 3);
    EXPECT_EQ(metric(server.http_port, "ddsimp_surfaces_deleted_total"), 0);
    // Hers to delete: both of them.
    alice.send(delete_message(hidden, 10));
    EXPECT_TRUE(alice.expect<v1::SurfaceDeleted>().removed());
    alice.send(delete_message(hers, 11));
    EXPECT_TRUE(alice.expect<v1::SurfaceDeleted>().removed());
    EXPECT_EQ(listed(bob).size(), 1u);
}

// A server with two workers and a surface whose runs last, uploaded by `owner`; `deleter` is
// another client of the same user (a server without tokens has one).
struct LargeUpload {
    explicit LargeUpload(const std::string& name)
        : server(temp_dir(name), {"--threads", "2", "--sample", ""}), owner(server.port),
          deleter(server.port) {
        owner.hello({});
        deleter.hello({});
        id = owner.upload(big, 1).surface();
    }
    ServerProcess server;
    const Surface big = with_test_fields(icosphere(7)); // 327,680 triangles
    RawClient owner, deleter;
    std::string id;
};

// A surface deleted while a job computes on it stays valid for that job: its levels arrive, the
// same as the library makes them; the next request for it is NOT_FOUND.
TEST(SurfaceDeletion, ARunningJobKeepsItsSurface) {
    LargeUpload u("delete-running");
    auto& [server, big, owner, deleter, id] = u;
    owner.send(level_request(id, {0.05f}, 2));
    // The job has its surface once its run counts.
    ASSERT_EQ(await_metric(server.http_port, "ddsimp_reductions_running", 1), 1);
    deleter.send(delete_message(id, 1)); // one user: any client of a server without tokens
    EXPECT_TRUE(deleter.expect<v1::SurfaceDeleted>().removed());
    RawClient::Level level = owner.level();
    while (level.begin.preview()) level = owner.level();
    EXPECT_EQ(owner.expect<v1::RequestDone>().request_id(), 2u);
    EXPECT_TRUE(same_bytes(protocol::decode_mesh(level.bytes, protocol::layout_of(level.begin)),
                           offline_level(big, 0.3f, 0.05f)));
    owner.send(level_request(id, {0.5f}, 3));
    EXPECT_EQ(next_error(owner).code(), v1::Error::NOT_FOUND);
}

// A job that gave its worker to another client's job runs again with the surface it had loaded,
// though the surface was deleted in between: the delete itself takes the worker of the newer of
// the owner's two running jobs.
TEST(SurfaceDeletion, AJobThatYieldedKeepsItsSurface) {
    LargeUpload u("delete-yielded");
    auto& [server, big, owner, deleter, id] = u;
    const std::map<uint64_t, float> alpha{{2, 0.2f}, {3, 0.7f}};
    for (const auto& [request, a] : alpha) owner.send(level_request(id, {0.05f}, request, a));
    ASSERT_EQ(await_metric(server.http_port, "ddsimp_reductions_running", 2), 2);
    deleter.send(delete_message(id, 1));
    EXPECT_TRUE(deleter.expect<v1::SurfaceDeleted>().removed());
    for (int i = 0; i < 2; ++i) {
        const RawClient::Level level = owner.level();
        const uint64_t request = level.begin.request_id();
        ASSERT_TRUE(alpha.count(request)) << request;
        EXPECT_TRUE(same_bytes(protocol::decode_mesh(level.bytes, protocol::layout_of(level.begin)),
                               offline_level(big, alpha.at(request), 0.05f)))
            << "request " << request;
    }
    EXPECT_EQ(metric(server.http_port, "ddsimp_reductions_yielded_total"), 1);
}

// At its quota, a token's re-upload of bytes already stored where it goes is answered with the
// stored surface (already_stored) and counts nothing twice; new bytes are refused once known.
TEST(HostileStorage, ReuploadingStoredBytesAtTheQuotaGetsTheStoredSurface) {
    const Users users = two_users("reupload-at-quota", "2");
    ServerProcess server(users.dir / "data", users.flags);
    const auto m = [&](const std::string& name) { return metric(server.http_port, name); };
    RawClient alice(server.port), bob(server.port);
    alice.hello({}, "a-secret");
    bob.hello({}, "b-secret");
    const v1::UploadResult first = alice.upload(numbered(1), 1);
    alice.upload(numbered(2), 2);

    const v1::UploadResult again = alice.upload(numbered(1), 3);
    EXPECT_EQ(again.surface(), first.surface());
    EXPECT_TRUE(again.already_stored());
    EXPECT_EQ(m("ddsimp_surfaces"), 2);
    EXPECT_EQ(m("ddsimp_quota_refusals_total"), 0);
    const v1::Error fresh = refused_after_bytes(alice, numbered(3), 4);
    EXPECT_TRUE(says(fresh, "your token has 2 stored surfaces")) << fresh.message();
    EXPECT_EQ(m("ddsimp_quota_refusals_total"), 1);
    EXPECT_EQ(m("ddsimp_upload_bytes"), 0);

    // Another token at its quota gets the public surface it uploads too, without owning it.
    bob.upload(numbered(5), 1);
    bob.upload(numbered(6), 2);
    const v1::UploadResult shared = bob.upload(numbered(1), 3);
    EXPECT_EQ(shared.surface(), first.surface());
    EXPECT_TRUE(shared.already_stored());
    bob.send(delete_message(first.surface(), 4));
    EXPECT_EQ(next_error(bob).code(), v1::Error::PERMISSION_DENIED);
    EXPECT_EQ(m("ddsimp_surfaces"), 4);
}

} // namespace
} // namespace ddsimp::test
