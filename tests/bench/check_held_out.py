#!/usr/bin/python3
"""bench/report/held_out.py's account of the goals: on rows made the way the report makes them
(row_of), a data loss, a run that stopped short, a Hausdorff loss and a run that changed the
topology must each be listed once, against the rival the report's rules pick, and a goal met must
not be; a rival that changed the topology is said to, with what it changed.

    check_held_out.py REPORT_DIR (bench/report: held_out.py, report.py, goals.py)
"""

import sys

sys.path.insert(0, sys.argv[1])
from goals import check_goals, goal_counts  # noqa: E402
from held_out import misses  # noqa: E402
from report import row_of  # noqa: E402


def run(status, data, hausdorff, topology=True, message=""):
    kept = {"euler": -6, "boundary_loops": 8, "components": 1, "nonmanifold_edges": 0}
    out = kept if topology else {"euler": -3, "boundary_loops": 5, "components": 1,
                                 "nonmanifold_edges": 0}
    return {"status": status, "message": message, "data_rms": data, "geometric_hausdorff":
            hausdorff, "topology_kept": topology, "triangles_in": 100, "triangles_out": 10,
            "topology_in": kept, "topology_out": out}


rows = [
    row_of("s", "ddsimp-edge", 0.0, 0.1, run("ok", 0.02, 0.01)),
    row_of("s", "ddsimp-edge", 1.0, 0.1, run("ok", 0.05, 0.01)),
    row_of("s", "ddsimp-vertex", 0.0, 0.1, run("not reached", 0.03, 0.02, message="stuck")),
    row_of("s", "ddsimp-vertex", 1.0, 0.1, run("ok", 0.05, 0.04)),
    row_of("s", "meshopt", None, 0.1, run("ok", 0.01, 0.02, topology=False)),
    row_of("t", "ddsimp-edge", 0.0, 0.1, run("ok", 0.01, 0.01, topology=False)),
    row_of("t", "ddsimp-edge", 1.0, 0.1, run("ok", 0.05, 0.01)),
    row_of("t", "ddsimp-vertex", 0.0, 0.1, run("ok", 0.01, 0.01)),
    row_of("t", "ddsimp-vertex", 1.0, 0.1, run("ok", 0.05, 0.01)),
    row_of("t", "meshopt", None, 0.1, run("ok", 0.02, 0.02)),
]
goals = check_goals(rows)
got = misses(goals)
expected = [
    "s 10% ddsimp-edge data_rms: 0.02 against meshopt's 0.01 (×2.000), which changed the"
    " topology (boundary loops 8 → 5, Euler characteristic -6 → -3)",
    "s 10% ddsimp-vertex data_rms: ddsimp's run not reached (stuck)",
    "s 10% ddsimp-vertex geometric_hausdorff: 0.04 against meshopt's 0.02 (×2.000), which changed"
    " the topology (boundary loops 8 → 5, Euler characteristic -6 → -3)",
    "t 10% ddsimp-edge data_rms: topology not kept",
]
failures = []
if got != expected:
    failures.append(f"misses:\n  got      {got}\n  expected {expected}")
if goal_counts(goals)["all"] != (1, 3, 4):
    failures.append(f"goal counts {goal_counts(goals)['all']}, expected (1, 3, 4)")
for f in failures:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
