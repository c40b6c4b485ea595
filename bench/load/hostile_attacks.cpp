#include "hostile_attacks.h"

#include "ddsimp/protocol/mesh_codec.h"

#include <chrono>
#include <condition_variable>
#include <functional>

namespace ddsimp::load {
namespace {

using namespace std::chrono_literals;

constexpr int kRequestsPerConnection = 16; // server/src/client_limits.h

std::string error_name(const protocol::Frame& f) {
    try {
        return v1::Error_Code_Name(protocol::parse_payload<v1::Error>(f).code());
    } catch (const protocol::FrameError&) {
        return "unparsable error";
    }
}

v1::Request request(const std::string& surface, uint64_t id, float alpha,
                    std::vector<float> keeps) {
    v1::Request r;
    r.set_request_id(id);
    r.set_surface(surface);
    r.set_alpha(alpha);
    for (float k : keeps) r.add_keep(k);
    r.set_encoding(v1::RAW);
    return r;
}

// Strings a client chooses that would end a log line, start a forged one and drive a terminal
// if they were logged as they are (valid UTF-8: a protobuf string is refused otherwise).
std::string forged(const std::string& where, int n) {
    return where + "\n2026-11-28T00:00:00.000 info " + kForgedMarker + " client " +
           std::to_string(n) + " is root\r\x1b[2J\x1b]0;owned\x07\u00e9";
}

} // namespace

void Attacks::track(RawConnection* c) {
    std::lock_guard lock(connections_mutex_);
    live_.push_back(c);
    if (stopping_) c->shut_down();
}

void Attacks::untrack(RawConnection* c) {
    std::lock_guard lock(connections_mutex_);
    live_.erase(std::remove(live_.begin(), live_.end(), c), live_.end());
}

bool Attacks::pause(double seconds) const {
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (!stopping_ && std::chrono::steady_clock::now() < until)
        std::this_thread::sleep_for(std::min<std::chrono::duration<double>>(
            until - std::chrono::steady_clock::now(), 50ms));
    return !stopping_;
}

float Attacks::fresh_alpha() {
    // 0.6 + n/10000, away from the normal clients' alpha.
    return 0.6f + float(alpha_counter_++ % 3000) * 1e-4f;
}

std::unique_ptr<RawConnection> Attacks::enter(const std::string& attack, const std::string& name) {
    auto c = std::make_unique<RawConnection>(target_.host, target_.port);
    if (!c->connected() ||
        !c->handshake(name.empty() ? "ddsimp-load " + attack : name, target_.token)) {
        tally_.add(attack + ": refused at the door");
        return nullptr;
    }
    tally_.add(attack + ": connections");
    track(c.get());
    return c;
}

std::thread Attacks::drain(RawConnection& c, const std::string& attack,
                           std::function<void(const protocol::Frame&)> on_frame) {
    return std::thread([this, &c, attack, on_frame] {
        while (const std::optional<protocol::Frame> f = c.next()) {
            if (f->type == v1::ERROR) tally_.add(attack + ": " + error_name(*f));
            if (f->type == v1::REQUEST_DONE) tally_.add(attack + ": done");
            if (on_frame) on_frame(*f);
        }
    });
}

void Attacks::start() {
    stopping_ = false;
    const std::vector<std::function<void()>> active = {
        [this] { half_sent_frames(); }, [this] { request_cancel_flood(); },
        [this] { padded_requests(); },  [this] { unknown_fields(); },
        [this] { many_levels(); },      [this] { stalled_uploads(0); },
        [this] { stalled_uploads(1); }, [this] { forged_names(); }};
    for (const auto& attack : active) threads_.emplace_back(attack);
    if (tls_in_use()) threads_.emplace_back([this] { half_tls_handshakes(); });
    const int attackers = int(active.size()) + (tls_in_use() ? 1 : 0);
    // The attackers above connect first; then silent sockets take whatever places are left.
    for (int i = 0; i < 100 && entered_ < attackers; ++i) std::this_thread::sleep_for(50ms);
    threads_.emplace_back([this] { silent_sockets(); });
}

void Attacks::stop() {
    stopping_ = true;
    {
        std::lock_guard lock(connections_mutex_);
        for (RawConnection* c : live_) c->shut_down();
    }
    for (std::thread& t : threads_) t.join();
    threads_.clear();
}

// Sockets that never say a word, on both ports, from eight addresses (127.0.0.2-9), more than
// the server has places for; each one the server closes (refused, or its handshake timed out)
// is opened again at once.
void Attacks::silent_sockets() {
    const int per_port = target_.max_clients / 2 + 32;
    std::vector<std::unique_ptr<RawConnection>> sockets(size_t(2 * per_port));
    while (pause(0.5)) {
        for (size_t i = 0; i < sockets.size() && !stopping_; ++i) {
            auto& s = sockets[i];
            if (s && s->connected() && !s->closed_by_server()) continue;
            if (s) tally_.add("silent: closed by the server");
            const uint16_t port = i % 2 ? target_.http_port : target_.port;
            s = std::make_unique<RawConnection>(target_.host, port,
                                                "127.0.0." + std::to_string(2 + i % 8));
            tally_.add(s->connected() ? "silent: opened" : "silent: connect failed");
        }
    }
}

// Against a server with TLS: connections to the HTTP port that send their ClientHello and never
// go on, each opened again when the server closes it (its handshake timeout). The silent sockets
// on both ports are TLS handshakes that never begin.
void Attacks::half_tls_handshakes() {
    constexpr int kConnections = 16;
    std::vector<std::unique_ptr<RawConnection>> held(kConnections);
    bool counted = false;
    while (!stopping_) {
        for (auto& c : held) {
            if (stopping_) break;
            if (c && c->connected() && !c->closed_by_server()) continue;
            if (c) tally_.add("half TLS handshake: closed by the server");
            c = std::make_unique<RawConnection>(target_.host, target_.http_port, "127.0.0.10");
            tally_.add(c->connected() && c->start_tls_handshake_only()
                           ? "half TLS handshake: ClientHello sent"
                           : "half TLS handshake: connect failed");
        }
        if (!counted) ++entered_, counted = true;
        pause(0.5);
    }
}

// Connections that are in, then send a frame header announcing the largest frame and half its
// payload, and stall; each holds a frame buffer until it is closed, and is opened again then.
void Attacks::half_sent_frames() {
    constexpr int kConnections = 16;
    std::vector<std::unique_ptr<RawConnection>> held(kConnections);
    ++entered_;
    while (!stopping_) {
        for (auto& c : held) {
            if (stopping_) break;
            if (c && !c->closed_by_server()) continue;
            if (c) {
                tally_.add("half frame: closed by the server");
                untrack(c.get());
            }
            c = enter("half frame");
            if (!c) continue;
            unsigned char header[protocol::kHeaderBytes];
            const size_t length = target_.max_frame_bytes;
            protocol::write_header(header, v1::UPLOAD_CHUNK, uint32_t(length));
            c->send_bytes(std::string(reinterpret_cast<char*>(header), sizeof header) +
                          std::string(length / 2, 'h'));
        }
        pause(1);
    }
    for (auto& c : held)
        if (c) untrack(c.get());
}

// Bursts of 40 request + cancel pairs for new alphas of the big surface on one connection: a
// cancelled request keeps its place until its job stops, so those past 16 are refused.
void Attacks::request_cancel_flood() {
    auto c = enter("request+cancel");
    ++entered_;
    if (!c) return;
    std::thread reader = drain(*c, "request+cancel");
    uint64_t id = 0;
    while (pause(0.5)) {
        std::string burst;
        for (int i = 0; i < 40; ++i) {
            burst +=
                protocol::encode_frame(request(target_.big_surface, ++id, fresh_alpha(), {0.5f}));
            v1::Cancel cancel;
            cancel.set_request_id(id);
            burst += protocol::encode_frame(cancel);
        }
        if (!c->send_bytes(burst)) break;
        tally_.add("request+cancel: pairs sent", 40);
    }
    c->shut_down();
    reader.join();
    untrack(c.get());
}

// Requests for new alphas of the big surface, each padded with an unknown field to nearly the
// frame limit, kept at the connection's 16 (a new one whenever one ends).
void Attacks::padded_requests() {
    auto c = enter("padded");
    ++entered_;
    if (!c) return;
    std::atomic<int> ended{0};
    std::thread reader = drain(*c, "padded", [&](const protocol::Frame& f) {
        if (f.type == v1::REQUEST_DONE || f.type == v1::ERROR) ++ended;
    });
    const size_t pad = target_.max_frame_bytes - (64u << 10);
    std::string padding = {char(0xC2), char(0x3E)}; // field 1000, length-delimited
    for (size_t n = pad; n > 0; n >>= 7) padding += char((n & 0x7F) | (n > 0x7F ? 0x80 : 0));
    padding += std::string(pad, 'p');
    uint64_t id = 0;
    while (!stopping_) {
        if (int(id) - ended < kRequestsPerConnection) {
            const std::string payload =
                request(target_.big_surface, ++id, fresh_alpha(), {0.5f}).SerializeAsString() +
                padding;
            unsigned char header[protocol::kHeaderBytes];
            protocol::write_header(header, v1::REQUEST, uint32_t(payload.size()));
            if (!c->send_bytes(std::string(reinterpret_cast<char*>(header), sizeof header) +
                               payload))
                break;
            tally_.add("padded: sent");
        }
        pause(0.2);
    }
    c->shut_down();
    reader.join();
    untrack(c.get());
}

// Requests that name a gradient field the surface does not have, a new name each time, about a
// thousand a second.
void Attacks::unknown_fields() {
    auto c = enter("unknown field");
    ++entered_;
    if (!c) return;
    std::thread reader = drain(*c, "unknown field");
    uint64_t id = 0;
    while (pause(0.1)) {
        std::string burst;
        for (int i = 0; i < 100; ++i) {
            v1::Request r = request(target_.big_surface, ++id, 0.5f, {0.1f});
            r.add_gradient_fields("no-such-field-" + std::to_string(id));
            burst += protocol::encode_frame(r);
        }
        if (!c->send_bytes(burst)) break;
        tally_.add("unknown field: sent", 100);
    }
    c->shut_down();
    reader.join();
    untrack(c.get());
}

// 64 levels of the big surface in one request: one set that cannot fit in the send queue's
// bound (refused up front), then one that fits, for a new alpha, read to its end; again.
void Attacks::many_levels() {
    auto c = enter("64 levels");
    ++entered_;
    if (!c) return;
    std::mutex mutex;
    std::condition_variable ended_cv;
    std::atomic<int> ended{0};
    std::thread reader = drain(*c, "64 levels", [&](const protocol::Frame& f) {
        if (f.type == v1::MESH_BEGIN) tally_.add("64 levels: levels received");
        if (f.type == v1::REQUEST_DONE || f.type == v1::ERROR) {
            ++ended;
            ended_cv.notify_all();
        }
    });
    uint64_t id = 0;
    while (!stopping_) {
        std::vector<float> too_many, fitting;
        for (int i = 1; i <= 64; ++i) {
            too_many.push_back(0.015f * float(i));
            fitting.push_back(0.0003f * float(i));
        }
        const int before = ended;
        if (!c->send(request(target_.big_surface, ++id, fresh_alpha(), too_many)) ||
            !c->send(request(target_.big_surface, ++id, fresh_alpha(), fitting)))
            break;
        tally_.add("64 levels: requests sent", 2);
        std::unique_lock lock(mutex);
        while (ended < before + 2 && !stopping_) ended_cv.wait_for(lock, 100ms);
    }
    c->shut_down();
    reader.join();
    untrack(c.get());
}

// Four uploads of 61 MB each reserved on one connection (the most a connection may have), a
// megabyte of each sent, then nothing but pings: they hold their share of the upload budget
// until --upload-timeout expires them, and are begun again then.
void Attacks::stalled_uploads(int index) {
    const std::string attack = "stalled upload";
    auto c = enter(attack);
    ++entered_;
    if (!c) return;
    std::mutex mutex;
    std::vector<uint64_t> to_begin;
    // An upload that expired (CANCELLED) or was refused on its UploadBegin is begun again at the
    // next ping; the errors for the chunks of a refused one are only counted.
    std::thread reader = drain(*c, attack, [&](const protocol::Frame& f) {
        if (f.type != v1::ERROR) return;
        const v1::Error e = protocol::parse_payload<v1::Error>(f);
        if (e.code() != v1::Error::CANCELLED && e.code() != v1::Error::RESOURCE_EXHAUSTED) return;
        std::lock_guard lock(mutex);
        if (e.request_id() != 0 &&
            std::find(to_begin.begin(), to_begin.end(), e.request_id()) == to_begin.end())
            to_begin.push_back(e.request_id());
    });
    constexpr uint64_t kVertices = 1'700'000, kTriangles = 3'400'000;
    const uint64_t total = protocol::raw_mesh_bytes(kVertices, kTriangles, {});
    const std::string chunk_data(512u << 10, '\0');
    uint64_t next_id = 0;
    const auto begin = [&] {
        v1::UploadBegin b;
        b.set_upload_id(++next_id);
        b.set_name(forged("upload", index));
        b.set_vertex_count(kVertices);
        b.set_triangle_count(kTriangles);
        b.set_total_bytes(total);
        bool ok = c->send(b);
        for (uint64_t offset = 0; ok && offset < 2 * chunk_data.size();
             offset += chunk_data.size()) {
            v1::UploadChunk chunk;
            chunk.set_upload_id(next_id);
            chunk.set_offset(offset);
            chunk.set_data(chunk_data);
            ok = c->send(chunk);
        }
        tally_.add(attack + ": begun");
        return ok;
    };
    bool ok = true;
    for (int i = 0; i < 4 && ok; ++i) ok = begin();
    uint64_t nonce = 0;
    while (ok && pause(2)) {
        v1::Ping ping;
        ping.set_nonce(++nonce);
        ok = c->send(ping);
        std::vector<uint64_t> again;
        {
            std::lock_guard lock(mutex);
            again.swap(to_begin);
        }
        for (size_t i = 0; i < again.size() && ok; ++i) ok = begin();
    }
    c->shut_down();
    reader.join();
    untrack(c.get());
}

// Client names, session names and upload labels that would forge a log line: connections that
// stay (one without the token), and new ones every 200 ms while there are places.
void Attacks::forged_names() {
    std::vector<std::unique_ptr<RawConnection>> held;
    for (int n = 0; n < 4; ++n)
        if (auto c = enter("forged name", forged("name", n))) {
            v1::JoinSession join;
            join.set_name(forged("session", n));
            c->send(join);
            held.push_back(std::move(c));
        }
    {
        RawConnection wrong(target_.host, target_.port);
        if (wrong.connected() && !target_.token.empty() &&
            !wrong.handshake(forged("unauthenticated", 0), target_.token + "-wrong"))
            tally_.add("forged name: wrong token refused");
    }
    ++entered_;
    for (int n = 4; pause(0.2); ++n) {
        RawConnection c(target_.host, target_.port);
        tally_.add(c.connected() && c.handshake(forged("name", n), target_.token)
                       ? "forged name: connections"
                       : "forged name: refused at the door");
    }
    for (auto& c : held) untrack(c.get());
}

} // namespace ddsimp::load
