// libddsimp-client — the C++ client of ddsimp-server, for renderers and tools.
//
// One ddsimp::Client is one connection (TCP, optionally TLS) speaking the protocol of
// docs/protocol.md. It is asynchronous underneath (Boost.Asio, one network thread per client)
// and offers a blocking facade: every call that waits for the server has a blocking form and
// an async_ form returning a std::future. Meshes arrive as ddsimp::Surface (see ddsimp.h).
//
// Thread safety: every public member function may be called from any thread at any time.
// Callbacks (level and session handlers) run on the client's network thread, in the order the
// server sent things; they must not block on the client (the blocking calls throw
// std::logic_error there) and should hand large work to another thread.
//
// Errors: everything the server refuses, and every local failure (cannot connect, connection
// lost, a frame this client cannot read), is a ClientError whose what() is the server's (or the
// local) message and whose code() says which kind.
#pragma once

#include "ddsimp/ddsimp.h"

#include <chrono>
#include <cstdint>
#include <functional>
#include <future>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace ddsimp {

// ---------------------------------------------------------------------------------------------
// Errors
// ---------------------------------------------------------------------------------------------

enum class ErrorCode {
    // The server's Error codes (docs/protocol.md, "Errors").
    BadFrame,
    UnsupportedVersion,
    Unauthenticated,
    InvalidArgument,
    NotFound,
    BadSurface,
    ResourceExhausted,
    Cancelled,
    Internal,
    Unavailable,
    PermissionDenied,
    // Local: cannot connect, the connection was lost or timed out.
    Connection,
    // Local: the server sent something this client cannot read (a bad frame or blob).
    Protocol,
};

// "NOT_FOUND", "CONNECTION", ... (the protocol's spelling for the server's codes).
const char* error_code_name(ErrorCode code);

// A refusal by the server or a local failure. what() is the message only (the server's text as
// it sent it); code() says what kind; request_id() the request or upload it ended (0: none).
class ClientError : public std::runtime_error {
public:
    ClientError(ErrorCode code, const std::string& message, uint64_t request_id = 0)
        : std::runtime_error(message), code_(code), request_id_(request_id) {}
    ErrorCode code() const { return code_; }
    uint64_t request_id() const { return request_id_; }

private:
    ErrorCode code_;
    uint64_t request_id_;
};

// ---------------------------------------------------------------------------------------------
// Connecting
// ---------------------------------------------------------------------------------------------

enum class ClientKind { Unspecified, VR, Desktop, Tool };

struct ConnectOptions {
    std::string host = "localhost";
    uint16_t port = 7420;
    // Sent when the server's Welcome says a token is required; a server that needs one and gets
    // none refuses with ErrorCode::Unauthenticated.
    std::string token;

    // TLS: on when `tls` is set. The server's certificate is checked against `ca_file` (PEM),
    // or the system's CAs when it is empty, and must name `host`; `tls_insecure` accepts any
    // certificate (self-signed test servers) and should never be used across a real network.
    bool tls = false;
    std::string ca_file;
    bool tls_insecure = false;

    std::string client_name = "libddsimp-client";
    ClientKind kind = ClientKind::Tool;
    // Offered in Hello; only those the server also has are used (see Client::capabilities()).
    std::vector<std::string> capabilities = {"meshopt-codec", "progressive", "sessions",
                                             "session-keys",  "previews",    "surface-delete"};

    // Limit for connecting and the handshake, and for the blocking calls that wait for a small
    // answer (list_surfaces, join_session, set_view). Uploads and levels wait as long as the
    // connection lives.
    std::chrono::milliseconds timeout{15000};
};

// Parses "HOST:PORT", "HOST" (port 7420) or "[v6addr]:PORT" into options.host/port; throws
// std::invalid_argument naming the problem.
void parse_server_address(const std::string& address, ConnectOptions& options);

// ---------------------------------------------------------------------------------------------
// What the server answers
// ---------------------------------------------------------------------------------------------

struct FieldInfo {
    std::string name;
    int components = 1;
    float min = 0, max = 0;
};

struct SurfaceInfo {
    std::string surface; // id: hex SHA-256 of the validated surface
    std::string name;
    uint64_t triangles = 0;
    uint64_t vertices = 0;
    std::vector<FieldInfo> fields;
};

struct UploadResult {
    std::string surface; // id, as in SurfaceInfo
    uint64_t triangles = 0;
    uint64_t vertices = 0;
    bool already_stored = false; // the same surface was stored before (it is stored once)
    std::string repairs;         // what the server's input checks repaired, empty if nothing
};

enum class Encoding { Raw, Meshopt };

// One reduction request: a surface (or the key of an earlier result), the library's options
// for it, and the levels wanted. The options are ddsimp::Options themselves (alpha, strategy,
// placement, data_placement, terms, gradient_fields, feature_angle travel; the levels come
// from `keep`, not keep_fraction or target_triangles), so a request gives the bytes
// ddsimp::simplify gives with the same options.
struct LevelRequest : Options {
    std::string surface; // surface id
    // Instead of surface and the options: the key of an earlier result (Level::result), to
    // resume after a reconnect. Only keep, progressive and encoding are used with it.
    std::string result;
    std::vector<double> keep; // fractions of the triangles, each in (0, 1]
    // The coarsest level whole, then each finer one as a refinement of the one before (used only
    // if the server has the "progressive" capability).
    bool progressive = false;
    // Meshopt is used only if the server has the "meshopt-codec" capability.
    Encoding encoding = Encoding::Meshopt;
    // This request replaces this client's older requests for the same surface: they end with
    // ClientError Cancelled and the server stops computing them unless another client waits.
    bool supersede = false;
};

// One level as it arrived.
struct Level {
    uint64_t request_id = 0; // 0 for a session's mesh
    std::string session;     // set for a session's mesh
    uint32_t index = 0;      // index into the request's keep list
    double keep = 0;
    // The level's triangles over its vertices, every field carried. In progressive mode the
    // vertices are those received so far (some may be unused by this level).
    Surface mesh;
    // Progressive mode only: the receiver's triangle slots after this level was applied, dead
    // slots as the degenerate triangle (0, 0, 0), so it can be drawn as an index buffer as is;
    // a refinement only appends to the previous level's vertices and rewrites some slots.
    Surface slots;
    bool refinement = false; // arrived as a refinement of the level before
    uint64_t triangles = 0;  // the level's triangle count (as the server counted it)
    Encoding encoding = Encoding::Raw;
    uint64_t wire_bytes = 0; // size of the blob as sent
    double seconds = 0;      // the server's simplification time for the result (0 if cached)
    bool cached = false;
    std::string result; // the result's key, for LevelRequest::result after a reconnect
    bool target_reached = false;
    // How far the level is from the surface (see LevelError: geometric in bounding-box
    // diagonals, data in field ranges); empty from a server that does not send it.
    std::optional<LevelError> error;
    // A stand-in the server sent at once while it computes the exact level (the nearest level
    // it had ready); the exact level with the same index follows. Never a refinement.
    bool preview = false;
};

// Called for every level of a request as it arrives (coarsest first), on the network thread.
using LevelCallback = std::function<void(const Level&)>;

// A request in flight. levels[i] becomes ready when level i (of the keep list) has arrived;
// done when the server said the request is complete. On a server error, a cancel or a lost
// connection, the futures not yet ready throw ClientError.
struct PendingRequest {
    uint64_t id = 0;
    std::vector<std::shared_future<Level>> levels;
    std::shared_future<void> done;
};

// ---------------------------------------------------------------------------------------------
// Sessions
// ---------------------------------------------------------------------------------------------

struct View {
    std::string surface;
    double alpha = 0;
    double keep = 0;
    std::string field;
    Strategy strategy = Strategy::EdgeCollapse;
};

struct Member {
    uint64_t client_id = 0;
    std::string name;
    ClientKind kind = ClientKind::Unspecified;
};

struct SessionState {
    std::string name;
    uint64_t version = 0;
    std::vector<Member> members;
    uint64_t leader = 0; // a member's client_id
    View view;
    std::string cause;       // "created", "joined", "left", "leader-left", "view"
    uint64_t changed_by = 0; // the client whose join, view change or leaving made this change
};

// What to change in a session's view; unset parts stay as they are.
struct ViewChange {
    std::optional<std::string> surface;
    std::optional<double> alpha;
    std::optional<double> keep;
    std::optional<std::string> field;
    std::optional<Strategy> strategy;
};

// Something that happened in a joined session: a new state, a mesh (the view's level), or an
// error the server sent outside any request (e.g. a refused change).
struct SessionEvent {
    enum class Kind { State, Mesh, Error };
    Kind kind = Kind::State;
    SessionState state; // Kind::State
    Level mesh;         // Kind::Mesh
    std::string error;  // Kind::Error: the server's message
    ErrorCode error_code = ErrorCode::Internal;
};

using SessionHandler = std::function<void(const SessionEvent&)>;

// ---------------------------------------------------------------------------------------------
// The client
// ---------------------------------------------------------------------------------------------

class Client {
public:
    // Starts the network thread; connects nothing yet.
    Client();
    // Closes the connection and joins the network thread; pending futures throw ClientError.
    ~Client();
    Client(const Client&) = delete;
    Client& operator=(const Client&) = delete;

    // Connects, says Hello, authenticates when the server asks and negotiates capabilities.
    // Throws ClientError: Connection ("cannot connect to HOST:PORT: Connection refused"), or
    // Unauthenticated with the server's message. A connected client is closed first.
    void connect(const ConnectOptions& options);
    std::future<void> async_connect(const ConnectOptions& options);
    // Closes and connects again with the last options, re-joining the sessions it was in.
    // Pending requests fail; resume them with LevelRequest::result.
    void reconnect();
    // Closes the connection (pending futures throw ClientError Connection). Idempotent.
    void close();

    bool connected() const;
    // From the server's Welcome: this connection's member id, the agreed capabilities, limits.
    uint64_t client_id() const;
    std::vector<std::string> capabilities() const;
    bool has_capability(const std::string& name) const;
    uint64_t max_surface_triangles() const;

    // Sends a surface in chunks of 512 KiB (raw) and waits until the server has stored it.
    // `name` labels it in lists. `session`, if set, must be a session this client joined: the
    // surface is then visible to that session's members only and the session's view switches to
    // it; without it, every client of the server may see the surface.
    // Throws ClientError (BadSurface with the library's message, ResourceExhausted, ...).
    UploadResult upload(const Surface& surface, const std::string& name = {},
                        const std::string& session = {});
    std::future<UploadResult> async_upload(const Surface& surface, const std::string& name = {},
                                           const std::string& session = {});

    // The surfaces this client may see: those uploaded without a session and those of the
    // sessions it joined.
    std::vector<SurfaceInfo> list_surfaces();
    std::future<std::vector<SurfaceInfo>> async_list_surfaces();

    // Deletes a stored surface: takes back this client's token's upload of it (see
    // docs/protocol.md, "Deleting"). True when the surface left the server; false when another
    // token that uploaded it keeps it. Throws ClientError NotFound (this client does not see it),
    // PermissionDenied (its token did not upload it), Unavailable (a server without the
    // capability "surface-delete", or one that cannot change its files).
    bool delete_surface(const std::string& surface);
    std::future<bool> async_delete_surface(const std::string& surface);

    // Asks for levels; on_level (optional) is called for each as it arrives, coarsest first.
    // Throws ClientError InvalidArgument at once for an empty keep list or a keep outside (0, 1].
    PendingRequest request(const LevelRequest& request, LevelCallback on_level = {});
    // The blocking form: every level, in the order of the keep list.
    std::vector<Level> request_levels(const LevelRequest& request);
    // Stops a request: its levels not yet received throw ClientError Cancelled at once, and the
    // server drops what it has not sent.
    void cancel(uint64_t request_id);

    // Joins (creating if needed) a session and returns its state as the server sent it to this
    // member; the current mesh, if any, follows as a session event. A session is its name and
    // its key together: the creator chooses the key, and only clients presenting the same key
    // join it and see the surfaces uploaded into it (a different key joins another session of
    // that name). A key needs the server's "session-keys" capability (else InvalidArgument).
    SessionState join_session(const std::string& name, const std::string& key = {});
    std::future<SessionState> async_join_session(const std::string& name,
                                                 const std::string& key = {});
    // Leaves a session (no answer is awaited).
    void leave_session(const std::string& name);
    // Changes the session's view (this member leads from then on); returns the state with the
    // change. The new mesh follows as a session event.
    SessionState set_view(const std::string& session, const ViewChange& change);
    std::future<SessionState> async_set_view(const std::string& session, const ViewChange& change);

    // Session events go to `handler` (on the network thread) once one is set; before that, and
    // after clearing it with {}, they are queued for next_session_event.
    void on_session_event(SessionHandler handler);
    // The oldest queued session event, waiting up to `timeout` for one; nullopt if none came.
    std::optional<SessionEvent> next_session_event(std::chrono::milliseconds timeout);

private:
    struct Impl;
    std::shared_ptr<Impl> impl_;
};

} // namespace ddsimp
