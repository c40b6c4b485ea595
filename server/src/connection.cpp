#include "connection.h"

#include "client_limits.h"
#include "log_text.h"
#include "service.h"

#include "ddsimp/protocol/mesh_codec.h"
#include "ddsimp/protocol/reduction_options.h"

#include <spdlog/spdlog.h>

#include <algorithm>

namespace ddsimp::server {
namespace {

// What this server can do; Welcome answers with the intersection.
const std::set<std::string> kCapabilities{"meshopt-codec", "progressive", "sessions",
                                          "session-keys",  "previews",    "surface-delete"};

} // namespace

Connection::Connection(Service& service, std::shared_ptr<Transport> transport, uint64_t id)
    : service_(service), transport_(std::move(transport)), id_(id), peer_(transport_->peer()),
      queue_(protocol::kDefaultChunkBytes), idle_timer_(service.io()), upload_timer_(service.io()) {
    member_.set_client_id(id);
}

std::set<std::string> Connection::scopes() const {
    std::set<std::string> out{kPublicScope};
    for (const auto& [name, scope] : sessions_) out.insert(scope);
    return out;
}

void Connection::start() {
    spdlog::debug("client {} connected from {}", id_, peer_);
    transport_->start(shared_from_this());
    // Until the handshake is done, the handshake timeout applies.
    idle_timer_.expires_after(to_duration(service_.config().timeouts.handshake));
    idle_timer_.async_wait([weak = weak_from_this()](boost::system::error_code ec) {
        auto self = weak.lock();
        if (!ec && self && !self->authenticated_) self->drop("no handshake within the timeout");
    });
}

void Connection::arm_idle_timer() {
    idle_timer_.expires_after(to_duration(service_.config().timeouts.idle));
    idle_timer_.async_wait([weak = weak_from_this()](boost::system::error_code ec) {
        auto self = weak.lock();
        if (ec || !self) return;
        // Waiting for its own request or upload, or being sent something, is not idleness: a
        // long simplification or storing a large surface sends nothing, and a client that stops
        // reading is dropped by the send timeout instead.
        if (!self->active_requests_.empty() || self->storing_uploads_ > 0 || self->writing_ ||
            !self->queue_.empty())
            return self->arm_idle_timer();
        self->drop("idle for the idle timeout");
    });
}

void Connection::on_frame(protocol::Frame frame) {
    if (closing_) return;
    service_.metrics().bytes_received += protocol::kHeaderBytes + frame.payload.size();
    if (authenticated_) arm_idle_timer();
    try {
        handle(frame);
    } catch (const protocol::FrameError& e) {
        on_bad_frame(e.what());
    } catch (const std::exception& e) {
        // A bug or an allocation that failed: end this connection, never the server.
        spdlog::error("client {} ({}): {} frame: {}", id_, peer_,
                      protocol::message_type_name(frame.type), loggable(e.what(), 300));
        send_error(v1::Error::INTERNAL, std::string("the server failed: ") + e.what(), 0, true);
    }
}

void Connection::on_bad_frame(const std::string& why) {
    ++service_.metrics().bad_frames;
    spdlog::warn("client {} ({}): bad frame: {}", id_, peer_, loggable(why, 300));
    send_error(v1::Error::BAD_FRAME, why, 0, true);
}

void Connection::handle(const protocol::Frame& frame) {
    using protocol::parse_payload;
    if (!hello_) {
        if (frame.type != v1::HELLO)
            return send_error(v1::Error::UNAUTHENTICATED, "the first message must be Hello", 0,
                              true);
        return on_hello(parse_payload<v1::Hello>(frame));
    }
    if (!authenticated_) {
        if (frame.type != v1::AUTH)
            return send_error(v1::Error::UNAUTHENTICATED, "authenticate first", 0, true);
        return on_auth(parse_payload<v1::Auth>(frame));
    }
    switch (frame.type) {
    case v1::PING: {
        v1::Pong pong;
        pong.set_nonce(parse_payload<v1::Ping>(frame).nonce());
        return send(pong);
    }
    case v1::PONG:
        return;
    case v1::UPLOAD_BEGIN:
        return on_upload_begin(parse_payload<v1::UploadBegin>(frame));
    case v1::UPLOAD_CHUNK: {
        v1::UploadChunk chunk = parse_payload<v1::UploadChunk>(frame);
        return on_upload_chunk(chunk);
    }
    case v1::UPLOAD_END:
        return on_upload_end(parse_payload<v1::UploadEnd>(frame));
    case v1::LIST_SURFACES:
        parse_payload<v1::ListSurfaces>(frame);
        return service_.list_surfaces(*this);
    case v1::DELETE_SURFACE:
        return service_.delete_surface(shared_from_this(), parse_payload<v1::DeleteSurface>(frame));
    case v1::REQUEST:
        return on_request(parse_payload<v1::Request>(frame));
    case v1::CANCEL:
        return on_cancel(parse_payload<v1::Cancel>(frame));
    case v1::JOIN_SESSION:
        return service_.join(shared_from_this(), parse_payload<v1::JoinSession>(frame));
    case v1::LEAVE_SESSION:
        return service_.leave(*this, parse_payload<v1::LeaveSession>(frame).name());
    case v1::SET_SESSION_STATE:
        return service_.set_state(shared_from_this(), parse_payload<v1::SetSessionState>(frame));
    default:
        return send_error(v1::Error::INVALID_ARGUMENT,
                          "a client does not send " + protocol::message_type_name(frame.type));
    }
}

void Connection::on_hello(const v1::Hello& hello) {
    if (hello.protocol_version() != protocol::kProtocolVersion)
        return send_error(v1::Error::UNSUPPORTED_VERSION,
                          "protocol version " + std::to_string(hello.protocol_version()) +
                              " is not supported (this server speaks version 1)",
                          0, true);
    hello_ = true;
    member_.set_name(hello.client_name().substr(0, kMaxNameBytes));
    member_.set_kind(hello.kind());
    for (const std::string& c : hello.capabilities())
        if (kCapabilities.count(c)) capabilities_.insert(c);
    const Config& config = service_.config();
    v1::Welcome welcome;
    welcome.set_protocol_version(protocol::kProtocolVersion);
    welcome.set_server_name(service_.server_name());
    for (const std::string& c : capabilities_) welcome.add_capabilities(c);
    welcome.set_auth_required(service_.tokens().required());
    welcome.set_client_id(id_);
    welcome.set_max_frame_bytes(config.max_frame_bytes);
    welcome.set_max_surface_triangles(config.max_surface_triangles);
    welcome.set_chunk_bytes(uint32_t(protocol::kDefaultChunkBytes));
    protocol::set_defaults(*welcome.mutable_defaults());
    send(welcome);
    if (!service_.tokens().required()) {
        authenticated_ = true;
        arm_idle_timer();
    }
    spdlog::info("client {} ({}) is \"{}\" ({})", id_, peer_, loggable(member_.name()),
                 v1::ClientKind_Name(member_.kind()));
}

void Connection::on_auth(const v1::Auth& auth) {
    std::optional<std::string> name = service_.tokens().match(auth.token());
    if (!name) {
        spdlog::warn("client {} ({}): wrong token", id_, peer_);
        return send_error(v1::Error::UNAUTHENTICATED, "wrong token", 0, true);
    }
    token_ = std::move(*name);
    authenticated_ = true;
    arm_idle_timer();
    send(v1::AuthOk{});
}

void Connection::on_upload_begin(const v1::UploadBegin& begin) {
    const Config& config = service_.config();
    const uint64_t id = begin.upload_id();
    const auto refuse = [&](v1::Error::Code code, const std::string& why) {
        send_error(code, "upload " + std::to_string(id) + ": " + why, id);
    };
    if (uploads_.count(id)) return refuse(v1::Error::INVALID_ARGUMENT, "already in progress");
    if (uploads_.size() >= kMaxUploadsPerConnection)
        return refuse(v1::Error::RESOURCE_EXHAUSTED, "at most " +
                                                         std::to_string(kMaxUploadsPerConnection) +
                                                         " uploads at once per connection");
    if (begin.triangle_count() > config.max_surface_triangles)
        return refuse(v1::Error::RESOURCE_EXHAUSTED,
                      std::to_string(begin.triangle_count()) +
                          " triangles, over the server's limit of " +
                          std::to_string(config.max_surface_triangles));
    if (begin.vertex_count() > kMaxVerticesPerTriangle * config.max_surface_triangles)
        return refuse(v1::Error::RESOURCE_EXHAUSTED,
                      std::to_string(begin.vertex_count()) + " vertices, over the server's limit");
    // The same answer whether the session does not exist or this client is not in it.
    if (!begin.session().empty() && !sessions_.count(begin.session()))
        return refuse(v1::Error::NOT_FOUND,
                      "you are not a member of a session \"" + begin.session() + "\"");
    if (begin.name().size() > kMaxNameBytes)
        return refuse(v1::Error::INVALID_ARGUMENT,
                      "a name of " + std::to_string(begin.name().size()) + " bytes (at most " +
                          std::to_string(kMaxNameBytes) + ")");
    if (size_t(begin.fields_size()) > kMaxFields)
        return refuse(v1::Error::RESOURCE_EXHAUSTED, std::to_string(begin.fields_size()) +
                                                         " fields (at most " +
                                                         std::to_string(kMaxFields) + ")");
    std::vector<protocol::FieldSpec> fields;
    for (const v1::FieldInfo& f : begin.fields()) {
        if (f.name().size() > kMaxNameBytes)
            return refuse(v1::Error::INVALID_ARGUMENT,
                          "a field name of " + std::to_string(f.name().size()) +
                              " bytes (at most " + std::to_string(kMaxNameBytes) + ")");
        if (f.components() < 1 || f.components() > kMaxFieldComponents)
            return refuse(v1::Error::INVALID_ARGUMENT,
                          "field \"" + f.name() + "\" has " + std::to_string(f.components()) +
                              " components (1 to " + std::to_string(kMaxFieldComponents) +
                              " allowed)");
        fields.push_back(protocol::field_spec_of(f));
    }
    uint64_t expected = 0;
    try {
        expected = protocol::raw_mesh_bytes(begin.vertex_count(), begin.triangle_count(), fields);
    } catch (const protocol::BlobError& e) {
        return refuse(v1::Error::INVALID_ARGUMENT, e.what());
    }
    if (begin.total_bytes() != expected)
        return refuse(v1::Error::INVALID_ARGUMENT,
                      "total_bytes is " + std::to_string(begin.total_bytes()) + " but " +
                          std::to_string(begin.vertex_count()) + " vertices, " +
                          std::to_string(begin.triangle_count()) +
                          " triangles and these fields take " + std::to_string(expected));
    if (expected > uint64_t(config.max_surface_mb) << 20)
        return refuse(v1::Error::RESOURCE_EXHAUSTED,
                      fmt::format("{:.1f} MiB, over the server's largest surface of {} MiB "
                                  "(--max-surface-mb)",
                                  double(expected) / double(1 << 20), config.max_surface_mb));
    // Nothing is allocated before the bytes are counted against the server-wide budget.
    UploadOwner owner{token_, begin.session(),
                      begin.session().empty() ? "" : sessions_.at(begin.session()), ""};
    if (auto why = service_.reserve_upload(owner, expected))
        return refuse(v1::Error::RESOURCE_EXHAUSTED, *why);
    Upload& u = uploads_[id];
    u.begin = begin;
    u.owner = std::move(owner);
    u.bytes.reserve(expected);
    u.last_heard = std::chrono::steady_clock::now();
    if (uploads_.size() == 1) expire_uploads();
}

void Connection::expire_uploads() {
    const auto timeout = to_duration(service_.config().timeouts.upload);
    const auto now = std::chrono::steady_clock::now();
    auto next = now + timeout;
    for (auto it = uploads_.begin(); it != uploads_.end();) {
        auto here = it++;
        if (now - here->second.last_heard < timeout) {
            next = std::min(next, here->second.last_heard + timeout);
            continue;
        }
        const uint64_t id = here->first;
        forget_upload(here);
        send_error(v1::Error::CANCELLED,
                   fmt::format("upload {}: no chunk for {:g} s (--upload-timeout); begin it again",
                               id, service_.config().timeouts.upload),
                   id);
    }
    if (uploads_.empty() || closed_) return;
    upload_timer_.expires_at(next);
    upload_timer_.async_wait([weak = weak_from_this()](boost::system::error_code ec) {
        auto self = weak.lock();
        if (!ec && self && !self->closed_) self->expire_uploads();
    });
}

void Connection::forget_upload(std::map<uint64_t, Upload>::iterator it) {
    service_.release_upload(it->second.owner, it->second.begin.total_bytes());
    uploads_.erase(it);
}

void Connection::on_upload_chunk(v1::UploadChunk& chunk) {
    auto it = uploads_.find(chunk.upload_id());
    if (it == uploads_.end())
        return send_error(v1::Error::INVALID_ARGUMENT,
                          "upload " + std::to_string(chunk.upload_id()) + " was not begun",
                          chunk.upload_id());
    Upload& u = it->second;
    std::string why;
    if (chunk.offset() != u.bytes.size())
        why = "a chunk at offset " + std::to_string(chunk.offset()) + " after " +
              std::to_string(u.bytes.size()) + " bytes";
    else if (u.bytes.size() + chunk.data().size() > u.begin.total_bytes())
        why = "more bytes than the announced " + std::to_string(u.begin.total_bytes());
    if (!why.empty()) {
        forget_upload(it);
        return send_error(v1::Error::INVALID_ARGUMENT,
                          "upload " + std::to_string(chunk.upload_id()) + ": " + why,
                          chunk.upload_id());
    }
    u.bytes += chunk.data();
    u.last_heard = std::chrono::steady_clock::now();
}

void Connection::on_upload_end(const v1::UploadEnd& end) {
    auto it = uploads_.find(end.upload_id());
    if (it == uploads_.end())
        return send_error(v1::Error::INVALID_ARGUMENT,
                          "upload " + std::to_string(end.upload_id()) + " was not begun",
                          end.upload_id());
    if (it->second.bytes.size() != it->second.begin.total_bytes()) {
        const Upload& u = it->second;
        const std::string why = "upload " + std::to_string(end.upload_id()) + " ended after " +
                                std::to_string(u.bytes.size()) + " of " +
                                std::to_string(u.begin.total_bytes()) + " bytes";
        forget_upload(it);
        return send_error(v1::Error::INVALID_ARGUMENT, why, end.upload_id());
    }
    // The service holds the bytes, and their share of the upload budget, until they are stored.
    Upload u = std::move(it->second);
    uploads_.erase(it);
    service_.upload(shared_from_this(), std::move(u.begin), std::move(u.bytes), std::move(u.owner));
}

void Connection::on_request(const v1::Request& request) {
    if (active_requests_.count(request.request_id()))
        return send_error(v1::Error::INVALID_ARGUMENT,
                          "request " + std::to_string(request.request_id()) + " is already running",
                          request.request_id());
    // Jobs that have not stopped yet count, those of cancelled requests too.
    const size_t held = std::max(active_requests_.size(), request_jobs_);
    if (held >= kMaxRequestsPerConnection) {
        const size_t stopping = held - active_requests_.size();
        return send_error(
            v1::Error::RESOURCE_EXHAUSTED,
            "request " + std::to_string(request.request_id()) + ": at most " +
                std::to_string(kMaxRequestsPerConnection) + " requests at once per connection" +
                (stopping > 0
                     ? " (" + std::to_string(stopping) + " cancelled ones are still stopping)"
                     : ""),
            request.request_id());
    }
    service_.request(shared_from_this(), request);
}

void Connection::on_cancel(const v1::Cancel& cancel) {
    const uint64_t id = cancel.request_id();
    if (!active_requests_.count(id)) return; // finished already: nothing to cancel
    active_requests_.erase(id);
    service_.cancel_request(*this, id);
    drop_unstarted([&](const BulkItem& item) { return item.request_id == id; });
    send_error(v1::Error::CANCELLED, "request " + std::to_string(id) + " cancelled", id);
}

void Connection::send_frame(std::string frame) {
    if (closing_ || closed_) return;
    queue_.push_control(std::move(frame));
    account_queue();
    pump();
}

void Connection::send_bulk(BulkItem item) {
    if (closing_ || closed_) return;
    queue_.push_bulk(std::move(item));
    account_queue();
    pump();
}

size_t Connection::drop_unstarted(const std::function<bool(const BulkItem&)>& stale) {
    const size_t n = queue_.drop_unstarted(stale);
    account_queue();
    return n;
}

void Connection::send_error(v1::Error::Code code, const std::string& message, uint64_t request_id,
                            bool close) {
    v1::Error e;
    e.set_code(code);
    e.set_message(message);
    e.set_request_id(request_id);
    send(e);
    if (close) {
        closing_ = true;
        pump(); // closes once the queue (with the error) is written
    }
}

void Connection::drop(const std::string& reason) {
    if (closed_) return;
    spdlog::warn("dropping client {} ({}): {}", id_, peer_, reason);
    ++service_.metrics().connections_dropped;
    closing_ = true;
    transport_->close(false);
}

void Connection::account_queue() {
    const int64_t now = int64_t(queue_.pending_bytes());
    const int64_t grew = now - accounted_queue_bytes_;
    service_.metrics().queue_bytes += grew;
    accounted_queue_bytes_ = now;
    if (now > service_.metrics().queue_bytes_peak) service_.metrics().queue_bytes_peak = now;
    const size_t limit = service_.config().max_queue_mb << 20;
    if (size_t(now) > limit && !closed_)
        return drop("over " + std::to_string(service_.config().max_queue_mb) +
                    " MiB waiting to be sent (it does not read fast enough)");
    const int64_t all = int64_t(service_.config().max_queue_total_mb << 20);
    if (grew > 0 && service_.metrics().queue_bytes > all && !closed_)
        drop("its level would pass the " + std::to_string(service_.config().max_queue_total_mb) +
             " MiB all clients may have waiting to be sent (--max-queue-total-mb)");
}

void Connection::pump() {
    if (writing_ || closed_) return;
    std::optional<OutgoingFrame> frame = queue_.next_frame();
    account_queue();
    if (!frame) {
        if (closing_) transport_->close(true);
        return;
    }
    writing_ = true;
    transport_->write(std::move(*frame));
}

void Connection::on_written(size_t bytes) {
    writing_ = false;
    service_.metrics().bytes_sent += bytes;
    if (authenticated_ && !closing_) arm_idle_timer();
    pump();
}

void Connection::on_write_timeout() {
    drop(fmt::format("no progress sending for {:g} s (it stopped reading)",
                     service_.config().timeouts.send));
}

void Connection::on_closed(const std::string& why) {
    if (closed_) return;
    closed_ = true;
    closing_ = true;
    idle_timer_.cancel();
    upload_timer_.cancel();
    queue_.drop_unstarted([](const BulkItem&) { return true; });
    account_queue();
    while (!uploads_.empty()) forget_upload(uploads_.begin());
    service_.metrics().queue_bytes -= accounted_queue_bytes_;
    accounted_queue_bytes_ = 0;
    spdlog::info("client {} ({}) disconnected: {}", id_, peer_, why);
    service_.connection_closed(*this);
}

} // namespace ddsimp::server
