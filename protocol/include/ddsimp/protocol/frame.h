// Framing: every protobuf message travels in one frame, a 12-byte header and the payload.
//
//   bytes 0..3   magic "DDSP"
//   bytes 4..5   protocol version (little endian), kProtocolVersion
//   bytes 6..7   message type (little endian), a ddsimp::v1::MessageType
//   bytes 8..11  payload length (little endian)
//
// The header is checked, the length against a configured limit, before a byte of the payload
// is allocated. Over WebSocket each binary message holds exactly one frame.
#pragma once

#include "ddsimp/v1/ddsimp.pb.h"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

namespace ddsimp::protocol {

inline constexpr uint16_t kProtocolVersion = 1;
inline constexpr size_t kHeaderBytes = 12;
// Large enough for a 1 MiB bulk chunk and its message around it.
inline constexpr size_t kDefaultMaxFrameBytes = 4u << 20;
// Bulk data is cut into chunks of this size (the protocol allows 256 KiB to 1 MiB).
inline constexpr size_t kDefaultChunkBytes = 512u << 10;
inline constexpr size_t kMinChunkBytes = 256u << 10;
inline constexpr size_t kMaxChunkBytes = 1u << 20;

// A frame that cannot be accepted; what() says why. The connection it came on is closed.
class FrameError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct FrameHeader {
    v1::MessageType type = v1::MESSAGE_TYPE_UNSPECIFIED;
    uint32_t length = 0;
};

// Writes a header for `length` payload bytes into out[0..kHeaderBytes).
void write_header(unsigned char* out, v1::MessageType type, uint32_t length);

// Checks and decodes a header: magic, version, a known message type, and a length of at most
// max_frame_bytes. Throws FrameError saying which check failed.
FrameHeader read_header(const unsigned char* in, size_t max_frame_bytes);

// A whole frame: header then payload. Throws FrameError if the payload exceeds 4 GiB.
std::string encode_frame(v1::MessageType type, const google::protobuf::MessageLite& message);

// The first bytes of the frame of `message` with its bytes field `field_number` (the highest
// field number of the message, left unset in `message`) holding `field_bytes` bytes: the header,
// `message`, and the field's tag and length. Followed by the field's bytes it equals
// encode_frame of the message with the field set, so bulk data is written without a copy.
std::string encode_frame_head(v1::MessageType type, const google::protobuf::MessageLite& message,
                              int field_number, size_t field_bytes);

template <class M>
std::string encode_frame_head(const M& message, int field_number, size_t field_bytes);

struct Frame {
    v1::MessageType type = v1::MESSAGE_TYPE_UNSPECIFIED;
    std::string payload;
};

// Splits a byte stream into frames. Feed bytes as they arrive, then take frames until next()
// returns nothing. A bad header throws FrameError; the decoder is unusable afterwards.
class FrameDecoder {
public:
    explicit FrameDecoder(size_t max_frame_bytes = kDefaultMaxFrameBytes)
        : max_frame_bytes_(max_frame_bytes) {}

    void feed(std::string_view bytes) { buffer_.append(bytes); }
    std::optional<Frame> next();
    // Bytes received but not yet part of a returned frame.
    size_t buffered() const { return buffer_.size() - consumed_; }

private:
    size_t max_frame_bytes_;
    std::string buffer_;
    size_t consumed_ = 0;
};

// Exactly one frame in `bytes` (a WebSocket message); throws FrameError otherwise.
Frame decode_single_frame(std::string_view bytes, size_t max_frame_bytes);

// Parses a frame's payload as M; throws FrameError if the type does not match or the payload
// is not a valid M.
template <class M> M parse_payload(const Frame& frame);

// The MessageType of each message class.
template <class M> constexpr v1::MessageType message_type_of();

template <class M> std::string encode_frame(const M& message) {
    return encode_frame(message_type_of<M>(), message);
}

template <class M>
std::string encode_frame_head(const M& message, int field_number, size_t field_bytes) {
    return encode_frame_head(message_type_of<M>(), message, field_number, field_bytes);
}

// A readable name for logs and errors ("UPLOAD_CHUNK", or "type 999").
std::string message_type_name(v1::MessageType type);

#define DDSIMP_MESSAGE_TYPE(Message, TYPE)                                                         \
    template <> constexpr v1::MessageType message_type_of<v1::Message>() {                         \
        return v1::TYPE;                                                                           \
    }
DDSIMP_MESSAGE_TYPE(Hello, HELLO)
DDSIMP_MESSAGE_TYPE(Welcome, WELCOME)
DDSIMP_MESSAGE_TYPE(Auth, AUTH)
DDSIMP_MESSAGE_TYPE(AuthOk, AUTH_OK)
DDSIMP_MESSAGE_TYPE(Error, ERROR)
DDSIMP_MESSAGE_TYPE(Ping, PING)
DDSIMP_MESSAGE_TYPE(Pong, PONG)
DDSIMP_MESSAGE_TYPE(JoinSession, JOIN_SESSION)
DDSIMP_MESSAGE_TYPE(LeaveSession, LEAVE_SESSION)
DDSIMP_MESSAGE_TYPE(SetSessionState, SET_SESSION_STATE)
DDSIMP_MESSAGE_TYPE(SessionState, SESSION_STATE)
DDSIMP_MESSAGE_TYPE(UploadBegin, UPLOAD_BEGIN)
DDSIMP_MESSAGE_TYPE(UploadChunk, UPLOAD_CHUNK)
DDSIMP_MESSAGE_TYPE(UploadEnd, UPLOAD_END)
DDSIMP_MESSAGE_TYPE(UploadResult, UPLOAD_RESULT)
DDSIMP_MESSAGE_TYPE(ListSurfaces, LIST_SURFACES)
DDSIMP_MESSAGE_TYPE(SurfaceList, SURFACE_LIST)
DDSIMP_MESSAGE_TYPE(DeleteSurface, DELETE_SURFACE)
DDSIMP_MESSAGE_TYPE(SurfaceDeleted, SURFACE_DELETED)
DDSIMP_MESSAGE_TYPE(Request, REQUEST)
DDSIMP_MESSAGE_TYPE(Cancel, CANCEL)
DDSIMP_MESSAGE_TYPE(MeshBegin, MESH_BEGIN)
DDSIMP_MESSAGE_TYPE(MeshChunk, MESH_CHUNK)
DDSIMP_MESSAGE_TYPE(MeshEnd, MESH_END)
DDSIMP_MESSAGE_TYPE(RequestDone, REQUEST_DONE)
#undef DDSIMP_MESSAGE_TYPE

template <class M> M parse_payload(const Frame& frame) {
    if (frame.type != message_type_of<M>())
        throw FrameError("expected a " + message_type_name(message_type_of<M>()) +
                         " message, got " + message_type_name(frame.type));
    M message;
    if (!message.ParseFromString(frame.payload))
        throw FrameError("a " + message_type_name(frame.type) + " message of " +
                         std::to_string(frame.payload.size()) + " bytes does not parse");
    return message;
}

} // namespace ddsimp::protocol
