// Between the client's public types (client.h) and the protocol's messages (ddsimp.pb.h).
#pragma once

#include "ddsimp/client.h"
#include "ddsimp/v1/ddsimp.pb.h"

namespace ddsimp::client_detail {

ErrorCode error_code_of(v1::Error::Code code);
ClientError error_of(const v1::Error& error);

v1::ClientKind to_wire(ClientKind kind);
ClientKind from_wire(v1::ClientKind kind);

FieldInfo from_wire(const v1::FieldInfo& field);
SurfaceInfo from_wire(const v1::SurfaceInfo& info);
UploadResult from_wire(const v1::UploadResult& result);
SessionState from_wire(const v1::SessionState& state);

// A Request message; `meshopt` and `progressive` as negotiated.
v1::Request to_wire(const LevelRequest& request, uint64_t id, bool meshopt, bool progressive);
v1::SetSessionState to_wire(const std::string& session, const ViewChange& change);

// Throws ClientError InvalidArgument for a request the server would refuse anyway.
void check_request(const LevelRequest& request);

} // namespace ddsimp::client_detail
