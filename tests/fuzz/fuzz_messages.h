// Parses a frame's payload as the message its type names, for targets that check what they
// decode or what the server writes.
#pragma once

#include "ddsimp/protocol/frame.h"

#include <google/protobuf/stubs/logging.h>

namespace ddsimp::fuzz {

// protobuf logs every string field that is not UTF-8 to stderr; for fuzz inputs that is most.
inline const bool protobuf_quiet = (google::protobuf::SetLogHandler(nullptr), true);

// Throws protocol::FrameError if the payload does not parse; returns the parsed message's size
// re-encoded.
inline size_t parse_frame(const protocol::Frame& frame) {
    using protocol::parse_payload;
    switch (frame.type) {
#define DDSIMP_PARSE(Message, TYPE)                                                                \
    case v1::TYPE:                                                                                 \
        return parse_payload<v1::Message>(frame).ByteSizeLong();
        DDSIMP_PARSE(Hello, HELLO)
        DDSIMP_PARSE(Welcome, WELCOME)
        DDSIMP_PARSE(Auth, AUTH)
        DDSIMP_PARSE(AuthOk, AUTH_OK)
        DDSIMP_PARSE(Error, ERROR)
        DDSIMP_PARSE(Ping, PING)
        DDSIMP_PARSE(Pong, PONG)
        DDSIMP_PARSE(JoinSession, JOIN_SESSION)
        DDSIMP_PARSE(LeaveSession, LEAVE_SESSION)
        DDSIMP_PARSE(SetSessionState, SET_SESSION_STATE)
        DDSIMP_PARSE(SessionState, SESSION_STATE)
        DDSIMP_PARSE(UploadBegin, UPLOAD_BEGIN)
        DDSIMP_PARSE(UploadChunk, UPLOAD_CHUNK)
        DDSIMP_PARSE(UploadEnd, UPLOAD_END)
        DDSIMP_PARSE(UploadResult, UPLOAD_RESULT)
        DDSIMP_PARSE(ListSurfaces, LIST_SURFACES)
        DDSIMP_PARSE(SurfaceList, SURFACE_LIST)
        DDSIMP_PARSE(Request, REQUEST)
        DDSIMP_PARSE(Cancel, CANCEL)
        DDSIMP_PARSE(MeshBegin, MESH_BEGIN)
        DDSIMP_PARSE(MeshChunk, MESH_CHUNK)
        DDSIMP_PARSE(MeshEnd, MESH_END)
        DDSIMP_PARSE(RequestDone, REQUEST_DONE)
#undef DDSIMP_PARSE
    default:
        throw protocol::FrameError("no message for " + protocol::message_type_name(frame.type));
    }
}

} // namespace ddsimp::fuzz
