// libddsimp-client against a scripted peer (fake_peer.h): what it sends on the wire (Hello,
// Auth only when asked, uploads in 512 KiB chunks, requests) and how it reads what a server
// sends (levels raw, meshopt and progressive, errors that end one request, sessions).
#include "fake_peer.h"
#include "mesh_comparison.h"
#include "test_surfaces.h"

#include "ddsimp/client.h"
#include "ddsimp/protocol/content_hash.h"
#include "ddsimp/protocol/mesh_codec.h"
#include "ddsimp/protocol/refinement.h"

namespace ddsimp {
namespace {

using test::FakePeer;
using test::FakeServer;

ConnectOptions local(uint16_t port) {
    ConnectOptions o;
    o.host = "127.0.0.1";
    o.port = port;
    o.timeout = std::chrono::milliseconds(20000);
    return o;
}

// A port nothing listens on: bound once by the kernel's choice, then released.
uint16_t closed_port() {
    boost::asio::io_context io;
    boost::asio::ip::tcp::acceptor a(io, {boost::asio::ip::make_address("127.0.0.1"), 0});
    return a.local_endpoint().port();
}

template <class F> ClientError error_from(F&& f) {
    try {
        f();
    } catch (const ClientError& e) {
        return e;
    }
    ADD_FAILURE() << "no ClientError";
    return ClientError(ErrorCode::Internal, "none");
}

// Sends `bytes` as MeshChunks of `chunk` bytes, then MeshEnd.
void send_blob(FakePeer& peer, uint64_t request, uint32_t level, const std::string& bytes,
               size_t chunk) {
    for (size_t at = 0; at < bytes.size(); at += chunk) {
        v1::MeshChunk c;
        c.set_request_id(request);
        c.set_level(level);
        c.set_offset(at);
        c.set_data(bytes.substr(at, chunk));
        peer.send(c);
    }
    v1::MeshEnd end;
    end.set_request_id(request);
    end.set_level(level);
    peer.send(end);
}

v1::MeshBegin begin_for(const protocol::EncodedBlob& blob, uint64_t request, uint32_t level,
                        float keep, v1::MeshBegin::Kind kind, uint64_t live_triangles) {
    v1::MeshBegin begin;
    begin.set_request_id(request);
    begin.set_level(level);
    begin.set_keep(keep);
    begin.set_kind(kind);
    protocol::set_layout(begin, blob.layout);
    begin.set_total_triangles(live_triangles);
    begin.set_result("feedface");
    begin.set_seconds(0.25);
    return begin;
}

TEST(ClientFakePeer, UnreachableServerSaysWhereAndWhy) {
    Client client;
    const uint16_t port = closed_port();
    const ClientError e = error_from([&] { client.connect(local(port)); });
    EXPECT_EQ(e.code(), ErrorCode::Connection);
    EXPECT_EQ(std::string(e.what()),
              "cannot connect to 127.0.0.1:" + std::to_string(port) + ": Connection refused");
    EXPECT_FALSE(client.connected());
}

TEST(ClientFakePeer, HelloOffersCapabilitiesAndOnlyAgreedOnesAreUsed) {
    v1::Hello hello;
    FakeServer server([&](FakePeer& peer) {
        hello = peer.handshake({"meshopt-codec"});
        EXPECT_TRUE(peer.closed_by_client());
    });
    {
        Client client;
        ConnectOptions o = local(server.port());
        o.client_name = "fake-peer test";
        o.kind = ClientKind::VR;
        client.connect(o);
        EXPECT_TRUE(client.connected());
        EXPECT_EQ(client.client_id(), 42u);
        EXPECT_EQ(client.capabilities(), std::vector<std::string>{"meshopt-codec"});
        EXPECT_FALSE(client.has_capability("progressive"));
    }
    server.wait();
    EXPECT_EQ(hello.protocol_version(), 1u);
    EXPECT_EQ(hello.client_name(), "fake-peer test");
    EXPECT_EQ(hello.kind(), v1::VR);
    EXPECT_EQ(std::vector<std::string>(hello.capabilities().begin(), hello.capabilities().end()),
              (std::vector<std::string>{"meshopt-codec", "progressive", "sessions", "session-keys",
                                        "previews", "surface-delete"}));
}

TEST(ClientFakePeer, TokenIsSentWhenAskedAndARefusalCarriesTheServersMessage) {
    std::string token_seen;
    FakeServer server([&](FakePeer& peer) {
        peer.read_as<v1::Hello>();
        v1::Welcome welcome;
        welcome.set_protocol_version(1);
        welcome.set_auth_required(true);
        peer.send(welcome);
        token_seen = peer.read_as<v1::Auth>().token();
        v1::Error error;
        error.set_code(v1::Error::UNAUTHENTICATED);
        error.set_message("wrong token");
        peer.send(error);
    });
    Client client;
    ConnectOptions o = local(server.port());
    o.token = "not-the-token";
    const ClientError e = error_from([&] { client.connect(o); });
    server.wait();
    EXPECT_EQ(token_seen, "not-the-token");
    EXPECT_EQ(e.code(), ErrorCode::Unauthenticated);
    EXPECT_EQ(std::string(e.what()), "wrong token");
    EXPECT_FALSE(client.connected());
}

TEST(ClientFakePeer, NoTokenForAServerThatNeedsOneIsRefusedLocally) {
    FakeServer server([&](FakePeer& peer) {
        peer.read_as<v1::Hello>();
        v1::Welcome welcome;
        welcome.set_auth_required(true);
        peer.send(welcome);
        EXPECT_TRUE(peer.closed_by_client()); // no Auth was sent
    });
    Client client;
    const ClientError e = error_from([&] { client.connect(local(server.port())); });
    server.wait();
    EXPECT_EQ(e.code(), ErrorCode::Unauthenticated);
    EXPECT_NE(std::string(e.what()).find("requires a token"), std::string::npos) << e.what();
}

TEST(ClientFakePeer, UploadTravelsInChunksOf512KiBAndArrivesWhole) {
    // 201 x 201 grid: 40401 vertices, 80000 triangles, two fields: about 1.6 MB raw.
    const Surface surface = test::with_test_fields(test::grid(200, 200));
    v1::UploadBegin begin;
    std::vector<size_t> chunk_sizes;
    std::string received;
    bool offsets_in_order = true;
    FakeServer server([&](FakePeer& peer) {
        peer.handshake();
        begin = peer.read_as<v1::UploadBegin>();
        for (;;) {
            const protocol::Frame f = peer.read();
            if (f.type == v1::UPLOAD_END) break;
            const auto chunk = protocol::parse_payload<v1::UploadChunk>(f);
            offsets_in_order &=
                chunk.offset() == received.size() && chunk.upload_id() == begin.upload_id();
            chunk_sizes.push_back(chunk.data().size());
            received += chunk.data();
        }
        v1::UploadResult result;
        result.set_upload_id(begin.upload_id());
        result.set_surface("abc123");
        result.set_triangles(begin.triangle_count());
        result.set_vertices(begin.vertex_count());
        result.set_already_stored(true);
        peer.send(result);
    });
    Client client;
    client.connect(local(server.port()));
    const UploadResult result = client.upload(surface, "grid", "room");
    server.wait();

    EXPECT_EQ(result.surface, "abc123");
    EXPECT_TRUE(result.already_stored);
    EXPECT_EQ(result.triangles, 80000u);
    EXPECT_EQ(begin.name(), "grid");
    EXPECT_EQ(begin.session(), "room");
    EXPECT_EQ(begin.vertex_count(), 201u * 201u);
    EXPECT_EQ(begin.triangle_count(), 80000u);
    // positions 12, triangles 12, test fields 4 + 12 bytes per vertex/triangle (by hand)
    const uint64_t expected_bytes = 40401 * 12 + 80000 * 12 + 40401 * (4 + 12);
    ASSERT_EQ(surface.fields.size(), 2u);
    ASSERT_EQ(surface.fields[0].components + surface.fields[1].components, 4);
    EXPECT_EQ(begin.total_bytes(), expected_bytes);
    EXPECT_TRUE(offsets_in_order);
    ASSERT_EQ(chunk_sizes.size(), (expected_bytes + (512u << 10) - 1) / (512u << 10));
    for (size_t i = 0; i + 1 < chunk_sizes.size(); ++i) EXPECT_EQ(chunk_sizes[i], 512u << 10);
    protocol::BlobLayout layout;
    layout.vertex_count = begin.vertex_count();
    layout.triangle_count = begin.triangle_count();
    for (const auto& f : begin.fields()) layout.fields.push_back({f.name(), f.components()});
    layout.section_bytes =
        protocol::raw_mesh_sections(layout.vertex_count, layout.triangle_count, layout.fields);
    EXPECT_TRUE(test::same_bytes(protocol::decode_mesh(received, layout), surface));
}

struct LevelCase {
    const char* name;
    v1::Encoding encoding;
    bool progressive;
};

class ClientLevels : public ::testing::TestWithParam<LevelCase> {};
INSTANTIATE_TEST_SUITE_P(Encodings, ClientLevels,
                         ::testing::Values(LevelCase{"Raw", v1::RAW, false},
                                           LevelCase{"Meshopt", v1::MESHOPT, false},
                                           LevelCase{"ProgressiveMeshopt", v1::MESHOPT, true},
                                           LevelCase{"ProgressiveRaw", v1::RAW, true}),
                         [](const auto& info) { return std::string(info.param.name); });

TEST_P(ClientLevels, EveryLevelArrivesAsTheServerEncodedIt) {
    const LevelCase param = GetParam();
    const Surface input = test::with_test_fields(test::icosphere(4)); // 5120 triangles
    Options o;
    o.keep_fraction = 0;
    const ProgressiveRecord rec = ProgressiveRecord::build(input, o);
    const std::vector<size_t> targets{512, 2048}; // coarsest first, as a server sends
    v1::Request seen;

    FakeServer server([&](FakePeer& peer) {
        peer.handshake();
        seen = peer.read_as<v1::Request>();
        const uint64_t id = seen.request_id();
        protocol::RefinementStream stream(rec.vertices());
        for (uint32_t i = 0; i < targets.size(); ++i) {
            const size_t ops = rec.operations_for(targets[i]);
            const float keep = seen.keep(int(1 - i)); // keep list was {0.4, 0.1}
            protocol::EncodedBlob blob;
            auto kind = v1::MeshBegin::FULL;
            if (!param.progressive) {
                blob = protocol::encode_mesh(rec.after(ops), param.encoding);
            } else if (i == 0) {
                blob =
                    protocol::encode_mesh(stream.base(rec.indexed_triangles(ops)), param.encoding);
            } else {
                blob = protocol::encode_refinement(stream.refine(rec.indexed_triangles(ops)),
                                                   param.encoding);
                kind = v1::MeshBegin::REFINEMENT;
            }
            peer.send(begin_for(blob, id, 1 - i, keep, kind, rec.after(ops).triangle_count()));
            send_blob(peer, id, 1 - i, blob.bytes, 4096); // many small chunks
        }
        v1::RequestDone done;
        done.set_request_id(id);
        peer.send(done);
    });

    Client client;
    client.connect(local(server.port()));
    LevelRequest request;
    request.surface = "abc";
    request.alpha = 0.25;
    request.keep = {0.4, 0.1};
    request.progressive = param.progressive;
    request.encoding = param.encoding == v1::MESHOPT ? Encoding::Meshopt : Encoding::Raw;
    std::vector<uint32_t> arrival;
    PendingRequest pending =
        client.request(request, [&](const Level& level) { arrival.push_back(level.index); });
    const Level fine = pending.levels[0].get();
    const Level coarse = pending.levels[1].get();
    pending.done.get();
    server.wait();

    EXPECT_EQ(seen.surface(), "abc");
    EXPECT_FLOAT_EQ(seen.alpha(), 0.25f);
    EXPECT_EQ(seen.progressive(), param.progressive);
    EXPECT_EQ(seen.encoding(), param.encoding);
    EXPECT_EQ(arrival, (std::vector<uint32_t>{1, 0}));
    // A refinement stream keeps each vertex's data from level to level: the record's own.
    auto level = [&](size_t target) {
        const size_t ops = rec.operations_for(target);
        return param.progressive ? rec.after_as_recorded(ops) : rec.after(ops);
    };
    const Surface expected_coarse = level(512);
    const Surface expected_fine = level(2048);
    EXPECT_EQ(test::triangles_by_content(coarse.mesh), test::triangles_by_content(expected_coarse));
    EXPECT_EQ(test::triangles_by_content(fine.mesh), test::triangles_by_content(expected_fine));
    EXPECT_EQ(fine.refinement, param.progressive);
    EXPECT_EQ(fine.triangles, expected_fine.triangle_count());
    EXPECT_EQ(fine.result, "feedface");
    EXPECT_DOUBLE_EQ(fine.seconds, 0.25);
    if (!param.progressive) {
        // Sent whole: the same vertices and data; raw keeps the triangles' bytes, meshopt's index
        // codec may start a triangle at another corner (same orientation, compared above).
        EXPECT_EQ(fine.mesh.positions, expected_fine.positions);
        if (param.encoding == v1::RAW) {
            EXPECT_TRUE(test::same_bytes(fine.mesh, expected_fine));
        }
        EXPECT_TRUE(fine.slots.triangles.empty());
    } else {
        // The slot mesh holds the live triangles plus degenerate (0,0,0) dead slots.
        size_t live = 0;
        for (size_t t = 0; t < fine.slots.triangles.size(); t += 3)
            live += !(fine.slots.triangles[t] == 0 && fine.slots.triangles[t + 1] == 0 &&
                      fine.slots.triangles[t + 2] == 0);
        EXPECT_EQ(live, expected_fine.triangle_count());
    }
}

TEST(ClientFakePeer, AnErrorEndsOnlyItsRequest) {
    FakeServer server([&](FakePeer& peer) {
        peer.handshake();
        const auto request = peer.read_as<v1::Request>();
        v1::Error error;
        error.set_code(v1::Error::NOT_FOUND);
        error.set_message("no surface \"nope\"");
        error.set_request_id(request.request_id());
        peer.send(error);
        peer.read_as<v1::ListSurfaces>();
        v1::SurfaceList list;
        auto* s = list.add_surfaces();
        s->set_surface("abc");
        s->set_triangles(12);
        auto* f = s->add_fields();
        f->set_name("T");
        f->set_components(1);
        peer.send(list);
    });
    Client client;
    client.connect(local(server.port()));
    LevelRequest request;
    request.surface = "nope";
    request.keep = {0.5};
    PendingRequest pending = client.request(request);
    const ClientError e = error_from([&] { pending.levels[0].get(); });
    EXPECT_EQ(e.code(), ErrorCode::NotFound);
    EXPECT_EQ(std::string(e.what()), "no surface \"nope\"");
    EXPECT_EQ(e.request_id(), pending.id);
    EXPECT_THROW(pending.done.get(), ClientError);
    const auto list = client.list_surfaces(); // the connection is still good
    server.wait();
    ASSERT_EQ(list.size(), 1u);
    EXPECT_EQ(list[0].surface, "abc");
    EXPECT_EQ(list[0].triangles, 12u);
    ASSERT_EQ(list[0].fields.size(), 1u);
    EXPECT_EQ(list[0].fields[0].name, "T");
}

TEST(ClientFakePeer, CancelFailsTheLevelsAtOnceAndTellsTheServer) {
    uint64_t cancelled = 0, requested = 0;
    FakeServer server([&](FakePeer& peer) {
        peer.handshake();
        requested = peer.read_as<v1::Request>().request_id();
        cancelled = peer.read_as<v1::Cancel>().request_id();
    });
    Client client;
    client.connect(local(server.port()));
    LevelRequest request;
    request.surface = "abc";
    request.keep = {0.5, 0.2};
    PendingRequest pending = client.request(request);
    client.cancel(pending.id);
    for (auto& level : pending.levels)
        EXPECT_EQ(error_from([&] { level.get(); }).code(), ErrorCode::Cancelled);
    server.wait();
    EXPECT_EQ(requested, pending.id);
    EXPECT_EQ(cancelled, pending.id);
}

TEST(ClientFakePeer, BadRequestsAreRefusedBeforeSending) {
    Client client; // not even connected: the check comes first
    LevelRequest request;
    request.surface = "abc";
    request.keep = {0.5, 1.5};
    EXPECT_EQ(error_from([&] { client.request(request); }).code(), ErrorCode::InvalidArgument);
    request.keep = {};
    EXPECT_EQ(error_from([&] { client.request(request); }).code(), ErrorCode::InvalidArgument);
}

// The states carry no changed_by, as from a server before it: each answers the waiting call.
TEST(ClientFakePeer, SessionStateAndMeshArriveAsEvents) {
    const Surface mesh = test::tetrahedron();
    v1::SetSessionState set;
    FakeServer server([&](FakePeer& peer) {
        peer.handshake();
        EXPECT_EQ(peer.read_as<v1::JoinSession>().name(), "room");
        v1::SessionState state;
        state.set_name("room");
        state.set_version(1);
        state.set_leader(42);
        state.set_cause("created");
        auto* m = state.add_members();
        m->set_client_id(42);
        m->set_kind(v1::DESKTOP);
        peer.send(state);
        set = peer.read_as<v1::SetSessionState>();
        state.set_version(2);
        state.set_cause("view");
        state.mutable_view()->set_alpha(0);
        state.mutable_view()->set_keep(0.5f);
        peer.send(state);
        const protocol::EncodedBlob blob = protocol::encode_mesh(mesh, v1::MESHOPT);
        v1::MeshBegin begin = begin_for(blob, 0, 0, 0.5f, v1::MeshBegin::FULL, 4);
        begin.set_session("room");
        peer.send(begin);
        send_blob(peer, 0, 0, blob.bytes, 1 << 20);
    });
    Client client;
    client.connect(local(server.port()));
    const SessionState joined = client.join_session("room");
    EXPECT_EQ(joined.version, 1u);
    EXPECT_EQ(joined.leader, 42u);
    ASSERT_EQ(joined.members.size(), 1u);
    EXPECT_EQ(joined.members[0].kind, ClientKind::Desktop);
    ViewChange change;
    change.alpha = 0.0;
    change.keep = 0.5;
    const SessionState changed = client.set_view("room", change);
    EXPECT_EQ(changed.version, 2u);
    EXPECT_EQ(changed.cause, "view");

    // Queued in order: both states, then the mesh.
    std::vector<SessionEvent> events;
    while (events.size() < 3) {
        auto e = client.next_session_event(std::chrono::seconds(20));
        ASSERT_TRUE(e);
        events.push_back(std::move(*e));
    }
    server.wait();
    EXPECT_TRUE(set.set_alpha()); // alpha 0 is a change, so it is flagged
    EXPECT_FLOAT_EQ(set.view().keep(), 0.5f);
    EXPECT_TRUE(set.view().surface().empty());
    EXPECT_EQ(events[0].kind, SessionEvent::Kind::State);
    EXPECT_EQ(events[0].state.cause, "created");
    EXPECT_EQ(events[1].state.cause, "view");
    ASSERT_EQ(events[2].kind, SessionEvent::Kind::Mesh);
    EXPECT_EQ(events[2].mesh.session, "room");
    EXPECT_EQ(events[2].mesh.encoding, Encoding::Meshopt);
    EXPECT_EQ(events[2].mesh.mesh.positions, mesh.positions);
    EXPECT_EQ(test::triangles_by_content(events[2].mesh.mesh), test::triangles_by_content(mesh));
}

// Another member's change can reach a client after it has asked for its own: set_view must return
// the state its own change made, not whichever state of that session comes next.
TEST(ClientFakePeer, SetViewReturnsItsOwnChangeNotAnotherMembersInFlight) {
    FakeServer server([&](FakePeer& peer) {
        peer.handshake();
        peer.read_as<v1::JoinSession>();
        v1::SessionState state;
        state.set_name("room");
        state.set_leader(42);
        state.add_members()->set_client_id(42);
        state.set_version(1);
        state.set_cause("created");
        state.set_changed_by(42);
        peer.send(state);
        peer.read_as<v1::SetSessionState>();
        // Client 7 joined just before the change arrived at the server.
        state.add_members()->set_client_id(7);
        state.set_version(2);
        state.set_cause("joined");
        state.set_changed_by(7);
        peer.send(state);
        state.set_version(3);
        state.set_cause("view");
        state.set_changed_by(42);
        state.mutable_view()->set_keep(0.25f);
        peer.send(state);
    });
    Client client;
    client.connect(local(server.port()));
    EXPECT_EQ(client.join_session("room").version, 1u);
    ViewChange change;
    change.keep = 0.25;
    const SessionState changed = client.set_view("room", change);
    EXPECT_EQ(changed.version, 3u);
    EXPECT_EQ(changed.cause, "view");
    EXPECT_EQ(changed.changed_by, 42u);
    EXPECT_EQ(changed.members.size(), 2u);
    // The other member's state is still an event, between the two of this client's.
    std::vector<uint64_t> versions;
    while (versions.size() < 3) {
        auto e = client.next_session_event(std::chrono::seconds(20));
        ASSERT_TRUE(e);
        versions.push_back(e->state.version);
    }
    server.wait();
    EXPECT_EQ(versions, (std::vector<uint64_t>{1, 2, 3}));
}

TEST(ClientFakePeer, ALostConnectionFailsWhatIsPending) {
    FakeServer server([&](FakePeer& peer) {
        peer.handshake();
        peer.read_as<v1::Request>(); // and hang up without an answer
    });
    Client client;
    client.connect(local(server.port()));
    LevelRequest request;
    request.surface = "abc";
    request.keep = {0.5};
    PendingRequest pending = client.request(request);
    const ClientError e = error_from([&] { pending.done.get(); });
    server.wait();
    EXPECT_EQ(e.code(), ErrorCode::Connection);
    EXPECT_NE(std::string(e.what()).find("closed the connection"), std::string::npos) << e.what();
    EXPECT_FALSE(client.connected());
}

TEST(ClientParseAddress, HostPortForms) {
    ConnectOptions o;
    parse_server_address("example.org:7000", o);
    EXPECT_EQ(o.host, "example.org");
    EXPECT_EQ(o.port, 7000);
    parse_server_address("[::1]:7001", o);
    EXPECT_EQ(o.host, "::1");
    EXPECT_EQ(o.port, 7001);
    parse_server_address("other", o);
    EXPECT_EQ(o.host, "other");
    EXPECT_EQ(o.port, 7001); // unchanged
    EXPECT_THROW(parse_server_address("host:99999", o), std::invalid_argument);
    EXPECT_THROW(parse_server_address("host:", o), std::invalid_argument);
    EXPECT_THROW(parse_server_address(":7420", o), std::invalid_argument);
    EXPECT_THROW(parse_server_address("::1", o), std::invalid_argument);
}

} // namespace
} // namespace ddsimp
