// ddsimp::Client: its life (the network thread it starts and stops), connecting, closing, and
// what the server said about itself in its Welcome.
#include "client_impl.h"

namespace ddsimp {

Client::Client() : impl_(std::make_shared<Impl>()) {}

Client::~Client() {
    Impl* impl = impl_.get();
    std::promise<void> closed;
    auto done = closed.get_future();
    asio::post(impl->io, [impl, &closed] {
        impl->shut(ClientError(ErrorCode::Connection, "the client was destroyed"));
        impl->resolver.reset();
        impl->connect_timer.reset();
        closed.set_value();
    });
    if (!impl->on_network_thread()) done.wait();
    impl->work.reset();
    impl->io.stop();
    if (impl->thread.joinable()) {
        if (impl->on_network_thread())
            impl->thread.detach(); // destroyed from its own callback: cannot join itself
        else
            impl->thread.join();
    }
}

std::future<void> Client::async_connect(const ConnectOptions& options) {
    auto promise = std::make_shared<std::promise<void>>();
    auto future = promise->get_future();
    {
        std::lock_guard lock(impl_->info_mutex);
        impl_->last_options = options;
    }
    impl_->run([impl = impl_.get(), options, promise] { impl->start_connect(options, promise); });
    return future;
}

void Client::connect(const ConnectOptions& options) {
    impl_->require_other_thread("connect");
    auto future = async_connect(options);
    // The network thread enforces the timeout itself; this only waits for it.
    future.get();
}

void Client::reconnect() {
    std::optional<ConnectOptions> options;
    std::map<std::string, std::string> sessions;
    {
        std::lock_guard lock(impl_->info_mutex);
        options = impl_->last_options;
        sessions = impl_->joined;
    }
    if (!options) throw ClientError(ErrorCode::Connection, "reconnect() before any connect()");
    connect(*options);
    for (const auto& [name, key] : sessions) join_session(name, key);
}

void Client::close() {
    impl_->require_other_thread("close");
    std::promise<void> closed;
    auto done = closed.get_future();
    asio::post(impl_->io, [impl = impl_.get(), &closed] {
        impl->shut(ClientError(ErrorCode::Connection, "the connection was closed by the client"));
        closed.set_value();
    });
    done.wait();
    std::lock_guard lock(impl_->info_mutex);
    impl_->joined.clear();
}

bool Client::connected() const {
    std::lock_guard lock(impl_->info_mutex);
    return impl_->is_connected;
}

uint64_t Client::client_id() const {
    std::lock_guard lock(impl_->info_mutex);
    return impl_->my_client_id;
}

std::vector<std::string> Client::capabilities() const {
    std::lock_guard lock(impl_->info_mutex);
    return impl_->caps;
}

bool Client::has_capability(const std::string& name) const {
    return impl_->capability(name);
}

uint64_t Client::max_surface_triangles() const {
    std::lock_guard lock(impl_->info_mutex);
    return impl_->max_triangles;
}

} // namespace ddsimp
