// ddsimp::Client: one connection, one network thread running an io_context. Every piece of
// connection state is touched only on that thread; public calls post work to it and wait on
// futures (the blocking facade). Frames go out through one write queue; upload chunks are cut
// only when that queue is empty, so control messages never wait behind a whole surface.
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
#include <set>
#include <thread>

namespace ddsimp {

using namespace client_detail;
namespace asio = boost::asio;
namespace ssl = boost::asio::ssl;
using tcp = asio::ip::tcp;

namespace {

// The exception a caller receives, with a message of its own: a copy of a std::runtime_error
// shares its message's buffer, reference-counted inside libstdc++ (which TSan cannot see), so the
// network thread, dropping its error after the caller had read the message, freed the buffer as
// its last owner, which TSan reported as a race. Now only the exception owns it.
std::exception_ptr as_exception(const ClientError& error) {
    return std::make_exception_ptr(
        ClientError(error.code(), std::string(error.what()), error.request_id()));
}

// A level's blob as it arrives in chunks.
// What this client accepts from a server: its chunks are at most 1 MiB, but a list of many
// surfaces may be longer; the limit only stops a broken peer from making it allocate without end.
constexpr size_t kMaxReceivedFrameBytes = 64u << 20;

struct IncomingMesh {
    v1::MeshBegin begin;
    protocol::BlobLayout layout;
    std::string bytes;
};

struct UploadJob {
    uint64_t id = 0;
    std::shared_ptr<const std::string> blob;
    size_t offset = 0;
};

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

Level level_from(const v1::MeshBegin& begin, uint64_t wire_bytes) {
    Level level;
    level.request_id = begin.request_id();
    level.session = begin.session();
    level.index = begin.level();
    level.keep = begin.keep();
    level.refinement = begin.kind() == v1::MeshBegin::REFINEMENT;
    level.triangles = begin.total_triangles();
    level.encoding = begin.encoding() == v1::MESHOPT ? Encoding::Meshopt : Encoding::Raw;
    level.wire_bytes = wire_bytes;
    level.seconds = begin.seconds();
    level.cached = begin.cached();
    level.result = begin.result();
    level.target_reached = begin.target_reached();
    level.preview = begin.preview();
    if (begin.has_error())
        level.error = LevelError{begin.error().geometric(), begin.error().data(),
                                 size_t(begin.error().data_components())};
    return level;
}

} // namespace

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

    // ----- session events -----

    void deliver(SessionEvent event) {
        SessionHandler h;
        {
            std::lock_guard lock(events_mutex);
            if (!handler) {
                events.push_back(std::move(event));
                events_ready.notify_all();
                return;
            }
            h = handler;
        }
        h(event);
    }

    // ----- connection -----

    template <class F> void with_stream(F&& f) {
        if (tls)
            f(*tls);
        else
            f(*plain);
    }

    // Ends the connection: every pending operation fails with `error`.
    void shut(const ClientError& error) {
        bool had_sessions = false;
        {
            std::lock_guard lock(info_mutex);
            is_connected = false; // before any waiter wakes up
            had_sessions = !joined.empty();
        }
        if (handshake) {
            handshake->set_exception(as_exception(error));
            handshake.reset();
        }
        for (auto& [id, promise] : uploads) promise.set_exception(as_exception(error));
        uploads.clear();
        upload_jobs.clear();
        for (auto& [id, r] : requests) fail_request(r, error);
        requests.clear();
        for (ControlOp& op : control) fail_control(op, error);
        control.clear();
        incoming.clear();
        session_meshes.clear();
        out.clear();
        writing = false;
        const bool was_open = plain || tls;
        boost::system::error_code ignored;
        if (tls) tls->lowest_layer().close(ignored);
        if (plain) plain->close(ignored);
        if (resolver) resolver->cancel();
        if (connect_timer) connect_timer->cancel();
        // The closed stream's aborted operations are already queued and still use it (an SSL
        // read reaches into its buffers): it is destroyed by a handler queued after them.
        if (was_open) asio::post(io, [p = std::move(plain), t = std::move(tls)] {});
        ++generation;
        if (was_open && had_sessions)
            deliver({SessionEvent::Kind::Error, {}, {}, error.what(), error.code()});
    }

    static void fail_request(RequestState& r, const ClientError& error) {
        for (size_t i = 0; i < r.levels.size(); ++i)
            if (!r.ready[i]) {
                r.ready[i] = true;
                r.levels[i].set_exception(as_exception(error));
            }
        r.done.set_exception(as_exception(error));
    }

    static void fail_control(ControlOp& op, const ClientError& error) {
        if (op.list) op.list->set_exception(as_exception(error));
        if (op.state) op.state->set_exception(as_exception(error));
    }

    void start_connect(const ConnectOptions& options, std::shared_ptr<std::promise<void>> done) {
        shut(ClientError(ErrorCode::Connection, "the connection was closed by the client"));
        active = options;
        handshake = std::move(done);
        decoder = protocol::FrameDecoder(kMaxReceivedFrameBytes);
        const uint64_t gen = generation;
        const std::string prefix = "cannot connect to " + where() + ": ";

        try {
            if (options.tls) {
                tls_context = std::make_unique<ssl::context>(ssl::context::tls_client);
                if (options.tls_insecure) {
                    tls_context->set_verify_mode(ssl::verify_none);
                } else {
                    if (options.ca_file.empty())
                        tls_context->set_default_verify_paths();
                    else
                        tls_context->load_verify_file(options.ca_file);
                    tls_context->set_verify_mode(ssl::verify_peer);
                }
                tls = std::make_unique<ssl::stream<tcp::socket>>(io, *tls_context);
                if (!options.tls_insecure)
                    tls->set_verify_callback(ssl::host_name_verification(options.host));
                SSL_set_tlsext_host_name(tls->native_handle(), options.host.c_str());
            } else {
                plain = std::make_unique<tcp::socket>(io);
            }
        } catch (const boost::system::system_error& e) {
            const std::string what = options.ca_file.empty()
                                         ? std::string("TLS set-up failed: ")
                                         : "cannot read the CA file " + options.ca_file + ": ";
            shut(ClientError(ErrorCode::Connection, prefix + what + e.code().message()));
            return;
        }

        connect_timer = std::make_unique<asio::steady_timer>(io, options.timeout);
        connect_timer->async_wait([this, gen, prefix](boost::system::error_code ec) {
            if (ec || gen != generation || !handshake) return;
            shut(ClientError(ErrorCode::Connection, prefix + "no answer within " +
                                                        std::to_string(active.timeout.count()) +
                                                        " ms"));
        });

        resolver = std::make_unique<tcp::resolver>(io);
        resolver->async_resolve(
            options.host, std::to_string(options.port),
            [this, gen, prefix](boost::system::error_code ec, tcp::resolver::results_type found) {
                if (gen != generation) return;
                if (ec) return shut(ClientError(ErrorCode::Connection, prefix + ec.message()));
                tcp::socket& socket = tls ? tls->next_layer() : *plain;
                asio::async_connect(
                    socket, found,
                    [this, gen, prefix](boost::system::error_code ec, const tcp::endpoint&) {
                        if (gen != generation) return;
                        if (ec)
                            return shut(ClientError(ErrorCode::Connection, prefix + ec.message()));
                        (tls ? tls->next_layer() : *plain).set_option(tcp::no_delay(true));
                        if (!tls) return on_transport_ready();
                        tls->async_handshake(
                            ssl::stream_base::client,
                            [this, gen, prefix](boost::system::error_code ec) {
                                if (gen != generation) return;
                                if (ec)
                                    return shut(ClientError(ErrorCode::Connection,
                                                            prefix + "TLS: " + ec.message()));
                                on_transport_ready();
                            });
                    });
            });
    }

    void on_transport_ready() {
        v1::Hello hello;
        hello.set_protocol_version(protocol::kProtocolVersion);
        hello.set_client_name(active.client_name);
        hello.set_kind(to_wire(active.kind));
        for (const std::string& c : active.capabilities) hello.add_capabilities(c);
        send(protocol::encode_frame(hello));
        read_more();
    }

    void read_more() {
        const uint64_t gen = generation;
        with_stream([this, gen](auto& stream) {
            stream.async_read_some(asio::buffer(read_buffer),
                                   [this, gen](boost::system::error_code ec, size_t n) {
                                       if (gen != generation) return;
                                       on_read(ec, n);
                                   });
        });
    }

    void on_read(boost::system::error_code ec, size_t n) {
        if (ec) {
            const bool eof = ec == asio::error::eof || ec == ssl::error::stream_truncated;
            const std::string text = handshake ? "cannot connect to " + where() + ": "
                                               : "the connection to " + where() + " was lost: ";
            // A TLS server hangs up on a plain Hello: say so.
            const std::string hint = handshake && !tls ? " (is it a TLS server?)" : "";
            shut(ClientError(ErrorCode::Connection,
                             text +
                                 (eof ? "the server closed the connection" + hint : ec.message())));
            return;
        }
        const uint64_t gen = generation;
        try {
            decoder.feed(std::string_view(read_buffer.data(), n));
            while (gen == generation) {
                std::optional<protocol::Frame> frame = decoder.next();
                if (!frame) break;
                dispatch(*frame);
            }
        } catch (const protocol::FrameError& e) {
            shut(ClientError(ErrorCode::Protocol,
                             "the server at " + where() + " sent a bad frame: " + e.what()));
            return;
        }
        if (gen == generation) read_more();
    }

    // ----- writing -----

    void send(std::string frame) {
        out.push_back(std::move(frame));
        write_next();
    }

    void write_next() {
        if (writing || !(plain || tls)) return;
        if (out.empty() && !upload_jobs.empty()) cut_upload_chunk();
        if (out.empty()) return;
        writing = true;
        const uint64_t gen = generation;
        with_stream([this, gen](auto& stream) {
            asio::async_write(stream, asio::buffer(out.front()),
                              [this, gen](boost::system::error_code ec, size_t) {
                                  if (gen != generation) return;
                                  writing = false;
                                  if (ec)
                                      return shut(ClientError(ErrorCode::Connection,
                                                              "the connection to " + where() +
                                                                  " was lost: " + ec.message()));
                                  out.pop_front();
                                  write_next();
                              });
        });
    }

    void cut_upload_chunk() {
        UploadJob& job = upload_jobs.front();
        const size_t n = std::min(protocol::kDefaultChunkBytes, job.blob->size() - job.offset);
        v1::UploadChunk chunk;
        chunk.set_upload_id(job.id);
        chunk.set_offset(job.offset);
        chunk.set_data(job.blob->data() + job.offset, n);
        out.push_back(protocol::encode_frame(chunk));
        job.offset += n;
        if (job.offset == job.blob->size()) {
            v1::UploadEnd end;
            end.set_upload_id(job.id);
            out.push_back(protocol::encode_frame(end));
            upload_jobs.pop_front();
        }
    }

    // ----- reading -----

    void dispatch(const protocol::Frame& frame) {
        using protocol::parse_payload;
        switch (frame.type) {
        case v1::WELCOME:
            return on_welcome(parse_payload<v1::Welcome>(frame));
        case v1::AUTH_OK:
            return finish_handshake();
        case v1::ERROR:
            return on_error(parse_payload<v1::Error>(frame));
        case v1::PING: {
            v1::Pong pong;
            pong.set_nonce(parse_payload<v1::Ping>(frame).nonce());
            return send(protocol::encode_frame(pong));
        }
        case v1::PONG:
            return;
        case v1::SESSION_STATE:
            return on_session_state(parse_payload<v1::SessionState>(frame));
        case v1::UPLOAD_RESULT:
            return on_upload_result(parse_payload<v1::UploadResult>(frame));
        case v1::SURFACE_LIST:
            return on_surface_list(parse_payload<v1::SurfaceList>(frame));
        case v1::MESH_BEGIN:
            return on_mesh_begin(parse_payload<v1::MeshBegin>(frame));
        case v1::MESH_CHUNK:
            return on_mesh_chunk(parse_payload<v1::MeshChunk>(frame));
        case v1::MESH_END:
            return on_mesh_end(parse_payload<v1::MeshEnd>(frame));
        case v1::REQUEST_DONE:
            return on_request_done(parse_payload<v1::RequestDone>(frame));
        default:
            throw protocol::FrameError("a " + protocol::message_type_name(frame.type) +
                                       " message, which a server does not send");
        }
    }

    void on_welcome(const v1::Welcome& welcome) {
        if (!handshake) throw protocol::FrameError("a second WELCOME");
        {
            std::lock_guard lock(info_mutex);
            my_client_id = welcome.client_id();
            caps.assign(welcome.capabilities().begin(), welcome.capabilities().end());
            max_triangles = welcome.max_surface_triangles();
        }
        if (!welcome.auth_required()) return finish_handshake();
        if (active.token.empty())
            return shut(ClientError(ErrorCode::Unauthenticated,
                                    "the server at " + where() + " requires a token"));
        v1::Auth auth;
        auth.set_token(active.token);
        send(protocol::encode_frame(auth));
    }

    void finish_handshake() {
        if (!handshake) throw protocol::FrameError("an AUTH_OK that answers nothing");
        if (connect_timer) connect_timer->cancel();
        {
            std::lock_guard lock(info_mutex);
            is_connected = true;
        }
        handshake->set_value();
        handshake.reset();
    }

    void on_error(const v1::Error& message) {
        const ClientError error = error_of(message);
        const auto code = message.code();
        if (code == v1::Error::BAD_FRAME || code == v1::Error::UNSUPPORTED_VERSION ||
            code == v1::Error::UNAUTHENTICATED || handshake)
            return shut(error); // the server closes the connection after these
        if (const uint64_t id = message.request_id()) {
            if (auto u = uploads.find(id); u != uploads.end()) {
                u->second.set_exception(as_exception(error));
                uploads.erase(u);
                std::erase_if(upload_jobs, [id](const UploadJob& j) { return j.id == id; });
            } else if (auto r = requests.find(id); r != requests.end()) {
                fail_request(r->second, error);
                requests.erase(r);
                std::erase_if(incoming, [id](const auto& kv) { return kv.first.first == id; });
            }
            return; // an error for something already cancelled or finished
        }
        if (!control.empty()) {
            fail_control(control.front(), error);
            control.pop_front();
            return;
        }
        deliver({SessionEvent::Kind::Error, {}, {}, error.what(), error.code()});
    }

    // Whether `state` answers `op`: the change this client asked for. Another member's change
    // (a join just before ours, say) may still be on its way to us when we ask.
    bool answers(const ControlOp& op, const SessionState& state) const {
        if (!op.state || op.session != state.name) return false;
        if (state.changed_by == 0) return true; // a server from before `changed_by`
        const bool joined = state.cause == "created" || state.cause == "joined";
        return state.changed_by == my_client_id &&
               (op.kind == ControlOp::Kind::Join ? joined : state.cause == "view");
    }

    void on_session_state(const v1::SessionState& message) {
        SessionState state = from_wire(message);
        for (auto op = control.begin(); op != control.end(); ++op)
            if (answers(*op, state)) {
                op->state->set_value(state);
                control.erase(op);
                break;
            }
        deliver({SessionEvent::Kind::State, std::move(state), {}, {}, ErrorCode::Internal});
    }

    void on_upload_result(const v1::UploadResult& message) {
        auto u = uploads.find(message.upload_id());
        if (u == uploads.end()) return;
        u->second.set_value(from_wire(message));
        uploads.erase(u);
    }

    void on_surface_list(const v1::SurfaceList& message) {
        auto op = std::find_if(control.begin(), control.end(),
                               [](const ControlOp& o) { return o.kind == ControlOp::Kind::List; });
        if (op == control.end()) return;
        std::vector<SurfaceInfo> list;
        for (const v1::SurfaceInfo& s : message.surfaces()) list.push_back(from_wire(s));
        op->list->set_value(std::move(list));
        control.erase(op);
    }

    void on_mesh_begin(const v1::MeshBegin& begin) {
        const uint64_t id = begin.request_id();
        if (id != 0 && !requests.count(id)) return; // cancelled: its chunks are dropped too
        if (id == 0 && begin.session().empty())
            throw protocol::FrameError("a MESH_BEGIN with neither a request nor a session");
        IncomingMesh mesh{begin, {}, {}};
        try {
            mesh.layout = protocol::layout_of(begin);
        } catch (const protocol::BlobError& e) {
            return fail_mesh(begin, e.what());
        }
        incoming[{id, begin.level()}] = std::move(mesh);
    }

    void on_mesh_chunk(const v1::MeshChunk& chunk) {
        auto it = incoming.find({chunk.request_id(), chunk.level()});
        if (it == incoming.end()) return;
        IncomingMesh& mesh = it->second;
        if (chunk.offset() != mesh.bytes.size() ||
            mesh.bytes.size() + chunk.data().size() > mesh.begin.total_bytes())
            return fail_mesh(mesh.begin, "a chunk at offset " + std::to_string(chunk.offset()) +
                                             " of " + std::to_string(chunk.data().size()) +
                                             " bytes after " + std::to_string(mesh.bytes.size()) +
                                             " of " + std::to_string(mesh.begin.total_bytes()));
        mesh.bytes += chunk.data();
    }

    void on_mesh_end(const v1::MeshEnd& end) {
        auto it = incoming.find({end.request_id(), end.level()});
        if (it == incoming.end()) return;
        IncomingMesh mesh = std::move(it->second);
        incoming.erase(it);
        const v1::MeshBegin& begin = mesh.begin;
        Level level = level_from(begin, mesh.bytes.size());
        RequestState* request = nullptr;
        if (begin.request_id() != 0) {
            auto r = requests.find(begin.request_id());
            if (r == requests.end()) return;
            request = &r->second;
        }
        try {
            if (mesh.bytes.size() != begin.total_bytes())
                throw protocol::BlobError(std::to_string(mesh.bytes.size()) + " bytes of " +
                                          std::to_string(begin.total_bytes()));
            // The mesh a refinement applies to: the request's, or the session's last one.
            std::optional<protocol::SlotMesh>& held =
                request ? request->mesh : session_meshes[begin.session()];
            if (begin.kind() == v1::MeshBegin::REFINEMENT) {
                if (!held) throw protocol::BlobError("a refinement with no level before it");
                held->apply(protocol::decode_refinement(mesh.bytes, mesh.layout));
                level.mesh = held->live();
                level.slots = held->slots();
            } else {
                Surface surface = protocol::decode_mesh(mesh.bytes, mesh.layout);
                if (begin.preview()) {
                    // Drawn now, replaced by the exact level: never the base of refinements.
                    if (request && request->progressive) level.slots = surface;
                } else if (!request || request->progressive) {
                    held.emplace(surface);
                    level.slots = surface;
                }
                level.mesh = std::move(surface);
            }
        } catch (const protocol::BlobError& e) {
            return fail_mesh(begin, e.what());
        }

        if (!request) {
            level.slots = Surface{}; // sessions: whole meshes (a refinement is applied anyway)
            SessionEvent event;
            event.kind = SessionEvent::Kind::Mesh;
            event.mesh = std::move(level);
            return deliver(std::move(event));
        }
        if (!request->progressive) level.slots = Surface{};
        if (request->on_level) request->on_level(level);
        // The callback may have cancelled this request.
        auto r = requests.find(begin.request_id());
        if (r == requests.end()) return;
        const uint32_t i = begin.level();
        if (!begin.preview() && i < r->second.levels.size() && !r->second.ready[i]) {
            r->second.ready[i] = true;
            r->second.levels[i].set_value(std::move(level));
        }
    }

    // A level this client cannot read ends its request (or is reported to the session).
    void fail_mesh(const v1::MeshBegin& begin, const std::string& why) {
        const uint64_t id = begin.request_id();
        const ClientError error(ErrorCode::Protocol,
                                "level " + std::to_string(begin.level()) + " from " + where() +
                                    " cannot be read: " + why,
                                id);
        incoming.erase({id, begin.level()});
        if (id == 0) {
            deliver({SessionEvent::Kind::Error, {}, {}, error.what(), error.code()});
            return;
        }
        auto r = requests.find(id);
        if (r == requests.end()) return;
        fail_request(r->second, error);
        requests.erase(r);
        v1::Cancel cancel;
        cancel.set_request_id(id);
        send(protocol::encode_frame(cancel));
    }

    void on_request_done(const v1::RequestDone& done) {
        auto r = requests.find(done.request_id());
        if (r == requests.end()) return;
        RequestState& state = r->second;
        for (size_t i = 0; i < state.levels.size(); ++i)
            if (!state.ready[i]) {
                state.ready[i] = true;
                state.levels[i].set_exception(as_exception(
                    ClientError(ErrorCode::Protocol,
                                "the server finished request " + std::to_string(done.request_id()) +
                                    " without level " + std::to_string(i),
                                done.request_id())));
            }
        state.done.set_value();
        requests.erase(r);
    }

    void cancel_request(uint64_t id) {
        auto r = requests.find(id);
        if (r == requests.end()) return;
        fail_request(r->second,
                     ClientError(ErrorCode::Cancelled,
                                 "request " + std::to_string(id) + " was cancelled", id));
        requests.erase(r);
        std::erase_if(incoming, [id](const auto& kv) { return kv.first.first == id; });
        v1::Cancel cancel;
        cancel.set_request_id(id);
        send(protocol::encode_frame(cancel));
    }

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

// ---------------------------------------------------------------------------------------------

Client::Client() : impl_(std::make_shared<Impl>()) {}

Client::~Client() {
    Impl* impl = impl_.get();
    std::promise<void> closed;
    auto done = closed.get_future();
    asio::post(impl->io, [impl, &closed] {
        impl->shut(ClientError(ErrorCode::Connection, "the client was destroyed"));
        impl->resolver.reset();
        impl->connect_timer.reset();
        closed.set_value();
    });
    if (!impl->on_network_thread()) done.wait();
    impl->work.reset();
    impl->io.stop();
    if (impl->thread.joinable()) {
        if (impl->on_network_thread())
            impl->thread.detach(); // destroyed from its own callback: cannot join itself
        else
            impl->thread.join();
    }
}

std::future<void> Client::async_connect(const ConnectOptions& options) {
    auto promise = std::make_shared<std::promise<void>>();
    auto future = promise->get_future();
    {
        std::lock_guard lock(impl_->info_mutex);
        impl_->last_options = options;
    }
    impl_->run([impl = impl_.get(), options, promise] { impl->start_connect(options, promise); });
    return future;
}

void Client::connect(const ConnectOptions& options) {
    impl_->require_other_thread("connect");
    auto future = async_connect(options);
    // The network thread enforces the timeout itself; this only waits for it.
    future.get();
}

void Client::reconnect() {
    std::optional<ConnectOptions> options;
    std::map<std::string, std::string> sessions;
    {
        std::lock_guard lock(impl_->info_mutex);
        options = impl_->last_options;
        sessions = impl_->joined;
    }
    if (!options) throw ClientError(ErrorCode::Connection, "reconnect() before any connect()");
    connect(*options);
    for (const auto& [name, key] : sessions) join_session(name, key);
}

void Client::close() {
    impl_->require_other_thread("close");
    std::promise<void> closed;
    auto done = closed.get_future();
    asio::post(impl_->io, [impl = impl_.get(), &closed] {
        impl->shut(ClientError(ErrorCode::Connection, "the connection was closed by the client"));
        closed.set_value();
    });
    done.wait();
    std::lock_guard lock(impl_->info_mutex);
    impl_->joined.clear();
}

bool Client::connected() const {
    std::lock_guard lock(impl_->info_mutex);
    return impl_->is_connected;
}

uint64_t Client::client_id() const {
    std::lock_guard lock(impl_->info_mutex);
    return impl_->my_client_id;
}

std::vector<std::string> Client::capabilities() const {
    std::lock_guard lock(impl_->info_mutex);
    return impl_->caps;
}

bool Client::has_capability(const std::string& name) const {
    return impl_->capability(name);
}

uint64_t Client::max_surface_triangles() const {
    std::lock_guard lock(impl_->info_mutex);
    return impl_->max_triangles;
}

std::future<UploadResult> Client::async_upload(const Surface& surface, const std::string& name,
                                               const std::string& session) {
    // Encoding happens on the caller's thread, so the network thread stays free.
    protocol::EncodedBlob blob;
    try {
        blob = protocol::encode_mesh(surface, v1::RAW);
    } catch (const protocol::BlobError& e) {
        throw ClientError(ErrorCode::InvalidArgument,
                          std::string("the surface cannot be sent: ") + e.what());
    }
    const uint64_t id = impl_->take_id();
    v1::UploadBegin begin;
    begin.set_upload_id(id);
    begin.set_name(name);
    begin.set_vertex_count(blob.layout.vertex_count);
    begin.set_triangle_count(blob.layout.triangle_count);
    for (const protocol::FieldSpec& f : blob.layout.fields) {
        v1::FieldInfo* info = begin.add_fields();
        info->set_name(f.name);
        info->set_components(f.components);
    }
    begin.set_total_bytes(blob.bytes.size());
    begin.set_session(session);

    auto promise = std::make_shared<std::promise<UploadResult>>();
    auto future = promise->get_future();
    auto bytes = std::make_shared<const std::string>(std::move(blob.bytes));
    impl_->run([impl = impl_.get(), id, begin = std::move(begin), bytes, promise] {
        if (!impl->require_connection(*promise)) return;
        impl->uploads.emplace(id, std::move(*promise));
        impl->send(protocol::encode_frame(begin));
        if (bytes->empty()) {
            v1::UploadEnd end;
            end.set_upload_id(id);
            impl->send(protocol::encode_frame(end));
        } else {
            impl->upload_jobs.push_back({id, bytes, 0});
            impl->write_next();
        }
    });
    return future;
}

UploadResult Client::upload(const Surface& surface, const std::string& name,
                            const std::string& session) {
    impl_->require_other_thread("upload");
    auto future = async_upload(surface, name, session);
    return impl_->wait(future, "upload", false);
}

std::future<std::vector<SurfaceInfo>> Client::async_list_surfaces() {
    auto promise = std::make_shared<std::promise<std::vector<SurfaceInfo>>>();
    auto future = promise->get_future();
    impl_->run([impl = impl_.get(), promise] {
        if (!impl->require_connection(*promise)) return;
        impl->control.push_back({ControlOp::Kind::List, {}, promise, nullptr});
        impl->send(protocol::encode_frame(v1::ListSurfaces{}));
    });
    return future;
}

std::vector<SurfaceInfo> Client::list_surfaces() {
    auto future = async_list_surfaces();
    return impl_->wait(future, "list_surfaces", true);
}

PendingRequest Client::request(const LevelRequest& request, LevelCallback on_level) {
    check_request(request);
    PendingRequest pending;
    pending.id = impl_->take_id();
    RequestState state;
    state.levels.resize(request.keep.size());
    state.ready.assign(request.keep.size(), false);
    for (auto& p : state.levels) pending.levels.push_back(p.get_future().share());
    pending.done = state.done.get_future().share();
    state.on_level = std::move(on_level);
    state.progressive = request.progressive && impl_->capability("progressive");
    const v1::Request message = to_wire(request, pending.id, impl_->capability("meshopt-codec"),
                                        impl_->capability("progressive"));
    auto shared_state = std::make_shared<RequestState>(std::move(state));
    impl_->run([impl = impl_.get(), id = pending.id, shared_state, message] {
        if (!(impl->plain || impl->tls)) {
            Impl::fail_request(*shared_state,
                               ClientError(ErrorCode::Connection, "the client is not connected"));
            return;
        }
        impl->requests.emplace(id, std::move(*shared_state));
        impl->send(protocol::encode_frame(message));
    });
    return pending;
}

std::vector<Level> Client::request_levels(const LevelRequest& request) {
    impl_->require_other_thread("request_levels");
    PendingRequest pending = this->request(request);
    std::vector<Level> levels;
    for (auto& f : pending.levels) levels.push_back(f.get());
    pending.done.get();
    return levels;
}

void Client::cancel(uint64_t request_id) {
    impl_->run([impl = impl_.get(), request_id] { impl->cancel_request(request_id); });
}

std::future<SessionState> Client::async_join_session(const std::string& name,
                                                     const std::string& key) {
    // A server without the capability would ignore the key and let anyone in: never send it.
    if (!key.empty() && connected() && !has_capability("session-keys"))
        throw ClientError(ErrorCode::InvalidArgument,
                          "the server does not support session keys (no \"session-keys\" "
                          "capability): the session \"" +
                              name + "\" would be open to anyone");
    auto promise = std::make_shared<std::promise<SessionState>>();
    auto future = promise->get_future();
    {
        std::lock_guard lock(impl_->info_mutex);
        impl_->joined[name] = key;
    }
    impl_->run([impl = impl_.get(), name, key, promise] {
        if (!impl->require_connection(*promise)) return;
        impl->control.push_back({ControlOp::Kind::Join, name, nullptr, promise});
        v1::JoinSession join;
        join.set_name(name);
        join.set_key(key);
        impl->send(protocol::encode_frame(join));
    });
    return future;
}

SessionState Client::join_session(const std::string& name, const std::string& key) {
    auto future = async_join_session(name, key);
    return impl_->wait(future, "join_session", true);
}

void Client::leave_session(const std::string& name) {
    {
        std::lock_guard lock(impl_->info_mutex);
        impl_->joined.erase(name);
    }
    impl_->run([impl = impl_.get(), name] {
        if (!(impl->plain || impl->tls)) return;
        impl->session_meshes.erase(name);
        v1::LeaveSession leave;
        leave.set_name(name);
        impl->send(protocol::encode_frame(leave));
    });
}

std::future<SessionState> Client::async_set_view(const std::string& session,
                                                 const ViewChange& change) {
    auto promise = std::make_shared<std::promise<SessionState>>();
    auto future = promise->get_future();
    const v1::SetSessionState message = to_wire(session, change);
    impl_->run([impl = impl_.get(), session, message, promise] {
        if (!impl->require_connection(*promise)) return;
        impl->control.push_back({ControlOp::Kind::Set, session, nullptr, promise});
        impl->send(protocol::encode_frame(message));
    });
    return future;
}

SessionState Client::set_view(const std::string& session, const ViewChange& change) {
    auto future = async_set_view(session, change);
    return impl_->wait(future, "set_view", true);
}

void Client::on_session_event(SessionHandler handler) {
    std::deque<SessionEvent> queued;
    {
        std::lock_guard lock(impl_->events_mutex);
        impl_->handler = std::move(handler);
        if (impl_->handler) queued.swap(impl_->events);
    }
    // Events queued before the handler was set go to it first, on the network thread.
    if (!queued.empty())
        impl_->run([impl = impl_.get(), queued = std::move(queued)]() mutable {
            for (SessionEvent& e : queued) impl->deliver(std::move(e));
        });
}

std::optional<SessionEvent> Client::next_session_event(std::chrono::milliseconds timeout) {
    impl_->require_other_thread("next_session_event");
    std::unique_lock lock(impl_->events_mutex);
    if (!impl_->events_ready.wait_for(lock, timeout, [&] { return !impl_->events.empty(); }))
        return std::nullopt;
    SessionEvent event = std::move(impl_->events.front());
    impl_->events.pop_front();
    return event;
}

} // namespace ddsimp
