// The keyword options of ddsimp.simplify and ddsimp.ProgressiveRecord -> ddsimp::Options, with
// the command line's names for the choices ("edge", "least-error", "quadrics", ...).
#pragma once

#include "ddsimp/ddsimp.h"

#include <pybind11/pybind11.h>

#include <memory>

namespace ddsimp::python {

namespace py = pybind11;

// The defaults of every option as a dict (Options{}'s values), for the Python signatures.
py::dict option_defaults();

// Options from keyword arguments; throws InputError for an unknown name or a bad choice.
// "progress" (a callable taking the fraction done, returning False to cancel) is not part of
// the result: see Progress.
Options options_from_kwargs(const py::kwargs& kwargs);

// The progress callback of a run that releases the GIL: it takes the GIL, turns Ctrl-C into a
// cancel, and calls the user's callable, if any. After the run, rethrow() raises what it caught
// (KeyboardInterrupt or the callable's exception).
class Progress {
public:
    // Takes "progress" out of `kwargs` (None if absent).
    explicit Progress(const py::kwargs& kwargs);
    // Installs the callback into `options`; the Progress must outlive the run.
    void install(Options& options);
    // With the GIL held: raises what the callback caught, if anything.
    void rethrow();

private:
    py::object callable_;
    std::shared_ptr<py::error_already_set> error_;
};

// "edge" / "vertex", and back.
Strategy strategy_from_name(const std::string& name);
const char* strategy_name(Strategy strategy);
// "target_reached", "weight_bound", "nothing_removable", "cancelled".
const char* stop_name(StopReason stop);

} // namespace ddsimp::python
