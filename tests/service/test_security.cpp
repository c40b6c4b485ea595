// What ddsimp-server promises about who gets in and who sees what (docs/security.md): a wrong or
// missing token is refused with one answer whatever it asked for; sessions are their name and
// key, and a client sees only the public surfaces and those of the sessions it joined with the
// right key, without learning that others exist; no client-chosen string becomes a file path;
// TLS with a certificate made in the test.
#include "hostile_support.h"
#include "self_signed_certificate.h"

#include "ddsimp/client.h"
#include "ddsimp/protocol/content_hash.h"

#include <cstdlib>
#include <regex>

namespace ddsimp::test {
namespace {

namespace fs = std::filesystem;

v1::SessionState join(RawClient& c, const std::string& name, const std::string& key) {
    v1::JoinSession j;
    j.set_name(name);
    j.set_key(key);
    c.send(j);
    return c.expect<v1::SessionState>();
}

// The next level that satisfies `want` (a request's, or a session's), skipping others.
RawClient::Level level_where(RawClient& c, const std::function<bool(const v1::MeshBegin&)>& want) {
    for (;;) {
        RawClient::Level l = c.level();
        if (want(l.begin)) return l;
    }
}
RawClient::Level level_of(RawClient& c, uint64_t request_id) {
    return level_where(c, [&](const v1::MeshBegin& b) { return b.request_id() == request_id; });
}

// The error payload a connection that skips or fails authentication gets, exactly as sent, and
// whether the server closed the connection after it.
struct Refusal {
    std::string payload;
    bool closed = false;
};

Refusal refusal_for(uint16_t port, bool say_hello, const std::optional<std::string>& token,
                    const std::string& frame) {
    RawClient c(port);
    if (say_hello) c.send(hello_message());
    if (token) {
        v1::Auth a;
        a.set_token(*token);
        c.send(a);
    }
    c.send_bytes(frame);
    Refusal r;
    while (auto f = c.next(std::chrono::seconds(30)))
        if (f->type == v1::ERROR) r.payload = f->payload;
    r.closed = c.closed_by_server();
    return r;
}

// With a token configured, everything before a correct Auth gets the same answer whether the
// session, surface or result it names exists or not, and the connection is closed.
TEST(Security, AWrongOrMissingTokenIsRefusedWithoutRevealingWhatExists) {
    const std::string token = "4f1c0c9a-token";
    ServerProcess server(temp_dir("token"), {"--token", token});
    RawClient owner(server.port);
    owner.hello({"sessions"}, token);
    join(owner, "lab", "");
    const std::string surface = owner.upload(small_surface(), 1, "mine", "lab").surface();
    owner.send(level_request(surface, {0.5f}, 2));
    const std::string result = level_of(owner, 2).begin.result();

    const auto frames_naming = [&](const std::string& session, const std::string& id,
                                   const std::string& key) {
        v1::JoinSession j;
        j.set_name(session);
        v1::Request r = level_request(id, {0.5f}, 3);
        v1::Request resume;
        resume.set_request_id(4);
        resume.set_result(key);
        resume.add_keep(0.5f);
        return std::vector<std::string>{protocol::encode_frame(j), protocol::encode_frame(r),
                                        protocol::encode_frame(resume),
                                        protocol::encode_frame(v1::ListSurfaces{})};
    };
    const std::vector<std::string> existing = frames_naming("lab", surface, result);
    const std::vector<std::string> missing =
        frames_naming("nope", protocol::sha256_hex("nothing"), protocol::sha256_hex("no result"));
    // No Hello; Hello without Auth; a wrong token; an empty one; one longer than the real one.
    struct Attempt {
        bool hello;
        std::optional<std::string> token;
    };
    const std::vector<Attempt> attempts{{false, std::nullopt},
                                        {true, std::nullopt},
                                        {true, "4f1c0c9a-tokem"},
                                        {true, ""},
                                        {true, token + std::string(100000, 'x')}};
    for (const Attempt& a : attempts) {
        std::string answer;
        for (size_t i = 0; i < existing.size(); ++i)
            for (const std::string* frame : {&existing[i], &missing[i]}) {
                const Refusal r = refusal_for(server.port, a.hello, a.token, *frame);
                EXPECT_TRUE(r.closed);
                ASSERT_FALSE(r.payload.empty());
                const v1::Error e = protocol::parse_payload<v1::Error>({v1::ERROR, r.payload});
                EXPECT_EQ(e.code(), v1::Error::UNAUTHENTICATED);
                if (answer.empty()) answer = r.payload;
                EXPECT_EQ(r.payload, answer) << "message " << i << ": " << e.message();
            }
    }
    // And the right token still works.
    RawClient later(server.port);
    later.hello({}, token);
    EXPECT_TRUE(listed(later).count(surface) == 0); // the session's surface: members only
}

// Two sessions named "lab" with different keys are two sessions. A surface uploaded into one is
// seen, listed, requested, resumed and shown only by its members; to everyone else it is exactly
// like a surface that does not exist, even to one who uploads the same bytes. Visibility
// survives a restart.
TEST(Security, SessionsAreIsolatedByTheirKeys) {
    const fs::path dir = temp_dir("isolation");
    ServerProcess server(dir);
    RawClient a(server.port), b(server.port), c(server.port), outsider(server.port);
    const uint64_t a_id = a.hello({"sessions"}).client_id();
    const uint64_t b_id = b.hello({"sessions"}).client_id();
    c.hello({"sessions"});
    outsider.hello({"sessions"});

    EXPECT_EQ(join(a, "lab", "k-1").cause(), "created");
    const Surface secret = with_test_fields(torus(20, 10));
    const v1::UploadResult up = a.upload(secret, 1, "secret.vtp", "lab");
    EXPECT_FALSE(up.already_stored());
    const std::string id = up.surface();
    a.send(level_request(id, {0.5f}, 2));
    const std::string result = level_of(a, 2).begin.result();

    // The wrong key: another session of the same name, with B alone in it and nothing in view.
    const v1::SessionState other = join(b, "lab", "k-2");
    EXPECT_EQ(other.cause(), "created");
    ASSERT_EQ(other.members_size(), 1);
    EXPECT_EQ(other.members(0).client_id(), b_id);
    EXPECT_TRUE(other.view().surface().empty());

    const std::string nothing = protocol::sha256_hex("no such surface");
    for (RawClient* stranger : {&b, &outsider}) {
        EXPECT_FALSE(listed(*stranger).count(id));
        // Asking for it, or for a surface that does not exist: the same answer but for the id.
        stranger->send(level_request(id, {0.5f}, 7));
        const std::string for_it = next_error(*stranger).SerializeAsString();
        stranger->send(level_request(nothing, {0.5f}, 7));
        const v1::Error for_nothing = next_error(*stranger);
        EXPECT_EQ(for_nothing.code(), v1::Error::NOT_FOUND);
        v1::Error expected = for_nothing;
        expected.set_message(std::regex_replace(for_nothing.message(), std::regex(nothing), id));
        EXPECT_EQ(for_it, expected.SerializeAsString());
        // Resuming its result: as for a result that never was.
        v1::Request resume;
        resume.set_request_id(8);
        resume.set_result(result);
        resume.add_keep(0.5f);
        stranger->send(resume);
        const v1::Error e = next_error(*stranger);
        EXPECT_EQ(e.code(), v1::Error::NOT_FOUND);
        EXPECT_EQ(e.message(), "request 8: no result " + result);
    }
    // Showing it in one's own session: refused as for a surface that does not exist.
    v1::SetSessionState show;
    show.set_name("lab");
    show.mutable_view()->set_surface(id);
    b.send(show);
    EXPECT_EQ(next_error(b).message(), "no surface " + id);
    // Uploading the same bytes does not tell B that someone has them; both keep their copy.
    const v1::UploadResult again = b.upload(secret, 3, "mine.vtp", "lab");
    EXPECT_EQ(again.surface(), id);
    EXPECT_FALSE(again.already_stored());
    EXPECT_EQ(fs::exists(dir / (id + ".ddsurf")), true); // stored once on disk
    b.send(v1::ListSurfaces{});
    const v1::SurfaceList seen_by_b = b.expect<v1::SurfaceList>();
    for (const auto& s : seen_by_b.surfaces()) {
        if (s.surface() == id) {
            EXPECT_EQ(s.name(), "mine.vtp"); // its own label, not A's
        }
    }

    // The right key: C joins A's session, sees its members, its surface and its levels.
    const v1::SessionState same = join(c, "lab", "k-1");
    EXPECT_EQ(same.members_size(), 2);
    EXPECT_EQ(same.members(0).client_id(), a_id);
    EXPECT_TRUE(listed(c).count(id));
    c.send(level_request(id, {0.5f}, 9));
    const RawClient::Level l = level_of(c, 9);
    EXPECT_TRUE(same_bytes(protocol::decode_mesh(l.bytes, protocol::layout_of(l.begin)),
                           offline_level(secret, 0.3f, 0.5f)));
    // A session's mesh reaches its members, not the other session of that name.
    v1::SetSessionState view;
    view.set_name("lab");
    view.mutable_view()->set_surface(id);
    view.mutable_view()->set_keep(0.25f);
    a.send(view);
    EXPECT_EQ(
        level_where(c, [](const v1::MeshBegin& b) { return b.keep() == 0.25f; }).begin.session(),
        "lab");
    // B gets its list, and no state or mesh of A's session before it (only its own session's).
    b.send(v1::ListSurfaces{});
    for (;;) {
        const std::optional<protocol::Frame> f = b.next();
        ASSERT_TRUE(f);
        if (f->type == v1::MESH_BEGIN) {
            EXPECT_NE(protocol::parse_payload<v1::MeshBegin>(*f).keep(), 0.25f);
        }
        if (f->type == v1::SESSION_STATE) {
            EXPECT_EQ(protocol::parse_payload<v1::SessionState>(*f).members_size(), 1);
        }
        if (f->type == v1::SURFACE_LIST) break;
    }

    // After a restart: still the members' only, for whoever rejoins with the key.
    server.stop();
    server.start();
    RawClient d(server.port), e(server.port);
    d.hello({"sessions"});
    e.hello({"sessions"});
    EXPECT_FALSE(listed(d).count(id));
    join(d, "lab", "k-3");
    EXPECT_FALSE(listed(d).count(id));
    join(e, "lab", "k-2"); // B's session: B uploaded the same bytes there
    EXPECT_TRUE(listed(e).count(id));
    RawClient f(server.port);
    f.hello({"sessions"});
    join(f, "lab", "k-1");
    EXPECT_TRUE(listed(f).count(id));
}

// A member of two sessions may show a surface of one in the other (it sees both): then the
// other's members see it too. A public upload is everyone's.
TEST(Security, AMemberSharesASurfaceBetweenItsSessions) {
    ServerProcess server(temp_dir("share"));
    RawClient a(server.port), b(server.port), outsider(server.port);
    a.hello({"sessions"});
    b.hello({"sessions"});
    outsider.hello({"sessions"});
    join(a, "one", "k1");
    join(a, "two", "k2");
    join(b, "two", "k2");
    const std::string id = a.upload(small_surface(), 1, "s", "one").surface();
    EXPECT_FALSE(listed(b).count(id));
    v1::SetSessionState show;
    show.set_name("two");
    show.mutable_view()->set_surface(id);
    a.send(show);
    // B receives the mesh (the whole surface: the view's keep is 1)...
    EXPECT_EQ(level_where(b, [](const v1::MeshBegin& m) { return m.session() == "two"; })
                  .begin.total_triangles(),
              small_surface().triangle_count());
    EXPECT_TRUE(listed(b).count(id)); // ...and may now ask for the surface itself
    EXPECT_FALSE(listed(outsider).count(id));
    const std::string shared = outsider.upload(with_test_fields(torus(12, 6)), 2).surface();
    EXPECT_TRUE(listed(a).count(shared));
    EXPECT_TRUE(listed(b).count(shared));
}

// Labels, session names, fields and ids full of "../": none becomes a path. The data directory
// holds only files named by content hashes, and nothing appears beside it.
TEST(Security, NoClientChosenStringBecomesAPath) {
    const fs::path dir = temp_dir("paths");
    ServerProcess server(dir / "data");
    RawClient c(server.port);
    c.hello({"sessions"});
    const std::string evil = "../../../../../../tmp/ddsimp-escape";
    join(c, evil, evil);
    Surface s = small_surface();
    s.fields[0].name = evil;
    const std::string id = c.upload(s, 1, evil, evil).surface();
    c.send(v1::ListSurfaces{});
    const v1::SurfaceList list = c.expect<v1::SurfaceList>();
    bool found = false;
    for (const auto& info : list.surfaces())
        if (info.surface() == id) {
            found = true;
            EXPECT_EQ(info.name(), evil); // a label, as given
            EXPECT_EQ(info.fields(0).name(), evil);
        }
    EXPECT_TRUE(found);
    for (const std::string& name : {evil, std::string("../../etc/passwd"), id + "/../" + id,
                                    std::string("/etc/passwd"), std::string(".")}) {
        c.send(level_request(name, {0.5f}, 2));
        EXPECT_EQ(next_error(c).code(), v1::Error::NOT_FOUND) << name;
        v1::Request resume;
        resume.set_request_id(3);
        resume.set_result(name);
        resume.add_keep(0.5f);
        c.send(resume);
        EXPECT_EQ(next_error(c).code(), v1::Error::NOT_FOUND) << name;
    }
    c.send(level_request(id, {0.5f}, 4));
    EXPECT_EQ(level_of(c, 4).begin.request_id(), 4u); // the real id still works
    EXPECT_FALSE(fs::exists("/tmp/ddsimp-escape"));
    EXPECT_FALSE(fs::exists("/tmp/ddsimp-escape.ddsurf"));
    std::vector<std::string> beside;
    for (const auto& e : fs::directory_iterator(dir)) beside.push_back(e.path().filename());
    EXPECT_EQ(beside, std::vector<std::string>{"data"});
    const std::regex content_named("[0-9a-f]{64}\\.(ddsurf|scopes)");
    for (const auto& e : fs::directory_iterator(dir / "data"))
        EXPECT_TRUE(std::regex_match(e.path().filename().string(), content_named))
            << e.path().filename();
}

// The static files never leave --web-dir: not through a symbolic link to a file or a directory
// outside it (a link that stays inside is followed).
TEST(Security, StaticFilesNeverFollowASymlinkOut) {
    const fs::path dir = temp_dir("web-symlinks");
    const fs::path web = dir / "web", outside = dir / "outside";
    fs::create_directories(web / "assets");
    fs::create_directories(outside);
    std::ofstream(web / "index.html") << "<!doctype html>the page";
    std::ofstream(outside / "secret.txt") << "the secret";
    fs::create_symlink(outside / "secret.txt", web / "leak.txt");
    fs::create_symlink(outside, web / "assets" / "out");
    fs::create_symlink("/etc/passwd", web / "passwd");
    fs::create_symlink(web / "index.html", web / "alias.html");
    ServerProcess server(dir / "data", {"--web-dir", web.string()});
    for (const std::string target : {"/leak.txt", "/assets/out/secret.txt", "/passwd"}) {
        const std::string answer = http_get(server.http_port, target);
        EXPECT_NE(answer.find("404 Not Found"), std::string::npos) << target << ": " << answer;
        EXPECT_EQ(answer.find("the secret"), std::string::npos) << target;
        EXPECT_EQ(answer.find("root:"), std::string::npos) << target;
    }
    const std::string inside = http_get(server.http_port, "/alias.html");
    EXPECT_NE(inside.find("200 OK"), std::string::npos) << inside;
    EXPECT_NE(inside.find("the page"), std::string::npos) << inside;
}

// Every size a client chooses has a limit (docs/security.md lists them); a few at their edge.
TEST(Security, ClientChosenSizesAreLimited) {
    ServerProcess server(temp_dir("sizes"), {"--threads", "1"});
    RawClient c(server.port);
    c.hello({"sessions"});
    v1::JoinSession j;
    j.set_name(std::string(201, 'n'));
    c.send(j);
    EXPECT_EQ(next_error(c).code(), v1::Error::INVALID_ARGUMENT);
    j.set_name("ok");
    j.set_key(std::string(1025, 'k'));
    c.send(j);
    EXPECT_EQ(next_error(c).code(), v1::Error::INVALID_ARGUMENT);
    for (int i = 0; i < 16; ++i) join(c, "s" + std::to_string(i), "");
    v1::SetSessionState field;
    field.set_name("s0");
    field.mutable_view()->set_field(std::string(201, 'f'));
    c.send(field);
    EXPECT_EQ(next_error(c).code(), v1::Error::INVALID_ARGUMENT);
    j.set_name("one too many");
    j.set_key("");
    c.send(j);
    EXPECT_EQ(next_error(c).code(), v1::Error::RESOURCE_EXHAUSTED);
    v1::UploadBegin b;
    b.set_upload_id(1);
    b.set_name(std::string(201, 'x'));
    b.set_vertex_count(3);
    b.set_triangle_count(1);
    b.set_total_bytes(48);
    c.send(b);
    EXPECT_EQ(next_error(c).code(), v1::Error::INVALID_ARGUMENT);
    v1::Request r = level_request("x", {0.5f}, 5);
    for (int i = 0; i < 65; ++i) r.add_gradient_fields("f");
    c.send(r);
    EXPECT_EQ(next_error(c).code(), v1::Error::INVALID_ARGUMENT);
    r = level_request("x", {}, 6);
    for (int i = 0; i < 65; ++i) r.add_keep(0.5f);
    c.send(r);
    EXPECT_EQ(next_error(c).code(), v1::Error::INVALID_ARGUMENT);
    // Seventeen requests at once, each its own computation of 20k triangles on one thread: the
    // server, stopped while they are sent, reads all seventeen long before the first is done,
    // and refuses the seventeenth.
    const std::string id = c.upload(with_test_fields(icosphere(5)), 2).surface();
    ::kill(server.pid(), SIGSTOP);
    for (int i = 0; i < 17; ++i)
        c.send(level_request(id, {0.5f}, uint64_t(100 + i), 0.05f * float(i)));
    ::kill(server.pid(), SIGCONT);
    std::vector<uint64_t> refused;
    for (int done = 0; done + int(refused.size()) < 17;) {
        const std::optional<protocol::Frame> f = c.next();
        ASSERT_TRUE(f);
        if (f->type == v1::REQUEST_DONE) ++done;
        if (f->type == v1::ERROR) {
            const v1::Error e = protocol::parse_payload<v1::Error>(*f);
            EXPECT_EQ(e.code(), v1::Error::RESOURCE_EXHAUSTED) << e.message();
            refused.push_back(e.request_id());
        }
    }
    EXPECT_EQ(refused, std::vector<uint64_t>{116});
}

// TLS with a certificate made here, a token and a session key, through the client library: the
// client that trusts the certificate gets in and gets its level; a plain-TCP client and one
// with the wrong token do not, and the first goes on.
TEST(Security, TlsWithTokenAndSessionKey) {
    const fs::path dir = temp_dir("tls");
    write_self_signed(dir / "cert.pem", dir / "key.pem", "ddsimp security test");
    const std::string token = "tls-token";
    ServerProcess server(dir / "data", {"--token", token, "--tls-cert", (dir / "cert.pem").string(),
                                        "--tls-key", (dir / "key.pem").string()});
    ConnectOptions o;
    o.host = "localhost";
    o.port = server.port;
    o.token = token;
    o.tls = true;
    o.ca_file = (dir / "cert.pem").string();
    Client client;
    client.connect(o);
    EXPECT_TRUE(client.has_capability("session-keys"));
    client.join_session("tls-lab", "tls-key");
    const Surface s = small_surface();
    const UploadResult up = client.upload(s, "s", "tls-lab");
    LevelRequest r;
    r.surface = up.surface;
    r.alpha = 0.3;
    r.keep = {0.5};
    r.encoding = Encoding::Raw;
    const std::vector<Level> levels = client.request_levels(r);
    ASSERT_EQ(levels.size(), 1u);
    EXPECT_TRUE(same_bytes(levels[0].mesh, offline_level(s, 0.3f, 0.5f)));

    // Plain TCP to the TLS port: no Welcome, closed.
    RawClient plain(server.port);
    plain.send(hello_message());
    EXPECT_FALSE(plain.next(std::chrono::seconds(20)).has_value());
    // The wrong token over TLS: refused. Another session key: the surface is not there.
    Client wrong;
    ConnectOptions w = o;
    w.token = "tls-tokem";
    try {
        wrong.connect(w);
        ADD_FAILURE() << "a wrong token was accepted";
    } catch (const ClientError& e) {
        EXPECT_EQ(e.code(), ErrorCode::Unauthenticated);
    }
    Client stranger;
    stranger.connect(o);
    stranger.join_session("tls-lab", "not-the-key");
    for (const SurfaceInfo& info : stranger.list_surfaces()) EXPECT_NE(info.surface, up.surface);
    EXPECT_EQ(client.request_levels(r)[0].triangles, levels[0].triangles);
}

#ifdef DDSIMP_CLI
// `ddsimp remote upload --session S --session-key K` joins the session with its key before it
// uploads (it used to upload without joining, so the server refused the session), and the
// surface is then the session's only.
TEST(Security, RemoteUploadIntoASessionWithItsKey) {
    const fs::path dir = temp_dir("remote-key");
    ServerProcess server(dir / "data", {"--sample", ""});
    const std::string sample = std::string(DDSIMP_SAMPLE_DATA) + "/SurfaceVectors.vtk";
    const std::string command = std::string(DDSIMP_CLI) + " remote upload " + sample +
                                " --session lab --server 127.0.0.1:" + std::to_string(server.port) +
                                " >" + (dir / "out").string();
    ASSERT_EQ(std::system(("DDSIMP_SESSION_KEY=k-1 " + command).c_str()), 0);
    std::ifstream out(dir / "out");
    std::string line;
    std::getline(out, line);
    std::smatch id;
    ASSERT_TRUE(std::regex_search(line, id, std::regex("\"surface\":\"([0-9a-f]{64})\""))) << line;
    RawClient member(server.port), stranger(server.port);
    member.hello({"sessions"});
    stranger.hello({"sessions"});
    join(member, "lab", "k-1");
    join(stranger, "lab", "k-2");
    EXPECT_TRUE(listed(member).count(id[1]));
    EXPECT_FALSE(listed(stranger).count(id[1]));
}
#endif

// Connections that never finish their TLS handshake count against --max-clients: those past it
// are closed at once, clients already in are served, and the places come back when they go.
TEST(Security, TlsHandshakesThatNeverFinishMeetTheClientLimit) {
    const fs::path dir = temp_dir("tls-flood");
    write_self_signed(dir / "cert.pem", dir / "key.pem", "ddsimp flood test");
    constexpr size_t kMaxClients = 8, kSilent = 20;
    ServerProcess server(dir / "data",
                         {"--max-clients", std::to_string(kMaxClients), "--handshake-timeout",
                          "120", "--tls-cert", (dir / "cert.pem").string(), "--tls-key",
                          (dir / "key.pem").string()});
    ConnectOptions o;
    o.host = "localhost";
    o.port = server.port;
    o.tls = true;
    o.ca_file = (dir / "cert.pem").string();
    Client in;
    in.connect(o); // one place
    asio::io_context io;
    std::vector<std::unique_ptr<BareConnection>> silent;
    for (size_t i = 0; i < kSilent; ++i)
        silent.push_back(std::make_unique<BareConnection>(io, server.port));
    // The first seven hold the other places (for the 120 s of the handshake timeout); the rest
    // are closed at once.
    for (size_t i = kMaxClients - 1; i < kSilent; ++i)
        EXPECT_TRUE(silent[i]->closed_within(std::chrono::seconds(60))) << i;
    for (size_t i = 0; i < kMaxClients - 1; ++i)
        EXPECT_FALSE(silent[i]->closed_within(std::chrono::milliseconds(0))) << i;
    EXPECT_TRUE(in.list_surfaces().size() >= 1); // served
    silent.clear();                              // they go: every place is free again
    std::vector<std::unique_ptr<Client>> newcomers;
    for (size_t i = 0; i + 1 < kMaxClients; ++i) {
        newcomers.push_back(std::make_unique<Client>());
        for (int attempt = 0;; ++attempt) { // a place comes back when its handshake fails
            try {
                newcomers.back()->connect(o);
                break;
            } catch (const ClientError& e) {
                ASSERT_LT(attempt, 100) << e.what();
                std::this_thread::sleep_for(std::chrono::milliseconds(100));
            }
        }
    }
    EXPECT_TRUE(newcomers.back()->connected());
}

} // namespace
} // namespace ddsimp::test
