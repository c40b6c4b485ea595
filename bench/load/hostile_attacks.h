// The attacks of ddsimp-load's hostile mode, all at once against one server: silent sockets on
// both ports up to the limits, frames sent in part, request + cancel floods, padded requests,
// requests naming unknown fields, many-level requests of the big surface, uploads that reserve
// the budget and stall, and client-chosen strings that try to forge log lines. Each attacker is
// a thread on bare sockets (hostile_wire.h); what the server answered is counted by kind. Against
// a server with TLS, every connection speaks TLS, and connections that stop halfway through
// their handshake are one more attack.
#pragma once

#include "hostile_wire.h"

#include <atomic>
#include <map>
#include <string>
#include <thread>
#include <vector>

namespace ddsimp::load {

struct Target {
    std::string host = "127.0.0.1";
    uint16_t port = 7420;
    uint16_t http_port = 7421;
    std::string token;
    std::string big_surface; // id of the large surface the attacks ask for
    size_t max_frame_bytes = size_t(4) << 20;
    int max_clients = 256; // the server's limit of connections (ddsimp_sockets_limit)
};

// The text every forged string carries where a forged log line would begin.
inline constexpr const char* kForgedMarker = "FORGED";

class Attacks {
public:
    explicit Attacks(Target target) : target_(std::move(target)) {}
    ~Attacks() { stop(); }

    // Starts every attacker; the silent sockets only once the others are in (they take every
    // place that is left).
    void start();
    // Closes every attacker's connections and waits for its thread.
    void stop();
    // What each attack sent and what the server answered ("padded: CANCELLED" …).
    std::map<std::string, long> counts() const { return tally_.counts(); }

private:
    void silent_sockets();
    void half_sent_frames();
    void request_cancel_flood();
    void padded_requests();
    void unknown_fields();
    void many_levels();
    void stalled_uploads(int index);
    void forged_names();
    void half_tls_handshakes();

    // A connection that is in (Hello, Auth), or nothing; counted under `attack`.
    std::unique_ptr<RawConnection> enter(const std::string& attack, const std::string& name = "");
    // Reads `c` until it closes, counting each Error by code and calling `on_frame`.
    std::thread drain(RawConnection& c, const std::string& attack,
                      std::function<void(const protocol::Frame&)> on_frame = {});
    // Sleeps up to `seconds`, returning early (false) when the attack stops.
    bool pause(double seconds) const;
    // An alpha no one asked for before: its levels must be computed.
    float fresh_alpha();

    Target target_;
    Tally tally_;
    std::atomic<bool> stopping_{false};
    std::atomic<int> entered_{0};
    std::atomic<uint32_t> alpha_counter_{0};
    std::mutex connections_mutex_;
    std::vector<RawConnection*> live_; // shut down on stop(), so blocked readers return
    std::vector<std::thread> threads_;
    void track(RawConnection* c);
    void untrack(RawConnection* c);
};

} // namespace ddsimp::load
