#include "service.h"

#include "client_limits.h"
#include "log_text.h"
#include "surface_file.h"

#include "ddsimp/protocol/content_hash.h"
#include "ddsimp/protocol/reduction_options.h"
#include "ddsimp/protocol/refinement.h"

#include <boost/asio/post.hpp>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <numeric>
#include <thread>

namespace ddsimp::server {
namespace asio = boost::asio;

namespace {

void set_fields(google::protobuf::RepeatedPtrField<v1::FieldInfo>* out, const StoredSurface& s) {
    for (const auto& f : s.fields) {
        v1::FieldInfo* info = out->Add();
        protocol::set_field_info(*info, {f.name, uint32_t(f.components), f.kind});
        info->set_min(f.min);
        info->set_max(f.max);
    }
}

std::string describe_repairs(const RepairReport& r) {
    std::string out;
    const auto add = [&](size_t n, const char* what) {
        if (n == 0) return;
        out += (out.empty() ? "" : ", ") + std::to_string(n) + " " + what;
    };
    add(r.degenerate_triangles_dropped, "degenerate triangles dropped");
    add(r.duplicate_triangles_dropped, "duplicate triangles dropped");
    add(r.triangles_flipped, "triangles flipped to agree with their neighbours");
    add(r.unused_vertices, "unused vertices");
    return out;
}

// An upload that would pass a quota of stored surfaces and is not stored already.
struct OverQuota : std::runtime_error {
    using std::runtime_error::runtime_error;
};

int cores() {
    return int(std::max(1u, std::thread::hardware_concurrency()));
}

} // namespace

Service::Service(asio::io_context& io, const Config& config)
    : io_(io), config_(config), tokens_(config_),
      store_(config.data_dir, config.surfaces_mb << 20, config.max_surface_mb << 20),
      quotas_(config_, store_, metrics_), cache_(config.cache_mb << 20),
      reductions_(store_, cache_, metrics_, cores()), sessions_(config.max_sessions),
      scheduler_(config.threads, io.get_executor(),
                 kMaxRequestsPerConnection + kMaxUploadsPerConnection + kMaxSessionsPerConnection),
      known_results_(config.max_remembered_kb << 10),
      downloads_(std::make_shared<DownloadBudget>(uint64_t(config.max_download_mb) << 20)) {
    if (config.threads > 0) preview_pool_.emplace(1);
    load_sample();
}

Service::~Service() {
    scheduler_.stop();
    if (preview_pool_) preview_pool_->join();
}

uint64_t Service::compute(uint64_t client, Scheduler::Work work) {
    return scheduler_.submit(client, std::move(work));
}

uint64_t Service::compute(uint64_t client, Scheduler::Resumable work) {
    return scheduler_.submit(client, std::move(work));
}

asio::any_io_executor Service::preview_executor() {
    if (preview_pool_) return preview_pool_->get_executor();
    return io_.get_executor();
}

void Service::load_sample() {
    if (config_.sample.empty()) return;
    try {
        SurfaceFile file = read_surface_file(config_.sample);
        validate(file.surface);
        const auto added = store_.add_in_memory(file.name, std::move(file.surface));
        spdlog::info("sample surface \"{}\" ({} triangles) is {}", added.info.name,
                     added.info.triangles, added.info.id);
        speculate(added.info.id);
    } catch (const std::exception& e) {
        spdlog::error("cannot load the sample surface: {}", e.what());
    }
}

void Service::accept(std::shared_ptr<Transport> transport) {
    auto c = std::make_shared<Connection>(*this, std::move(transport), next_id_++);
    ++metrics_.connections_total;
    ++metrics_.connections;
    connections_[c->id()] = c;
    c->start();
    // The client limits are the listeners' (admission.h): every connection is counted there.
    if (stopping_) c->send_error(v1::Error::UNAVAILABLE, "the server is shutting down", 0, true);
}

void Service::connection_closed(Connection& c) {
    --metrics_.connections;
    for (const auto& [name, scope] : std::map(c.sessions())) leave(c, name);
    std::vector<uint64_t> requests;
    for (auto it = running_.lower_bound({c.id(), 0});
         it != running_.end() && it->first.first == c.id(); ++it)
        requests.push_back(it->first.second);
    for (uint64_t rid : requests) forget_request(c.id(), rid);
    connections_.erase(c.id());
}

std::shared_ptr<Connection> Service::find(uint64_t id) {
    auto it = connections_.find(id);
    if (it == connections_.end()) return nullptr;
    auto c = it->second.lock();
    return c && c->open() ? c : nullptr;
}

std::string Service::metrics_text() {
    const ResultCache::Stats cs = cache_.stats();
    Metrics::Snapshot s;
    s.sessions = sessions_.size();
    s.surfaces = store_.size();
    const SurfaceStore::Residency r = store_.residency();
    s.surfaces_resident = r.resident, s.surface_bytes = r.resident_bytes;
    s.surface_pinned_bytes = r.pinned_bytes, s.surface_limit_bytes = r.limit_bytes;
    s.surface_loads = r.loads, s.surface_evictions = r.evictions;
    s.surfaces_deleted = r.removals;
    s.cache_hits = cs.hits, s.cache_misses = cs.misses, s.cache_bytes = cs.bytes;
    s.cache_entries = cs.entries, s.computations = cs.computations, s.evictions = cs.evictions;
    s.speculations_pending = scheduler_.background();
    s.download_bytes = downloads_->held(), s.download_limit_bytes = downloads_->limit();
    return metrics_.render(s);
}

void Service::stop() {
    stopping_ = true;
    for (auto& [id, weak] : std::map(connections_))
        if (auto c = weak.lock()) c->drop("the server is shutting down");
}

// ----- surfaces -----

void Service::upload(std::shared_ptr<Connection> c, v1::UploadBegin begin, std::string bytes,
                     UploadOwner owner) {
    ++metrics_.uploads;
    // Into a session: visible to its members only. (Checked at UploadBegin; it may have left.)
    std::string scope = kPublicScope;
    if (!begin.session().empty()) {
        auto it = c->sessions().find(begin.session());
        if (it == c->sessions().end()) {
            release_upload(owner, begin.total_bytes());
            return c->send_error(v1::Error::NOT_FOUND,
                                 "you are not a member of a session \"" + begin.session() + "\"",
                                 begin.upload_id());
        }
        scope = it->second;
    }
    c->begin_storing();
    const uint64_t upload_id = begin.upload_id(), upload_bytes = begin.total_bytes();
    // The job holds its client weakly: a Connection is let go on the network thread only.
    const uint64_t client = c->id();
    const bool queued = compute(client, [this, weak = std::weak_ptr<Connection>(c), client, scope,
                                         owner, begin = std::move(begin),
                                         bytes = std::move(bytes)] {
        const uint64_t id = begin.upload_id();
        v1::UploadResult result;
        v1::Error error;
        try {
            protocol::BlobLayout layout;
            layout.vertex_count = begin.vertex_count();
            layout.triangle_count = begin.triangle_count();
            for (const v1::FieldInfo& f : begin.fields())
                layout.fields.push_back(protocol::field_spec_of(f));
            layout.section_bytes = protocol::raw_mesh_sections(
                layout.vertex_count, layout.triangle_count, layout.fields);
            Surface surface = protocol::decode_mesh(bytes, layout);
            const RepairReport repairs = validate(surface);
            // Over a quota of stored surfaces: stored only if that charges nobody again.
            if (!owner.over_quota.empty() &&
                store_.would_charge(protocol::surface_hash(surface), scope)) {
                ++metrics_.quota_refusals;
                throw OverQuota(owner.over_quota);
            }
            const SurfaceStore::Added added =
                store_.add(begin.name(), std::move(surface), scope, owner.token);
            result.set_upload_id(id);
            result.set_surface(added.info.id);
            result.set_triangles(added.info.triangles);
            result.set_vertices(added.info.vertices);
            result.set_already_stored(added.already_stored);
            result.set_repairs(describe_repairs(repairs));
            spdlog::info("client {} uploaded \"{}\" ({} triangles) as {}{}", client,
                         loggable(begin.name()), added.info.triangles, added.info.id,
                         added.already_stored ? " (already stored)" : "");
        } catch (const OverQuota& e) {
            error.set_code(v1::Error::RESOURCE_EXHAUSTED);
            error.set_message("upload " + std::to_string(id) + ": " + e.what());
        } catch (const protocol::BlobError& e) {
            error.set_code(v1::Error::INVALID_ARGUMENT);
            error.set_message("upload " + std::to_string(id) + ": " + e.what());
        } catch (const InputError& e) {
            error.set_code(v1::Error::BAD_SURFACE);
            error.set_message("upload " + std::to_string(id) + ": " + e.what());
        } catch (const SurfaceFileError& e) {
            spdlog::error("cannot store an upload: {}", e.what());
            error.set_code(v1::Error::UNAVAILABLE);
            error.set_message("upload " + std::to_string(id) +
                              ": the server cannot store it: " + e.what());
        } catch (const std::exception& e) { // e.g. out of memory: this upload fails, not the server
            spdlog::error("upload {} of client {} failed: {}", id, client, loggable(e.what(), 300));
            error.set_code(v1::Error::INTERNAL);
            error.set_message("upload " + std::to_string(id) + ": the server failed: " + e.what());
        }
        error.set_request_id(id);
        asio::post(
            io_, [this, weak, begin, owner, result = std::move(result), error = std::move(error)] {
                release_upload(owner, begin.total_bytes());
                const std::shared_ptr<Connection> c = weak.lock();
                if (c) c->end_storing();
                if (error.code() != v1::Error::CODE_UNSPECIFIED) {
                    if (c) c->send(error);
                    return;
                }
                if (!result.already_stored()) speculate(result.surface());
                if (!c) return;
                c->send(result);
                if (!begin.session().empty()) {
                    v1::SetSessionState change;
                    change.set_name(begin.session());
                    change.mutable_view()->set_surface(result.surface());
                    set_state(c, change);
                }
            });
    });
    if (!queued) {
        c->end_storing();
        release_upload(owner, upload_bytes);
        c->send_error(v1::Error::RESOURCE_EXHAUSTED,
                      "upload " + std::to_string(upload_id) + ": too many jobs of yours waiting",
                      upload_id);
    }
}

void Service::list_surfaces(Connection& c) {
    v1::SurfaceList list;
    for (const StoredSurface& s : store_.list(c.scopes())) {
        v1::SurfaceInfo* info = list.add_surfaces();
        info->set_surface(s.id);
        info->set_name(s.name);
        info->set_triangles(s.triangles);
        info->set_vertices(s.vertices);
        set_fields(info->mutable_fields(), s);
    }
    c.send(list);
}

void Service::delete_surface(std::shared_ptr<Connection> c, const v1::DeleteSurface& del) {
    const uint64_t id = del.delete_id();
    const std::string& surface = del.surface();
    if (surface.size() > kMaxNameBytes)
        return c->send_error(v1::Error::NOT_FOUND, "no surface of that id", id);
    // A server without per-user tokens is one user: every client's upload is the same user's.
    const bool one_user = config_.tokens_file.empty();
    // Held by the job: the client weakly, so that a Connection is let go on the network thread.
    const auto done = [this, weak = std::weak_ptr<Connection>(c), id,
                       surface](SurfaceStore::Removal outcome, std::string failure) {
        using R = SurfaceStore::Removal;
        const std::shared_ptr<Connection> c = weak.lock();
        if (outcome == R::Removed) {
            known_results_.forget_surface(surface);
            metrics_.remembered_results = int64_t(known_results_.size());
            metrics_.remembered_bytes = int64_t(known_results_.bytes());
        }
        if (!c) return;
        if (!failure.empty())
            return c->send_error(v1::Error::UNAVAILABLE,
                                 "surface " + surface + " cannot be deleted: " + failure, id);
        switch (outcome) {
        case R::NotFound:
            return c->send_error(v1::Error::NOT_FOUND, "no surface " + surface, id);
        case R::Pinned:
            return c->send_error(v1::Error::PERMISSION_DENIED,
                                 "surface " + surface + " is the built-in sample, which stays", id);
        case R::NotOwner:
            return c->send_error(v1::Error::PERMISSION_DENIED,
                                 "surface " + surface +
                                     " was not uploaded with your token: only a token that "
                                     "uploaded it deletes it",
                                 id);
        case R::Released:
        case R::Removed:
            break;
        }
        spdlog::info("client {} deleted surface {}{}", c->id(), surface,
                     outcome == R::Removed ? "" : " (another token keeps it)");
        v1::SurfaceDeleted answer;
        answer.set_delete_id(id);
        answer.set_surface(surface);
        answer.set_removed(outcome == R::Removed);
        c->send(answer);
    };
    // Removing files waits for a write of the same surface: on the pool.
    const bool queued =
        compute(c->id(), [this, done, surface, scopes = c->scopes(), token = c->token(), one_user] {
            SurfaceStore::Removal outcome = SurfaceStore::Removal::NotFound;
            std::string failure;
            try {
                outcome = store_.remove(surface, scopes, token, one_user);
                if (outcome == SurfaceStore::Removal::Removed) reductions_.forget_surface(surface);
            } catch (const std::exception& e) {
                spdlog::error("cannot delete surface {}: {}", surface, e.what());
                failure = e.what();
            }
            asio::post(io_, [done, outcome, failure] { done(outcome, failure); });
        });
    if (!queued) c->send_error(v1::Error::RESOURCE_EXHAUSTED, "too many jobs of yours waiting", id);
}

// ----- sessions -----

void Service::broadcast(const Session& s, const std::string& cause, uint64_t changed_by) {
    const std::string frame = protocol::encode_frame(s.state(cause, changed_by));
    for (const v1::Member& m : s.members)
        if (auto c = find(m.client_id())) c->send_frame(frame);
}

void Service::join(std::shared_ptr<Connection> c, const v1::JoinSession& join) {
    const std::string& name = join.name();
    if (name.empty() || name.size() > kMaxNameBytes)
        return c->send_error(v1::Error::INVALID_ARGUMENT,
                             "a session name has 1 to " + std::to_string(kMaxNameBytes) + " bytes");
    if (join.key().size() > kMaxSessionKeyBytes)
        return c->send_error(v1::Error::INVALID_ARGUMENT, "a session key has at most " +
                                                              std::to_string(kMaxSessionKeyBytes) +
                                                              " bytes");
    const std::string scope = session_scope(name, join.key());
    auto joined = c->sessions().find(name);
    if (joined != c->sessions().end() && joined->second != scope)
        return c->send_error(v1::Error::INVALID_ARGUMENT,
                             "you are in another session named \"" + name + "\"; leave it first");
    if (joined == c->sessions().end() && c->sessions().size() >= kMaxSessionsPerConnection)
        return c->send_error(v1::Error::RESOURCE_EXHAUSTED,
                             "at most " + std::to_string(kMaxSessionsPerConnection) +
                                 " sessions per connection");
    bool created = false;
    Session* s = sessions_.join(scope, name, c->member(), &created);
    if (!s)
        return c->send_error(v1::Error::RESOURCE_EXHAUSTED,
                             "the server has its maximum of " +
                                 std::to_string(config_.max_sessions) + " sessions");
    c->sessions()[name] = scope;
    spdlog::info("client {} joined session \"{}\" ({} members)", c->id(), loggable(name),
                 s->members.size());
    broadcast(*s, created ? "created" : "joined", c->id());
    if (!s->view.surface().empty()) send_session_mesh(*s, {c->id()});
}

void Service::leave(Connection& c, const std::string& name) {
    auto joined = c.sessions().find(name);
    if (joined == c.sessions().end()) return;
    const std::string scope = joined->second;
    c.sessions().erase(joined);
    bool leader_changed = false;
    Session* s = sessions_.leave(scope, c.id(), &leader_changed);
    if (!s) { // the last member left: nobody waits for the session's mesh any more
        session_versions_.erase(scope);
        if (auto k = session_keys_.find(scope); k != session_keys_.end()) {
            computations_.leave(k->second, Computations::session_waiter(scope));
            session_keys_.erase(k);
        }
    }
    spdlog::info("client {} left session \"{}\"", c.id(), loggable(name));
    if (s) broadcast(*s, leader_changed ? "leader-left" : "left", c.id());
}

void Service::set_state(std::shared_ptr<Connection> c, const v1::SetSessionState& change) {
    auto joined = c->sessions().find(change.name());
    Session* s = joined == c->sessions().end() ? nullptr : sessions_.find(joined->second);
    // The same answer whether the session does not exist or the client is not in it.
    if (!s || !s->has(c->id()))
        return c->send_error(v1::Error::NOT_FOUND,
                             "you are not a member of a session \"" + change.name() + "\"");
    const v1::View& v = change.view();
    // A member shows the session a surface it may see (public, or of another of its sessions).
    if (!v.surface().empty() && !store_.share(v.surface(), c->scopes(), s->scope))
        return c->send_error(v1::Error::NOT_FOUND, "no surface " + v.surface());
    if (!v.surface().empty())
        compute(c->id(), [this, id = v.surface()] {
            try {
                store_.persist_scopes(id);
            } catch (const std::exception& e) {
                spdlog::error("cannot store who may see surface {}: {}", id, e.what());
            }
        });
    if (v.field().size() > kMaxNameBytes)
        return c->send_error(v1::Error::INVALID_ARGUMENT,
                             "a field name of " + std::to_string(v.field().size()) +
                                 " bytes (at most " + std::to_string(kMaxNameBytes) + ")");
    if (v.keep() != 0 && !(v.keep() > 0 && v.keep() <= 1))
        return c->send_error(v1::Error::INVALID_ARGUMENT, "keep must be in (0, 1]");
    v1::View after = s->view;
    if (!v.surface().empty()) after.set_surface(v.surface());
    if (change.set_alpha()) {
        after.set_alpha(v.alpha());
        if (v.has_alpha_exact())
            after.set_alpha_exact(v.alpha_exact());
        else
            after.clear_alpha_exact();
    }
    if (v.keep() != 0) after.set_keep(v.keep());
    if (!v.field().empty()) after.set_field(v.field());
    if (v.strategy() != v1::STRATEGY_UNSPECIFIED) after.set_strategy(v.strategy());
    if (v.placement() != v1::PLACEMENT_UNSPECIFIED) after.set_placement(v.placement());
    Options options;
    try {
        options = protocol::options_from(after);
    } catch (const InputError& e) {
        return c->send_error(v1::Error::INVALID_ARGUMENT, e.what());
    }
    const bool mesh_changed =
        s->view.surface() != after.surface() || s->view.keep() != after.keep() ||
        protocol::result_key(after.surface(), options) !=
            protocol::result_key(s->view.surface(), protocol::options_from(s->view));
    s->view = std::move(after);
    s->leader = c->id();
    ++s->version;
    broadcast(*s, "view", c->id());
    if (mesh_changed) ++s->view_version;
    if (mesh_changed && !s->view.surface().empty()) {
        std::vector<uint64_t> all;
        for (const v1::Member& m : s->members) all.push_back(m.client_id());
        send_session_mesh(*s, all);
    }
}

} // namespace ddsimp::server
