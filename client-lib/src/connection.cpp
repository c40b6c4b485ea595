// The connection: resolving, connecting (TLS when asked), the Hello/Welcome/Auth handshake,
// the read loop that decodes frames and dispatches them, and the write queue.
#include "client_impl.h"

namespace ddsimp {

namespace client_detail {

std::exception_ptr as_exception(const ClientError& error) {
    return std::make_exception_ptr(
        ClientError(error.code(), std::string(error.what()), error.request_id()));
}

} // namespace client_detail

// Ends the connection: every pending operation fails with `error`.
void Client::Impl::shut(const ClientError& error) {
    bool had_sessions = false;
    {
        std::lock_guard lock(info_mutex);
        is_connected = false; // before any waiter wakes up
        had_sessions = !joined.empty();
    }
    if (handshake) {
        handshake->set_exception(as_exception(error));
        handshake.reset();
    }
    for (auto& [id, promise] : uploads) promise.set_exception(as_exception(error));
    uploads.clear();
    for (auto& [id, promise] : deletes) promise.set_exception(as_exception(error));
    deletes.clear();
    upload_jobs.clear();
    for (auto& [id, r] : requests) fail_request(r, error);
    requests.clear();
    for (ControlOp& op : control) fail_control(op, error);
    control.clear();
    incoming.clear();
    session_meshes.clear();
    out.clear();
    writing = false;
    const bool was_open = plain || tls;
    boost::system::error_code ignored;
    if (tls) tls->lowest_layer().close(ignored);
    if (plain) plain->close(ignored);
    if (resolver) resolver->cancel();
    if (connect_timer) connect_timer->cancel();
    // The closed stream's aborted operations are already queued and still use it (an SSL
    // read reaches into its buffers): it is destroyed by a handler queued after them.
    if (was_open) asio::post(io, [p = std::move(plain), t = std::move(tls)] {});
    ++generation;
    if (was_open && had_sessions)
        deliver({SessionEvent::Kind::Error, {}, {}, error.what(), error.code()});
}

void Client::Impl::fail_control(ControlOp& op, const ClientError& error) {
    if (op.list) op.list->set_exception(as_exception(error));
    if (op.state) op.state->set_exception(as_exception(error));
}

void Client::Impl::start_connect(const ConnectOptions& options,
                                 std::shared_ptr<std::promise<void>> done) {
    shut(ClientError(ErrorCode::Connection, "the connection was closed by the client"));
    active = options;
    handshake = std::move(done);
    decoder = protocol::FrameDecoder(kMaxReceivedFrameBytes);
    const uint64_t gen = generation;
    const std::string prefix = "cannot connect to " + where() + ": ";

    try {
        if (options.tls) {
            tls_context = std::make_unique<ssl::context>(ssl::context::tls_client);
            if (options.tls_insecure) {
                tls_context->set_verify_mode(ssl::verify_none);
            } else {
                if (options.ca_file.empty())
                    tls_context->set_default_verify_paths();
                else
                    tls_context->load_verify_file(options.ca_file);
                tls_context->set_verify_mode(ssl::verify_peer);
            }
            tls = std::make_unique<ssl::stream<tcp::socket>>(io, *tls_context);
            if (!options.tls_insecure)
                tls->set_verify_callback(ssl::host_name_verification(options.host));
            SSL_set_tlsext_host_name(tls->native_handle(), options.host.c_str());
        } else {
            plain = std::make_unique<tcp::socket>(io);
        }
    } catch (const boost::system::system_error& e) {
        const std::string what = options.ca_file.empty()
                                     ? std::string("TLS set-up failed: ")
                                     : "cannot read the CA file " + options.ca_file + ": ";
        shut(ClientError(ErrorCode::Connection, prefix + what + e.code().message()));
        return;
    }

    connect_timer = std::make_unique<asio::steady_timer>(io, options.timeout);
    connect_timer->async_wait([this, gen, prefix](boost::system::error_code ec) {
        if (ec || gen != generation || !handshake) return;
        shut(ClientError(ErrorCode::Connection, prefix + "no answer within " +
                                                    std::to_string(active.timeout.count()) +
                                                    " ms"));
    });

    resolver = std::make_unique<tcp::resolver>(io);
    resolver->async_resolve(
        options.host, std::to_string(options.port),
        [this, gen, prefix](boost::system::error_code ec, tcp::resolver::results_type found) {
            if (gen != generation) return;
            if (ec) return shut(ClientError(ErrorCode::Connection, prefix + ec.message()));
            tcp::socket& socket = tls ? tls->next_layer() : *plain;
            asio::async_connect(
                socket, found,
                [this, gen, prefix](boost::system::error_code ec, const tcp::endpoint&) {
                    if (gen != generation) return;
                    if (ec) return shut(ClientError(ErrorCode::Connection, prefix + ec.message()));
                    (tls ? tls->next_layer() : *plain).set_option(tcp::no_delay(true));
                    if (!tls) return on_transport_ready();
                    tls->async_handshake(ssl::stream_base::client,
                                         [this, gen, prefix](boost::system::error_code ec) {
                                             if (gen != generation) return;
                                             if (ec)
                                                 return shut(
                                                     ClientError(ErrorCode::Connection,
                                                                 prefix + "TLS: " + ec.message()));
                                             on_transport_ready();
                                         });
                });
        });
}

void Client::Impl::on_transport_ready() {
    v1::Hello hello;
    hello.set_protocol_version(protocol::kProtocolVersion);
    hello.set_client_name(active.client_name);
    hello.set_kind(to_wire(active.kind));
    for (const std::string& c : active.capabilities) hello.add_capabilities(c);
    send(protocol::encode_frame(hello));
    read_more();
}

void Client::Impl::read_more() {
    const uint64_t gen = generation;
    with_stream([this, gen](auto& stream) {
        stream.async_read_some(asio::buffer(read_buffer),
                               [this, gen](boost::system::error_code ec, size_t n) {
                                   if (gen != generation) return;
                                   on_read(ec, n);
                               });
    });
}

void Client::Impl::on_read(boost::system::error_code ec, size_t n) {
    if (ec) {
        const bool eof = ec == asio::error::eof || ec == ssl::error::stream_truncated;
        const std::string text = handshake ? "cannot connect to " + where() + ": "
                                           : "the connection to " + where() + " was lost: ";
        // A TLS server hangs up on a plain Hello: say so.
        const std::string hint = handshake && !tls ? " (is it a TLS server?)" : "";
        shut(ClientError(ErrorCode::Connection,
                         text + (eof ? "the server closed the connection" + hint : ec.message())));
        return;
    }
    const uint64_t gen = generation;
    try {
        decoder.feed(std::string_view(read_buffer.data(), n));
        while (gen == generation) {
            std::optional<protocol::Frame> frame = decoder.next();
            if (!frame) break;
            dispatch(*frame);
        }
    } catch (const protocol::FrameError& e) {
        shut(ClientError(ErrorCode::Protocol,
                         "the server at " + where() + " sent a bad frame: " + e.what()));
        return;
    }
    if (gen == generation) read_more();
}

void Client::Impl::send(std::string frame) {
    out.push_back(std::move(frame));
    write_next();
}

void Client::Impl::write_next() {
    if (writing || !(plain || tls)) return;
    if (out.empty() && !upload_jobs.empty()) cut_upload_chunk();
    if (out.empty()) return;
    writing = true;
    const uint64_t gen = generation;
    with_stream([this, gen](auto& stream) {
        asio::async_write(stream, asio::buffer(out.front()),
                          [this, gen](boost::system::error_code ec, size_t) {
                              if (gen != generation) return;
                              writing = false;
                              if (ec)
                                  return shut(ClientError(ErrorCode::Connection,
                                                          "the connection to " + where() +
                                                              " was lost: " + ec.message()));
                              out.pop_front();
                              write_next();
                          });
    });
}

void Client::Impl::dispatch(const protocol::Frame& frame) {
    using protocol::parse_payload;
    switch (frame.type) {
    case v1::WELCOME:
        return on_welcome(parse_payload<v1::Welcome>(frame));
    case v1::AUTH_OK:
        return finish_handshake();
    case v1::ERROR:
        return on_error(parse_payload<v1::Error>(frame));
    case v1::PING: {
        v1::Pong pong;
        pong.set_nonce(parse_payload<v1::Ping>(frame).nonce());
        return send(protocol::encode_frame(pong));
    }
    case v1::PONG:
        return;
    case v1::SESSION_STATE:
        return on_session_state(parse_payload<v1::SessionState>(frame));
    case v1::UPLOAD_RESULT:
        return on_upload_result(parse_payload<v1::UploadResult>(frame));
    case v1::SURFACE_LIST:
        return on_surface_list(parse_payload<v1::SurfaceList>(frame));
    case v1::SURFACE_DELETED:
        return on_surface_deleted(parse_payload<v1::SurfaceDeleted>(frame));
    case v1::MESH_BEGIN:
        return on_mesh_begin(parse_payload<v1::MeshBegin>(frame));
    case v1::MESH_CHUNK:
        return on_mesh_chunk(parse_payload<v1::MeshChunk>(frame));
    case v1::MESH_END:
        return on_mesh_end(parse_payload<v1::MeshEnd>(frame));
    case v1::REQUEST_DONE:
        return on_request_done(parse_payload<v1::RequestDone>(frame));
    default:
        throw protocol::FrameError("a " + protocol::message_type_name(frame.type) +
                                   " message, which a server does not send");
    }
}

void Client::Impl::on_welcome(const v1::Welcome& welcome) {
    if (!handshake) throw protocol::FrameError("a second WELCOME");
    {
        std::lock_guard lock(info_mutex);
        my_client_id = welcome.client_id();
        caps.assign(welcome.capabilities().begin(), welcome.capabilities().end());
        max_triangles = welcome.max_surface_triangles();
    }
    if (!welcome.auth_required()) return finish_handshake();
    if (active.token.empty())
        return shut(ClientError(ErrorCode::Unauthenticated,
                                "the server at " + where() + " requires a token"));
    v1::Auth auth;
    auth.set_token(active.token);
    send(protocol::encode_frame(auth));
}

void Client::Impl::finish_handshake() {
    if (!handshake) throw protocol::FrameError("an AUTH_OK that answers nothing");
    if (connect_timer) connect_timer->cancel();
    {
        std::lock_guard lock(info_mutex);
        is_connected = true;
    }
    handshake->set_value();
    handshake.reset();
}

void Client::Impl::on_error(const v1::Error& message) {
    const ClientError error = error_of(message);
    const auto code = message.code();
    if (code == v1::Error::BAD_FRAME || code == v1::Error::UNSUPPORTED_VERSION ||
        code == v1::Error::UNAUTHENTICATED || handshake)
        return shut(error); // the server closes the connection after these
    if (const uint64_t id = message.request_id()) {
        if (auto u = uploads.find(id); u != uploads.end()) {
            u->second.set_exception(as_exception(error));
            uploads.erase(u);
            std::erase_if(upload_jobs, [id](const UploadJob& j) { return j.id == id; });
        } else if (auto d = deletes.find(id); d != deletes.end()) {
            d->second.set_exception(as_exception(error));
            deletes.erase(d);
        } else if (auto r = requests.find(id); r != requests.end()) {
            fail_request(r->second, error);
            requests.erase(r);
            std::erase_if(incoming, [id](const auto& kv) { return kv.first.first == id; });
        }
        return; // an error for something already cancelled or finished
    }
    if (!control.empty()) {
        fail_control(control.front(), error);
        control.pop_front();
        return;
    }
    deliver({SessionEvent::Kind::Error, {}, {}, error.what(), error.code()});
}
} // namespace ddsimp
