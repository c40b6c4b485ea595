// ddsimp.simplify's keyword options (see options.h).
#include "options.h"

#include <pybind11/stl.h>

#include <set>
#include <string>

namespace ddsimp::python {

namespace {

template <class T> T option(const py::kwargs& kwargs, const char* name, T value) {
    if (!kwargs.contains(name) || kwargs[name].is_none()) return value;
    try {
        return kwargs[name].cast<T>();
    } catch (const py::cast_error&) {
        throw InputError(std::string(name) +
                         " has the wrong type: " + py::repr(kwargs[name]).cast<std::string>());
    }
}

std::string choices(std::initializer_list<const char*> names) {
    std::string out;
    for (const char* n : names) out += (out.empty() ? "\"" : ", \"") + std::string(n) + "\"";
    return out;
}

} // namespace

Strategy strategy_from_name(const std::string& name) {
    if (name == "edge") return Strategy::EdgeCollapse;
    if (name == "vertex") return Strategy::VertexRemoval;
    throw InputError("strategy must be one of " + choices({"edge", "vertex"}) + ", not \"" + name +
                     "\"");
}

const char* strategy_name(Strategy strategy) {
    return strategy == Strategy::VertexRemoval ? "vertex" : "edge";
}

const char* stop_name(StopReason stop) {
    switch (stop) {
    case StopReason::TargetReached:
        return "target_reached";
    case StopReason::WeightBound:
        return "weight_bound";
    case StopReason::NothingRemovable:
        return "nothing_removable";
    case StopReason::Cancelled:
        return "cancelled";
    }
    return "unknown";
}

py::dict option_defaults() {
    const Options o;
    py::dict d;
    d["alpha"] = o.alpha;
    d["keep"] = o.keep_fraction;
    d["target_triangles"] = py::none();
    d["max_weight"] = o.max_weight;
    d["strategy"] = strategy_name(o.strategy);
    d["placement"] = "least-error";
    d["data_placement"] = "least-error";
    d["terms"] = "quadrics";
    d["gradient_fields"] = py::none();
    d["feature_angle"] = o.feature_angle;
    d["line_tolerance"] = o.line_tolerance;
    d["max_normal_turn"] = o.max_normal_turn;
    d["threads"] = o.threads;
    return d;
}

Options options_from_kwargs(const py::kwargs& kwargs) {
    static const std::set<std::string> known{"alpha",          "keep",           "target_triangles",
                                             "max_weight",     "strategy",       "placement",
                                             "data_placement", "terms",          "gradient_fields",
                                             "feature_angle",  "line_tolerance", "max_normal_turn",
                                             "threads",        "progress"};
    for (auto item : kwargs) {
        const auto name = item.first.cast<std::string>();
        if (!known.count(name)) throw InputError("unknown option \"" + name + "\"");
    }
    Options o;
    o.alpha = option(kwargs, "alpha", o.alpha);
    o.keep_fraction = option(kwargs, "keep", o.keep_fraction);
    const long long target = option(kwargs, "target_triangles", 0LL);
    if (kwargs.contains("target_triangles") && !kwargs["target_triangles"].is_none() && target < 1)
        throw InputError("target_triangles must be at least 1, not " + std::to_string(target));
    o.target_triangles = size_t(target);
    o.max_weight = option(kwargs, "max_weight", o.max_weight);
    o.strategy = strategy_from_name(option(kwargs, "strategy", std::string("edge")));
    const auto placement = option(kwargs, "placement", std::string("least-error"));
    if (placement == "least-error")
        o.placement = Placement::LeastError;
    else if (placement == "midpoint")
        o.placement = Placement::Midpoint;
    else if (placement == "volume")
        o.placement = Placement::VolumePreserving;
    else
        throw InputError("placement must be one of " +
                         choices({"least-error", "midpoint", "volume"}) + ", not \"" + placement +
                         "\"");
    const auto data = option(kwargs, "data_placement", std::string("least-error"));
    if (data == "least-error")
        o.data_placement = DataPlacement::LeastError;
    else if (data == "interpolated")
        o.data_placement = DataPlacement::Interpolated;
    else
        throw InputError("data_placement must be one of " +
                         choices({"least-error", "interpolated"}) + ", not \"" + data + "\"");
    const auto terms = option(kwargs, "terms", std::string("quadrics"));
    if (terms == "quadrics")
        o.terms = Terms::ErrorQuadrics;
    else if (terms == "paper")
        o.terms = Terms::AngleDeficitGradient;
    else
        throw InputError("terms must be one of " + choices({"quadrics", "paper"}) + ", not \"" +
                         terms + "\"");
    if (kwargs.contains("gradient_fields") && py::isinstance<py::str>(kwargs["gradient_fields"]))
        throw InputError("gradient_fields must be a list of field names, e.g. [\"T\"]");
    o.gradient_fields = option(kwargs, "gradient_fields", std::vector<std::string>{});
    o.feature_angle = option(kwargs, "feature_angle", o.feature_angle);
    o.line_tolerance = option(kwargs, "line_tolerance", o.line_tolerance);
    o.max_normal_turn = option(kwargs, "max_normal_turn", o.max_normal_turn);
    o.threads = option(kwargs, "threads", o.threads);
    return o;
}

Progress::Progress(const py::kwargs& kwargs) {
    if (kwargs.contains("progress")) callable_ = kwargs["progress"];
    if (callable_ && !callable_.is_none() && !PyCallable_Check(callable_.ptr()))
        throw InputError("progress must be callable (it gets the fraction done)");
}

void Progress::install(Options& options) {
    options.progress = [this](double done) {
        py::gil_scoped_acquire gil;
        if (error_) return false;
        try {
            if (PyErr_CheckSignals() != 0) throw py::error_already_set();
            if (callable_ && !callable_.is_none()) {
                py::object answer = callable_(done);
                // Only an explicit False cancels; None (no return) goes on.
                if (answer.is(py::bool_(false))) return false;
            }
            return true;
        } catch (py::error_already_set& e) {
            error_ = std::make_shared<py::error_already_set>(std::move(e));
            return false;
        }
    };
}

void Progress::rethrow() {
    if (error_) {
        auto e = std::move(error_);
        throw py::error_already_set(std::move(*e));
    }
}

} // namespace ddsimp::python
