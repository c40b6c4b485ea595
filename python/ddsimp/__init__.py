"""ddsimp: data-dependent surface simplification (Frank & Lang) for Python.

A surface is numpy arrays: ``points`` (N, 3), ``triangles`` (M, 3) and ``fields``, a dict of
per-vertex arrays, (N,) for a scalar or (N, k) for k components, with ``kinds`` naming a field's
kind where it is not "continuous": "label" (ids: never mixed, not driving the data term by
default) or "direction" (normals: kept unit length). ``read`` gives each field's kind. Results come back as float32 /
uint32 arrays that own the library's memory (no copy); inputs are copied once into the library.

    import ddsimp
    mesh = ddsimp.read("wing.vtp")
    r = ddsimp.simplify(mesh, alpha=0.5, keep=0.1)
    print(r.triangles.shape, r.target_reached, r.stop_reason)
    ddsimp.write("wing-10.vtp", r)

Errors: ddsimp.InputError (a ValueError) for a surface or option the library refuses,
ddsimp.IoError (an OSError) for a file, ddsimp.ClientError (with .code) for the server.
The GIL is released while the library computes, reads, writes or waits for the server, and
Ctrl-C cancels a run.
"""

from . import _ddsimp
from ._ddsimp import (
    ClientError,
    InputError,
    IoError,
    Level,
    Mesh,
    Result,
    SessionEvent,
    SessionState,
    SurfaceInfo,
    UploadResult,
)

__all__ = [
    "simplify", "ProgressiveRecord", "read", "write", "Client",
    "Mesh", "Result", "Level", "SurfaceInfo", "UploadResult", "SessionState", "SessionEvent",
    "InputError", "IoError", "ClientError",
]

for _type in (ClientError, InputError, IoError, Level, Mesh, Result, SessionEvent, SessionState,
              SurfaceInfo, UploadResult):
    _type.__module__ = __name__

_D = _ddsimp.option_defaults()


def _unpack(points, triangles, fields, kinds=None):
    """(points, triangles, fields, kinds), also from one Mesh-like object passed as `points`
    (given kinds win over the mesh's)."""
    if triangles is None and hasattr(points, "points") and hasattr(points, "triangles"):
        if kinds is None:
            kinds = getattr(points, "kinds", None)
        return points.points, points.triangles, getattr(points, "fields", None), kinds
    if triangles is None:
        raise InputError("give points and triangles, or one mesh with .points and .triangles")
    return points, triangles, fields, kinds


def simplify(points, triangles=None, fields=None, *, alpha=_D["alpha"], keep=_D["keep"],
             target_triangles=None, max_weight=_D["max_weight"], strategy=_D["strategy"],
             placement=_D["placement"], data_placement=_D["data_placement"], terms=_D["terms"],
             gradient_fields=None, feature_angle=_D["feature_angle"],
             line_tolerance=_D["line_tolerance"], max_normal_turn=_D["max_normal_turn"],
             threads=_D["threads"], progress=None, kinds=None):
    """Reduces a surface; returns a Result (points, triangles, fields, target_reached, stop...).

    points (N, 3), triangles (M, 3), fields {name: (N,) or (N, k)}; or one mesh as `points`.
    alpha: weight of curvature against the data gradient, in [0, 1].
    keep: fraction of the triangles to keep; target_triangles: a count instead (wins over keep).
    max_weight: also stop when the lightest element weighs more than this.
    strategy: "edge" (collapse) or "vertex" (removal; data stays exact).
    placement: "least-error", "midpoint" or "volume" (edge collapse's new point).
    data_placement: "least-error" (clamped to the two values it replaces, then fitted over the
        whole level) or "interpolated" (along the edge): edge collapse's data at the new point.
    terms: "quadrics" (error against the input) or "paper" (angle deficit and data gradient).
    gradient_fields: names of the fields that drive the data term (None: the continuous ones).
    feature_angle: dihedral angle in degrees above which an edge is a feature (180: none).
    line_tolerance, max_normal_turn: degrees (see docs/python.md).
    threads: threads for the engine, 0 for every core (same output at any count).
    progress: callable(fraction done); returning False cancels (stop == "cancelled").
    kinds: {name: "label" or "direction"} for fields that are not continuous (a mesh's own).
    """
    points, triangles, fields, kinds = _unpack(points, triangles, fields, kinds)
    return _ddsimp.simplify(
        points, triangles, fields, alpha=alpha, keep=keep, target_triangles=target_triangles,
        max_weight=max_weight, strategy=strategy, placement=placement,
        data_placement=data_placement, terms=terms, gradient_fields=gradient_fields,
        feature_angle=feature_angle, line_tolerance=line_tolerance,
        max_normal_turn=max_normal_turn, threads=threads, progress=progress, kinds=kinds)


class ProgressiveRecord(_ddsimp.ProgressiveRecord):
    """Every operation of one run for (surface, options): each coarser level without re-running.

    Takes simplify's arguments (keep defaults to 0: record as far as the surface allows).
    level(keep) / level(triangles=n) give the surface at that level as a Mesh, equal to
    simplify's result for that target; error(keep) how far it is from the input.
    """

    def __init__(self, points, triangles=None, fields=None, *, alpha=_D["alpha"], keep=0.0,
                 target_triangles=None, max_weight=_D["max_weight"], strategy=_D["strategy"],
                 placement=_D["placement"], data_placement=_D["data_placement"],
                 terms=_D["terms"], gradient_fields=None, feature_angle=_D["feature_angle"],
                 line_tolerance=_D["line_tolerance"], max_normal_turn=_D["max_normal_turn"],
                 threads=_D["threads"], progress=None, kinds=None):
        points, triangles, fields, kinds = _unpack(points, triangles, fields, kinds)
        super().__init__(
            points, triangles, fields, alpha=alpha, keep=keep, target_triangles=target_triangles,
            max_weight=max_weight, strategy=strategy, placement=placement,
            data_placement=data_placement, terms=terms, gradient_fields=gradient_fields,
            feature_angle=feature_angle, line_tolerance=line_tolerance,
            max_normal_turn=max_normal_turn, threads=threads, progress=progress, kinds=kinds)


def read(path):
    """Reads a surface file (.vtk .vtp .ply .obj .off .stl) with its point data; returns a Mesh."""
    return _ddsimp.read(str(path))


def write(path, points, triangles=None, fields=None, *, kinds=None):
    """Writes a surface (.vtk .vtp .ply .obj .off .glb), from arrays or one mesh as `points`.

    Fields are kept where the format holds them (.vtk, .vtp, .ply, .glb); .vtk and .vtp write
    labels as integers and the direction "Normals" as the normals.
    """
    points, triangles, fields, kinds = _unpack(points, triangles, fields, kinds)
    _ddsimp.write(str(path), points, triangles, fields, kinds)


class Client(_ddsimp.Client):
    """A connection to ddsimp-server (the C++ client library underneath).

    Client(server="localhost:7420", token="", tls=False, ca_file="", tls_insecure=False,
           name="ddsimp-python", timeout=15.0) connects at once (ClientError if it cannot).
    Use it as a context manager to close it.
    """

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def upload(self, points, triangles=None, fields=None, *, name="", session="", kinds=None):
        """Stores a surface on the server; returns an UploadResult (.surface is its id).

        With `session` (joined first, see join) only that session's members see it and the
        session's view switches to it.
        """
        points, triangles, fields, kinds = _unpack(points, triangles, fields, kinds)
        return super().upload(points, triangles, fields, kinds, name=name, session=session)

    def simplify(self, surface, keep=(0.5, 0.25, 0.1), *, alpha=0.5, strategy="edge",
                 placement=_D["placement"], data_placement=_D["data_placement"],
                 gradient_fields=None, feature_angle=180.0):
        """Asks the server for levels of a stored surface (its id); returns a list of Level
        (Mesh with keep, triangle_count, target_reached, cached, error...) in the order of
        `keep`, or one Level when `keep` is a number."""
        single = isinstance(keep, (int, float))
        levels = self.request_levels(surface, [keep] if single else list(keep), alpha, strategy,
                                     placement, data_placement, list(gradient_fields or []),
                                     feature_angle)
        return levels[0] if single else levels

    def watch(self, session, key="", *, timeout=None):
        """Joins `session` and yields its SessionEvents (state, mesh, error) as they come;
        stops after `timeout` seconds without an event (None: never)."""
        self.join(session, key)
        while True:
            event = self.next_event(1.0 if timeout is None else timeout)
            if event is None:
                if timeout is None:
                    continue
                return
            yield event
