// Sessions: joining and leaving, changing the shared view, and the session events (states,
// meshes, errors) delivered to a handler or queued for next_session_event.
#include "client_impl.h"

namespace ddsimp {

void Client::Impl::deliver(SessionEvent event) {
    SessionHandler h;
    {
        std::lock_guard lock(events_mutex);
        if (!handler) {
            events.push_back(std::move(event));
            events_ready.notify_all();
            return;
        }
        h = handler;
    }
    h(event);
}

// Whether `state` answers `op`: the change this client asked for. Another member's change
// (a join just before ours, say) may still be on its way to us when we ask.
bool Client::Impl::answers(const ControlOp& op, const SessionState& state) const {
    if (!op.state || op.session != state.name) return false;
    if (state.changed_by == 0) return true; // a server from before `changed_by`
    const bool joined = state.cause == "created" || state.cause == "joined";
    return state.changed_by == my_client_id &&
           (op.kind == ControlOp::Kind::Join ? joined : state.cause == "view");
}

void Client::Impl::on_session_state(const v1::SessionState& message) {
    SessionState state = from_wire(message);
    for (auto op = control.begin(); op != control.end(); ++op)
        if (answers(*op, state)) {
            op->state->set_value(state);
            control.erase(op);
            break;
        }
    deliver({SessionEvent::Kind::State, std::move(state), {}, {}, ErrorCode::Internal});
}

std::future<SessionState> Client::async_join_session(const std::string& name,
                                                     const std::string& key) {
    // A server without the capability would ignore the key and let anyone in: never send it.
    if (!key.empty() && connected() && !has_capability("session-keys"))
        throw ClientError(ErrorCode::InvalidArgument,
                          "the server does not support session keys (no \"session-keys\" "
                          "capability): the session \"" +
                              name + "\" would be open to anyone");
    auto promise = std::make_shared<std::promise<SessionState>>();
    auto future = promise->get_future();
    {
        std::lock_guard lock(impl_->info_mutex);
        impl_->joined[name] = key;
    }
    impl_->run([impl = impl_.get(), name, key, promise] {
        if (!impl->require_connection(*promise)) return;
        impl->control.push_back({ControlOp::Kind::Join, name, nullptr, promise});
        v1::JoinSession join;
        join.set_name(name);
        join.set_key(key);
        impl->send(protocol::encode_frame(join));
    });
    return future;
}

SessionState Client::join_session(const std::string& name, const std::string& key) {
    auto future = async_join_session(name, key);
    return impl_->wait(future, "join_session", true);
}

void Client::leave_session(const std::string& name) {
    {
        std::lock_guard lock(impl_->info_mutex);
        impl_->joined.erase(name);
    }
    impl_->run([impl = impl_.get(), name] {
        if (!(impl->plain || impl->tls)) return;
        impl->session_meshes.erase(name);
        v1::LeaveSession leave;
        leave.set_name(name);
        impl->send(protocol::encode_frame(leave));
    });
}

std::future<SessionState> Client::async_set_view(const std::string& session,
                                                 const ViewChange& change) {
    auto promise = std::make_shared<std::promise<SessionState>>();
    auto future = promise->get_future();
    const v1::SetSessionState message = to_wire(session, change);
    impl_->run([impl = impl_.get(), session, message, promise] {
        if (!impl->require_connection(*promise)) return;
        impl->control.push_back({ControlOp::Kind::Set, session, nullptr, promise});
        impl->send(protocol::encode_frame(message));
    });
    return future;
}

SessionState Client::set_view(const std::string& session, const ViewChange& change) {
    auto future = async_set_view(session, change);
    return impl_->wait(future, "set_view", true);
}

void Client::on_session_event(SessionHandler handler) {
    std::deque<SessionEvent> queued;
    {
        std::lock_guard lock(impl_->events_mutex);
        impl_->handler = std::move(handler);
        if (impl_->handler) queued.swap(impl_->events);
    }
    // Events queued before the handler was set go to it first, on the network thread.
    if (!queued.empty())
        impl_->run([impl = impl_.get(), queued = std::move(queued)]() mutable {
            for (SessionEvent& e : queued) impl->deliver(std::move(e));
        });
}

std::optional<SessionEvent> Client::next_session_event(std::chrono::milliseconds timeout) {
    impl_->require_other_thread("next_session_event");
    std::unique_lock lock(impl_->events_mutex);
    if (!impl_->events_ready.wait_for(lock, timeout, [&] { return !impl_->events.empty(); }))
        return std::nullopt;
    SessionEvent event = std::move(impl_->events.front());
    impl_->events.pop_front();
    return event;
}

} // namespace ddsimp
