#include "fake_server.h"

#include "fuzz_check.h"
#include "fuzz_messages.h"
#include "fuzz_temp_dir.h"

#include "service.h"
#include "surface_file.h"

#include "ddsimp/protocol/content_hash.h"

#include <boost/asio/post.hpp>
#include <spdlog/spdlog.h>

#include <filesystem>

namespace ddsimp::fuzz {
namespace fs = std::filesystem;

// Frames go straight to the connection; a write completes on the next turn of the io_context,
// as a socket write would. Mirrors StreamTransport's closing rules.
class FakeTransport : public server::Transport, public std::enable_shared_from_this<FakeTransport> {
public:
    explicit FakeTransport(boost::asio::io_context& io) : io_(io) {}

    void start(std::shared_ptr<server::TransportHandler> handler) override {
        handler_ = std::move(handler);
    }

    void write(server::OutgoingFrame out) override {
        FUZZ_CHECK(!writing_); // one write at a time
        std::string frame = out.head;
        if (out.body) frame.append(*out.body, out.body_offset, out.body_bytes);
        check_frame(frame);
        writing_ = true;
        boost::asio::post(io_, [self = shared_from_this(), n = frame.size()] {
            self->writing_ = false;
            if (self->closing_) return self->shutdown("closed by the server");
            if (self->handler_) self->handler_->on_written(n);
        });
    }

    void close(bool graceful) override {
        closing_ = true;
        if (!graceful || !writing_) shutdown("closed by the server");
    }

    std::string peer() const override { return "fuzz"; }

    // Reading stops once the server closes or a frame was bad, as in StreamTransport.
    bool reading() const { return handler_ && !closing_ && !bad_frame_; }
    void deliver(protocol::Frame frame) {
        if (reading()) handler_->on_frame(std::move(frame));
    }
    void deliver_bad_frame(const std::string& why) {
        if (!reading()) return;
        bad_frame_ = true;
        handler_->on_bad_frame(why);
    }
    void shutdown(const std::string& why) {
        closing_ = true;
        if (auto h = std::move(handler_)) h->on_closed(why);
    }

private:
    // Whatever the server writes is one well-formed frame of a message it may send.
    static void check_frame(const std::string& bytes) {
        protocol::Frame frame;
        try {
            frame = protocol::decode_single_frame(bytes, UINT32_MAX);
            parse_frame(frame);
        } catch (const protocol::FrameError& e) {
            std::fprintf(stderr, "the server wrote a bad frame: %s\n", e.what());
            FUZZ_CHECK(!"the server writes well-formed frames");
        }
        FUZZ_CHECK(frame.type != v1::HELLO && frame.type != v1::AUTH &&
                   frame.type != v1::UPLOAD_BEGIN && frame.type != v1::REQUEST);
    }

    boost::asio::io_context& io_;
    std::shared_ptr<server::TransportHandler> handler_;
    bool writing_ = false, closing_ = false, bad_frame_ = false;
};

const Surface& sample_surface() {
    static const Surface sample = [] {
        Surface s;
        constexpr uint32_t n = 6;
        s.fields = {{"temperature", 1, {}}, {"velocity", 3, {}}};
        for (uint32_t j = 0; j < n; ++j)
            for (uint32_t i = 0; i < n; ++i) {
                const float x = float(i), y = float(j), z = float((i * j) % 3) / 4;
                s.positions.insert(s.positions.end(), {x, y, z});
                s.fields[0].values.push_back(x * x - y);
                s.fields[1].values.insert(s.fields[1].values.end(), {y, -x, z});
            }
        for (uint32_t j = 0; j + 1 < n; ++j)
            for (uint32_t i = 0; i + 1 < n; ++i) {
                const uint32_t v = j * n + i;
                s.triangles.insert(s.triangles.end(), {v, v + 1, v + n, v + 1, v + n + 1, v + n});
            }
        return s;
    }();
    return sample;
}

const std::string& sample_id() {
    static const std::string id = protocol::surface_hash(sample_surface());
    return id;
}

namespace {

const std::string& sample_file() {
    static const std::string path = [] {
        const std::string p = temp_dir() + "/sample.ddsurf";
        server::write_file_atomically(p, server::encode_surface_file("grid", sample_surface()));
        spdlog::set_level(spdlog::level::off); // a line per connection would drown the fuzzer
        return p;
    }();
    return path;
}

} // namespace

FakeServer::FakeServer(bool token) : data_dir_(temp_dir() + "/data") {
    server::Config config;
    config.data_dir = data_dir_;
    config.sample = sample_file();
    config.threads = 0;
    config.cache_mb = 16;
    if (token) config.token = kToken;
    service_ = std::make_unique<server::Service>(io_, config);
    transport_ = std::make_shared<FakeTransport>(io_);
    service_->accept(transport_);
    run();
}

FakeServer::~FakeServer() {
    run();
    transport_->shutdown("the client closed the connection");
    run();
    service_->stop();
    run();
    const server::Metrics& m = service_->metrics();
    FUZZ_CHECK(m.connections == 0);
    FUZZ_CHECK(m.queue_bytes == 0);
    service_.reset();
    std::error_code ec;
    fs::remove_all(data_dir_, ec);
}

void FakeServer::deliver(const protocol::Frame& frame) {
    transport_->deliver(frame);
}

void FakeServer::deliver_stream(std::string_view bytes, bool step) {
    protocol::FrameDecoder decoder(protocol::kDefaultMaxFrameBytes);
    decoder.feed(bytes);
    try {
        while (std::optional<protocol::Frame> frame = decoder.next()) {
            transport_->deliver(std::move(*frame));
            if (step) run();
        }
    } catch (const protocol::FrameError& e) {
        transport_->deliver_bad_frame(e.what());
    }
}

void FakeServer::run() {
    io_.restart();
    io_.poll();
}

} // namespace ddsimp::fuzz
