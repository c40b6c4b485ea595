// The reduction half of the Service: requests and session meshes. A request's record runs on the
// scheduler's pool (fair between clients) only as deep as its coarsest level; the finest level
// leaves as soon as a run has passed it; a preview goes out at once when the exact level is not
// ready; a computation nobody waits for any more is cancelled (computations.h). The library
// cannot hand out a level in the middle of a run, so the finest level's run and the run on to the
// coarsest are two runs (the second repeats the first's operations: same bytes).
#include "service.h"

#include "client_limits.h"
#include "log_text.h"
#include "previews.h"

#include "ddsimp/protocol/reduction_options.h"
#include "ddsimp/protocol/refinement.h"

#include <boost/asio/post.hpp>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <set>

namespace ddsimp::server {
namespace asio = boost::asio;

using Clock = std::chrono::steady_clock;

// One level or refinement, ready to queue.
struct Service::PreparedLevel {
    v1::MeshBegin begin;
    std::shared_ptr<const std::string> blob;
};

namespace {

// The bytes of a request's levels as the client receives them: raw, 12 per triangle and, for a
// share of the vertices as large as the level's share of the triangles, 12 plus 4 per field
// component. meshopt's encoding is counted at a quarter (it compresses from about 2 to 5 times),
// so that a request that may fit is never refused.
uint64_t estimated_bytes(const StoredSurface& s, const std::vector<size_t>& targets,
                         v1::Encoding encoding) {
    uint64_t components = 0;
    for (const StoredSurface::FieldRange& f : s.fields) components += uint64_t(f.components);
    uint64_t bytes = 0;
    for (size_t t : targets) {
        const uint64_t triangles = std::min<uint64_t>(t, s.triangles);
        const uint64_t vertices = s.triangles ? s.vertices * triangles / s.triangles : 0;
        bytes += 12 * triangles + vertices * (12 + 4 * components);
    }
    return encoding == v1::MESHOPT ? bytes / 4 : bytes;
}

} // namespace

// A request between the network thread and the pool: only what its levels need, never the
// request message (whose unknown fields a client may pad). It holds its client weakly: the pool
// or the preview thread may let go of the job last, and a Connection (with its transport and
// its place among the clients) is let go on the network thread only.
struct Service::RequestJob {
    std::weak_ptr<Connection> connection;
    uint64_t client = 0;
    uint64_t request_id = 0;
    std::vector<float> keep; // per level, as asked
    ReductionParams params;
    std::string key;
    v1::Encoding encoding = v1::RAW;
    bool progressive = false;
    std::vector<size_t> targets;      // per level of the keep list: its triangle count
    std::vector<size_t> finest_first; // level indices, finest (most triangles) first
    CancelFlag cancelled;             // the computation's: nobody waits for it any more
    CancelFlag ended;                 // this request's: cancelled, superseded or disconnected
    Clock::time_point start;
    bool exact_sent = false; // network thread: a level went out, so a late preview is dropped
    size_t sent_early = 0;   // pool: finest levels sent before a yield (never sent twice)
    // Pool: the surface once a run of this job loaded it, for its runs after a yield (a delete
    // meanwhile does not take it away).
    std::shared_ptr<const Surface> surface;
    size_t accounted_bytes = 0;

    // What the job holds, for the accounting in /metrics.
    size_t bytes() const {
        size_t b = sizeof(*this) + key.capacity() + params.surface.capacity() +
                   keep.capacity() * sizeof(float) +
                   (targets.capacity() + finest_first.capacity()) * sizeof(size_t);
        for (const std::string& f : params.options.gradient_fields) b += sizeof(f) + f.capacity();
        return b;
    }
};

void Service::request(std::shared_ptr<Connection> c, const v1::Request& r) {
    ++metrics_.requests;
    const uint64_t rid = r.request_id();
    const auto refuse = [&](v1::Error::Code code, const std::string& why) {
        ++metrics_.request_errors;
        c->send_error(code, "request " + std::to_string(rid) + ": " + why, rid);
    };
    if (r.keep_size() == 0)
        return refuse(v1::Error::INVALID_ARGUMENT, "no levels (keep) asked for");
    if (size_t(r.keep_size()) > kMaxLevelsPerRequest)
        return refuse(v1::Error::INVALID_ARGUMENT,
                      "more than " + std::to_string(kMaxLevelsPerRequest) + " levels");
    if (size_t(r.gradient_fields_size()) > kMaxFields)
        return refuse(v1::Error::INVALID_ARGUMENT,
                      "more than " + std::to_string(kMaxFields) + " gradient fields");
    for (const std::string& f : r.gradient_fields())
        if (f.size() > kMaxNameBytes)
            return refuse(v1::Error::INVALID_ARGUMENT,
                          "a field name of " + std::to_string(f.size()) + " bytes (at most " +
                              std::to_string(kMaxNameBytes) + ")");
    for (float k : r.keep())
        if (!(k > 0 && k <= 1))
            return refuse(v1::Error::INVALID_ARGUMENT,
                          "keep " + std::to_string(k) + " is not in (0, 1]");

    auto job = std::make_shared<RequestJob>();
    job->connection = c;
    job->client = c->id();
    job->request_id = rid;
    job->keep.assign(r.keep().begin(), r.keep().end());
    job->ended = std::make_shared<std::atomic<bool>>(false);
    ReductionParams& params = job->params;
    std::optional<StoredSurface> stored;
    if (!r.result().empty()) {
        // The same answer whether the result is unknown or of a surface this client may not see.
        const ReductionParams* known = known_results_.find(r.result());
        if (known) stored = store_.find(known->surface, c->scopes());
        if (!stored) return refuse(v1::Error::NOT_FOUND, "no result " + r.result());
        params = *known;
        job->key = r.result();
    } else {
        stored = store_.find(r.surface(), c->scopes());
        if (!stored) return refuse(v1::Error::NOT_FOUND, "no surface " + r.surface());
        params.surface = r.surface();
        try {
            params.options = protocol::options_from(r);
        } catch (const InputError& e) {
            return refuse(v1::Error::INVALID_ARGUMENT, e.what());
        }
        job->key = protocol::result_key(params.surface, params.options);
    }
    if (r.supersede()) supersede(*c, rid, params.surface);

    job->encoding =
        r.encoding() == v1::MESHOPT && c->has_capability("meshopt-codec") ? v1::MESHOPT : v1::RAW;
    job->progressive = r.progressive() && c->has_capability("progressive");
    for (float k : r.keep())
        job->targets.push_back(protocol::target_for_keep(k, stored->triangles));
    job->finest_first.resize(size_t(r.keep_size()));
    std::iota(job->finest_first.begin(), job->finest_first.end(), 0);
    std::stable_sort(job->finest_first.begin(), job->finest_first.end(),
                     [&](size_t a, size_t b) { return r.keep(int(a)) > r.keep(int(b)); });
    job->start = Clock::now();
    // The levels are queued whole for the client, within --max-queue-mb: a request whose levels
    // cannot fit is refused before anything is computed.
    const uint64_t bytes = estimated_bytes(*stored, job->targets, job->encoding);
    const uint64_t queue_bound =
        uint64_t(std::min(config_.max_queue_mb, config_.max_queue_total_mb)) << 20;
    if (bytes > queue_bound)
        return refuse(v1::Error::RESOURCE_EXHAUSTED,
                      "its " + std::to_string(job->targets.size()) + " levels take about " +
                          std::to_string((bytes + (1 << 20) - 1) >> 20) + " MiB, more than the " +
                          std::to_string(queue_bound >> 20) +
                          " MiB a client may have waiting to be sent (--max-queue-mb, "
                          "--max-queue-total-mb); ask for "
                          "fewer or coarser levels");

    const std::string waiter = Computations::request_waiter(c->id(), rid);
    job->cancelled = computations_.wait(job->key, waiter);
    const bool ready =
        reductions_.cached_record(
            job->key, *std::min_element(job->targets.begin(), job->targets.end())) != nullptr;
    // A request whose levels are all ready is answered on the preview thread: it never waits
    // behind a computation, however busy the workers are (ticket 0: nothing to withdraw).
    uint64_t ticket = 0;
    if (ready && preview_pool_) {
        asio::post(preview_executor(), [this, job] {
            static const std::atomic<bool> never_yield{false};
            run_request(job, never_yield);
        });
    } else if ((ticket = compute(c->id(), [this, job](const std::atomic<bool>& yield) {
                    return run_request(job, yield);
                })) == 0) {
        computations_.leave(job->key, waiter);
        return refuse(v1::Error::RESOURCE_EXHAUSTED,
                      "too many jobs of yours waiting (at most " +
                          std::to_string(kMaxRequestsPerConnection + kMaxUploadsPerConnection +
                                         kMaxSessionsPerConnection) +
                          ")");
    }
    c->begin_request(rid);
    c->begin_job();
    job->accounted_bytes = job->bytes();
    ++metrics_.request_jobs;
    metrics_.request_job_bytes += int64_t(job->accounted_bytes);
    running_[{c->id(), rid}] = {job->key, params.surface, job->ended, ticket, job->accounted_bytes};
    if (!ready && c->has_capability("previews")) send_preview(job);
}

bool Service::run_request(const std::shared_ptr<RequestJob>& job, const std::atomic<bool>& yield) {
    const uint64_t rid = job->request_id;
    v1::Error error;
    error.set_request_id(rid);
    std::vector<PreparedLevel> levels;
    std::vector<size_t> todo(job->finest_first.begin() + ptrdiff_t(job->sent_early),
                             job->finest_first.end());
    // Levels are made and queued one at a time; the newest is held back to go out with the
    // request's end.
    std::optional<PreparedLevel> held;
    const auto vector_of = [](PreparedLevel p) {
        std::vector<PreparedLevel> out;
        out.push_back(std::move(p));
        return out;
    };
    const auto emit = [&](PreparedLevel p) {
        if (held) deliver(job, vector_of(std::move(*held)), {}, false);
        held = std::move(p);
        if (job->ended->load()) throw Cancelled();
    };
    try {
        if (job->ended->load()) throw Cancelled(); // cancelled while it waited for a worker
        if (job->cancelled->load()) {
            ++metrics_.reductions_cancelled;
            throw Cancelled();
        }
        const size_t coarsest = job->targets[todo.back()];
        bool computed = false;
        auto rec = reductions_.cached_record(job->key, coarsest);
        if (!rec && !job->progressive && todo.size() > 1 && job->targets[todo.front()] > coarsest) {
            // The finest level leaves once a run has passed it, before the run to the coarsest
            // (a progressive request keeps its order: a whole coarsest level, then refinements).
            auto first = record_for(reductions_, job->params, job->key, job->targets[todo.front()],
                                    *job->cancelled, &computed, &yield, &job->surface);
            prepare_levels(*job, *first, {todo.front()}, computed, emit);
            deliver(job, vector_of(std::move(*held)), {}, false);
            held.reset();
            todo.erase(todo.begin());
            ++job->sent_early;
            if (job->ended->load()) throw Cancelled();
        }
        if (!rec)
            rec = record_for(reductions_, job->params, job->key, coarsest, *job->cancelled,
                             &computed, &yield, &job->surface);
        job->surface.reset();                   // the levels need the record only
        std::reverse(todo.begin(), todo.end()); // the rest coarsest first: all are ready
        prepare_levels(*job, *rec, todo, computed, emit);
        if (held) levels = vector_of(std::move(*held));
    } catch (const Cancelled&) {
        // Its worker went to another client's job: it runs again, first of its client's.
        if (yield.load() && !job->ended->load() && !job->cancelled->load()) return false;
        error.set_code(v1::Error::CANCELLED);
        error.set_message("request " + std::to_string(rid) + " cancelled");
    } catch (const std::invalid_argument& e) {
        error.set_code(v1::Error::NOT_FOUND);
        error.set_message("request " + std::to_string(rid) + ": " + e.what());
    } catch (const InputError& e) {
        error.set_code(v1::Error::INVALID_ARGUMENT);
        error.set_message("request " + std::to_string(rid) + ": " + e.what());
    } catch (const std::exception& e) {
        error.set_code(v1::Error::INTERNAL);
        error.set_message("request " + std::to_string(rid) + ": " + e.what());
    }
    metrics_.observe_job_seconds(std::chrono::duration<double>(Clock::now() - job->start).count());
    deliver(job, std::move(levels), std::move(error), true);
    return true;
}

void Service::prepare_levels(const RequestJob& job, const ComputedRecord& rec,
                             const std::vector<size_t>& indices, bool computed,
                             const std::function<void(PreparedLevel)>& emit) {
    const auto begin_of = [&](size_t i) {
        v1::MeshBegin b;
        b.set_request_id(job.request_id);
        b.set_level(uint32_t(i));
        b.set_keep(job.keep[i]);
        b.set_seconds(computed ? rec.seconds : 0);
        b.set_cached(!computed);
        b.set_result(job.key);
        b.set_surface(job.params.surface);
        return b;
    };
    if (!job.progressive) {
        for (size_t i : indices) {
            auto level =
                reductions_.level(rec, job.key, job.keep[i], job.encoding, job.cancelled.get());
            PreparedLevel p{begin_of(i), {level, &level->blob.bytes}};
            p.begin.set_kind(v1::MeshBegin::FULL);
            protocol::set_layout(p.begin, level->blob.layout);
            p.begin.set_total_triangles(level->triangles);
            p.begin.set_target_reached(level->target_reached);
            set_level_error(*p.begin.mutable_error(), rec.record, level->operations);
            emit(std::move(p));
        }
        return;
    }
    protocol::RefinementStream stream(rec.record.vertices());
    bool first = true;
    for (size_t i : indices) {
        const size_t target = job.targets[i];
        const size_t ops = rec.record.operations_for(target);
        const std::vector<uint32_t> triangles = rec.record.indexed_triangles(ops);
        auto blob = std::make_shared<protocol::EncodedBlob>(
            first ? protocol::encode_mesh(stream.base(triangles), job.encoding)
                  : protocol::encode_refinement(stream.refine(triangles), job.encoding));
        PreparedLevel p{begin_of(i), {blob, &blob->bytes}};
        p.begin.set_kind(first ? v1::MeshBegin::FULL : v1::MeshBegin::REFINEMENT);
        protocol::set_layout(p.begin, blob->layout);
        p.begin.set_total_triangles(triangles.size() / 3);
        p.begin.set_target_reached(triangles.size() / 3 <= target);
        set_level_error(*p.begin.mutable_error(), rec.record, ops);
        first = false;
        emit(std::move(p));
    }
}

void Service::deliver(const std::shared_ptr<RequestJob>& job, std::vector<PreparedLevel> levels,
                      v1::Error error, bool last) {
    asio::post(io_,
               [this, job, levels = std::move(levels), error = std::move(error), last]() mutable {
                   const std::shared_ptr<Connection> c = job->connection.lock();
                   const uint64_t rid = job->request_id;
                   if (last) {
                       auto it = running_.find({job->client, rid});
                       if (it != running_.end() && it->second.ended == job->ended)
                           forget_request(job->client, rid);
                       end_request_job(c.get(), job->accounted_bytes);
                   }
                   // A key is remembered once a level has named it: a request that fails
                   // (an unknown field, a cancel) leaves nothing behind.
                   if (!levels.empty()) remember_result(job->key, job->params);
                   if (!c || !c->open() || !c->request_active(rid)) return; // gone or cancelled
                   if (last) c->end_request(rid);
                   if (error.code() != v1::Error::CODE_UNSPECIFIED) {
                       ++metrics_.request_errors;
                       return c->send(error);
                   }
                   job->exact_sent = job->exact_sent || !levels.empty();
                   for (size_t i = 0; i < levels.size(); ++i) {
                       BulkItem item;
                       item.request_id = rid;
                       item.surface = job->params.surface;
                       item.level = levels[i].begin.level();
                       item.begin_frame = protocol::encode_frame(levels[i].begin);
                       item.blob = std::move(levels[i].blob);
                       if (last && i + 1 == levels.size()) {
                           v1::RequestDone done;
                           done.set_request_id(rid);
                           item.after.push_back(protocol::encode_frame(done));
                       }
                       ++metrics_.levels_sent;
                       c->send_bulk(std::move(item));
                   }
               });
}

void Service::send_preview(const std::shared_ptr<RequestJob>& job) {
    // The nearest alpha of the same surface and strategy whose record holds the finest level.
    const size_t level = job->finest_first.front();
    const size_t target = job->targets[level];
    std::shared_ptr<const ComputedRecord> nearest;
    std::string nearest_key;
    double distance = 2;
    known_results_.for_surface(
        job->params.surface, [&](const std::string& key, const ReductionParams& params) {
            if (key == job->key || params.options.strategy != job->params.options.strategy) return;
            const double d = std::abs(params.options.alpha - job->params.options.alpha);
            if (d >= distance) return;
            if (auto rec = reductions_.cached_record(key, target)) {
                nearest = rec, nearest_key = key, distance = d;
            }
        });
    asio::post(preview_executor(), [this, job, level, target, nearest, nearest_key] {
        v1::MeshBegin begin;
        std::shared_ptr<const protocol::EncodedBlob> blob;
        try {
            size_t triangles = 0;
            if (nearest) {
                // Through the cache: a slider's previews near one record cut its level once.
                auto cut =
                    reductions_.level(*nearest, nearest_key, job->keep[level], job->encoding);
                blob = std::shared_ptr<const protocol::EncodedBlob>(cut, &cut->blob);
                triangles = cut->triangles;
            } else {
                std::shared_ptr<const Surface> surface = store_.load(job->params.surface);
                if (!surface) return;
                const Surface preview = clustered_preview(*surface, target);
                blob = std::make_shared<protocol::EncodedBlob>(
                    protocol::encode_mesh(preview, job->encoding));
                triangles = preview.triangle_count();
            }
            begin.set_request_id(job->request_id);
            begin.set_level(uint32_t(level));
            begin.set_keep(job->keep[level]);
            begin.set_kind(v1::MeshBegin::FULL);
            protocol::set_layout(begin, blob->layout);
            begin.set_total_triangles(triangles);
            begin.set_target_reached(triangles <= target);
            begin.set_surface(job->params.surface);
            begin.set_preview(true);
        } catch (const std::exception& e) {
            spdlog::warn("no preview for request {}: {}", job->request_id, loggable(e.what(), 300));
            return;
        }
        asio::post(io_, [this, job, begin = std::move(begin), blob = std::move(blob)] {
            const std::shared_ptr<Connection> c = job->connection.lock();
            const uint64_t rid = job->request_id;
            if (!c || !c->open() || !c->request_active(rid) || job->exact_sent) return;
            BulkItem item;
            item.request_id = rid;
            item.surface = job->params.surface;
            item.level = begin.level();
            item.begin_frame = protocol::encode_frame(begin);
            item.blob = std::shared_ptr<const std::string>(blob, &blob->bytes);
            ++metrics_.previews_sent;
            c->send_bulk(std::move(item));
        });
    });
}

void Service::forget_request(uint64_t client, uint64_t request_id) {
    auto it = running_.find({client, request_id});
    if (it == running_.end()) return;
    computations_.leave(it->second.key, Computations::request_waiter(client, request_id));
    it->second.ended->store(true);
    if (scheduler_.withdraw(it->second.ticket))
        end_request_job(find(client).get(), it->second.job_bytes);
    running_.erase(it);
}

void Service::end_request_job(Connection* c, uint64_t job_bytes) {
    if (c) c->end_job();
    --metrics_.request_jobs;
    metrics_.request_job_bytes -= int64_t(job_bytes);
}

void Service::cancel_request(Connection& c, uint64_t request_id) {
    forget_request(c.id(), request_id);
}

void Service::supersede(Connection& c, uint64_t request_id, const std::string& surface) {
    // The client's older requests for the surface: those still computing, and those whose
    // levels wait unsent in its queue.
    std::set<uint64_t> older;
    for (auto it = running_.lower_bound({c.id(), 0});
         it != running_.end() && it->first.first == c.id(); ++it)
        if (it->first.second != request_id && it->second.surface == surface)
            older.insert(it->first.second);
    c.drop_unstarted([&](const BulkItem& item) {
        const bool stale =
            item.request_id != 0 && item.request_id != request_id && item.surface == surface;
        if (stale) older.insert(item.request_id);
        return stale;
    });
    for (uint64_t old : older) {
        forget_request(c.id(), old);
        if (!c.request_active(old)) continue;
        c.end_request(old);
        c.send_error(v1::Error::CANCELLED,
                     "request " + std::to_string(old) + " superseded by request " +
                         std::to_string(request_id),
                     old);
    }
}

void Service::remember_result(const std::string& key, const ReductionParams& params) {
    known_results_.remember(key, params);
    metrics_.remembered_results = int64_t(known_results_.size());
    metrics_.remembered_bytes = int64_t(known_results_.bytes());
}

// ----- sessions -----

void Service::send_session_mesh(const Session& s, std::vector<uint64_t> targets) {
    ReductionParams params;
    params.surface = s.view.surface();
    params.options = protocol::options_from(s.view);
    const std::string key = protocol::result_key(params.surface, params.options);
    const float keep = s.view.keep() > 0 ? s.view.keep() : 1.0f;
    const std::string name = s.name, scope = s.scope;
    // The session's mesh before this view: nobody in the session waits for it any more.
    const std::string waiter = Computations::session_waiter(scope);
    std::string& waited = session_keys_[scope];
    if (!waited.empty() && waited != key) computations_.leave(waited, waiter);
    waited = key;
    const CancelFlag cancelled = computations_.wait(key, waiter);
    const std::optional<StoredSurface> stored =
        store_.find(params.surface, {s.scope, kPublicScope});
    const size_t depth = protocol::target_for_keep(keep, stored ? stored->triangles : 0);
    const uint64_t version = s.view_version;
    std::shared_ptr<std::atomic<uint64_t>>& latest = session_versions_[scope];
    if (!latest) latest = std::make_shared<std::atomic<uint64_t>>(version);
    latest->store(version);
    // Encode only what the members asked for.
    bool need_raw = false, need_meshopt = false;
    for (uint64_t id : targets)
        if (auto c = find(id))
            (c->has_capability("meshopt-codec") ? need_meshopt : need_raw) = true;
    const uint64_t client = targets.empty() ? 0 : targets.front();
    compute(client, [this, params, key, keep, name, scope, version, latest, need_raw, need_meshopt,
                     depth, cancelled, targets = std::move(targets)] {
        // A newer view came while this one waited for a worker: only the newest is computed.
        if (latest->load() != version) {
            ++metrics_.session_views_skipped;
            return;
        }
        std::shared_ptr<const EncodedLevel> raw, meshopt;
        std::string failure;
        double seconds = 0;
        v1::LevelError error;
        try {
            bool computed = false;
            auto rec = record_for(reductions_, params, key, depth, *cancelled, &computed);
            seconds = computed ? rec->seconds : 0;
            if (need_raw) raw = reductions_.level(*rec, key, keep, v1::RAW, cancelled.get());
            if (need_meshopt)
                meshopt = reductions_.level(*rec, key, keep, v1::MESHOPT, cancelled.get());
            set_level_error(error, rec->record,
                            rec->record.operations_for(
                                protocol::target_for_keep(keep, rec->record.triangles_in())));
        } catch (const Cancelled&) {
            return; // a newer view (or nobody) waits for another mesh
        } catch (const std::exception& e) {
            failure = e.what();
        }
        asio::post(io_, [=, this] {
            if (auto k = session_keys_.find(scope); k != session_keys_.end() && k->second == key) {
                computations_.leave(key, Computations::session_waiter(scope));
                session_keys_.erase(k);
            }
            if (failure.empty()) remember_result(key, params);
            Session* now = sessions_.find(scope);
            if (!now || now->view_version != version) return; // superseded by a newer view
            for (uint64_t id : targets) {
                auto c = find(id);
                if (!c || !now->has(id)) continue;
                if (!failure.empty()) {
                    c->send_error(v1::Error::INTERNAL, "session \"" + name + "\": " + failure);
                    continue;
                }
                const auto& level = c->has_capability("meshopt-codec") ? meshopt : raw;
                if (!level) continue; // connected after the mesh was asked for
                c->drop_unstarted([&](const BulkItem& item) { return item.session == name; });
                v1::MeshBegin begin;
                begin.set_session(name);
                begin.set_keep(keep);
                begin.set_kind(v1::MeshBegin::FULL);
                protocol::set_layout(begin, level->blob.layout);
                begin.set_total_triangles(level->triangles);
                begin.set_target_reached(level->target_reached);
                begin.set_seconds(seconds);
                begin.set_result(key);
                begin.set_surface(params.surface);
                *begin.mutable_error() = error;
                BulkItem item;
                item.session = name;
                item.begin_frame = protocol::encode_frame(begin);
                item.blob = std::shared_ptr<const std::string>(level, &level->blob.bytes);
                ++metrics_.levels_sent;
                c->send_bulk(std::move(item));
            }
        });
    });
}

} // namespace ddsimp::server
