// ddsimp-server on loopback, driven frame by frame: round trips equal the offline library
// exactly, levels come in the documented order, uploads and computations are deduplicated, sessions
// broadcast and hand over the lead, bad frames and wrong tokens end only their connection,
// acknowledged surfaces survive a restart and a SIGKILL, slow readers are dropped.
#include "server_harness.h"

#include "ddsimp/protocol/content_hash.h"
#include "ddsimp/protocol/reduction_options.h"
#include "ddsimp/protocol/refinement.h"
#include "mesh_comparison.h"
#include "test_surfaces.h"

#include <fstream>
#include <regex>

namespace ddsimp::test {
namespace {

Surface test_surface() {
    return with_test_fields(icosphere(4));
} // 5120 triangles

v1::Request request_for(const std::string& surface, std::vector<float> keeps, uint64_t id,
                        v1::Encoding encoding = v1::RAW) {
    v1::Request r;
    r.set_request_id(id);
    r.set_surface(surface);
    r.set_alpha(0.3f);
    for (float k : keeps) r.add_keep(k);
    r.set_encoding(encoding);
    return r;
}

// The offline result for a keep fraction, as `ddsimp simplify --keep` computes it.
Surface offline(const Surface& in, float alpha, float keep, Strategy strategy) {
    Options o; // the library's defaults for what a request leaves unset, as the server's
    o.alpha = protocol::from_wire(alpha); // the request's floats, read as the server reads them
    o.strategy = strategy;
    o.keep_fraction = protocol::from_wire(keep);
    return simplify(in, o).surface;
}

class Server : public ::testing::Test {
protected:
    void SetUp() override { server_ = std::make_unique<ServerProcess>(temp_dir(test_name())); }
    static std::string test_name() {
        return ::testing::UnitTest::GetInstance()->current_test_info()->name();
    }
    std::unique_ptr<ServerProcess> server_;
};

TEST_F(Server, WelcomesAndListsItsSample) {
    RawClient c(server_->port);
    const v1::Welcome w = c.hello({"meshopt-codec", "unknown-capability"});
    EXPECT_EQ(w.protocol_version(), 1u);
    EXPECT_FALSE(w.auth_required());
    ASSERT_EQ(w.capabilities_size(), 1); // the intersection
    EXPECT_EQ(w.capabilities(0), "meshopt-codec");
    c.send(v1::ListSurfaces{});
    const v1::SurfaceList list = c.expect<v1::SurfaceList>();
    ASSERT_EQ(list.surfaces_size(), 1);
    EXPECT_EQ(list.surfaces(0).triangles(), 756u); // data/SurfaceVectors.vtk
    EXPECT_EQ(list.surfaces(0).fields_size(), 7);
}

// Without --sample the server starts with the sample it ships (data/Carotid.ddsurf.tar.xz,
// unpacked by the build): a real 3-D surface of at least 200 k triangles with its vector field,
// listed at start and served.
TEST(BuiltInSample, IsARealSurfaceWithDataListedAtStart) {
    ServerProcess server(temp_dir("built-in-sample"), {"--sample", kBuiltInSample});
    RawClient c(server.port);
    c.hello();
    c.send(v1::ListSurfaces{});
    const v1::SurfaceList list = c.expect<v1::SurfaceList>();
    ASSERT_EQ(list.surfaces_size(), 1);
    const v1::SurfaceInfo& sample = list.surfaces(0);
    EXPECT_NE(sample.name().find("Carotid"), std::string::npos) << sample.name();
    EXPECT_GE(sample.triangles(), 200000u);
    ASSERT_EQ(sample.fields_size(), 1);
    EXPECT_EQ(sample.fields(0).name(), "vectors"); // the blood velocity
    EXPECT_EQ(sample.fields(0).components(), 3u);
    EXPECT_LT(sample.fields(0).min(), sample.fields(0).max());

    // A coarse level of it is served, with its field.
    c.send(request_for(sample.surface(), {0.01f}, 1));
    const RawClient::Level level = c.level();
    EXPECT_LE(level.begin.total_triangles(), sample.triangles() / 100);
    EXPECT_GT(level.begin.total_triangles(), sample.triangles() / 200);
    EXPECT_EQ(level.begin.fields_size(), 1);
}

TEST_F(Server, UploadIsContentAddressedAndStoredOnce) {
    RawClient c(server_->port);
    c.hello();
    const Surface s = test_surface();
    const v1::UploadResult first = c.upload(s, 1);
    Surface validated = s;
    validate(validated);
    EXPECT_EQ(first.surface(), protocol::surface_hash(validated));
    EXPECT_EQ(first.triangles(), s.triangle_count());
    EXPECT_FALSE(first.already_stored());
    const v1::UploadResult second = c.upload(s, 2);
    EXPECT_EQ(second.surface(), first.surface());
    EXPECT_TRUE(second.already_stored());
}

// Every level equals the offline library's result byte for byte, in both encodings. Not cached,
// the finest level comes first (as soon as a run has passed it), then the others; cached, the
// coarsest comes first whatever order the request lists them in.
TEST_F(Server, LevelsEqualTheOfflineResultCoarsestFirst) {
    RawClient c(server_->port);
    c.hello();
    const Surface s = test_surface();
    const std::string id = c.upload(s, 1).surface();
    for (v1::Encoding encoding : {v1::RAW, v1::MESHOPT}) {
        const uint64_t rid = encoding == v1::RAW ? 10 : 11;
        c.send(request_for(id, {0.5f, 0.1f, 0.25f}, rid, encoding));
        std::vector<float> order;
        for (int i = 0; i < 3; ++i) {
            const RawClient::Level l = c.level();
            EXPECT_EQ(l.begin.request_id(), rid);
            EXPECT_EQ(l.begin.surface(), id);
            EXPECT_EQ(l.begin.encoding(), encoding);
            EXPECT_EQ(l.bytes.size(), l.begin.total_bytes());
            order.push_back(l.begin.keep());
            Surface got = protocol::decode_mesh(l.bytes, protocol::layout_of(l.begin));
            const Surface expected = offline(s, 0.3f, l.begin.keep(), Strategy::EdgeCollapse);
            // meshopt's index codec may start a triangle at another corner (same orientation).
            if (encoding == v1::MESHOPT) rotate_to_match(got, expected);
            EXPECT_TRUE(same_bytes(got, expected)) << "keep " << l.begin.keep();
        }
        EXPECT_EQ(order, encoding == v1::RAW ? (std::vector<float>{0.5f, 0.1f, 0.25f})
                                             : (std::vector<float>{0.1f, 0.25f, 0.5f}));
        EXPECT_EQ(c.expect<v1::RequestDone>().request_id(), rid);
    }
}

// Progressive: the coarsest level whole, then refinements; applied, each equals the level.
TEST_F(Server, ProgressiveRefinementsRebuildEveryLevel) {
    RawClient c(server_->port);
    c.hello();
    const Surface s = test_surface();
    const std::string id = c.upload(s, 1).surface();
    v1::Request r = request_for(id, {1.0f, 0.05f, 0.3f}, 5, v1::MESHOPT);
    r.set_strategy(v1::VERTEX_REMOVAL);
    r.set_progressive(true);
    c.send(r);
    std::optional<protocol::SlotMesh> mesh;
    for (float keep : {0.05f, 0.3f, 1.0f}) {
        const RawClient::Level l = c.level();
        EXPECT_EQ(l.begin.keep(), keep);
        if (!mesh) {
            EXPECT_EQ(l.begin.kind(), v1::MeshBegin::FULL);
            mesh.emplace(protocol::decode_mesh(l.bytes, protocol::layout_of(l.begin)));
        } else {
            EXPECT_EQ(l.begin.kind(), v1::MeshBegin::REFINEMENT);
            mesh->apply(protocol::decode_refinement(l.bytes, protocol::layout_of(l.begin)));
        }
        const Surface expected = offline(s, 0.3f, keep, Strategy::VertexRemoval);
        EXPECT_EQ(mesh->live_triangles(), expected.triangle_count()) << keep;
        EXPECT_EQ(l.begin.total_triangles(), expected.triangle_count()) << keep;
    }
}

// The library's record for (surface, alpha, options) as the server computes it.
ProgressiveRecord offline_record(const Surface& in, float alpha, Strategy strategy,
                                 Placement placement) {
    Options o;
    o.alpha = protocol::from_wire(alpha);
    o.strategy = strategy;
    o.placement = placement;
    o.keep_fraction = 0;
    return ProgressiveRecord::build(in, o);
}

// The error the library records for the level a keep fraction asks for.
LevelError offline_error(const ProgressiveRecord& rec, float keep) {
    return rec.error_after(rec.operations_for(protocol::target_for_keep(keep, rec.triangles_in())));
}

void expect_error(const v1::MeshBegin& begin, const LevelError& expected) {
    ASSERT_TRUE(begin.has_error()) << "keep " << begin.keep();
    EXPECT_EQ(begin.error().geometric(), expected.geometric) << "keep " << begin.keep();
    EXPECT_EQ(begin.error().data(), expected.data) << "keep " << begin.keep();
    EXPECT_EQ(begin.error().data_components(), expected.data_components);
}

// Every level carries the library's error for that level, whole or as a refinement, and
// PLACEMENT LEAST_ERROR asks for the library's least-error point (a result of its own).
TEST_F(Server, LevelsCarryTheLibrarysErrorAndLeastErrorPlacement) {
    RawClient c(server_->port);
    c.hello();
    const Surface s = test_surface();
    const std::string id = c.upload(s, 1).surface();
    const ProgressiveRecord least =
        offline_record(s, 0.3f, Strategy::EdgeCollapse, Placement::LeastError);
    std::string least_key;
    for (bool progressive : {false, true}) {
        v1::Request r = request_for(id, {0.5f, 0.05f, 0.2f}, progressive ? 21 : 20);
        r.set_placement(v1::LEAST_ERROR);
        r.set_progressive(progressive);
        c.send(r);
        std::map<float, float> geometric;
        // Not cached (the first request): the finest first; progressive: coarsest first.
        for (float keep : progressive ? std::vector<float>{0.05f, 0.2f, 0.5f}
                                      : std::vector<float>{0.5f, 0.05f, 0.2f}) {
            const RawClient::Level l = c.level();
            ASSERT_EQ(l.begin.keep(), keep);
            expect_error(l.begin, offline_error(least, keep));
            geometric[keep] = l.begin.error().geometric();
            least_key = l.begin.result();
            if (progressive) continue;
            Surface got = protocol::decode_mesh(l.bytes, protocol::layout_of(l.begin));
            Options o;
            o.alpha = protocol::from_wire(0.3f);
            o.placement = Placement::LeastError;
            o.keep_fraction = protocol::from_wire(keep);
            EXPECT_TRUE(same_bytes(got, simplify(s, o).surface)) << "keep " << keep;
        }
        // Finer levels, no larger errors.
        EXPECT_LE(geometric[0.5f], geometric[0.2f]);
        EXPECT_LE(geometric[0.2f], geometric[0.05f]);
        EXPECT_GT(geometric[0.5f], 0.0f);
        c.expect<v1::RequestDone>();
    }
    // The default placement is the library's (least error): the same result.
    c.send(request_for(id, {0.05f}, 23));
    EXPECT_EQ(c.level().begin.result(), least_key);
    c.expect<v1::RequestDone>();
    // The midpoint is a different result with its own errors.
    v1::Request midpoint = request_for(id, {0.05f}, 22);
    midpoint.set_placement(v1::MIDPOINT);
    c.send(midpoint);
    const RawClient::Level l = c.level();
    EXPECT_NE(l.begin.result(), least_key);
    expect_error(
        l.begin,
        offline_error(offline_record(s, 0.3f, Strategy::EdgeCollapse, Placement::Midpoint), 0.05f));
    c.expect<v1::RequestDone>();

    // A session's mesh carries its error too, and the view's placement.
    v1::JoinSession join;
    join.set_name("errors");
    c.send(join);
    c.expect<v1::SessionState>();
    v1::SetSessionState set;
    set.set_name("errors");
    set.mutable_view()->set_surface(id);
    set.mutable_view()->set_keep(0.2f);
    set.mutable_view()->set_alpha(0.3f);
    set.mutable_view()->set_placement(v1::LEAST_ERROR);
    set.set_set_alpha(true);
    c.send(set);
    EXPECT_EQ(c.expect<v1::SessionState>().view().placement(), v1::LEAST_ERROR);
    const RawClient::Level shown = c.level();
    EXPECT_EQ(shown.begin.session(), "errors");
    expect_error(shown.begin, offline_error(least, 0.2f));
}

// Four clients ask for the same reduction at once: one computation of the record.
TEST_F(Server, IdenticalConcurrentRequestsComputeOnce) {
    const Surface s = with_test_fields(icosphere(6)); // 81920 triangles: a run worth sharing
    std::string id;
    {
        RawClient up(server_->port);
        up.hello();
        id = up.upload(s, 1).surface();
    }
    const double before = metric(server_->http_port, "ddsimp_computations_total");
    std::vector<std::unique_ptr<RawClient>> clients;
    for (int i = 0; i < 4; ++i) {
        clients.push_back(std::make_unique<RawClient>(server_->port));
        clients.back()->hello();
    }
    for (auto& c : clients) c->send(request_for(id, {0.2f}, 1));
    std::vector<std::string> blobs;
    for (auto& c : clients) blobs.push_back(c->level().bytes);
    for (const std::string& b : blobs) EXPECT_EQ(b, blobs[0]);
    // One record and one level computed, whoever asked first.
    EXPECT_EQ(metric(server_->http_port, "ddsimp_computations_total") - before, 2);
}

TEST_F(Server, BadRequestsEndOnlyThemselves) {
    RawClient c(server_->port);
    c.hello();
    c.send(request_for("no-such-surface", {0.5f}, 3));
    const v1::Error e = c.expect<v1::Error>();
    EXPECT_EQ(e.code(), v1::Error::NOT_FOUND);
    EXPECT_EQ(e.request_id(), 3u);
    c.send(request_for("x", {1.5f}, 4));
    EXPECT_EQ(c.expect<v1::Error>().code(), v1::Error::INVALID_ARGUMENT);
    // A surface the library rejects (an index out of range) is BAD_SURFACE with its reason.
    Surface bad = single_triangle();
    bad.triangles[2] = 7;
    bad.positions.resize(3 * 8, 0.f);
    bad.triangles.push_back(0), bad.triangles.push_back(0), bad.triangles.push_back(9);
    v1::UploadBegin b;
    try {
        c.upload(bad, 9);
        ADD_FAILURE() << "a bad surface was accepted";
    } catch (const std::runtime_error& err) {
        EXPECT_NE(std::string(err.what()).find("refers to vertex 9"), std::string::npos)
            << err.what();
    }
    // The connection still works.
    c.send(v1::ListSurfaces{});
    EXPECT_EQ(c.expect<v1::SurfaceList>().surfaces_size(), 1);
}

TEST_F(Server, MalformedAndOversizedFramesCloseOnlyThatConnection) {
    RawClient other(server_->port);
    other.hello();
    {
        RawClient garbage(server_->port);
        garbage.send_bytes("GET / HTTP/1.1\r\n\r\n");
        auto f = garbage.next();
        ASSERT_TRUE(f);
        const v1::Error e = protocol::parse_payload<v1::Error>(*f);
        EXPECT_EQ(e.code(), v1::Error::BAD_FRAME);
        EXPECT_NE(e.message().find("not a ddsimp frame"), std::string::npos);
        EXPECT_TRUE(garbage.closed_by_server());
    }
    {
        RawClient huge(server_->port);
        huge.hello();
        unsigned char h[protocol::kHeaderBytes];
        protocol::write_header(h, v1::UPLOAD_CHUNK, 0xfffffff0u);
        huge.send_bytes(std::string(reinterpret_cast<char*>(h), sizeof h));
        const v1::Error e = huge.expect<v1::Error>();
        EXPECT_EQ(e.code(), v1::Error::BAD_FRAME);
        EXPECT_NE(e.message().find("over the limit"), std::string::npos);
        EXPECT_TRUE(huge.closed_by_server());
    }
    {
        RawClient truncated(server_->port);
        truncated.hello();
        v1::Ping p;
        p.set_nonce(1);
        const std::string frame = protocol::encode_frame(p);
        truncated.send_bytes(frame.substr(0, frame.size() - 1));
    } // closes mid-frame
    {
        RawClient unparsable(server_->port);
        unparsable.hello();
        unsigned char h[protocol::kHeaderBytes];
        protocol::write_header(h, v1::REQUEST, 4);
        unparsable.send_bytes(std::string(reinterpret_cast<char*>(h), sizeof h) +
                              "\xff\xff\xff\xff");
        EXPECT_EQ(unparsable.expect<v1::Error>().code(), v1::Error::BAD_FRAME);
    }
    v1::Ping p;
    p.set_nonce(77);
    other.send(p);
    EXPECT_EQ(other.expect<v1::Pong>().nonce(), 77u);
    EXPECT_GE(metric(server_->http_port, "ddsimp_bad_frames_total"), 3);
}

TEST(ServerAuth, WrongOrMissingTokenIsRefused) {
    ServerProcess server(temp_dir("auth"), {"--token", "s3cret"});
    {
        RawClient c(server.port);
        EXPECT_TRUE(c.hello({}, "s3cret").auth_required());
        c.send(v1::ListSurfaces{});
        EXPECT_EQ(c.expect<v1::SurfaceList>().surfaces_size(), 1);
    }
    {
        RawClient c(server.port);
        v1::Hello h;
        h.set_protocol_version(1);
        c.send(h);
        EXPECT_TRUE(c.expect<v1::Welcome>().auth_required());
        v1::Auth a;
        a.set_token("guess");
        c.send(a);
        const v1::Error e = c.expect<v1::Error>();
        EXPECT_EQ(e.code(), v1::Error::UNAUTHENTICATED);
        EXPECT_TRUE(c.closed_by_server());
    }
    {
        RawClient c(server.port);
        v1::Hello h;
        h.set_protocol_version(1);
        c.send(h);
        c.expect<v1::Welcome>();
        c.send(v1::ListSurfaces{}); // skipping Auth
        EXPECT_EQ(c.expect<v1::Error>().code(), v1::Error::UNAUTHENTICATED);
        EXPECT_TRUE(c.closed_by_server());
    }
}

// Acknowledged surfaces survive a clean restart and a SIGKILL; a leftover temporary file (a
// write the crash interrupted) is never loaded.
TEST(ServerRestart, AcknowledgedSurfacesSurviveRestartAndKill) {
    const auto dir = temp_dir("restart");
    ServerProcess server(dir);
    std::string a, b;
    {
        RawClient c(server.port);
        c.hello();
        a = c.upload(test_surface(), 1).surface();
    }
    EXPECT_EQ(server.stop(SIGTERM), 0);
    server.start();
    {
        RawClient c(server.port);
        c.hello();
        b = c.upload(with_test_fields(torus(24, 12)), 2).surface();
    }
    EXPECT_EQ(server.stop(SIGKILL), -SIGKILL);
    {
        std::ofstream partial(dir / "0000.ddsurf.tmp");
        partial << "DDSURF1\n half a file";
    }
    server.start();
    RawClient c(server.port);
    c.hello();
    c.send(v1::ListSurfaces{});
    std::set<std::string> ids;
    const v1::SurfaceList list = c.expect<v1::SurfaceList>();
    for (const auto& s : list.surfaces()) ids.insert(s.surface());
    EXPECT_TRUE(ids.count(a));
    EXPECT_TRUE(ids.count(b));
    EXPECT_EQ(ids.size(), 3u); // and the sample
    EXPECT_FALSE(std::filesystem::exists(dir / "0000.ddsurf.tmp"));
}

TEST_F(Server, HealthAndMetrics) {
    EXPECT_EQ(http_get(server_->http_port, "/healthz").rfind("HTTP/1.1 200", 0), 0u);
    RawClient c(server_->port);
    c.hello();
    const std::string text = http_get(server_->http_port, "/metrics");
    for (const char* name :
         {"ddsimp_connections 1", "ddsimp_sessions 0", "ddsimp_requests_total",
          "ddsimp_cache_hits_total", "ddsimp_cache_misses_total", "ddsimp_cache_bytes",
          "ddsimp_queue_bytes", "ddsimp_job_latency_seconds_bucket"})
        EXPECT_NE(text.find(name), std::string::npos) << name;
    EXPECT_NE(http_get(server_->http_port, "/../etc/passwd").find("404"), std::string::npos);
}

v1::SessionState next_state(RawClient& c) {
    return c.expect<v1::SessionState>();
}

// Two members: the leader's change reaches both with the new mesh; when the leader leaves the
// other leads; a late joiner gets the current state and mesh.
TEST_F(Server, SessionsBroadcastHandOverAndCatchUpLateJoiners) {
    auto a = std::make_unique<RawClient>(server_->port);
    RawClient b(server_->port);
    const uint64_t a_id = a->hello().client_id();
    const uint64_t b_id = b.hello().client_id();
    const Surface s = test_surface();
    const std::string id = a->upload(s, 1).surface();

    v1::JoinSession join;
    join.set_name("lab");
    a->send(join);
    EXPECT_EQ(next_state(*a).cause(), "created");
    b.send(join);
    EXPECT_EQ(next_state(*a).cause(), "joined");
    const v1::SessionState joined = next_state(b);
    EXPECT_EQ(joined.members_size(), 2);
    EXPECT_EQ(joined.leader(), a_id);

    v1::SetSessionState set;
    set.set_name("lab");
    set.mutable_view()->set_surface(id);
    set.mutable_view()->set_keep(0.2f);
    set.mutable_view()->set_alpha(0.3f);
    set.set_set_alpha(true);
    a->send(set);
    for (RawClient* c : {a.get(), &b}) {
        const v1::SessionState st = next_state(*c);
        EXPECT_EQ(st.cause(), "view");
        EXPECT_EQ(st.view().surface(), id);
        const RawClient::Level l = c->level();
        EXPECT_EQ(l.begin.session(), "lab");
        EXPECT_EQ(l.begin.surface(), id);
        Surface got = protocol::decode_mesh(l.bytes, protocol::layout_of(l.begin));
        const Surface expected = offline(s, 0.3f, 0.2f, Strategy::EdgeCollapse);
        rotate_to_match(got, expected); // both clients asked for the meshopt codec
        EXPECT_TRUE(same_bytes(got, expected));
    }

    a.reset(); // the leader disconnects
    const v1::SessionState handed = next_state(b);
    EXPECT_EQ(handed.cause(), "leader-left");
    EXPECT_EQ(handed.leader(), b_id);
    EXPECT_EQ(handed.members_size(), 1);

    RawClient late(server_->port);
    late.hello();
    late.send(join);
    const v1::SessionState st = next_state(late);
    EXPECT_EQ(st.view().surface(), id);
    EXPECT_EQ(st.view().keep(), 0.2f);
    EXPECT_EQ(late.level().begin.total_triangles(),
              offline(s, 0.3f, 0.2f, Strategy::EdgeCollapse).triangle_count());

    // A client outside the session cannot steer it, and learns nothing about it.
    RawClient outsider(server_->port);
    outsider.hello();
    outsider.send(set);
    const v1::Error e = outsider.expect<v1::Error>();
    EXPECT_EQ(e.code(), v1::Error::NOT_FOUND);
}

// A client that stops reading in the middle of a large mesh is dropped; others go on.
TEST(ServerSlowReader, IsDroppedWhileOthersContinue) {
    ServerProcess server(temp_dir("slow"), {"--send-timeout", "1"});
    RawClient fast(server.port);
    fast.hello();
    const Surface big = with_test_fields(icosphere(7)); // 327680 triangles, ~12 MB raw
    const std::string id = fast.upload(big, 1).surface();
    RawClient slow(server.port);
    slow.hello();
    boost::asio::socket_base::receive_buffer_size small(4096);
    slow.socket().set_option(small);
    // Four near-full levels, ~34 MB: more than loopback's socket buffers can hold.
    slow.send(request_for(id, {1.0f, 0.99f, 0.98f, 0.97f}, 1));
    // fast keeps being served while slow does not read (the record of 327680 triangles is
    // computed first: allow a loaded machine a minute for it).
    for (int i = 0; i < 600 && metric(server.http_port, "ddsimp_connections_dropped_total") < 1;
         ++i) {
        v1::Ping p;
        p.set_nonce(uint64_t(i));
        fast.send(p);
        EXPECT_EQ(fast.expect<v1::Pong>().nonce(), uint64_t(i));
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    EXPECT_EQ(metric(server.http_port, "ddsimp_connections_dropped_total"), 1);
    fast.send(request_for(id, {0.01f}, 2));
    EXPECT_EQ(fast.level().begin.request_id(), 2u);
}

} // namespace
} // namespace ddsimp::test
