#include "send_queue.h"

#include <algorithm>

namespace ddsimp::server {

size_t SendQueue::item_bytes(const BulkItem& item) {
    size_t b = item.begin_frame.size() + (item.blob ? item.blob->size() : 0);
    for (const std::string& f : item.after) b += f.size();
    return b;
}

void SendQueue::push_control(std::string frame) {
    pending_ += frame.size();
    control_.push_back(std::move(frame));
}

void SendQueue::push_bulk(BulkItem item) {
    pending_ += item_bytes(item);
    bulk_.push_back(Active{std::move(item)});
}

size_t SendQueue::drop_unstarted(const std::function<bool(const BulkItem&)>& stale) {
    size_t dropped = 0;
    for (auto it = bulk_.begin(); it != bulk_.end();) {
        if (!it->begun && stale(it->item)) {
            pending_ -= item_bytes(it->item);
            it = bulk_.erase(it);
            ++dropped;
        } else {
            ++it;
        }
    }
    return dropped;
}

std::optional<OutgoingFrame> SendQueue::next_frame() {
    OutgoingFrame frame;
    if (!control_.empty()) {
        frame.head = std::move(control_.front());
        control_.pop_front();
        pending_ -= frame.head.size();
        return frame;
    }
    if (bulk_.empty()) return std::nullopt;
    Active& a = bulk_.front();
    const size_t blob_size = a.item.blob ? a.item.blob->size() : 0;
    if (!a.begun) {
        a.begun = true;
        pending_ -= a.item.begin_frame.size();
        frame.head = std::move(a.item.begin_frame);
    } else if (a.offset < blob_size) {
        const size_t n = std::min(chunk_bytes_, blob_size - a.offset);
        v1::MeshChunk chunk; // its data (field 4, the last) is the blob's slice
        chunk.set_request_id(a.item.request_id);
        chunk.set_level(a.item.level);
        chunk.set_offset(a.offset);
        frame.head = protocol::encode_frame_head(chunk, v1::MeshChunk::kDataFieldNumber, n);
        frame.body = a.item.blob;
        frame.body_offset = a.offset;
        frame.body_bytes = n;
        a.offset += n;
        pending_ -= n;
    } else if (!a.ended) {
        a.ended = true;
        v1::MeshEnd end;
        end.set_request_id(a.item.request_id);
        end.set_level(a.item.level);
        frame.head = protocol::encode_frame(end);
    } else {
        frame.head = std::move(a.item.after[a.after_sent++]);
        pending_ -= frame.head.size();
    }
    if (a.ended && a.after_sent == a.item.after.size()) bulk_.pop_front();
    return frame;
}

} // namespace ddsimp::server
