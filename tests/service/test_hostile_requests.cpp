// Hostile requests against a real ddsimp-server: request + cancel floods that try to get more jobs
// computed than a client's places allow, requests padded with unknown fields, a burst of session
// views, and requests that leave result keys behind. Each is checked with the server's own
// accounting (/metrics) and, where memory is at stake, against its resident set.
//
// One compute worker (--threads 1) held by a long computation of another client makes the
// attacker's jobs wait in the queue, so that what a job holds while it waits can be seen.
#include "hostile_support.h"

namespace ddsimp::test {
namespace {

class HostileRequests : public ::testing::Test {
protected:
    void start(std::vector<std::string> flags) {
        flags.insert(flags.end(), {"--threads", "1", "--sample", ""});
        server_ = std::make_unique<ServerProcess>(temp_dir(name()), flags);
        blocker_ = std::make_unique<RawClient>(server_->port);
        blocker_->hello({});
        large_ = blocker_->upload(icosphere(7), 1, "large").surface(); // 327,680 triangles
        attacker_ = std::make_unique<RawClient>(server_->port);
        attacker_->hello({"sessions"});
        small_ = attacker_->upload(small_surface(), 1, "small").surface();
    }
    static std::string name() {
        return ::testing::UnitTest::GetInstance()->current_test_info()->name();
    }
    double metric(const std::string& name) { return test::metric(server_->http_port, name); }

    // The only worker computes the large surface down to 1% until cancel_blocker().
    void hold_the_worker() {
        blocker_->send(level_request(large_, {0.01f}, 1, 0.5f));
        ASSERT_EQ(await_metric(server_->http_port, "ddsimp_reductions_running", 1), 1);
    }
    void cancel_blocker() {
        v1::Cancel cancel;
        cancel.set_request_id(1);
        blocker_->send(cancel);
        EXPECT_EQ(next_error(*blocker_).code(), v1::Error::CANCELLED);
    }
    // Everything the attacker sent before has been handled once the Pong is back; the errors
    // that came before it.
    std::vector<v1::Error> errors_until_pong(uint64_t nonce = 7) {
        v1::Ping ping;
        ping.set_nonce(nonce);
        attacker_->send(ping);
        std::vector<v1::Error> errors;
        for (;;) {
            const std::optional<protocol::Frame> f = attacker_->next();
            if (!f) throw std::runtime_error("closed before the Pong");
            if (f->type == v1::ERROR) errors.push_back(protocol::parse_payload<v1::Error>(*f));
            if (f->type == v1::PONG) return errors;
        }
    }

    std::unique_ptr<ServerProcess> server_;
    std::unique_ptr<RawClient> blocker_, attacker_;
    std::string large_, small_;
};

size_t count(const std::vector<v1::Error>& errors, v1::Error::Code code) {
    return size_t(std::count_if(errors.begin(), errors.end(),
                                [&](const v1::Error& e) { return e.code() == code; }));
}

// 40 request + cancel pairs in one burst while the worker is busy: a cancelled request's job that
// has not started is taken back, so its place is free at once and nothing of it is ever computed.
TEST_F(HostileRequests, ACancelTakesBackAJobThatHasNotStarted) {
    start({});
    hold_the_worker();
    const double computations = metric("ddsimp_computations_total");
    std::string burst;
    for (uint64_t id = 1; id <= 40; ++id) {
        burst += protocol::encode_frame(level_request(large_, {0.5f}, id, 0.01f * float(id)));
        v1::Cancel cancel;
        cancel.set_request_id(id);
        burst += protocol::encode_frame(cancel);
    }
    attacker_->send_bytes(burst);
    const std::vector<v1::Error> errors = errors_until_pong();
    EXPECT_EQ(count(errors, v1::Error::CANCELLED), 40u);
    EXPECT_EQ(count(errors, v1::Error::RESOURCE_EXHAUSTED), 0u);
    EXPECT_EQ(metric("ddsimp_request_jobs"), 1); // the blocker's only
    EXPECT_EQ(metric("ddsimp_reductions_running"), 1) << "the blocker finished too early";

    cancel_blocker();
    EXPECT_EQ(await_metric(server_->http_port, "ddsimp_request_jobs", 0), 0);
    EXPECT_EQ(metric("ddsimp_request_job_bytes"), 0);
    EXPECT_EQ(metric("ddsimp_computations_total"), computations);
    attacker_->send(level_request(small_, {0.5f}, 41));
    EXPECT_EQ(attacker_->level().begin.request_id(), 41u);
}

// Requests that are not cancelled keep their places while they wait: the 17th is refused.
TEST_F(HostileRequests, WaitingRequestsKeepTheirPlaces) {
    start({});
    hold_the_worker();
    std::string burst;
    for (uint64_t id = 1; id <= 17; ++id)
        burst += protocol::encode_frame(level_request(large_, {0.5f}, id, 0.01f * float(id)));
    attacker_->send_bytes(burst);
    const std::vector<v1::Error> errors = errors_until_pong();
    ASSERT_EQ(errors.size(), 1u);
    EXPECT_EQ(errors[0].code(), v1::Error::RESOURCE_EXHAUSTED);
    EXPECT_EQ(errors[0].request_id(), 17u);
    EXPECT_EQ(metric("ddsimp_request_jobs"), 17); // the blocker's and the attacker's 16
}

// An unknown field of 4 MiB in each of 16 queued requests: a job keeps what its levels need,
// never the request, so the server holds a few hundred bytes per job, not 4 MiB.
TEST_F(HostileRequests, APaddedRequestCostsOnlyWhatItsJobNeeds) {
    constexpr size_t kPadding = 4 * kMiB;
    start({"--max-frame-bytes", std::to_string(kPadding + kMiB)});
    hold_the_worker();
    // Field 1000, length-delimited: unknown to the server, kept by the parser.
    std::string padding = {char(0xC2), char(0x3E)}; // the tag (1000 << 3 | 2) as a varint
    for (size_t n = kPadding; n > 0; n >>= 7) padding += char((n & 0x7F) | (n > 0x7F ? 0x80 : 0));
    padding += std::string(kPadding, 'p');
    const auto send_padded = [&](uint64_t id) {
        const std::string payload =
            level_request(large_, {0.5f}, id, 0.02f * float(id)).SerializeAsString() + padding;
        unsigned char header[protocol::kHeaderBytes];
        protocol::write_header(header, v1::REQUEST, uint32_t(payload.size()));
        attacker_->send_bytes(std::string(reinterpret_cast<char*>(header), sizeof header) +
                              payload);
    };
    // The first one leaves the allocator holding a frame's buffers for the next frames.
    send_padded(1);
    EXPECT_TRUE(errors_until_pong(1).empty());
    const size_t before = server_->status_bytes("VmRSS");
    for (uint64_t id = 2; id <= 16; ++id) send_padded(id);
    EXPECT_TRUE(errors_until_pong(2).empty());
    EXPECT_EQ(metric("ddsimp_request_jobs"), 17);
    const double job_bytes = metric("ddsimp_request_job_bytes");
    EXPECT_GT(job_bytes, 0);
    EXPECT_LT(job_bytes, 17 * 4096) << "a job holds more than its levels need";
    const size_t after = server_->status_bytes("VmRSS");
    RecordProperty("rss_kib_one_padded", int(before >> 10));
    RecordProperty("rss_kib_sixteen_padded", int(after >> 10));
    RecordProperty("request_job_bytes", int(job_bytes));
    // The blocker's run goes on meanwhile, and its engine's arrays grow in 2 MiB huge pages.
    constexpr size_t kBlockerGrowth = 16 * kMiB; // with the slack, under the 60 MiB of padding
    EXPECT_LE(after,
              before + with_sanitizer_memory(size_t(job_bytes) + kAllocatorSlack + kBlockerGrowth))
        << "resident " << (before >> 10) << " KiB with one padded request queued, " << (after >> 10)
        << " KiB with 16 (" << 15 * (kPadding >> 10) << " KiB more padding)";
    attacker_.reset(); // its jobs end with its connection and stop when their turn comes
    cancel_blocker();
    EXPECT_EQ(await_metric(server_->http_port, "ddsimp_request_jobs", 0), 0);
    EXPECT_EQ(metric("ddsimp_request_job_bytes"), 0);
}

// 30 views of a session in a row while the worker is busy: only the newest is computed and
// sent; the older ones' jobs are skipped.
TEST_F(HostileRequests, OnlyTheNewestSessionViewIsComputed) {
    start({});
    v1::JoinSession join;
    join.set_name("views");
    attacker_->send(join);
    attacker_->expect<v1::SessionState>();
    hold_the_worker();
    const double computations = metric("ddsimp_computations_total");
    std::string burst;
    for (int i = 1; i <= 30; ++i) {
        v1::SetSessionState change;
        change.set_name("views");
        change.set_set_alpha(true);
        if (i == 1) change.mutable_view()->set_surface(small_);
        change.mutable_view()->set_alpha(0.01f * float(i));
        change.mutable_view()->set_keep(0.5f);
        burst += protocol::encode_frame(change);
    }
    attacker_->send_bytes(burst);
    EXPECT_TRUE(errors_until_pong().empty());
    cancel_blocker();
    const RawClient::Level level = attacker_->level();
    EXPECT_EQ(level.begin.session(), "views");
    v1::View newest;
    newest.set_surface(small_);
    newest.set_alpha(0.01f * float(30));
    newest.set_keep(0.5f);
    EXPECT_EQ(level.begin.result(), protocol::result_key(small_, protocol::options_from(newest)));
    EXPECT_EQ(await_metric(server_->http_port, "ddsimp_session_views_skipped_total", 29), 29);
    // The newest view's record and level, nothing for the 29 before it.
    EXPECT_EQ(metric("ddsimp_computations_total"), computations + 2);
}

// Requests that fail (a gradient field the surface does not have, 64 names of 200 bytes each)
// leave no key behind; the keys of results that exist stay within --max-remembered-kb, the
// least recently used forgotten first, and their bytes are in /metrics.
TEST_F(HostileRequests, RememberedResultKeysStayWithinTheirBound) {
    constexpr size_t kBoundKiB = 64;
    start({"--max-remembered-kb", std::to_string(kBoundKiB)});
    for (uint64_t id = 1; id <= 300; ++id) {
        v1::Request r = level_request(small_, {0.5f}, id, 0.001f * float(id));
        for (int f = 0; f < 64; ++f)
            r.add_gradient_fields(std::string(190, 'a') + std::to_string(id * 100 + f));
        attacker_->send(r);
        EXPECT_EQ(next_error(*attacker_).code(), v1::Error::NOT_FOUND);
    }
    EXPECT_EQ(metric("ddsimp_remembered_results"), 0);
    EXPECT_EQ(metric("ddsimp_remembered_bytes"), 0);

    const Surface tiny = with_test_fields(icosphere(1));
    const std::string surface = attacker_->upload(tiny, 2, "tiny").surface();
    std::vector<std::string> keys;
    for (uint64_t id = 1000; id < 1400; ++id) {
        attacker_->send(level_request(surface, {0.5f}, id, 0.002f * float(id - 999)));
        keys.push_back(attacker_->level().begin.result());
        attacker_->expect<v1::RequestDone>();
    }
    const double remembered = metric("ddsimp_remembered_results");
    const double bytes = metric("ddsimp_remembered_bytes");
    EXPECT_GT(remembered, 0);
    EXPECT_LT(remembered, 400) << "the bound forgot nothing";
    RecordProperty("remembered_results", int(remembered));
    RecordProperty("remembered_bytes", int(bytes));
    EXPECT_LE(bytes, kBoundKiB << 10);
    EXPECT_GT(bytes, (kBoundKiB << 10) / 2);
    // The newest key resumes; the oldest is forgotten.
    v1::Request resume;
    resume.set_request_id(2000);
    resume.set_result(keys.back());
    resume.add_keep(0.25f);
    attacker_->send(resume);
    EXPECT_EQ(attacker_->level().begin.result(), keys.back());
    attacker_->expect<v1::RequestDone>();
    resume.set_request_id(2001);
    resume.set_result(keys.front());
    attacker_->send(resume);
    const v1::Error forgotten = next_error(*attacker_);
    EXPECT_EQ(forgotten.code(), v1::Error::NOT_FOUND);
    EXPECT_EQ(forgotten.request_id(), 2001u);
}

// A request for 64 levels of a surface whose levels together cannot fit in the client's send
// queue is refused up front, with what it would take, before anything is computed; one that
// fits is answered level by level within the queue bound.
TEST_F(HostileRequests, ARequestWhoseLevelsCannotFitIsRefusedUpFront) {
    constexpr size_t kQueueMiB = 8;
    start({"--max-queue-mb", std::to_string(kQueueMiB)});
    const double computations = metric("ddsimp_computations_total");
    std::vector<float> keeps;
    for (int i = 1; i <= 64; ++i) keeps.push_back(0.01f * float(i));
    attacker_->send(level_request(large_, keeps, 1));
    const v1::Error refused = next_error(*attacker_);
    EXPECT_EQ(refused.code(), v1::Error::RESOURCE_EXHAUSTED);
    EXPECT_EQ(refused.request_id(), 1u);
    EXPECT_NE(refused.message().find("its 64 levels take about"), std::string::npos)
        << refused.message();
    EXPECT_NE(refused.message().find("--max-queue-mb"), std::string::npos) << refused.message();
    EXPECT_EQ(metric("ddsimp_computations_total"), computations);
    EXPECT_EQ(metric("ddsimp_request_jobs"), 0);

    // 64 levels of the small surface fit: every one arrives, the queue stays within its bound.
    attacker_->send(level_request(small_, keeps, 2));
    std::set<uint32_t> levels;
    for (int i = 0; i < 64; ++i) {
        const RawClient::Level l = attacker_->level();
        EXPECT_EQ(l.begin.request_id(), 2u);
        levels.insert(l.begin.level());
    }
    EXPECT_EQ(levels.size(), 64u);
    EXPECT_EQ(attacker_->expect<v1::RequestDone>().request_id(), 2u);
    EXPECT_LE(metric("ddsimp_client_queue_bytes_max"), double(kQueueMiB << 20));
    EXPECT_EQ(metric("ddsimp_connections_dropped_total"), 0);
}

// A request whose levels are cached is answered while the only worker computes another client's
// surface: it does not wait behind that computation.
TEST_F(HostileRequests, ACachedLevelIsAnsweredWhileTheWorkersAreBusy) {
    start({});
    attacker_->send(level_request(small_, {0.5f}, 1));
    EXPECT_FALSE(attacker_->level().begin.cached());
    EXPECT_EQ(attacker_->expect<v1::RequestDone>().request_id(), 1u);
    hold_the_worker();
    attacker_->send(level_request(small_, {0.5f}, 2));
    const RawClient::Level again = attacker_->level();
    EXPECT_EQ(again.begin.request_id(), 2u);
    EXPECT_TRUE(again.begin.cached());
    EXPECT_EQ(attacker_->expect<v1::RequestDone>().request_id(), 2u);
    EXPECT_EQ(metric("ddsimp_reductions_running"), 1) << "answered only once the worker was free";
    cancel_blocker();
}

} // namespace
} // namespace ddsimp::test
