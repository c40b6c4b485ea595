// libddsimp-client and `ddsimp remote` against the real ddsimp-server on loopback: levels equal
// the offline library's, coarsest first; uploads deduplicated; sessions (two watchers, leader
// handoff, late joiner); tokens; resuming a result after a reconnect.
#include "mesh_comparison.h"
#include "self_signed_certificate.h"
#include "server_harness.h"
#include "test_surfaces.h"

#include "ddsimp/client.h"
#include "ddsimp/protocol/content_hash.h"

#include <nlohmann/json.hpp>

#include <fstream>
#include <set>
#include <sstream>

namespace ddsimp {
namespace {

using test::ServerProcess;

ConnectOptions local(uint16_t port, const std::string& token = {}) {
    ConnectOptions o;
    o.host = "127.0.0.1";
    o.port = port;
    o.token = token;
    o.timeout = std::chrono::milliseconds(60000);
    return o;
}

// 5120 triangles with a scalar and a vector field: every keep below divides it exactly.
Surface test_surface() {
    return test::with_test_fields(test::icosphere(4));
}

Surface offline(const Surface& input, double alpha, double keep) {
    Options o;
    o.alpha = alpha;
    o.keep_fraction = keep; // everything else the library's default, as for the server
    return simplify(input, o).surface;
}

// The same level as a refinement stream shows it: each vertex's data as the record carries it,
// the same in every level (ProgressiveRecord::after_as_recorded).
Surface offline_streamed(const Surface& input, double alpha, double keep) {
    Options o;
    o.alpha = alpha;
    o.keep_fraction = 0;
    const ProgressiveRecord record = ProgressiveRecord::build(input, o);
    o.keep_fraction = keep;
    return record.after_as_recorded(
        record.operations_for(target_triangles(o, record.triangles_in())));
}

// The next session event that satisfies `want`, skipping others (a guard against a hang only).
SessionEvent wait_for(Client& client, const std::function<bool(const SessionEvent&)>& want) {
    for (int i = 0; i < 100; ++i) {
        std::optional<SessionEvent> e = client.next_session_event(std::chrono::seconds(60));
        if (!e) break;
        if (want(*e)) return *e;
    }
    ADD_FAILURE() << "the expected session event did not come";
    return {};
}

bool is_mesh(const SessionEvent& e) {
    return e.kind == SessionEvent::Kind::Mesh;
}

class ClientServer : public ::testing::Test {
protected:
    ClientServer() : dir_(test::temp_dir(name())), server_(dir_, {"--sample", ""}) {}
    ~ClientServer() override {
        server_.stop();
        std::filesystem::remove_all(dir_);
    }
    static std::string name() {
        return std::string("client-") +
               ::testing::UnitTest::GetInstance()->current_test_info()->name();
    }
    std::filesystem::path dir_;
    ServerProcess server_;
};

struct RoundTrip {
    const char* name;
    Encoding encoding;
    bool progressive;
};

class ClientRoundTrip : public ClientServer, public ::testing::WithParamInterface<RoundTrip> {};
INSTANTIATE_TEST_SUITE_P(Modes, ClientRoundTrip,
                         ::testing::Values(RoundTrip{"Raw", Encoding::Raw, false},
                                           RoundTrip{"Meshopt", Encoding::Meshopt, false},
                                           RoundTrip{"Progressive", Encoding::Meshopt, true}),
                         [](const auto& info) { return std::string(info.param.name); });

TEST_P(ClientRoundTrip, EveryLevelEqualsTheOfflineResultCoarsestFirst) {
    const RoundTrip mode = GetParam();
    const Surface input = test_surface();
    Client client;
    client.connect(local(server_.port));
    EXPECT_TRUE(client.has_capability("meshopt-codec"));
    EXPECT_TRUE(client.has_capability("progressive"));
    LevelRequest request;
    request.surface = client.upload(input, "icosphere").surface;
    request.alpha = 0.25;
    request.keep = {0.5, 0.125, 0.25};
    request.encoding = mode.encoding;
    request.progressive = mode.progressive;
    std::vector<uint32_t> arrival;
    PendingRequest pending = client.request(request, [&](const Level& level) {
        if (!level.preview) arrival.push_back(level.index);
    });
    pending.done.get();
    // Not cached: progressive levels coarsest first; whole levels the finest as soon as it
    // exists, then the rest coarsest first.
    EXPECT_EQ(arrival, mode.progressive ? (std::vector<uint32_t>{1, 2, 0})
                                        : (std::vector<uint32_t>{0, 1, 2}));

    for (size_t i = 0; i < request.keep.size(); ++i) {
        const Level level = pending.levels[i].get();
        const Surface expected = mode.progressive
                                     ? offline_streamed(input, request.alpha, request.keep[i])
                                     : offline(input, request.alpha, request.keep[i]);
        EXPECT_EQ(level.triangles, expected.triangle_count()) << i;
        EXPECT_EQ(level.encoding, mode.encoding) << i;
        EXPECT_EQ(test::triangles_by_content(level.mesh), test::triangles_by_content(expected))
            << "level " << i;
        if (mode.encoding == Encoding::Raw) {
            EXPECT_TRUE(test::same_bytes(level.mesh, expected)) << "level " << i;
        } else if (!mode.progressive) {
            // The index codec may start a triangle at another corner; vertices stay as they are.
            EXPECT_EQ(level.mesh.positions, expected.positions) << i;
            ASSERT_EQ(level.mesh.fields.size(), expected.fields.size());
            for (size_t f = 0; f < expected.fields.size(); ++f)
                EXPECT_EQ(level.mesh.fields[f].values, expected.fields[f].values) << i;
        }
        EXPECT_EQ(level.refinement, mode.progressive && i != 1) << i;
    }
}

// A label field (ids) keeps its kind through the upload, the server's simplification and the
// level sent back: every value of a level is one of the input's ids, never a mix of two.
TEST_F(ClientServer, ALabelFieldIsCarriedNotInterpolated) {
    Surface input = test_surface();
    Field ids{"PointId", 1, {}, FieldKind::Label};
    for (size_t v = 0; v < input.vertex_count(); ++v) ids.values.push_back(float(10 * v + 1));
    input.fields.push_back(ids);
    Client client;
    client.connect(local(server_.port));
    LevelRequest request;
    request.surface = client.upload(input, "ids").surface;
    request.alpha = 0.25;
    request.keep = {0.1};
    request.encoding = Encoding::Raw;
    PendingRequest pending = client.request(request, [](const Level&) {});
    pending.done.get();
    const Level level = pending.levels[0].get();
    ASSERT_EQ(level.mesh.fields.size(), 3u);
    const Field& got = level.mesh.fields[2];
    EXPECT_EQ(got.kind, FieldKind::Label);
    const std::set<float> input_ids(ids.values.begin(), ids.values.end());
    for (size_t v = 0; v < got.values.size(); ++v)
        ASSERT_TRUE(input_ids.count(got.values[v])) << "vertex " << v << ": " << got.values[v];
    EXPECT_TRUE(test::same_bytes(level.mesh, offline(input, request.alpha, 0.1)));
}

TEST_F(ClientServer, OneClientServesRequestsFromSeveralThreads) {
    const Surface input = test_surface();
    Client client;
    client.connect(local(server_.port));
    const std::string surface = client.upload(input).surface;
    const std::vector<double> alphas{0, 0.25, 0.5, 1};
    std::vector<Level> got(alphas.size());
    std::vector<std::thread> threads;
    for (size_t t = 0; t < alphas.size(); ++t)
        threads.emplace_back([&, t] {
            LevelRequest request;
            request.surface = surface;
            request.alpha = alphas[t];
            request.keep = {0.25};
            got[t] = client.request_levels(request).at(0);
        });
    for (std::thread& t : threads) t.join();
    for (size_t t = 0; t < alphas.size(); ++t)
        EXPECT_EQ(test::triangles_by_content(got[t].mesh),
                  test::triangles_by_content(offline(input, alphas[t], 0.25)))
            << "alpha " << alphas[t];
}

TEST_F(ClientServer, TheSameSurfaceTwiceIsStoredOnce) {
    Surface input = test_surface();
    Client client;
    client.connect(local(server_.port));
    const UploadResult first = client.upload(input, "a");
    const UploadResult second = client.upload(input, "b");
    EXPECT_FALSE(first.already_stored);
    EXPECT_TRUE(second.already_stored);
    EXPECT_EQ(first.surface, second.surface);
    validate(input);
    EXPECT_EQ(first.surface, protocol::surface_hash(input));
    EXPECT_EQ(first.triangles, 5120u);
    const auto list = client.list_surfaces();
    ASSERT_EQ(list.size(), 1u);
    EXPECT_EQ(list[0].surface, first.surface);
    ASSERT_EQ(list[0].fields.size(), 2u);
    EXPECT_EQ(list[0].fields[1].components, 3);
}

TEST_F(ClientServer, TwoWatchersBothReceiveTheLeadersChange) {
    const Surface input = test_surface();
    Client leader, a, b;
    for (Client* c : {&leader, &a, &b}) c->connect(local(server_.port));
    const std::string surface = leader.upload(input).surface;
    leader.join_session("room");
    a.join_session("room");
    b.join_session("room");
    ViewChange change;
    change.surface = surface;
    change.alpha = 0.25;
    change.keep = 0.25;
    const SessionState state = leader.set_view("room", change);
    EXPECT_EQ(state.cause, "view");
    EXPECT_EQ(state.changed_by, leader.client_id());
    EXPECT_EQ(state.leader, leader.client_id());
    EXPECT_EQ(state.members.size(), 3u);
    const Surface expected = offline(input, 0.25, 0.25);
    for (Client* watcher : {&a, &b}) {
        const SessionEvent s = wait_for(*watcher, [](const SessionEvent& e) {
            return e.kind == SessionEvent::Kind::State && e.state.cause == "view";
        });
        EXPECT_EQ(s.state.view.surface, surface);
        EXPECT_EQ(s.state.leader, leader.client_id());
        EXPECT_EQ(s.state.changed_by, leader.client_id());
        const SessionEvent m = wait_for(*watcher, is_mesh);
        EXPECT_EQ(m.mesh.session, "room");
        EXPECT_EQ(test::triangles_by_content(m.mesh.mesh), test::triangles_by_content(expected));
    }
}

TEST_F(ClientServer, LeadershipPassesOnWhenTheLeaderDisconnects) {
    Client first, second, third;
    for (Client* c : {&first, &second, &third}) c->connect(local(server_.port));
    EXPECT_EQ(first.join_session("hall").leader, first.client_id());
    const uint64_t first_id = first.client_id();
    second.join_session("hall");
    third.join_session("hall");
    first.close();
    const SessionEvent e = wait_for(third, [](const SessionEvent& e) {
        return e.kind == SessionEvent::Kind::State && e.state.cause == "leader-left";
    });
    // The longest-present member leads.
    EXPECT_EQ(e.state.leader, second.client_id());
    EXPECT_EQ(e.state.changed_by, first_id); // the one that left
    EXPECT_EQ(e.state.members.size(), 2u);
}

TEST_F(ClientServer, ALateJoinerGetsTheCurrentStateAndMesh) {
    const Surface input = test_surface();
    Client leader, late;
    leader.connect(local(server_.port));
    late.connect(local(server_.port));
    const std::string surface = leader.upload(input).surface;
    leader.join_session("late");
    ViewChange change;
    change.surface = surface;
    change.alpha = 0.5;
    change.keep = 0.125;
    leader.set_view("late", change);
    wait_for(leader, is_mesh); // the view has a mesh before the late one comes

    const SessionState joined = late.join_session("late");
    EXPECT_EQ(joined.view.surface, surface);
    EXPECT_DOUBLE_EQ(joined.view.keep, 0.125);
    EXPECT_EQ(joined.leader, leader.client_id());
    const SessionEvent m = wait_for(late, is_mesh);
    EXPECT_EQ(test::triangles_by_content(m.mesh.mesh),
              test::triangles_by_content(offline(input, 0.5, 0.125)));
}

TEST_F(ClientServer, AResultIsResumedByItsKeyAfterAReconnect) {
    const Surface input = test_surface();
    Client client;
    client.connect(local(server_.port));
    LevelRequest request;
    request.surface = client.upload(input).surface;
    request.alpha = 0.75;
    request.keep = {0.5};
    const Level first = client.request_levels(request).at(0);
    ASSERT_FALSE(first.result.empty());

    client.reconnect();
    EXPECT_TRUE(client.connected());
    LevelRequest resume;
    resume.result = first.result;
    resume.keep = {0.25};
    const Level resumed = client.request_levels(resume).at(0);
    EXPECT_EQ(resumed.result, first.result);
    EXPECT_EQ(test::triangles_by_content(resumed.mesh),
              test::triangles_by_content(offline(input, 0.75, 0.25)));

    resume.result = std::string(64, '0');
    try {
        client.request_levels(resume);
        ADD_FAILURE() << "an unknown result was served";
    } catch (const ClientError& e) {
        EXPECT_EQ(e.code(), ErrorCode::NotFound) << e.what();
    }
}

TEST(ClientServerToken, AWrongTokenIsRefusedWithTheServersMessage) {
    const auto dir = test::temp_dir("client-token");
    ServerProcess server(dir, {"--sample", "", "--token", "s3cret"});
    Client client;
    try {
        client.connect(local(server.port, "wrong"));
        ADD_FAILURE() << "a wrong token was accepted";
    } catch (const ClientError& e) {
        EXPECT_EQ(e.code(), ErrorCode::Unauthenticated);
        EXPECT_FALSE(std::string(e.what()).empty());
    }
    EXPECT_FALSE(client.connected());
    client.connect(local(server.port, "s3cret"));
    EXPECT_TRUE(client.connected());
    EXPECT_TRUE(client.list_surfaces().empty());
    server.stop();
    std::filesystem::remove_all(dir);
}

TEST(ClientServerTls, CertificatesAreCheckedUnlessInsecureIsAsked) {
    const auto dir = test::temp_dir("client-tls");
    test::write_self_signed(dir / "cert.pem", dir / "key.pem", "ddsimp test");
    test::write_self_signed(dir / "other.pem", dir / "other-key.pem", "someone else");
    ServerProcess server(dir / "data", {"--sample", "", "--tls-cert", (dir / "cert.pem").string(),
                                        "--tls-key", (dir / "key.pem").string()});
    ConnectOptions o = local(server.port);
    o.tls = true;
    auto refusal = [&](const ConnectOptions& options) {
        Client client;
        try {
            client.connect(options);
        } catch (const ClientError& e) {
            EXPECT_EQ(e.code(), ErrorCode::Connection);
            return std::string(e.what());
        }
        return std::string("connected");
    };

    o.ca_file = (dir / "other.pem").string(); // not the server's
    EXPECT_NE(refusal(o).find("certificate verify failed"), std::string::npos) << refusal(o);
    for (const char* host : {"127.0.0.1", "localhost"}) {
        o.host = host;
        o.ca_file = (dir / "cert.pem").string(); // the server's own: trusted, names match
        Client client;
        client.connect(o);
        EXPECT_TRUE(client.list_surfaces().empty()) << host;
    }
    o.ca_file.clear();
    o.tls_insecure = true; // anything goes
    Client insecure;
    insecure.connect(o);
    EXPECT_TRUE(insecure.connected());

    ConnectOptions plain = local(server.port);
    EXPECT_NE(refusal(plain), "connected"); // no TLS to a TLS server
    server.stop();
    std::filesystem::remove_all(dir);
}

// ----- programs run as processes: the example and ddsimp remote -----

struct CliRun {
    int status = -1;
    std::string out, err;
};

std::string read_all(const std::filesystem::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

CliRun run_program(const std::string& command_line, const std::filesystem::path& scratch) {
    const auto out = scratch / "stdout", err = scratch / "stderr";
    const std::string command = command_line + " >" + out.string() + " 2>" + err.string();
    const int raw = std::system(command.c_str());
    return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, read_all(out), read_all(err)};
}

TEST_F(ClientServer, TheExampleProgramPrintsTwoLevelsCoarsestFirst) {
    {
        Client client;
        client.connect(local(server_.port));
        client.upload(test_surface(), "icosphere");
    }
    const CliRun run = run_program(
        std::string(DDSIMP_CLIENT_EXAMPLE) + " 127.0.0.1:" + std::to_string(server_.port), dir_);
    ASSERT_EQ(run.status, 0) << run.err;
    std::istringstream lines(run.out);
    std::string first, second, done;
    const auto next_exact = [&](std::string& line) { // previews (a stand-in) are skipped
        while (std::getline(lines, line) && line.rfind("preview ", 0) == 0) {
        }
    };
    next_exact(first);
    next_exact(second);
    next_exact(done);
    // 5120 triangles: 10% is 512, 50% is 2560 (by hand), the second as a refinement.
    EXPECT_EQ(first.rfind("level keep=0.1: 512 triangles", 0), 0u) << run.out;
    EXPECT_EQ(second.rfind("level keep=0.5: 2560 triangles", 0), 0u) << run.out;
    EXPECT_NE(second.find("(refinement)"), std::string::npos) << run.out;
    EXPECT_EQ(done.rfind("done: surface ", 0), 0u) << run.out;
}

#ifdef DDSIMP_CLI

CliRun run_cli(const std::string& args, const std::filesystem::path& scratch) {
    return run_program(std::string(DDSIMP_CLI) + " " + args, scratch);
}

std::vector<nlohmann::json> json_lines(const std::string& text) {
    std::vector<nlohmann::json> out;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) out.push_back(nlohmann::json::parse(line));
    return out;
}

TEST_F(ClientServer, RemoteCommandsEndToEnd) {
    const std::string sample = std::string(DDSIMP_SAMPLE_DATA) + "/SurfaceVectors.vtk"; // 756 tri
    const std::string server = " --server 127.0.0.1:" + std::to_string(server_.port);

    CliRun up = run_cli("remote upload " + sample + server, dir_);
    ASSERT_EQ(up.status, 0) << up.err;
    auto lines = json_lines(up.out);
    ASSERT_EQ(lines.size(), 1u);
    const std::string id = lines[0]["surface"];
    EXPECT_EQ(id.size(), 64u);
    EXPECT_EQ(lines[0]["triangles"], 756);

    CliRun list = run_cli("remote list --json" + server, dir_);
    ASSERT_EQ(list.status, 0) << list.err;
    lines = json_lines(list.out);
    ASSERT_EQ(lines.size(), 1u);
    EXPECT_EQ(lines[0]["surface"], id);
    EXPECT_EQ(lines[0]["triangles"], 756);
    EXPECT_EQ(lines[0]["fields"].size(), 7u); // V, Temp, Pres, AsH3, GaMe3, CH4, H2

    // For a person: a table of titles, a rule and one row, the columns aligned.
    CliRun table = run_cli("remote list" + server, dir_);
    ASSERT_EQ(table.status, 0) << table.err;
    std::vector<std::string> rows;
    for (size_t at = 0, end; (end = table.out.find('\n', at)) != std::string::npos; at = end + 1)
        rows.push_back(table.out.substr(at, end - at));
    ASSERT_EQ(rows.size(), 3u) << table.out;
    EXPECT_EQ(rows[0].rfind("surface", 0), 0u) << rows[0];
    EXPECT_EQ(rows[2].rfind(id, 0), 0u) << rows[2];
    EXPECT_EQ(rows[0].find("triangles") + 9, rows[2].find(" 756 ", id.size()) + 4) << table.out;
    EXPECT_NE(rows[2].find("V(3), Temp, Pres, AsH3, GaMe3, CH4, H2"), std::string::npos);

    const auto out = dir_ / "levels";
    CliRun simp = run_cli("remote simplify --surface " + id + " --alpha 0.5 --keep 0.5,0.25 -o " +
                              out.string() + server,
                          dir_);
    ASSERT_EQ(simp.status, 0) << simp.err;
    // One line per mesh received: a preview (when the server sent one before the exact level;
    // no file) and the exact levels (each written to a file).
    const auto exact_lines = [](const std::string& out) {
        std::vector<nlohmann::json> exact;
        for (const auto& line : json_lines(out)) {
            EXPECT_TRUE(line.contains("preview")) << line;
            EXPECT_GE(line["seconds"].get<double>(), 0);
            if (line["preview"].get<bool>())
                EXPECT_FALSE(line.contains("file")) << line;
            else
                exact.push_back(line);
        }
        return exact;
    };
    lines = exact_lines(simp.out);
    ASSERT_EQ(lines.size(), 2u);
    EXPECT_EQ(lines[0]["keep"], 0.5); // not cached: the finest as soon as it exists
    EXPECT_EQ(lines[1]["keep"], 0.25);
    for (const auto& line : lines) {
        EXPECT_TRUE(std::filesystem::file_size(line["file"].get<std::string>()) > 0);
        EXPECT_LE(line["triangles"].get<double>(), line["keep"].get<double>() * 756);
    }
    const std::string least_error_result = lines[0]["result"];

    // Cached now: coarsest first.
    CliRun again = run_cli("remote simplify --surface " + id + " --alpha 0.5 --keep 0.5,0.25 -o " +
                               out.string() + server,
                           dir_);
    ASSERT_EQ(again.status, 0) << again.err;
    lines = exact_lines(again.out);
    ASSERT_EQ(lines.size(), 2u);
    EXPECT_EQ(lines[0]["keep"], 0.25);
    EXPECT_EQ(lines[1]["keep"], 0.5);

    // --placement midpoint is a result of its own; every line says the level's error, which
    // is no smaller for the coarser level (the sample is a plane: its geometric error is 0).
    CliRun midpoint = run_cli("remote simplify --surface " + id +
                                  " --alpha 0.5 --keep 0.5,0.25 --placement midpoint -o " +
                                  (dir_ / "midpoint").string() + server,
                              dir_);
    ASSERT_EQ(midpoint.status, 0) << midpoint.err;
    lines = exact_lines(midpoint.out);
    ASSERT_EQ(lines.size(), 2u);
    EXPECT_NE(lines[0]["result"], least_error_result);
    for (const char* error : {"geometric_error", "data_error"}) {
        ASSERT_TRUE(lines[0].contains(error) && lines[1].contains(error)) << midpoint.out;
        EXPECT_GE(lines[1][error].get<double>(), lines[0][error].get<double>()) << error;
    }
    EXPECT_EQ(lines[0]["geometric_error"].get<double>(), 0);
    EXPECT_GT(lines[0]["data_error"].get<double>(), 0);

    // So is --data interpolated.
    CliRun interpolated = run_cli("remote simplify --surface " + id +
                                      " --alpha 0.5 --keep 0.5 --data interpolated -o " +
                                      (dir_ / "interpolated").string() + server,
                                  dir_);
    ASSERT_EQ(interpolated.status, 0) << interpolated.err;
    lines = exact_lines(interpolated.out);
    ASSERT_EQ(lines.size(), 1u);
    EXPECT_NE(lines[0]["result"], least_error_result);

    CliRun missing =
        run_cli("remote simplify --surface nope --keep 0.5 -o " + out.string() + server, dir_);
    EXPECT_EQ(missing.status, 1);
    EXPECT_EQ(missing.err.rfind("ddsimp: ", 0), 0u) << missing.err;
    EXPECT_NE(missing.err.find("NOT_FOUND"), std::string::npos) << missing.err;

    CliRun usage = run_cli("remote simplify --keep 0.5" + server, dir_); // no -o
    EXPECT_EQ(usage.status, 2) << usage.err;

    // Deleted: gone from the list; a second delete is NOT_FOUND.
    CliRun deleted = run_cli("remote delete " + id + server, dir_);
    ASSERT_EQ(deleted.status, 0) << deleted.err;
    lines = json_lines(deleted.out);
    ASSERT_EQ(lines.size(), 1u);
    EXPECT_EQ(lines[0]["surface"], id);
    EXPECT_EQ(lines[0]["removed"], true);
    EXPECT_EQ(run_cli("remote list --json" + server, dir_).out, "");
    CliRun twice = run_cli("remote delete " + id + server, dir_);
    EXPECT_EQ(twice.status, 1);
    EXPECT_NE(twice.err.find("NOT_FOUND"), std::string::npos) << twice.err;

    const uint16_t closed = test::free_port();
    CliRun unreachable = run_cli("remote list --server localhost:" + std::to_string(closed), dir_);
    EXPECT_EQ(unreachable.status, 1);
    EXPECT_EQ(unreachable.err, "ddsimp: cannot connect to localhost:" + std::to_string(closed) +
                                   ": Connection refused\n");
}

TEST_F(ClientServer, RemoteWatchReportsTheChangeAndWritesTheMesh) {
    const std::string sample = std::string(DDSIMP_SAMPLE_DATA) + "/SurfaceVectors.vtk";
    const std::string server = " --server 127.0.0.1:" + std::to_string(server_.port);
    const std::string id =
        json_lines(run_cli("remote upload " + sample + server, dir_).out).at(0)["surface"];
    // The watcher runs until interrupted; its output is followed as a file.
    const auto watch_dir = dir_ / "watch";
    const auto watch_out = dir_ / "watch.out";
    const pid_t pid = ::fork();
    if (pid == 0) {
        std::freopen(watch_out.c_str(), "w", stdout);
        ::execl(DDSIMP_CLI, DDSIMP_CLI, "remote", "watch", "--session", "w", "-o",
                watch_dir.c_str(), "--server",
                ("127.0.0.1:" + std::to_string(server_.port)).c_str(), nullptr);
        ::_exit(127);
    }
    auto wait_for_line = [&](const std::string& text) {
        for (int i = 0; i < 1200; ++i) { // a guard against a hang, not a speed limit
            if (read_all(watch_out).find(text) != std::string::npos) return true;
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
        }
        return false;
    };
    ASSERT_TRUE(wait_for_line("\"cause\":\"created\"")) << read_all(watch_out);
    CliRun set = run_cli(
        "remote set --session w --surface " + id + " --alpha 0.5 --keep 0.25" + server, dir_);
    ASSERT_EQ(set.status, 0) << set.err;
    const auto set_state = json_lines(set.out).at(0);
    EXPECT_EQ(set_state["cause"], "view");
    EXPECT_EQ(set_state["view"]["surface"], id);
    EXPECT_TRUE(wait_for_line("\"event\":\"mesh\"")) << read_all(watch_out);
    ::kill(pid, SIGINT);
    int status = 0;
    ::waitpid(pid, &status, 0);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;

    const auto events = json_lines(read_all(watch_out));
    bool saw_view = false, saw_mesh = false;
    for (const auto& e : events) {
        if (e["event"] == "state" && e["cause"] == "view") saw_view = true;
        if (e["event"] == "mesh") {
            saw_mesh = true;
            EXPECT_TRUE(saw_view); // the state comes before its mesh
            EXPECT_LE(e["triangles"].get<double>(), 0.25 * 756);
            EXPECT_GT(e["triangles"].get<double>(), 0);
            EXPECT_GT(std::filesystem::file_size(e["file"].get<std::string>()), 0u);
        }
    }
    EXPECT_TRUE(saw_mesh);
}
#endif

} // namespace
} // namespace ddsimp
