// One client, on any transport: the handshake, the protocol's per-connection state (uploads in
// progress, requests, sessions joined) and the send queue with its limits. Network thread only;
// work for the compute pool goes through the Service.
#pragma once

#include "quotas.h"
#include "send_queue.h"
#include "transport.h"

#include <boost/asio/steady_timer.hpp>

#include <map>
#include <memory>
#include <set>
#include <string>

namespace ddsimp::server {

class Service;

class Connection : public TransportHandler, public std::enable_shared_from_this<Connection> {
public:
    Connection(Service& service, std::shared_ptr<Transport> transport, uint64_t id);

    void start();
    uint64_t id() const { return id_; }
    const v1::Member& member() const { return member_; }
    const std::string& peer() const { return peer_; }
    // The name of the token it presented (tokens.h); empty: none.
    const std::string& token() const { return token_; }
    bool open() const { return !closed_; }
    bool has_capability(const std::string& name) const { return capabilities_.count(name) > 0; }
    // The sessions joined: name -> scope (a connection is in at most one session of a name).
    std::map<std::string, std::string>& sessions() { return sessions_; }
    // What this client may see: the public scope and those of its sessions.
    std::set<std::string> scopes() const;

    template <class M> void send(const M& message) { send_frame(protocol::encode_frame(message)); }
    void send_frame(std::string frame);
    void send_bulk(BulkItem item);
    size_t drop_unstarted(const std::function<bool(const BulkItem&)>& stale);
    // Sends Error; `close` ends the connection after it is written.
    void send_error(v1::Error::Code code, const std::string& message, uint64_t request_id = 0,
                    bool close = false);
    // Drops the client now, logging why (slow reader, over-limit queue, shutdown).
    void drop(const std::string& reason);

    void begin_request(uint64_t request_id) { active_requests_.insert(request_id); }
    bool request_active(uint64_t request_id) const { return active_requests_.count(request_id); }
    void end_request(uint64_t request_id) { active_requests_.erase(request_id); }
    // A request's job, from its queueing until it stops: a cancelled request's job still counts
    // against the client's request limit until it has actually stopped.
    void begin_job() { ++request_jobs_; }
    void end_job() { --request_jobs_; }
    // An upload being checked and stored: its client waits for the UploadResult.
    void begin_storing() { ++storing_uploads_; }
    void end_storing() { --storing_uploads_; }

    // TransportHandler
    void on_frame(protocol::Frame frame) override;
    void on_bad_frame(const std::string& why) override;
    void on_closed(const std::string& why) override;
    void on_written(size_t bytes) override;
    void on_write_timeout() override;

private:
    void handle(const protocol::Frame& frame);
    void on_hello(const v1::Hello& hello);
    void on_auth(const v1::Auth& auth);
    void on_upload_begin(const v1::UploadBegin& begin);
    void on_upload_chunk(v1::UploadChunk& chunk);
    void on_upload_end(const v1::UploadEnd& end);
    struct Upload {
        v1::UploadBegin begin;
        UploadOwner owner;
        std::string bytes;
        std::chrono::steady_clock::time_point last_heard; // UploadBegin or the latest chunk
    };
    // Forgets the uploads that have heard nothing for the upload timeout; runs while any is open.
    void expire_uploads();
    // Drops an upload in progress and returns its bytes to the server's upload budget.
    void forget_upload(std::map<uint64_t, Upload>::iterator it);
    void on_request(const v1::Request& request);
    void on_cancel(const v1::Cancel& cancel);
    void pump();
    void account_queue();
    void arm_idle_timer();

    Service& service_;
    std::shared_ptr<Transport> transport_;
    const uint64_t id_;
    std::string peer_;
    v1::Member member_;
    std::set<std::string> capabilities_;
    bool hello_ = false, authenticated_ = false;
    std::string token_; // the name of the token it presented (tokens.h); empty: none
    bool writing_ = false, closing_ = false, closed_ = false;
    SendQueue queue_;
    int64_t accounted_queue_bytes_ = 0;
    std::map<uint64_t, Upload> uploads_;
    std::set<uint64_t> active_requests_;
    size_t request_jobs_ = 0;
    size_t storing_uploads_ = 0;
    std::map<std::string, std::string> sessions_;
    boost::asio::steady_timer idle_timer_;
    boost::asio::steady_timer upload_timer_;
};

} // namespace ddsimp::server
