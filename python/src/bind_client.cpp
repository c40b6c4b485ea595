// ddsimp.Client: libddsimp-client (ddsimp/client.h) for Python. Every call that waits for the
// server releases the GIL and wakes every 0.1 s to let Ctrl-C through.
#include "arrays.h"
#include "bindings.h"
#include "options.h"

#include "ddsimp/client.h"

#include <pybind11/chrono.h>
#include <pybind11/stl.h>

#include <chrono>
#include <future>
#include <optional>

namespace ddsimp::python {

namespace {

using namespace std::chrono_literals;

// Waits for `future` without the GIL; a pending Ctrl-C raises KeyboardInterrupt (after
// `on_interrupt`, e.g. a cancel).
template <class Future> void wait(Future& future, const std::function<void()>& on_interrupt = {}) {
    for (;;) {
        {
            py::gil_scoped_release released;
            if (future.wait_for(100ms) == std::future_status::ready) return;
        }
        if (PyErr_CheckSignals() != 0) {
            if (on_interrupt) on_interrupt();
            throw py::error_already_set();
        }
    }
}

// A level as numpy arrays and what the server said about it.
struct PyLevel : Mesh {
    double keep = 0;
    uint32_t index = 0;
    uint64_t triangle_count = 0;
    bool target_reached = false;
    bool cached = false;
    double seconds = 0;
    std::string result;
    std::string session;
    py::object error = py::none(); // dict: geometric, data, data_components
};

PyLevel level_to_python(Level level) {
    PyLevel out;
    static_cast<Mesh&>(out) = mesh_from_surface(std::move(level.mesh));
    out.keep = level.keep;
    out.index = level.index;
    out.triangle_count = level.triangles;
    out.target_reached = level.target_reached;
    out.cached = level.cached;
    out.seconds = level.seconds;
    out.result = level.result;
    out.session = level.session;
    if (level.error) {
        py::dict e;
        e["geometric"] = level.error->geometric;
        e["data"] = level.error->data;
        e["data_components"] = level.error->data_components;
        out.error = e;
    }
    return out;
}

struct PyEvent {
    std::string kind; // "state", "mesh", "error"
    std::optional<SessionState> state;
    std::optional<PyLevel> mesh;
    std::string error;
    std::string error_code;
};

PyEvent event_to_python(SessionEvent event) {
    PyEvent out;
    switch (event.kind) {
    case SessionEvent::Kind::State:
        out.kind = "state";
        out.state = std::move(event.state);
        break;
    case SessionEvent::Kind::Mesh:
        out.kind = "mesh";
        out.mesh = level_to_python(std::move(event.mesh));
        break;
    case SessionEvent::Kind::Error:
        out.kind = "error";
        out.error = event.error;
        out.error_code = error_code_name(event.error_code);
        break;
    }
    return out;
}

const char* kind_name(ClientKind kind) {
    switch (kind) {
    case ClientKind::VR:
        return "vr";
    case ClientKind::Desktop:
        return "desktop";
    case ClientKind::Tool:
        return "tool";
    case ClientKind::Unspecified:
        break;
    }
    return "unspecified";
}

std::unique_ptr<Client> connect(const std::string& server, const std::string& token, bool tls,
                                const std::string& ca_file, bool tls_insecure,
                                const std::string& name, double timeout) {
    ConnectOptions options;
    parse_server_address(server, options);
    options.token = token;
    options.tls = tls;
    options.ca_file = ca_file;
    options.tls_insecure = tls_insecure;
    options.client_name = name;
    options.timeout = std::chrono::milliseconds(int64_t(timeout * 1000));
    auto client = std::make_unique<Client>();
    auto connected = client->async_connect(options);
    wait(connected);
    connected.get();
    return client;
}

UploadResult upload(Client& client, py::handle points, py::handle triangles, py::handle fields,
                    py::handle kinds, const std::string& name, const std::string& session) {
    auto stored =
        client.async_upload(surface_from_arrays(points, triangles, fields, kinds), name, session);
    wait(stored);
    return stored.get();
}

std::vector<PyLevel> request_levels(Client& client, const std::string& surface,
                                    const std::vector<double>& keep, double alpha,
                                    const std::string& strategy, const std::string& placement,
                                    const std::string& data_placement,
                                    const std::vector<std::string>& gradient_fields,
                                    double feature_angle) {
    LevelRequest r;
    r.surface = surface;
    r.keep = keep;
    r.alpha = alpha;
    r.strategy = strategy_from_name(strategy);
    if (placement == "midpoint")
        r.placement = Placement::Midpoint;
    else if (placement == "least-error")
        r.placement = Placement::LeastError;
    else if (placement == "volume")
        r.placement = Placement::VolumePreserving;
    else
        throw InputError("placement must be \"least-error\", \"midpoint\" or \"volume\", not \"" +
                         placement + "\"");
    if (data_placement == "least-error")
        r.data_placement = DataPlacement::LeastError;
    else if (data_placement == "interpolated")
        r.data_placement = DataPlacement::Interpolated;
    else
        throw InputError("data_placement must be \"least-error\" or \"interpolated\", not \"" +
                         data_placement + "\"");
    r.gradient_fields = gradient_fields;
    r.feature_angle = feature_angle;
    PendingRequest pending = client.request(r);
    std::vector<PyLevel> out;
    for (auto& level : pending.levels) {
        wait(level, [&] { client.cancel(pending.id); });
        out.push_back(level_to_python(level.get()));
    }
    return out;
}

std::optional<PyEvent> next_event(Client& client, double timeout) {
    const auto until = std::chrono::steady_clock::now() +
                       std::chrono::milliseconds(int64_t(std::max(0.0, timeout) * 1000));
    for (;;) {
        std::optional<SessionEvent> event;
        {
            py::gil_scoped_release released;
            const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                until - std::chrono::steady_clock::now());
            event = client.next_session_event(std::clamp(left, 0ms, 100ms));
        }
        if (event) return event_to_python(std::move(*event));
        if (PyErr_CheckSignals() != 0) throw py::error_already_set();
        if (std::chrono::steady_clock::now() >= until) return std::nullopt;
    }
}

template <class T> SessionState wait_state(std::future<T> f) {
    wait(f);
    return f.get();
}

} // namespace

void bind_client(py::module_& m) {
    py::class_<UploadResult>(m, "UploadResult")
        .def_readonly("surface", &UploadResult::surface)
        .def_readonly("triangles", &UploadResult::triangles)
        .def_readonly("vertices", &UploadResult::vertices)
        .def_readonly("already_stored", &UploadResult::already_stored)
        .def_readonly("repairs", &UploadResult::repairs);
    py::class_<FieldInfo>(m, "FieldInfo")
        .def_readonly("name", &FieldInfo::name)
        .def_readonly("components", &FieldInfo::components)
        .def_readonly("min", &FieldInfo::min)
        .def_readonly("max", &FieldInfo::max);
    py::class_<SurfaceInfo>(m, "SurfaceInfo")
        .def_readonly("surface", &SurfaceInfo::surface)
        .def_readonly("name", &SurfaceInfo::name)
        .def_readonly("triangles", &SurfaceInfo::triangles)
        .def_readonly("vertices", &SurfaceInfo::vertices)
        .def_readonly("fields", &SurfaceInfo::fields);
    py::class_<PyLevel, Mesh>(m, "Level")
        .def_readonly("keep", &PyLevel::keep)
        .def_readonly("index", &PyLevel::index)
        .def_readonly("triangle_count", &PyLevel::triangle_count)
        .def_readonly("target_reached", &PyLevel::target_reached)
        .def_readonly("cached", &PyLevel::cached)
        .def_readonly("seconds", &PyLevel::seconds)
        .def_readonly("result", &PyLevel::result)
        .def_readonly("session", &PyLevel::session)
        .def_readonly("error", &PyLevel::error);
    py::class_<View>(m, "View")
        .def_readonly("surface", &View::surface)
        .def_readonly("alpha", &View::alpha)
        .def_readonly("keep", &View::keep)
        .def_readonly("field", &View::field)
        .def_property_readonly("strategy", [](const View& v) { return strategy_name(v.strategy); });
    py::class_<Member>(m, "Member")
        .def_readonly("client_id", &Member::client_id)
        .def_readonly("name", &Member::name)
        .def_property_readonly("kind", [](const Member& x) { return kind_name(x.kind); });
    py::class_<SessionState>(m, "SessionState")
        .def_readonly("name", &SessionState::name)
        .def_readonly("version", &SessionState::version)
        .def_readonly("members", &SessionState::members)
        .def_readonly("leader", &SessionState::leader)
        .def_readonly("view", &SessionState::view)
        .def_readonly("cause", &SessionState::cause)
        .def_readonly("changed_by", &SessionState::changed_by);
    py::class_<PyEvent>(m, "SessionEvent")
        .def_readonly("kind", &PyEvent::kind, "\"state\", \"mesh\" or \"error\"")
        .def_readonly("state", &PyEvent::state)
        .def_readonly("mesh", &PyEvent::mesh)
        .def_readonly("error", &PyEvent::error)
        .def_readonly("error_code", &PyEvent::error_code);

    py::class_<Client>(m, "Client")
        .def(py::init(&connect), py::arg("server") = "localhost:7420", py::arg("token") = "",
             py::arg("tls") = false, py::arg("ca_file") = "", py::arg("tls_insecure") = false,
             py::arg("name") = "ddsimp-python", py::arg("timeout") = 15.0)
        .def("close", &Client::close)
        .def_property_readonly("connected", &Client::connected)
        .def_property_readonly("client_id", &Client::client_id)
        .def_property_readonly("capabilities", &Client::capabilities)
        .def("upload", &upload, py::arg("points"), py::arg("triangles"),
             py::arg("fields") = py::none(), py::arg("kinds") = py::none(), py::arg("name") = "",
             py::arg("session") = "")
        .def("list",
             [](Client& c) {
                 auto f = c.async_list_surfaces();
                 wait(f);
                 return f.get();
             })
        .def(
            "delete",
            [](Client& c, const std::string& surface) {
                auto f = c.async_delete_surface(surface);
                wait(f);
                return f.get();
            },
            py::arg("surface"),
            "Takes back this token's upload of a surface; True when it left the server")
        .def("request_levels", &request_levels, py::arg("surface"), py::arg("keep"),
             py::arg("alpha"), py::arg("strategy"), py::arg("placement"), py::arg("data_placement"),
             py::arg("gradient_fields"), py::arg("feature_angle"))
        .def(
            "join",
            [](Client& c, const std::string& s, const std::string& key) {
                return wait_state(c.async_join_session(s, key));
            },
            py::arg("session"), py::arg("key") = "")
        .def("leave", &Client::leave_session, py::arg("session"))
        .def(
            "set_view",
            [](Client& c, const std::string& session, std::optional<std::string> surface,
               std::optional<double> alpha, std::optional<double> keep,
               std::optional<std::string> field, std::optional<std::string> strategy) {
                ViewChange change{surface, alpha, keep, field, std::nullopt};
                if (strategy) change.strategy = strategy_from_name(*strategy);
                return wait_state(c.async_set_view(session, change));
            },
            py::arg("session"), py::kw_only(), py::arg("surface") = py::none(),
            py::arg("alpha") = py::none(), py::arg("keep") = py::none(),
            py::arg("field") = py::none(), py::arg("strategy") = py::none())
        .def("next_event", &next_event, py::arg("timeout") = 1.0);
}

} // namespace ddsimp::python
