#include "service.h"

#include "client_limits.h"
#include "surface_file.h"

#include "ddsimp/protocol/refinement.h"

#include <boost/asio/post.hpp>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <numeric>

namespace ddsimp::server {
namespace asio = boost::asio;

namespace {

Strategy strategy_of(v1::Strategy s) {
    return s == v1::VERTEX_REMOVAL ? Strategy::VertexRemoval : Strategy::EdgeCollapse;
}

// PLACEMENT_UNSPECIFIED (and a value this server does not know) is the midpoint, as in protocol
// version 1 from the start.
Placement placement_of(v1::Placement p) {
    return p == v1::VOLUME        ? Placement::VolumePreserving
           : p == v1::LEAST_ERROR ? Placement::LeastError
                                  : Placement::Midpoint;
}

void set_fields(google::protobuf::RepeatedPtrField<v1::FieldInfo>* out, const StoredSurface& s) {
    for (const auto& f : s.fields) {
        v1::FieldInfo* info = out->Add();
        info->set_name(f.name);
        info->set_components(uint32_t(f.components));
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

// One level or refinement, ready to queue.
struct PreparedLevel {
    v1::MeshBegin begin;
    std::shared_ptr<const std::string> blob;
};

using Clock = std::chrono::steady_clock;

} // namespace

Service::Service(asio::io_context& io, const Config& config)
    : io_(io), config_(config), store_(config.data_dir), cache_(config.cache_mb << 20),
      reductions_(store_, cache_), sessions_(config.max_sessions) {
    if (config.threads > 0) pool_.emplace(size_t(config.threads));
    load_sample();
}

Service::~Service() {
    if (pool_) pool_->join();
}

asio::any_io_executor Service::compute() {
    if (pool_) return pool_->get_executor();
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
    if (stopping_) {
        c->send_error(v1::Error::UNAVAILABLE, "the server is shutting down", 0, true);
    } else if (connections_.size() > config_.max_clients) {
        spdlog::warn("refusing {}: {} clients connected", c->peer(), config_.max_clients);
        c->send_error(v1::Error::RESOURCE_EXHAUSTED,
                      "the server has its maximum of " + std::to_string(config_.max_clients) +
                          " clients",
                      0, true);
    }
}

void Service::connection_closed(Connection& c) {
    --metrics_.connections;
    for (const auto& [name, scope] : std::map(c.sessions())) leave(c, name);
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
    s.cache_hits = cs.hits, s.cache_misses = cs.misses, s.cache_bytes = cs.bytes;
    s.cache_entries = cs.entries, s.computations = cs.computations, s.evictions = cs.evictions;
    return metrics_.render(s);
}

void Service::stop() {
    stopping_ = true;
    for (auto& [id, weak] : std::map(connections_))
        if (auto c = weak.lock()) c->drop("the server is shutting down");
}

// ----- surfaces -----

bool Service::reserve_upload_bytes(uint64_t bytes) {
    if (bytes > (uint64_t(config_.max_upload_mb) << 20) - upload_bytes_) return false;
    upload_bytes_ += bytes;
    metrics_.upload_bytes = int64_t(upload_bytes_);
    return true;
}

void Service::release_upload_bytes(uint64_t bytes) {
    upload_bytes_ -= std::min(bytes, upload_bytes_);
    metrics_.upload_bytes = int64_t(upload_bytes_);
}

void Service::upload(std::shared_ptr<Connection> c, v1::UploadBegin begin, std::string bytes) {
    ++metrics_.uploads;
    // Into a session: visible to its members only. (Checked at UploadBegin; it may have left.)
    std::string scope = kPublicScope;
    if (!begin.session().empty()) {
        auto it = c->sessions().find(begin.session());
        if (it == c->sessions().end()) {
            release_upload_bytes(begin.total_bytes());
            return c->send_error(v1::Error::NOT_FOUND,
                                 "you are not a member of a session \"" + begin.session() + "\"",
                                 begin.upload_id());
        }
        scope = it->second;
    }
    c->begin_storing();
    asio::post(compute(), [this, c, scope, begin = std::move(begin), bytes = std::move(bytes)] {
        const uint64_t id = begin.upload_id();
        v1::UploadResult result;
        v1::Error error;
        try {
            protocol::BlobLayout layout;
            layout.vertex_count = begin.vertex_count();
            layout.triangle_count = begin.triangle_count();
            for (const v1::FieldInfo& f : begin.fields())
                layout.fields.push_back({f.name(), f.components()});
            layout.section_bytes = protocol::raw_mesh_sections(
                layout.vertex_count, layout.triangle_count, layout.fields);
            Surface surface = protocol::decode_mesh(bytes, layout);
            const RepairReport repairs = validate(surface);
            const SurfaceStore::Added added = store_.add(begin.name(), std::move(surface), scope);
            result.set_upload_id(id);
            result.set_surface(added.info.id);
            result.set_triangles(added.info.triangles);
            result.set_vertices(added.info.vertices);
            result.set_already_stored(added.already_stored);
            result.set_repairs(describe_repairs(repairs));
            spdlog::info("client {} uploaded \"{}\" ({} triangles) as {}{}", c->id(), begin.name(),
                         added.info.triangles, added.info.id,
                         added.already_stored ? " (already stored)" : "");
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
            spdlog::error("upload {} of client {} failed: {}", id, c->id(), e.what());
            error.set_code(v1::Error::INTERNAL);
            error.set_message("upload " + std::to_string(id) + ": the server failed: " + e.what());
        }
        error.set_request_id(id);
        asio::post(io_, [this, c, begin, result = std::move(result), error = std::move(error)] {
            c->end_storing();
            release_upload_bytes(begin.total_bytes());
            if (error.code() != v1::Error::CODE_UNSPECIFIED) return c->send(error);
            c->send(result);
            if (!begin.session().empty()) {
                v1::SetSessionState change;
                change.set_name(begin.session());
                change.mutable_view()->set_surface(result.surface());
                set_state(c, change);
            }
        });
    });
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

// ----- requests -----

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

    ReductionParams params;
    std::string key;
    if (!r.result().empty()) {
        // The same answer whether the result is unknown or of a surface this client may not see.
        auto it = known_results_.find(r.result());
        if (it == known_results_.end() || !store_.find(it->second.surface, c->scopes()))
            return refuse(v1::Error::NOT_FOUND, "no result " + r.result());
        params = it->second;
        key = r.result();
    } else {
        if (!store_.find(r.surface(), c->scopes()))
            return refuse(v1::Error::NOT_FOUND, "no surface " + r.surface());
        if (!(r.alpha() >= 0 && r.alpha() <= 1))
            return refuse(v1::Error::INVALID_ARGUMENT, "alpha must be in [0, 1]");
        params.surface = r.surface();
        params.alpha = r.alpha();
        params.strategy = strategy_of(r.strategy());
        params.placement = placement_of(r.placement());
        params.gradient_fields.assign(r.gradient_fields().begin(), r.gradient_fields().end());
        params.feature_angle = r.feature_angle();
        if (!(params.feature_angle >= 0 && params.feature_angle <= 180))
            return refuse(v1::Error::INVALID_ARGUMENT, "feature angle must be in [0, 180]");
        key = result_key(params);
        remember_result(key, params);
    }
    // A newer request for the same surface replaces the client's unsent older levels.
    std::set<uint64_t> replaced;
    c->drop_unstarted([&](const BulkItem& item) {
        const bool stale =
            item.request_id != 0 && item.request_id != rid && item.surface == params.surface;
        if (stale) replaced.insert(item.request_id);
        return stale;
    });
    for (uint64_t old : replaced) {
        c->end_request(old);
        c->send_error(
            v1::Error::CANCELLED,
            "request " + std::to_string(old) + " replaced by request " + std::to_string(rid), old);
    }

    const v1::Encoding encoding =
        r.encoding() == v1::MESHOPT && c->has_capability("meshopt-codec") ? v1::MESHOPT : v1::RAW;
    const bool progressive = r.progressive() && c->has_capability("progressive");
    std::vector<size_t> order(size_t(r.keep_size()));
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return r.keep(int(a)) < r.keep(int(b)); });

    c->begin_request(rid);
    const auto start = Clock::now();
    asio::post(compute(), [this, c, r, params, key, encoding, progressive, order, start] {
        std::vector<PreparedLevel> levels;
        v1::Error error;
        error.set_request_id(r.request_id());
        try {
            bool computed = false;
            auto rec = reductions_.record(params, key, &computed);
            const auto begin_of = [&](size_t i) {
                v1::MeshBegin b;
                b.set_request_id(r.request_id());
                b.set_level(uint32_t(i));
                b.set_keep(r.keep(int(i)));
                b.set_seconds(computed ? rec->seconds : 0);
                b.set_cached(!computed);
                b.set_result(key);
                b.set_surface(params.surface);
                return b;
            };
            if (!progressive) {
                for (size_t i : order) {
                    auto level = reductions_.level(*rec, key, r.keep(int(i)), encoding);
                    PreparedLevel p{begin_of(i), {level, &level->blob.bytes}};
                    p.begin.set_kind(v1::MeshBegin::FULL);
                    protocol::set_layout(p.begin, level->blob.layout);
                    p.begin.set_total_triangles(level->triangles);
                    p.begin.set_target_reached(level->target_reached);
                    set_level_error(*p.begin.mutable_error(), rec->record, level->operations);
                    levels.push_back(std::move(p));
                }
            } else {
                protocol::RefinementStream stream(rec->record.vertices());
                bool first = true;
                for (size_t i : order) {
                    const size_t target = target_triangles(rec->record, r.keep(int(i)));
                    const size_t ops = rec->record.operations_for(target);
                    const std::vector<uint32_t> triangles = rec->record.indexed_triangles(ops);
                    auto blob = std::make_shared<protocol::EncodedBlob>(
                        first ? protocol::encode_mesh(stream.base(triangles), encoding)
                              : protocol::encode_refinement(stream.refine(triangles), encoding));
                    PreparedLevel p{begin_of(i), {blob, &blob->bytes}};
                    p.begin.set_kind(first ? v1::MeshBegin::FULL : v1::MeshBegin::REFINEMENT);
                    protocol::set_layout(p.begin, blob->layout);
                    p.begin.set_total_triangles(triangles.size() / 3);
                    p.begin.set_target_reached(triangles.size() / 3 <= target);
                    set_level_error(*p.begin.mutable_error(), rec->record, ops);
                    levels.push_back(std::move(p));
                    first = false;
                }
            }
        } catch (const std::invalid_argument& e) {
            error.set_code(v1::Error::NOT_FOUND);
            error.set_message("request " + std::to_string(r.request_id()) + ": " + e.what());
        } catch (const InputError& e) {
            error.set_code(v1::Error::INVALID_ARGUMENT);
            error.set_message("request " + std::to_string(r.request_id()) + ": " + e.what());
        } catch (const std::exception& e) {
            error.set_code(v1::Error::INTERNAL);
            error.set_message("request " + std::to_string(r.request_id()) + ": " + e.what());
        }
        metrics_.observe_job_seconds(std::chrono::duration<double>(Clock::now() - start).count());
        asio::post(io_, [this, c, surface = params.surface, levels = std::move(levels),
                         error = std::move(error)]() mutable {
            const uint64_t rid = error.request_id();
            if (!c->open() || !c->request_active(rid)) return; // gone or cancelled
            c->end_request(rid);
            if (error.code() != v1::Error::CODE_UNSPECIFIED) {
                ++metrics_.request_errors;
                return c->send(error);
            }
            for (size_t i = 0; i < levels.size(); ++i) {
                BulkItem item;
                item.request_id = rid;
                item.surface = surface;
                item.level = levels[i].begin.level();
                item.begin_frame = protocol::encode_frame(levels[i].begin);
                item.blob = std::move(levels[i].blob);
                if (i + 1 == levels.size()) {
                    v1::RequestDone done;
                    done.set_request_id(rid);
                    item.after.push_back(protocol::encode_frame(done));
                }
                ++metrics_.levels_sent;
                c->send_bulk(std::move(item));
            }
        });
    });
}

void Service::remember_result(const std::string& key, const ReductionParams& params) {
    if (!known_results_.emplace(key, params).second) return;
    known_order_.push_back(key);
    while (known_order_.size() > kMaxRememberedResults) {
        known_results_.erase(known_order_.front());
        known_order_.pop_front();
    }
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
    spdlog::info("client {} joined session \"{}\" ({} members)", c->id(), name, s->members.size());
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
    spdlog::info("client {} left session \"{}\"", c.id(), name);
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
        asio::post(compute(), [this, id = v.surface()] {
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
    if (change.set_alpha() && !(v.alpha() >= 0 && v.alpha() <= 1))
        return c->send_error(v1::Error::INVALID_ARGUMENT, "alpha must be in [0, 1]");
    if (v.keep() != 0 && !(v.keep() > 0 && v.keep() <= 1))
        return c->send_error(v1::Error::INVALID_ARGUMENT, "keep must be in (0, 1]");
    v1::View before = s->view;
    if (!v.surface().empty()) s->view.set_surface(v.surface());
    if (change.set_alpha()) s->view.set_alpha(v.alpha());
    if (v.keep() != 0) s->view.set_keep(v.keep());
    if (!v.field().empty()) s->view.set_field(v.field());
    if (v.strategy() != v1::STRATEGY_UNSPECIFIED) s->view.set_strategy(v.strategy());
    if (v.placement() != v1::PLACEMENT_UNSPECIFIED) s->view.set_placement(v.placement());
    s->leader = c->id();
    ++s->version;
    broadcast(*s, "view", c->id());
    const bool mesh_changed =
        before.surface() != s->view.surface() || before.alpha() != s->view.alpha() ||
        before.keep() != s->view.keep() || before.strategy() != s->view.strategy() ||
        before.placement() != s->view.placement();
    if (mesh_changed) ++s->view_version;
    if (mesh_changed && !s->view.surface().empty()) {
        std::vector<uint64_t> all;
        for (const v1::Member& m : s->members) all.push_back(m.client_id());
        send_session_mesh(*s, all);
    }
}

void Service::send_session_mesh(const Session& s, std::vector<uint64_t> targets) {
    ReductionParams params;
    params.surface = s.view.surface();
    params.alpha = s.view.alpha();
    params.strategy = strategy_of(s.view.strategy());
    params.placement = placement_of(s.view.placement());
    const std::string key = result_key(params);
    remember_result(key, params);
    const float keep = s.view.keep() > 0 ? s.view.keep() : 1.0f;
    const std::string name = s.name, scope = s.scope;
    const uint64_t version = s.view_version;
    // Encode only what the members asked for.
    bool need_raw = false, need_meshopt = false;
    for (uint64_t id : targets)
        if (auto c = find(id))
            (c->has_capability("meshopt-codec") ? need_meshopt : need_raw) = true;
    asio::post(compute(), [this, params, key, keep, name, scope, version, need_raw, need_meshopt,
                           targets = std::move(targets)] {
        std::shared_ptr<const EncodedLevel> raw, meshopt;
        std::string failure;
        double seconds = 0;
        v1::LevelError error;
        try {
            bool computed = false;
            auto rec = reductions_.record(params, key, &computed);
            seconds = computed ? rec->seconds : 0;
            if (need_raw) raw = reductions_.level(*rec, key, keep, v1::RAW);
            if (need_meshopt) meshopt = reductions_.level(*rec, key, keep, v1::MESHOPT);
            set_level_error(error, rec->record,
                            rec->record.operations_for(target_triangles(rec->record, keep)));
        } catch (const std::exception& e) {
            failure = e.what();
        }
        asio::post(io_, [=, this] {
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
