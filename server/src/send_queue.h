// One client's outgoing frames: control messages ahead of bulk, bulk levels cut into chunk
// frames only when they are about to be written (the level's bytes are shared with the cache,
// neither copied per client nor into the chunk frames), and a count of the bytes still to send so a
// client that cannot keep up is noticed. Used on the network thread only.
#pragma once

#include "transport.h"

#include "ddsimp/protocol/frame.h"

#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace ddsimp::server {

// One level (or refinement) to send: MeshBegin, the blob in MeshChunks, MeshEnd, and any frames
// that must follow it (e.g. RequestDone).
struct BulkItem {
    uint64_t request_id = 0;
    std::string session; // set for a session's mesh
    std::string surface; // set for a request's level (a newer request replaces it)
    uint32_t level = 0;
    std::string begin_frame;
    std::shared_ptr<const std::string> blob;
    std::vector<std::string> after; // frames sent after MeshEnd
};

class SendQueue {
public:
    explicit SendQueue(size_t chunk_bytes) : chunk_bytes_(chunk_bytes) {}

    void push_control(std::string frame);
    void push_bulk(BulkItem item);
    // Removes bulk items not yet begun for which `stale` is true; returns how many.
    size_t drop_unstarted(const std::function<bool(const BulkItem&)>& stale);

    // The next frame to write, control first; nothing if the queue is empty. A chunk's data
    // stays in the shared blob (OutgoingFrame::body).
    std::optional<OutgoingFrame> next_frame();
    bool empty() const { return control_.empty() && bulk_.empty(); }
    size_t pending_bytes() const { return pending_; }

private:
    static size_t item_bytes(const BulkItem& item);

    struct Active {
        BulkItem item;
        size_t offset = 0;
        bool begun = false, ended = false;
        size_t after_sent = 0;
    };
    size_t chunk_bytes_;
    std::deque<std::string> control_;
    std::deque<Active> bulk_;
    size_t pending_ = 0; // frames and blob bytes not yet handed out
};

} // namespace ddsimp::server
