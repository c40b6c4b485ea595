// Level requests: sending them, cancelling them, and assembling the levels (whole meshes or
// refinements of the last one) that arrive for them in chunks; also the meshes a session pushes.
#include "client_impl.h"

namespace ddsimp {

namespace {

Level level_from(const v1::MeshBegin& begin, uint64_t wire_bytes) {
    Level level;
    level.request_id = begin.request_id();
    level.session = begin.session();
    level.index = begin.level();
    level.keep = begin.keep();
    level.refinement = begin.kind() == v1::MeshBegin::REFINEMENT;
    level.triangles = begin.total_triangles();
    level.encoding = begin.encoding() == v1::MESHOPT ? Encoding::Meshopt : Encoding::Raw;
    level.wire_bytes = wire_bytes;
    level.seconds = begin.seconds();
    level.cached = begin.cached();
    level.result = begin.result();
    level.target_reached = begin.target_reached();
    level.preview = begin.preview();
    if (begin.has_error())
        level.error = LevelError{begin.error().geometric(), begin.error().data(),
                                 size_t(begin.error().data_components())};
    return level;
}

} // namespace

void Client::Impl::on_mesh_begin(const v1::MeshBegin& begin) {
    const uint64_t id = begin.request_id();
    if (id != 0 && !requests.count(id)) return; // cancelled: its chunks are dropped too
    if (id == 0 && begin.session().empty())
        throw protocol::FrameError("a MESH_BEGIN with neither a request nor a session");
    IncomingMesh mesh{begin, {}, {}};
    try {
        mesh.layout = protocol::layout_of(begin);
    } catch (const protocol::BlobError& e) {
        return fail_mesh(begin, e.what());
    }
    incoming[{id, begin.level()}] = std::move(mesh);
}

void Client::Impl::on_mesh_chunk(const v1::MeshChunk& chunk) {
    auto it = incoming.find({chunk.request_id(), chunk.level()});
    if (it == incoming.end()) return;
    IncomingMesh& mesh = it->second;
    if (chunk.offset() != mesh.bytes.size() ||
        mesh.bytes.size() + chunk.data().size() > mesh.begin.total_bytes())
        return fail_mesh(mesh.begin, "a chunk at offset " + std::to_string(chunk.offset()) +
                                         " of " + std::to_string(chunk.data().size()) +
                                         " bytes after " + std::to_string(mesh.bytes.size()) +
                                         " of " + std::to_string(mesh.begin.total_bytes()));
    mesh.bytes += chunk.data();
}

void Client::Impl::on_mesh_end(const v1::MeshEnd& end) {
    auto it = incoming.find({end.request_id(), end.level()});
    if (it == incoming.end()) return;
    IncomingMesh mesh = std::move(it->second);
    incoming.erase(it);
    const v1::MeshBegin& begin = mesh.begin;
    Level level = level_from(begin, mesh.bytes.size());
    RequestState* request = nullptr;
    if (begin.request_id() != 0) {
        auto r = requests.find(begin.request_id());
        if (r == requests.end()) return;
        request = &r->second;
    }
    try {
        if (mesh.bytes.size() != begin.total_bytes())
            throw protocol::BlobError(std::to_string(mesh.bytes.size()) + " bytes of " +
                                      std::to_string(begin.total_bytes()));
        // The mesh a refinement applies to: the request's, or the session's last one.
        std::optional<protocol::SlotMesh>& held =
            request ? request->mesh : session_meshes[begin.session()];
        if (begin.kind() == v1::MeshBegin::REFINEMENT) {
            if (!held) throw protocol::BlobError("a refinement with no level before it");
            held->apply(protocol::decode_refinement(mesh.bytes, mesh.layout));
            level.mesh = held->live();
            level.slots = held->slots();
        } else {
            Surface surface = protocol::decode_mesh(mesh.bytes, mesh.layout);
            if (begin.preview()) {
                // Drawn now, replaced by the exact level: never the base of refinements.
                if (request && request->progressive) level.slots = surface;
            } else if (!request || request->progressive) {
                held.emplace(surface);
                level.slots = surface;
            }
            level.mesh = std::move(surface);
        }
    } catch (const protocol::BlobError& e) {
        return fail_mesh(begin, e.what());
    }

    if (!request) {
        level.slots = Surface{}; // sessions: whole meshes (a refinement is applied anyway)
        SessionEvent event;
        event.kind = SessionEvent::Kind::Mesh;
        event.mesh = std::move(level);
        return deliver(std::move(event));
    }
    if (!request->progressive) level.slots = Surface{};
    if (request->on_level) request->on_level(level);
    // The callback may have cancelled this request.
    auto r = requests.find(begin.request_id());
    if (r == requests.end()) return;
    const uint32_t i = begin.level();
    if (!begin.preview() && i < r->second.levels.size() && !r->second.ready[i]) {
        r->second.ready[i] = true;
        r->second.levels[i].set_value(std::move(level));
    }
}

// A level this client cannot read ends its request (or is reported to the session).
void Client::Impl::fail_mesh(const v1::MeshBegin& begin, const std::string& why) {
    const uint64_t id = begin.request_id();
    const ClientError error(ErrorCode::Protocol,
                            "level " + std::to_string(begin.level()) + " from " + where() +
                                " cannot be read: " + why,
                            id);
    incoming.erase({id, begin.level()});
    if (id == 0) {
        deliver({SessionEvent::Kind::Error, {}, {}, error.what(), error.code()});
        return;
    }
    auto r = requests.find(id);
    if (r == requests.end()) return;
    fail_request(r->second, error);
    requests.erase(r);
    v1::Cancel cancel;
    cancel.set_request_id(id);
    send(protocol::encode_frame(cancel));
}

void Client::Impl::on_request_done(const v1::RequestDone& done) {
    auto r = requests.find(done.request_id());
    if (r == requests.end()) return;
    RequestState& state = r->second;
    for (size_t i = 0; i < state.levels.size(); ++i)
        if (!state.ready[i]) {
            state.ready[i] = true;
            state.levels[i].set_exception(as_exception(
                ClientError(ErrorCode::Protocol,
                            "the server finished request " + std::to_string(done.request_id()) +
                                " without level " + std::to_string(i),
                            done.request_id())));
        }
    state.done.set_value();
    requests.erase(r);
}

void Client::Impl::fail_request(RequestState& r, const ClientError& error) {
    for (size_t i = 0; i < r.levels.size(); ++i)
        if (!r.ready[i]) {
            r.ready[i] = true;
            r.levels[i].set_exception(as_exception(error));
        }
    r.done.set_exception(as_exception(error));
}

void Client::Impl::cancel_request(uint64_t id) {
    auto r = requests.find(id);
    if (r == requests.end()) return;
    fail_request(r->second, ClientError(ErrorCode::Cancelled,
                                        "request " + std::to_string(id) + " was cancelled", id));
    requests.erase(r);
    std::erase_if(incoming, [id](const auto& kv) { return kv.first.first == id; });
    v1::Cancel cancel;
    cancel.set_request_id(id);
    send(protocol::encode_frame(cancel));
}

PendingRequest Client::request(const LevelRequest& request, LevelCallback on_level) {
    check_request(request);
    PendingRequest pending;
    pending.id = impl_->take_id();
    RequestState state;
    state.levels.resize(request.keep.size());
    state.ready.assign(request.keep.size(), false);
    for (auto& p : state.levels) pending.levels.push_back(p.get_future().share());
    pending.done = state.done.get_future().share();
    state.on_level = std::move(on_level);
    state.progressive = request.progressive && impl_->capability("progressive");
    const v1::Request message = to_wire(request, pending.id, impl_->capability("meshopt-codec"),
                                        impl_->capability("progressive"));
    auto shared_state = std::make_shared<RequestState>(std::move(state));
    impl_->run([impl = impl_.get(), id = pending.id, shared_state, message] {
        if (!(impl->plain || impl->tls)) {
            Impl::fail_request(*shared_state,
                               ClientError(ErrorCode::Connection, "the client is not connected"));
            return;
        }
        impl->requests.emplace(id, std::move(*shared_state));
        impl->send(protocol::encode_frame(message));
    });
    return pending;
}

std::vector<Level> Client::request_levels(const LevelRequest& request) {
    impl_->require_other_thread("request_levels");
    PendingRequest pending = this->request(request);
    std::vector<Level> levels;
    for (auto& f : pending.levels) levels.push_back(f.get());
    pending.done.get();
    return levels;
}

void Client::cancel(uint64_t request_id) {
    impl_->run([impl = impl_.get(), request_id] { impl->cancel_request(request_id); });
}

} // namespace ddsimp
