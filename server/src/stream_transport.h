// Frames over a byte stream: a plain TCP socket or a TLS stream over one. Reads a header, checks
// it (protocol::read_header, before allocating), then reads the payload.
#pragma once

#include "admission.h"
#include "transport.h"

#include <boost/asio.hpp>
#include <boost/asio/ssl.hpp>

#include <chrono>

namespace ddsimp::server {

namespace asio = boost::asio;
using tcp = asio::ip::tcp;

struct StreamLimits {
    size_t max_frame_bytes = protocol::kDefaultMaxFrameBytes;
    std::chrono::milliseconds send_timeout; // Timeouts::send
};

template <class Stream>
class StreamTransport : public Transport,
                        public std::enable_shared_from_this<StreamTransport<Stream>> {
public:
    // `slot`: the connection's place (Admission), released when the transport goes.
    StreamTransport(Stream stream, std::string peer, StreamLimits limits, Slot slot)
        : stream_(std::move(stream)), peer_(std::move(peer)), limits_(limits),
          slot_(std::move(slot)), write_timer_(stream_.get_executor()) {}

    void start(std::shared_ptr<TransportHandler> handler) override {
        handler_ = std::move(handler);
        read_header();
    }

    void write(OutgoingFrame frame) override {
        out_ = std::move(frame);
        write_timer_.expires_after(limits_.send_timeout);
        write_timer_.async_wait([self = this->shared_from_this()](boost::system::error_code ec) {
            if (!ec && self->handler_) self->handler_->on_write_timeout();
        });
        asio::async_write(
            stream_, out_.buffers(),
            [self = this->shared_from_this()](boost::system::error_code ec, size_t n) {
                self->write_timer_.cancel();
                self->writing_ = false;
                if (ec) return self->shutdown("write failed: " + ec.message());
                if (self->closing_) return self->shutdown("closed by the server");
                if (self->handler_) self->handler_->on_written(n);
            });
        writing_ = true;
    }

    void close(bool graceful) override {
        closing_ = true;
        if (!graceful || !writing_) shutdown("closed by the server");
    }

    std::string peer() const override { return peer_; }

private:
    void read_header() {
        asio::async_read(stream_, asio::buffer(header_),
                         [self = this->shared_from_this()](boost::system::error_code ec, size_t) {
                             if (ec) return self->shutdown(describe_read_error(ec));
                             self->on_header();
                         });
    }

    void on_header() {
        protocol::FrameHeader h;
        try {
            h = protocol::read_header(header_.data(), limits_.max_frame_bytes);
        } catch (const protocol::FrameError& e) {
            if (handler_) handler_->on_bad_frame(e.what());
            return;
        }
        type_ = h.type;
        payload_.assign(h.length, '\0');
        asio::async_read(stream_, asio::buffer(payload_),
                         [self = this->shared_from_this()](boost::system::error_code ec, size_t) {
                             if (ec)
                                 return self->shutdown("truncated frame: " +
                                                       describe_read_error(ec));
                             if (!self->handler_ || self->closing_) return;
                             self->handler_->on_frame({self->type_, std::move(self->payload_)});
                             if (!self->closing_) self->read_header();
                         });
    }

    static std::string describe_read_error(boost::system::error_code ec) {
        if (ec == asio::error::eof || ec == asio::ssl::error::stream_truncated)
            return "the client closed the connection";
        return ec.message();
    }

    void shutdown(const std::string& why) {
        if (closed_) return;
        closed_ = true;
        closing_ = true;
        write_timer_.cancel();
        boost::system::error_code ignored;
        lowest_layer().shutdown(tcp::socket::shutdown_both, ignored);
        lowest_layer().close(ignored);
        if (auto h = std::move(handler_)) h->on_closed(why);
    }

    tcp::socket::lowest_layer_type& lowest_layer() { return stream_.lowest_layer(); }

    Stream stream_;
    std::string peer_;
    StreamLimits limits_;
    Slot slot_;
    asio::steady_timer write_timer_;
    std::shared_ptr<TransportHandler> handler_;
    std::array<unsigned char, protocol::kHeaderBytes> header_{};
    v1::MessageType type_ = v1::MESSAGE_TYPE_UNSPECIFIED;
    std::string payload_;
    OutgoingFrame out_;
    bool writing_ = false, closing_ = false, closed_ = false;
};

} // namespace ddsimp::server
