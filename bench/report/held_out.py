#!/usr/bin/python3
"""The report's goals on isosurfaces the report does not hold: the same volumes at other values
(make-surfaces.sh --held-out), every simplifier of the report at the goal levels (ddsimp at the
goals' α, 0 and 1), counted by the report's own rules (goals.check_goals). A library change tuned
to the report's surfaces shows here as goals lost.

    bench/report/held_out.py --build DIR --out DIR

Writes OUT/results.csv (the report's columns) and prints the goals met and every miss. The runs
are cached in OUT/runs as the report's are: delete them after a library change.
"""

import argparse
import csv
import os
import subprocess
import sys

from goals import GOAL_LEVELS, check_goals, goal_counts, label
from report import (COLUMNS, cached_run, configurations, node_peers_missing, row_of, run_key,
                    run_one, surface_sizes)

HERE = os.path.dirname(os.path.abspath(__file__))
GOAL_ALPHAS = (None, 0.0, 1.0)  # the peers (no α), then the data goal's and the Hausdorff goal's


def topology_change(row):
    """What a run changed of its input's topology, as a clause; empty if it kept the topology."""
    if row.get("topology_kept") is not False:
        return ""
    changed = [f"{name} {row[key + '_in']} → {row[key + '_out']}"
               for name, key in (("components", "components"), ("boundary loops", "boundary_loops"),
                                 ("Euler characteristic", "euler"),
                                 ("non-manifold edges", "nonmanifold_edges"))
               if row.get(key + "_in") is not None and row.get(key + "_out") is not None
               and row[key + "_in"] != row[key + "_out"]]
    return ", which changed the topology" + (f" ({', '.join(changed)})" if changed else "")


def misses(goals):
    """One line per goal missed: the run, the rival that beats it, by how much, and what the rival
    changed of the topology (ddsimp keeps it)."""
    out = []
    for g in goals:
        where = f"{g['surface']} {g['level']:.0%} {g['strategy']}"
        for ok, run, rival, measure in ((g["data_ok"], g["d0"], g["best_data"], "data_rms"),
                                        (g["hd_ok"], g["d1"], g["best_hd"], "geometric_hausdorff")):
            if ok:
                continue
            if not run or run["status"] != "ok":
                out.append(f"{where} {measure}: ddsimp's run {run['status'] if run else 'missing'}"
                           f" ({run['message'] if run else ''})")
            elif measure == "data_rms" and not run["topology_kept"]:
                out.append(f"{where} {measure}: topology not kept")
            elif rival:
                out.append(f"{where} {measure}: {run[measure]:.4g} against {label(rival)}'s "
                           f"{rival[measure]:.4g} (×{run[measure] / rival[measure]:.3f})"
                           + topology_change(rival))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--build", required=True)
    ap.add_argument("--out", required=True)
    args = ap.parse_args()
    surfaces = os.path.join(args.out, "surfaces")
    cache = os.path.join(args.out, "runs")
    os.makedirs(cache, exist_ok=True)
    subprocess.run([os.path.join(HERE, "make-surfaces.sh"), args.build, surfaces, "--held-out"],
                   check=True)
    tool = os.path.join(args.build, "bench", "report", "ddsimp_report")
    names = [f[:-4] for f in os.listdir(surfaces) if f.endswith(".vtp")
             and not f.endswith(".partial.vtp")]
    sizes = surface_sizes(surfaces, names)
    names.sort(key=lambda n: (sizes[n], n))
    missing = node_peers_missing()
    if missing:
        print(f"held_out.py: meshoptimizer's attribute-aware peers left out: {missing}",
              file=sys.stderr)
    configs = [c for c in configurations(node_peers=not missing) if c[1] in GOAL_ALPHAS]
    rows = []
    for surface in names:
        for keep in GOAL_LEVELS:
            for simplifier, alpha, weight in configs:
                r = cached_run(cache, run_key(surface, simplifier, alpha, keep, weight), None,
                               lambda: run_one(tool, os.path.join(surfaces, surface + ".vtp"),
                                               simplifier, alpha, keep, 600, weight=weight))
                rows.append(row_of(surface, simplifier, alpha, keep, r, weight))
    with open(os.path.join(args.out, "results.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=COLUMNS)
        w.writeheader()
        for r in rows:
            w.writerow({k: ("" if r[k] is None else r[k]) for k in COLUMNS})
    goals = check_goals(rows)
    data, hd, pairs = goal_counts(goals)["all"]
    print(f"held-out surfaces: {', '.join(names)}")
    print(f"data goal at α = 0: {data} of {pairs}; Hausdorff goal at α = 1: {hd} of {pairs}")
    for line in misses(goals):
        print("  " + line)


if __name__ == "__main__":
    main()
