#include "convert.h"

#include "ddsimp/protocol/reduction_options.h"

#include <cmath>
#include <stdexcept>

namespace ddsimp {

const char* error_code_name(ErrorCode code) {
    switch (code) {
    case ErrorCode::BadFrame:
        return "BAD_FRAME";
    case ErrorCode::UnsupportedVersion:
        return "UNSUPPORTED_VERSION";
    case ErrorCode::Unauthenticated:
        return "UNAUTHENTICATED";
    case ErrorCode::InvalidArgument:
        return "INVALID_ARGUMENT";
    case ErrorCode::NotFound:
        return "NOT_FOUND";
    case ErrorCode::BadSurface:
        return "BAD_SURFACE";
    case ErrorCode::ResourceExhausted:
        return "RESOURCE_EXHAUSTED";
    case ErrorCode::Cancelled:
        return "CANCELLED";
    case ErrorCode::Internal:
        return "INTERNAL";
    case ErrorCode::Unavailable:
        return "UNAVAILABLE";
    case ErrorCode::PermissionDenied:
        return "PERMISSION_DENIED";
    case ErrorCode::Connection:
        return "CONNECTION";
    case ErrorCode::Protocol:
        return "PROTOCOL";
    }
    return "UNKNOWN";
}

void parse_server_address(const std::string& address, ConnectOptions& options) {
    std::string host = address;
    std::string port;
    if (!address.empty() && address.front() == '[') { // [v6]:port
        const size_t close = address.find(']');
        if (close == std::string::npos)
            throw std::invalid_argument("'" + address + "' has no closing ']'");
        host = address.substr(1, close - 1);
        if (close + 1 < address.size()) {
            if (address[close + 1] != ':')
                throw std::invalid_argument("'" + address + "': expected ':' after ']'");
            port = address.substr(close + 2);
        }
    } else if (const size_t colon = address.rfind(':'); colon != std::string::npos) {
        if (address.find(':') != colon)
            throw std::invalid_argument("'" + address + "': write an IPv6 address as [ADDR]:PORT");
        host = address.substr(0, colon);
        port = address.substr(colon + 1);
        if (port.empty()) throw std::invalid_argument("'" + address + "' has an empty port");
    }
    if (host.empty()) throw std::invalid_argument("'" + address + "' has no host name");
    if (!port.empty()) {
        size_t used = 0;
        unsigned long value = 0;
        try {
            value = std::stoul(port, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (used != port.size() || port.front() == '-' || value < 1 || value > 65535)
            throw std::invalid_argument("'" + port + "' is not a port (1 to 65535)");
        options.port = uint16_t(value);
    }
    options.host = host;
}

namespace client_detail {

ErrorCode error_code_of(v1::Error::Code code) {
    switch (code) {
    case v1::Error::BAD_FRAME:
        return ErrorCode::BadFrame;
    case v1::Error::UNSUPPORTED_VERSION:
        return ErrorCode::UnsupportedVersion;
    case v1::Error::UNAUTHENTICATED:
        return ErrorCode::Unauthenticated;
    case v1::Error::INVALID_ARGUMENT:
        return ErrorCode::InvalidArgument;
    case v1::Error::NOT_FOUND:
        return ErrorCode::NotFound;
    case v1::Error::BAD_SURFACE:
        return ErrorCode::BadSurface;
    case v1::Error::RESOURCE_EXHAUSTED:
        return ErrorCode::ResourceExhausted;
    case v1::Error::CANCELLED:
        return ErrorCode::Cancelled;
    case v1::Error::UNAVAILABLE:
        return ErrorCode::Unavailable;
    case v1::Error::PERMISSION_DENIED:
        return ErrorCode::PermissionDenied;
    default:
        return ErrorCode::Internal; // INTERNAL, and codes newer than this client
    }
}

ClientError error_of(const v1::Error& error) {
    std::string text = error.message();
    if (text.empty()) text = "the server refused (" + v1::Error::Code_Name(error.code()) + ")";
    return ClientError(error_code_of(error.code()), text, error.request_id());
}

v1::ClientKind to_wire(ClientKind kind) {
    switch (kind) {
    case ClientKind::VR:
        return v1::VR;
    case ClientKind::Desktop:
        return v1::DESKTOP;
    case ClientKind::Tool:
        return v1::TOOL;
    default:
        return v1::CLIENT_KIND_UNSPECIFIED;
    }
}
ClientKind from_wire(v1::ClientKind kind) {
    switch (kind) {
    case v1::VR:
        return ClientKind::VR;
    case v1::DESKTOP:
        return ClientKind::Desktop;
    case v1::TOOL:
        return ClientKind::Tool;
    default:
        return ClientKind::Unspecified;
    }
}

FieldInfo from_wire(const v1::FieldInfo& field) {
    return {field.name(), int(field.components()), field.min(), field.max()};
}

SurfaceInfo from_wire(const v1::SurfaceInfo& info) {
    SurfaceInfo out{info.surface(), info.name(), info.triangles(), info.vertices(), {}};
    for (const v1::FieldInfo& f : info.fields()) out.fields.push_back(from_wire(f));
    return out;
}

UploadResult from_wire(const v1::UploadResult& result) {
    return {result.surface(), result.triangles(), result.vertices(), result.already_stored(),
            result.repairs()};
}

SessionState from_wire(const v1::SessionState& state) {
    SessionState out;
    out.name = state.name();
    out.version = state.version();
    for (const v1::Member& m : state.members())
        out.members.push_back({m.client_id(), m.name(), from_wire(m.kind())});
    out.leader = state.leader();
    const v1::View& view = state.view();
    out.view = {view.surface(),
                view.has_alpha_exact() ? view.alpha_exact() : protocol::from_wire(view.alpha()),
                view.keep(), view.field(), protocol::from_wire(view.strategy())};
    out.cause = state.cause();
    out.changed_by = state.changed_by();
    return out;
}

v1::Request to_wire(const LevelRequest& request, uint64_t id, bool meshopt, bool progressive) {
    v1::Request out;
    out.set_request_id(id);
    for (double k : request.keep) out.add_keep(float(k));
    out.set_progressive(progressive && request.progressive);
    out.set_supersede(request.supersede);
    out.set_encoding(meshopt && request.encoding == Encoding::Meshopt ? v1::MESHOPT : v1::RAW);
    if (!request.result.empty()) {
        out.set_result(request.result);
        return out;
    }
    out.set_surface(request.surface);
    protocol::set_options(out, request);
    return out;
}

v1::SetSessionState to_wire(const std::string& session, const ViewChange& change) {
    v1::SetSessionState out;
    out.set_name(session);
    v1::View& view = *out.mutable_view();
    if (change.surface) view.set_surface(*change.surface);
    if (change.alpha) {
        protocol::set_alpha(view, *change.alpha);
        out.set_set_alpha(true);
    }
    if (change.keep) view.set_keep(float(*change.keep));
    if (change.field) view.set_field(*change.field);
    if (change.strategy) view.set_strategy(protocol::to_wire(*change.strategy));
    return out;
}

void check_request(const LevelRequest& request) {
    auto refuse = [](const std::string& text) {
        throw ClientError(ErrorCode::InvalidArgument, text);
    };
    if (request.surface.empty() && request.result.empty())
        refuse("a request names no surface and no result");
    if (request.keep.empty()) refuse("a request asks for no level (the keep list is empty)");
    for (double k : request.keep)
        if (!(k > 0 && k <= 1)) refuse("keep " + std::to_string(k) + " is outside (0, 1]");
    if (!request.result.empty()) return;
    try {
        check_options(request);
    } catch (const InputError& e) {
        refuse(e.what());
    }
}

} // namespace client_detail
} // namespace ddsimp
