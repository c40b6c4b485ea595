// The same request made locally (ddsimp::simplify) and remotely (libddsimp-client through the
// real ddsimp-server) gives identical bytes: both strategies, every placement, and alpha values a
// float cannot hold exactly, with the library's defaults for everything a request leaves unset;
// and a level downloaded as .glb holds the same surface.
#include "glb_reader.h"
#include "mesh_comparison.h"
#include "server_harness.h"
#include "test_surfaces.h"

#include "ddsimp/client.h"

namespace ddsimp {
namespace {

struct Case {
    Strategy strategy;
    Placement placement;
    double alpha;
};

std::string case_name(const ::testing::TestParamInfo<Case>& info) {
    const Case& c = info.param;
    std::string name = c.strategy == Strategy::EdgeCollapse ? "Edge" : "Vertex";
    name += c.placement == Placement::LeastError ? "LeastError"
            : c.placement == Placement::Midpoint ? "Midpoint"
                                                 : "Volume";
    return name + "Alpha" + std::to_string(int(c.alpha * 10 + 0.5));
}

std::vector<Case> all_cases() {
    std::vector<Case> out;
    for (Strategy s : {Strategy::EdgeCollapse, Strategy::VertexRemoval})
        for (Placement p :
             {Placement::LeastError, Placement::Midpoint, Placement::VolumePreserving})
            for (double alpha : {0.3, 0.7}) out.push_back({s, p, alpha});
    return out;
}

class SameBytes : public ::testing::TestWithParam<Case> {
protected:
    static void SetUpTestSuite() {
        dir_ = new std::filesystem::path(test::temp_dir("same-bytes"));
        server_ = new test::ServerProcess(*dir_, {"--sample", ""});
        client_ = new Client;
        ConnectOptions o;
        o.host = "127.0.0.1";
        o.port = server_->port;
        o.timeout = std::chrono::milliseconds(60000);
        client_->connect(o);
        surface_ = new std::string(client_->upload(input(), "icosphere").surface);
    }
    static void TearDownTestSuite() {
        delete client_;
        server_->stop();
        delete server_;
        std::filesystem::remove_all(*dir_);
        delete dir_;
        delete surface_;
    }
    // 5120 triangles with a scalar and a vector field.
    static Surface input() { return test::with_test_fields(test::icosphere(4)); }

    static std::filesystem::path* dir_;
    static test::ServerProcess* server_;
    static Client* client_;
    static std::string* surface_;
};
std::filesystem::path* SameBytes::dir_ = nullptr;
test::ServerProcess* SameBytes::server_ = nullptr;
Client* SameBytes::client_ = nullptr;
std::string* SameBytes::surface_ = nullptr;

INSTANTIATE_TEST_SUITE_P(All, SameBytes, ::testing::ValuesIn(all_cases()), case_name);

TEST_P(SameBytes, RemoteLevelEqualsTheLibrarysResult) {
    const Case c = GetParam();
    LevelRequest request;
    request.surface = *surface_;
    request.alpha = c.alpha;
    request.strategy = c.strategy;
    request.placement = c.placement;
    request.keep = {0.1};
    request.encoding = Encoding::Raw;
    const Level level = client_->request_levels(request).at(0);

    Options local = request; // the request's options, as the library takes them
    local.keep_fraction = 0.1;
    const Surface expected = simplify(input(), local).surface;
    EXPECT_EQ(level.triangles, expected.triangle_count());
    EXPECT_TRUE(test::same_bytes(level.mesh, expected));
}

// What a request leaves unset is what the library leaves unset.
TEST_F(SameBytes, DefaultsAreTheLibrarys) {
    LevelRequest request;
    request.surface = *surface_;
    request.keep = {0.25};
    request.encoding = Encoding::Raw;
    const Level level = client_->request_levels(request).at(0);
    Options local;
    local.keep_fraction = 0.25;
    EXPECT_TRUE(test::same_bytes(level.mesh, simplify(input(), local).surface));
}

// GET /surfaces/ID/level.glb holds the library's result for the same options: the same
// positions, triangles and fields (as _NAME attributes; the edge collapse's data interpolated).
TEST_F(SameBytes, ADownloadedGlbHoldsTheLibrarysLevel) {
    for (const Case c : {Case{Strategy::EdgeCollapse, Placement::VolumePreserving, 0.3},
                         Case{Strategy::VertexRemoval, Placement::LeastError, 0.7}}) {
        const bool edge = c.strategy == Strategy::EdgeCollapse;
        const std::string query =
            std::string("?alpha=") + (c.alpha < 0.5 ? "0.3" : "0.7") +
            "&keep=0.1&strategy=" + (edge ? "edge" : "vertex") +
            "&placement=" + (edge ? "volume&data=interpolated" : "least-error");
        SCOPED_TRACE(query);
        const std::string response =
            test::http_get(server_->http_port, "/surfaces/" + *surface_ + "/level.glb" + query);
        const size_t body = response.find("\r\n\r\n");
        ASSERT_NE(body, std::string::npos) << response;
        ASSERT_EQ(response.rfind("HTTP/1.1 200 OK", 0), 0u) << response.substr(0, 400);
        const test::Glb glb(response.substr(body + 4));

        Options local;
        local.alpha = c.alpha;
        local.strategy = c.strategy;
        local.placement = c.placement;
        if (edge) local.data_placement = DataPlacement::Interpolated;
        local.keep_fraction = 0.1;
        const Surface expected = simplify(input(), local).surface;
        const std::vector<double> positions(expected.positions.begin(), expected.positions.end());
        EXPECT_EQ(glb.attribute("POSITION"), positions);
        const std::vector<double> triangles(expected.triangles.begin(), expected.triangles.end());
        EXPECT_EQ(glb.accessor(glb.primitive()["indices"]), triangles);
        ASSERT_EQ(expected.fields.size(), 2u);
        for (const Field& f : expected.fields)
            EXPECT_EQ(glb.attribute("_" + f.name),
                      std::vector<double>(f.values.begin(), f.values.end()))
                << f.name;
    }
}

// The download takes the rest of a request's options too: the driving fields, the feature angle
// and the term set, and gives the library's level for them.
TEST_F(SameBytes, ADownloadTakesDrivingFieldsFeatureAngleAndTerms) {
    const std::string query = "?alpha=0.6&keep=0.2&fields=pressure&feature-angle=40&terms=paper";
    const std::string response =
        test::http_get(server_->http_port, "/surfaces/" + *surface_ + "/level.glb" + query);
    const size_t body = response.find("\r\n\r\n");
    ASSERT_NE(body, std::string::npos) << response;
    ASSERT_EQ(response.rfind("HTTP/1.1 200 OK", 0), 0u) << response.substr(0, 400);
    const test::Glb glb(response.substr(body + 4));

    Options local;
    local.alpha = 0.6;
    local.keep_fraction = 0.2;
    local.gradient_fields = {"pressure"};
    local.feature_angle = 40;
    local.terms = Terms::AngleDeficitGradient;
    const Surface expected = simplify(input(), local).surface;
    EXPECT_EQ(glb.attribute("POSITION"),
              std::vector<double>(expected.positions.begin(), expected.positions.end()));
    EXPECT_EQ(glb.accessor(glb.primitive()["indices"]),
              std::vector<double>(expected.triangles.begin(), expected.triangles.end()));
    // and not the level of the defaults
    Options defaults;
    defaults.alpha = 0.6;
    defaults.keep_fraction = 0.2;
    const Surface other = simplify(input(), defaults).surface;
    EXPECT_NE(glb.attribute("POSITION"),
              std::vector<double>(other.positions.begin(), other.positions.end()));

    const std::string unknown = test::http_get(
        server_->http_port, "/surfaces/" + *surface_ + "/level.glb?keep=0.5&fields=nothing");
    // as a request names it: NOT_FOUND
    EXPECT_EQ(unknown.rfind("HTTP/1.1 404", 0), 0u) << unknown.substr(0, 400);
    EXPECT_NE(unknown.find("nothing"), std::string::npos) << unknown;
}

} // namespace
} // namespace ddsimp
