// The service answers at once (libddsimp-client against the real ddsimp-server): a preview
// marked as such and then replaced by the exact level; the finest level leaving before the run
// to the coarsest ends; cancellation (by the client, by a superseding request) counted and the
// computation stopped, unless another client still waits for it; fair order between clients;
// speculation after an upload, yielding its worker to any client job.
#include "mesh_comparison.h"
#include "server_harness.h"
#include "test_surfaces.h"

#include "ddsimp/client.h"

#include <mutex>
#include <thread>

namespace ddsimp {
namespace {

using test::ServerProcess;

ConnectOptions local(uint16_t port) {
    ConnectOptions o;
    o.host = "127.0.0.1";
    o.port = port;
    o.timeout = std::chrono::milliseconds(120000);
    return o;
}

Surface sphere(int level) {
    return test::with_test_fields(test::icosphere(level));
}

Surface offline(const Surface& input, double alpha, double keep) {
    Options o;
    o.alpha = alpha;
    o.keep_fraction = keep;
    return simplify(input, o).surface;
}

// Waits (polling /metrics) until `name` reads `value`; false after two minutes.
bool metric_reaches(uint16_t http_port, const std::string& name, double value) {
    for (int i = 0; i < 12000; ++i) {
        if (test::metric(http_port, name) == value) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
}

ErrorCode error_of(const std::shared_future<Level>& level) {
    try {
        level.get();
    } catch (const ClientError& e) {
        return e.code();
    }
    return ErrorCode::Internal;
}

LevelRequest raw_request(const std::string& surface, double alpha, float keep) {
    LevelRequest request;
    request.surface = surface;
    request.alpha = alpha;
    request.keep = {keep};
    request.encoding = Encoding::Raw;
    return request;
}

// Every mesh a one-level request received, previews included, and its exact level.
struct Answer {
    std::vector<Level> seen;
    Level exact;
};
Answer ask(Client& client, const LevelRequest& request) {
    Answer answer;
    PendingRequest pending =
        client.request(request, [&](const Level& l) { answer.seen.push_back(l); });
    pending.done.get();
    answer.exact = pending.levels[0].get();
    return answer;
}

class AnswersAtOnce : public ::testing::Test {
protected:
    explicit AnswersAtOnce(std::vector<std::string> flags = {})
        : dir_(test::temp_dir(name())), server_(dir_, with_sample_off(std::move(flags))) {}
    ~AnswersAtOnce() override {
        server_.stop();
        std::filesystem::remove_all(dir_);
    }
    static std::vector<std::string> with_sample_off(std::vector<std::string> flags) {
        flags.insert(flags.end(), {"--sample", ""});
        return flags;
    }
    static std::string name() {
        return std::string("at-once-") +
               ::testing::UnitTest::GetInstance()->current_test_info()->name();
    }
    std::filesystem::path dir_;
    ServerProcess server_;
};

TEST_F(AnswersAtOnce, APreviewIsMarkedAndThenReplacedByTheExactLevel) {
    const Surface input = sphere(6);
    Client client;
    client.connect(local(server_.port));
    EXPECT_TRUE(client.has_capability("previews"));
    LevelRequest request;
    request.surface = client.upload(input, "sphere").surface;
    request.alpha = 0.3;
    request.keep = {0.1};
    request.encoding = Encoding::Raw;
    std::vector<Level> seen;
    PendingRequest pending = client.request(request, [&](const Level& l) { seen.push_back(l); });
    pending.done.get();
    ASSERT_EQ(seen.size(), 2u);
    EXPECT_TRUE(seen[0].preview); // a vertex clustering: nothing of this surface was ready
    EXPECT_GT(seen[0].triangles, 0u);
    EXPECT_FALSE(seen[1].preview);
    const Level exact = pending.levels[0].get();
    EXPECT_FALSE(exact.preview); // the future holds the exact level, never the preview
    EXPECT_TRUE(test::same_bytes(exact.mesh, offline(input, 0.3, 0.1)));

    // Another alpha: the preview is the same level of the nearest ready record (alpha 0.3).
    request.alpha = 0.35;
    seen.clear();
    pending = client.request(request, [&](const Level& l) { seen.push_back(l); });
    pending.done.get();
    ASSERT_EQ(seen.size(), 2u);
    EXPECT_TRUE(seen[0].preview);
    EXPECT_TRUE(test::same_bytes(seen[0].mesh, offline(input, 0.3, 0.1)));
    EXPECT_TRUE(test::same_bytes(pending.levels[0].get().mesh, offline(input, 0.35, 0.1)));

    // Ready now: no preview.
    seen.clear();
    client.request(request, [&](const Level& l) { seen.push_back(l); }).done.get();
    ASSERT_EQ(seen.size(), 1u);
    EXPECT_FALSE(seen[0].preview);
    EXPECT_GE(test::metric(server_.http_port, "ddsimp_previews_sent_total"), 2);
}

TEST_F(AnswersAtOnce, TheFinestLevelLeavesBeforeTheRunToTheCoarsestEnds) {
    const Surface input = sphere(6);
    Client client;
    client.connect(local(server_.port));
    LevelRequest request;
    request.surface = client.upload(input, "sphere").surface;
    request.alpha = 0.6;
    request.keep = {0.05, 0.5};
    request.encoding = Encoding::Raw;
    std::vector<uint32_t> exact;
    auto arrived = [&](const Level& l) {
        if (!l.preview) exact.push_back(l.index);
    };
    PendingRequest pending = client.request(request, arrived);
    pending.done.get();
    // Not cached: the finest (0.5) as soon as a run has passed it, then the coarsest.
    EXPECT_EQ(exact, (std::vector<uint32_t>{1, 0}));
    for (size_t i = 0; i < request.keep.size(); ++i)
        EXPECT_TRUE(
            test::same_bytes(pending.levels[i].get().mesh, offline(input, 0.6, request.keep[i])))
            << i;
    // All ready: coarsest first.
    exact.clear();
    client.request(request, arrived).done.get();
    EXPECT_EQ(exact, (std::vector<uint32_t>{0, 1}));
}

TEST_F(AnswersAtOnce, ACancelledRequestStopsItsComputation) {
    Client client;
    client.connect(local(server_.port));
    LevelRequest request;
    request.surface = client.upload(sphere(6), "sphere").surface;
    request.keep = {0.01};
    PendingRequest pending = client.request(request);
    ASSERT_TRUE(metric_reaches(server_.http_port, "ddsimp_reductions_running", 1));
    client.cancel(pending.id);
    EXPECT_EQ(error_of(pending.levels[0]), ErrorCode::Cancelled);
    EXPECT_TRUE(metric_reaches(server_.http_port, "ddsimp_reductions_running", 0));
    EXPECT_EQ(test::metric(server_.http_port, "ddsimp_reductions_cancelled_total"), 1);
}

TEST_F(AnswersAtOnce, ASupersedingRequestCancelsTheOlderOne) {
    Client client;
    client.connect(local(server_.port));
    LevelRequest request;
    request.surface = client.upload(sphere(6), "sphere").surface;
    request.keep = {0.01};
    request.alpha = 0.2;
    request.supersede = true;
    PendingRequest older = client.request(request);
    ASSERT_TRUE(metric_reaches(server_.http_port, "ddsimp_reductions_running", 1));
    request.alpha = 0.8;
    request.keep = {0.9};
    PendingRequest newer = client.request(request);
    EXPECT_EQ(error_of(older.levels[0]), ErrorCode::Cancelled);
    EXPECT_FALSE(newer.levels[0].get().preview);
    // The older job counts itself cancelled when it stops, which may be after its answer left.
    EXPECT_TRUE(metric_reaches(server_.http_port, "ddsimp_reductions_cancelled_total", 1));
}

TEST_F(AnswersAtOnce, AComputationAnotherClientWaitsForGoesOn) {
    const Surface input = sphere(6);
    Client first, second;
    first.connect(local(server_.port));
    second.connect(local(server_.port));
    LevelRequest request;
    request.surface = first.upload(input, "sphere").surface;
    request.keep = {0.05};
    request.encoding = Encoding::Raw;
    // The second client's request starts the computation; the first's joins it, and its cancel
    // follows it on the same connection.
    PendingRequest b = second.request(request);
    ASSERT_TRUE(metric_reaches(server_.http_port, "ddsimp_reductions_running", 1));
    PendingRequest a = first.request(request);
    first.cancel(a.id);
    EXPECT_EQ(error_of(a.levels[0]), ErrorCode::Cancelled);
    EXPECT_TRUE(test::same_bytes(b.levels[0].get().mesh, offline(input, 0.5, 0.05)));
    EXPECT_EQ(test::metric(server_.http_port, "ddsimp_reductions_cancelled_total"), 0);
}

class FairCompute : public AnswersAtOnce {
protected:
    FairCompute() : AnswersAtOnce({"--threads", "1"}) {}
};

// One worker: a client's burst of requests waits its turn behind another client's one request,
// which runs after at most the job already running.
TEST_F(FairCompute, AnotherClientsRequestRunsNextAfterTheJobRunning) {
    const Surface input = sphere(6);
    Client busy, other;
    busy.connect(local(server_.port));
    other.connect(local(server_.port));
    const std::string surface = busy.upload(input, "sphere").surface;
    std::mutex mutex;
    std::vector<std::string> finished;
    std::promise<void> busy_started;
    bool started = false;
    std::vector<PendingRequest> burst;
    for (int i = 0; i < 4; ++i) {
        LevelRequest request;
        request.surface = surface;
        request.alpha = 0.1 * (i + 1);
        request.keep = {0.05};
        burst.push_back(busy.request(request, [&, i](const Level& l) {
            std::lock_guard lock(mutex);
            if (!started) started = true, busy_started.set_value();
            if (!l.preview) finished.push_back("busy " + std::to_string(i));
        }));
    }
    busy_started.get_future().wait(); // the server has read the burst's first request
    LevelRequest mine;
    mine.surface = surface;
    mine.alpha = 0.95;
    mine.keep = {0.05};
    other
        .request(mine,
                 [&](const Level& l) {
                     std::lock_guard lock(mutex);
                     if (!l.preview) finished.push_back("other");
                 })
        .done.get();
    for (PendingRequest& p : burst) p.done.get();
    ASSERT_EQ(finished.size(), 5u);
    const size_t position =
        size_t(std::find(finished.begin(), finished.end(), "other") - finished.begin());
    EXPECT_LE(position, 2u) << "finished " << position << "th of 5";
}

class FairComputeTwoWorkers : public AnswersAtOnce {
protected:
    FairComputeTwoWorkers() : AnswersAtOnce({"--threads", "2"}) {}
};

// Both workers run one client's jobs: another client's request takes the newer job's worker at
// once, and that job runs again afterwards, with the library's bytes.
TEST_F(FairComputeTwoWorkers, AClientWithNothingRunningTakesAWorkerFromOneRunningTwo) {
    const Surface large = sphere(7), small = sphere(3); // 327,680 and 1,280 triangles
    Client busy, other;
    busy.connect(local(server_.port));
    other.connect(local(server_.port));
    const std::string large_id = busy.upload(large, "large").surface;
    const std::string small_id = other.upload(small, "small").surface;
    std::vector<PendingRequest> burst;
    for (double alpha : {0.2, 0.7})
        burst.push_back(busy.request(raw_request(large_id, alpha, 0.05f)));
    ASSERT_TRUE(metric_reaches(server_.http_port, "ddsimp_reductions_running", 2));

    const Level mine = other.request(raw_request(small_id, 0.3, 0.1f)).levels[0].get();
    EXPECT_TRUE(test::same_bytes(mine.mesh, offline(small, 0.3, 0.1)));
    EXPECT_EQ(test::metric(server_.http_port, "ddsimp_reductions_yielded_total"), 1);
    EXPECT_TRUE(test::same_bytes(burst[0].levels[0].get().mesh, offline(large, 0.2, 0.05)));
    EXPECT_TRUE(test::same_bytes(burst[1].levels[0].get().mesh, offline(large, 0.7, 0.05)));
}

// Speculation (on by default; the test harness turns it off elsewhere).
class Speculation : public AnswersAtOnce {
protected:
    explicit Speculation(std::vector<std::string> flags = {})
        : AnswersAtOnce(with_speculation(std::move(flags))) {}
    static std::vector<std::string> with_speculation(std::vector<std::string> flags) {
        flags.insert(flags.end(), {"--speculate", "true"});
        return flags;
    }
};

// After an upload the idle pool makes the records at alpha 0, 0.5 and 1: a request at alpha 0.4
// first gets the level of the alpha 0.5 record as its preview, and a request at alpha 1 is cut
// from a ready record, with the library's bytes.
TEST_F(Speculation, AnUploadGetsRecordsAtThreeAlphasWhileIdle) {
    const Surface input = sphere(5);
    Client client;
    client.connect(local(server_.port));
    const std::string surface = client.upload(input, "sphere").surface;
    ASSERT_TRUE(metric_reaches(server_.http_port, "ddsimp_speculative_records_total", 3));
    ASSERT_TRUE(metric_reaches(server_.http_port, "ddsimp_speculations_pending", 0));

    const Answer between = ask(client, raw_request(surface, 0.4, 0.1f));
    ASSERT_EQ(between.seen.size(), 2u);
    EXPECT_TRUE(between.seen[0].preview);
    EXPECT_TRUE(test::same_bytes(between.seen[0].mesh, offline(input, 0.5, 0.1)));
    EXPECT_TRUE(test::same_bytes(between.exact.mesh, offline(input, 0.4, 0.1)));

    const Answer ready = ask(client, raw_request(surface, 1, 0.1f));
    ASSERT_EQ(ready.seen.size(), 1u);
    EXPECT_FALSE(ready.seen[0].preview);
    EXPECT_TRUE(ready.seen[0].cached);
    EXPECT_TRUE(test::same_bytes(ready.exact.mesh, offline(input, 1, 0.1)));
}

class SpeculationOneWorker : public Speculation {
protected:
    SpeculationOneWorker() : Speculation({"--threads", "1"}) {}
};

// A client's job takes the only worker from a running speculation, which runs again later.
TEST_F(SpeculationOneWorker, YieldsItsWorkerToAClientsJob) {
    Client client;
    client.connect(local(server_.port));
    client.upload(sphere(7), "large"); // 327,680 triangles: its speculation runs a while
    ASSERT_TRUE(metric_reaches(server_.http_port, "ddsimp_reductions_running", 1));
    const Surface small = sphere(3);
    LevelRequest request;
    request.surface = client.upload(small, "small").surface; // a job of the client's: it waits
    request.alpha = 0.3;
    request.keep = {0.1};
    request.encoding = Encoding::Raw;
    EXPECT_TRUE(
        test::same_bytes(client.request(request).levels[0].get().mesh, offline(small, 0.3, 0.1)));
    EXPECT_GE(test::metric(server_.http_port, "ddsimp_reductions_yielded_total"), 1);
    EXPECT_GT(test::metric(server_.http_port, "ddsimp_speculations_pending"), 0);
}

} // namespace
} // namespace ddsimp
