// Client::Impl: the state behind ddsimp::Client, one connection and the network thread that owns
// it. Every piece of connection state is touched only on that thread; public calls post work to
// it and wait on futures (the blocking facade). Frames go out through one write queue; upload
// chunks are cut only when that queue is empty, so control messages never wait behind a whole
// surface. The public calls and the members are defined by concept: client.cpp (the client's
// life, connecting, what the server said about itself), connection.cpp (connect, handshake, read
// and write loop), level_requests.cpp (requests and the levels they receive), surfaces.cpp
// (uploads and the surface list), sessions.cpp (joining, views, session events).
#pragma once

#include "ddsimp/client.h"

#include "convert.h"

#include "ddsimp/protocol/frame.h"
#include "ddsimp/protocol/mesh_codec.h"
#include "ddsimp/protocol/refinement.h"

#include <boost/asio.hpp>
#include <boost/asio/ssl.hpp>

#include <algorithm>
#include <condition_variable>
#include <deque>
#include <map>
#include <mutex>
#include <thread>

namespace ddsimp::client_detail {

namespace asio = boost::asio;
namespace ssl = boost::asio::ssl;
using tcp = asio::ip::tcp;

// The exception a caller receives, with a message of its own: a copy of a std::runtime_error
// shares its message's buffer through a reference count inside libstdc++ that TSan cannot see,
// so the network thread dropping its copy would look like a race with the caller reading it.
std::exception_ptr as_exception(const ClientError& error);

// What this client accepts from a server: its chunks are at most 1 MiB, but a list of many
// surfaces may be longer; the limit only stops a broken peer from making it allocate without end.
constexpr size_t kMaxReceivedFrameBytes = 64u << 20;

// A level's blob as it arrives in chunks.
struct IncomingMesh {
    v1::MeshBegin begin;
    protocol::BlobLayout layout;
    std::string bytes;
};

// An upload whose chunks are still to be cut.
struct UploadJob {
    uint64_t id = 0;
    std::shared_ptr<const std::string> blob;
    size_t offset = 0;
};

// A level request in flight: one promise per level asked for.
struct RequestState {
    std::vector<std::promise<Level>> levels;
    std::vector<bool> ready;
    std::promise<void> done;
    LevelCallback on_level;
    std::optional<protocol::SlotMesh> mesh; // what the server refines, in progressive mode
    bool progressive = false;
};

// A message that waits for an answer carrying no request id (a list, a join, a view change):
// answered by its reply in order, or failed by the next Error with request_id 0.
struct ControlOp {
    enum class Kind { List, Join, Set } kind;
    std::string session;
    std::shared_ptr<std::promise<std::vector<SurfaceInfo>>> list;
    std::shared_ptr<std::promise<SessionState>> state;
};

} // namespace ddsimp::client_detail

namespace ddsimp {

using namespace client_detail; // client-lib's own sources only: this header is private

struct Client::Impl {
    asio::io_context io;
    asio::executor_work_guard<asio::io_context::executor_type> work{io.get_executor()};
    std::thread thread;
    std::thread::id thread_id;

    // ----- network-thread state -----
    uint64_t generation = 0; // one per connection attempt; handlers of an older one do nothing
    std::unique_ptr<tcp::socket> plain;
    std::unique_ptr<ssl::context> tls_context;
    std::unique_ptr<ssl::stream<tcp::socket>> tls;
    std::unique_ptr<tcp::resolver> resolver;
    std::unique_ptr<asio::steady_timer> connect_timer;
    std::array<char, 64 * 1024> read_buffer{};
    protocol::FrameDecoder decoder;
    std::deque<std::string> out;
    bool writing = false;
    std::deque<UploadJob> upload_jobs;

    std::shared_ptr<std::promise<void>> handshake;
    ConnectOptions active; // the options of the current connection
    std::map<uint64_t, std::promise<UploadResult>> uploads;
    std::map<uint64_t, std::promise<bool>> deletes;
    std::map<uint64_t, RequestState> requests;
    std::deque<ControlOp> control;
    std::map<std::pair<uint64_t, uint32_t>, IncomingMesh> incoming;
    std::map<std::string, std::optional<protocol::SlotMesh>> session_meshes;

    // ----- shared with callers -----
    mutable std::mutex info_mutex;
    bool is_connected = false;
    uint64_t my_client_id = 0;
    std::vector<std::string> caps;
    uint64_t max_triangles = 0;
    std::optional<ConnectOptions> last_options;
    std::map<std::string, std::string> joined; // session name -> key, re-joined on reconnect
    uint64_t next_id = 1;

    std::mutex events_mutex;
    std::condition_variable events_ready;
    std::deque<SessionEvent> events;
    SessionHandler handler;

    Impl() {
        thread = std::thread([this] { io.run(); });
        thread_id = thread.get_id();
    }

    bool on_network_thread() const { return std::this_thread::get_id() == thread_id; }

    void require_other_thread(const char* what) const {
        if (on_network_thread())
            throw std::logic_error(std::string("ddsimp::Client::") + what +
                                   " blocks and cannot be called from a client callback");
    }

    uint64_t take_id() {
        std::lock_guard lock(info_mutex);
        return next_id++;
    }

    bool capability(const std::string& name) const {
        std::lock_guard lock(info_mutex);
        return std::find(caps.begin(), caps.end(), name) != caps.end();
    }

    std::string where() const { return active.host + ":" + std::to_string(active.port); }

    template <class T> T wait(std::future<T>& future, const char* what, bool limited) {
        require_other_thread(what);
        if (limited) {
            std::chrono::milliseconds timeout;
            std::string server;
            {
                std::lock_guard lock(info_mutex);
                timeout = last_options ? last_options->timeout : std::chrono::milliseconds(15000);
                server = last_options
                             ? last_options->host + ":" + std::to_string(last_options->port)
                             : "the server";
            }
            if (future.wait_for(timeout) != std::future_status::ready)
                throw ClientError(ErrorCode::Connection,
                                  "no answer from " + server + " within " +
                                      std::to_string(timeout.count() / 1000.0).substr(0, 4) + " s");
        }
        return future.get();
    }

    // ----- connection (connection.cpp) -----

    template <class F> void with_stream(F&& f) {
        if (tls)
            f(*tls);
        else
            f(*plain);
    }

    // Ends the connection: every pending operation fails with `error`.
    void shut(const ClientError& error);
    static void fail_control(ControlOp& op, const ClientError& error);
    void start_connect(const ConnectOptions& options, std::shared_ptr<std::promise<void>> done);
    void on_transport_ready();
    void read_more();
    void on_read(boost::system::error_code ec, size_t n);
    void send(std::string frame);
    void write_next();
    void dispatch(const protocol::Frame& frame);
    void on_welcome(const v1::Welcome& welcome);
    void finish_handshake();
    void on_error(const v1::Error& message);

    // ----- requests and levels (level_requests.cpp) -----

    void on_mesh_begin(const v1::MeshBegin& begin);
    void on_mesh_chunk(const v1::MeshChunk& chunk);
    void on_mesh_end(const v1::MeshEnd& end);

    // A level this client cannot read ends its request (or is reported to the session).
    void fail_mesh(const v1::MeshBegin& begin, const std::string& why);

    void on_request_done(const v1::RequestDone& done);
    static void fail_request(RequestState& r, const ClientError& error);
    void cancel_request(uint64_t id);

    // ----- surfaces on the server (surfaces.cpp) -----

    void cut_upload_chunk();
    void on_upload_result(const v1::UploadResult& message);
    void on_surface_list(const v1::SurfaceList& message);
    void on_surface_deleted(const v1::SurfaceDeleted& message);

    // ----- sessions (sessions.cpp) -----

    // Whether `state` answers `op`: the change this client asked for. Another member's change
    // (a join just before ours, say) may still be on its way to us when we ask.
    bool answers(const ControlOp& op, const SessionState& state) const;

    void on_session_state(const v1::SessionState& message);

    // To the handler if one is set, else to the queue next_session_event reads.
    void deliver(SessionEvent event);

    // Posts `f` to the network thread, or runs it now if already there.
    template <class F> void run(F&& f) {
        if (on_network_thread())
            f();
        else
            asio::post(io, std::forward<F>(f));
    }

    // Fails `promise` with "not connected" unless a connection is up.
    template <class P> bool require_connection(P& promise) {
        if (plain || tls) return true;
        promise.set_exception(
            as_exception(ClientError(ErrorCode::Connection, "the client is not connected")));
        return false;
    }
};

} // namespace ddsimp
