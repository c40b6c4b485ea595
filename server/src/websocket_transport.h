// Frames over a WebSocket (for browsers): each binary message is exactly one frame.
#pragma once

#include "admission.h"
#include "transport.h"

#include <boost/asio/ssl.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/ssl.hpp>
#include <boost/beast/websocket.hpp>
#include <boost/beast/websocket/ssl.hpp>

#include <chrono>

namespace ddsimp::server {

namespace beast = boost::beast;
namespace websocket = beast::websocket;

template <class NextLayer>
class WebSocketTransport : public Transport,
                           public std::enable_shared_from_this<WebSocketTransport<NextLayer>> {
public:
    // `slot`: the connection's place (Admission), released when the transport goes.
    WebSocketTransport(websocket::stream<NextLayer> ws, std::string peer, size_t max_frame_bytes,
                       std::chrono::milliseconds send_timeout, Slot slot)
        : ws_(std::move(ws)), peer_(std::move(peer)), max_frame_bytes_(max_frame_bytes),
          send_timeout_(send_timeout), slot_(std::move(slot)), write_timer_(ws_.get_executor()) {
        ws_.binary(true);
        ws_.read_message_max(max_frame_bytes + protocol::kHeaderBytes);
    }

    void start(std::shared_ptr<TransportHandler> handler) override {
        handler_ = std::move(handler);
        read();
    }

    void write(OutgoingFrame frame) override {
        out_ = std::move(frame);
        writing_ = true;
        write_timer_.expires_after(send_timeout_);
        write_timer_.async_wait([self = this->shared_from_this()](boost::system::error_code ec) {
            if (!ec && self->handler_) self->handler_->on_write_timeout();
        });
        ws_.async_write(out_.buffers(),
                        [self = this->shared_from_this()](beast::error_code ec, size_t n) {
                            self->write_timer_.cancel();
                            self->writing_ = false;
                            if (ec) return self->shutdown("write failed: " + ec.message());
                            if (self->closing_) return self->shutdown("closed by the server");
                            if (self->handler_) self->handler_->on_written(n);
                        });
    }

    void close(bool graceful) override {
        closing_ = true;
        if (!graceful || !writing_) shutdown("closed by the server");
    }

    std::string peer() const override { return peer_; }

private:
    void read() {
        ws_.async_read(in_, [self = this->shared_from_this()](beast::error_code ec, size_t) {
            if (ec == websocket::error::message_too_big && self->handler_)
                return self->handler_->on_bad_frame("a WebSocket message over the frame limit of " +
                                                    std::to_string(self->max_frame_bytes_) +
                                                    " bytes");
            if (ec)
                return self->shutdown(ec == websocket::error::closed
                                          ? "the client closed the connection"
                                          : ec.message());
            self->on_message();
        });
    }

    void on_message() {
        if (!handler_ || closing_) return;
        if (!ws_.got_binary()) return handler_->on_bad_frame("a text WebSocket message");
        const std::string bytes = beast::buffers_to_string(in_.data());
        in_.consume(in_.size());
        protocol::Frame frame;
        try {
            frame = protocol::decode_single_frame(bytes, max_frame_bytes_);
        } catch (const protocol::FrameError& e) {
            return handler_->on_bad_frame(e.what());
        }
        handler_->on_frame(std::move(frame));
        if (!closing_) read();
    }

    void shutdown(const std::string& why) {
        if (closed_) return;
        closed_ = closing_ = true;
        write_timer_.cancel();
        beast::error_code ignored;
        beast::get_lowest_layer(ws_).socket().shutdown(boost::asio::ip::tcp::socket::shutdown_both,
                                                       ignored);
        beast::get_lowest_layer(ws_).socket().close(ignored);
        if (auto h = std::move(handler_)) h->on_closed(why);
    }

    websocket::stream<NextLayer> ws_;
    std::string peer_;
    size_t max_frame_bytes_;
    std::chrono::milliseconds send_timeout_;
    Slot slot_;
    boost::asio::steady_timer write_timer_;
    std::shared_ptr<TransportHandler> handler_;
    beast::flat_buffer in_;
    OutgoingFrame out_;
    bool writing_ = false, closing_ = false, closed_ = false;
};

} // namespace ddsimp::server
