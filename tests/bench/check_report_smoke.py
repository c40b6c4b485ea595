#!/usr/bin/python3
"""Smoke test of the fidelity report: runs `bench/report/run.sh --quick` and checks what it wrote.

    check_report_smoke.py RUN_SH BUILD_DIR OUT_DIR

Quick mode reduces two small surfaces of the shared data to 10% with every simplifier. The
expected rows, columns and input sizes are written out here (the sizes from the shared data's
README), not taken from the report code; no time is asserted. meshoptimizer's attribute-aware
peers run only where `npm ci` installed them in bench/report (never in CI): then all their rows
must be there, else none, and the report must say why they were left out.
"""

import csv
import math
import os
import subprocess
import sys

SURFACES = {
    # name: input triangles, per ../shared/data/README.md
    "disk-cut": 756,  # surfaces/SurfaceVectors.vtk, a planar cut with one boundary
    "disk-temp400": 2056,  # volumes/disk_out_ref.ex2, isosurface Temp = 400
}
SIMPLIFIERS = [(s, a) for s in ("ddsimp-edge", "ddsimp-vertex") for a in ("0.0", "0.5", "1.0")] + [
    (p, "") for p in ("meshopt", "vtk-quadric", "vtk-decimatepro", "openmesh")]
NODE_PEERS = ("meshopt-attributes", "meshopt-update")
WEIGHTS = ("1.0", "2.0", "4.0", "8.0", "16.0", "32.0")
COLUMNS = [
    "surface", "simplifier", "alpha", "weight", "keep", "status", "message", "triangles_in",
    "target", "triangles_out", "triangles_seen", "seconds", "cpu_seconds", "runtime",
    "peak_rss_mb", "call_rss_mb",
    "geometric_rms", "geometric_hausdorff", "data_rms", "data_max", "fields_lost", "topology_kept",
    "euler_in", "euler_out", "boundary_loops_in", "boundary_loops_out", "components_in",
    "components_out", "nonmanifold_edges_in", "nonmanifold_edges_out",
]
STATUSES = {"ok", "not reached", "failed", "crashed", "timeout"}

failures = []


def expect(condition, what):
    if not condition:
        failures.append(what)


def number(row, key):
    value = float(row[key])
    expect(math.isfinite(value), f"{key} is not finite in {row['surface']}/{row['simplifier']}")
    return value


def main():
    run_sh, build, out = sys.argv[1:4]
    env = dict(os.environ, DDSIMP_REPORT_BUILD_DIR=build)
    done = subprocess.run([run_sh, "--quick", "--out", out], env=env)
    if done.returncode != 0:
        sys.exit(f"run.sh --quick exited with {done.returncode}")

    with open(os.path.join(out, "results.csv"), newline="") as f:
        reader = csv.DictReader(f)
        expect(reader.fieldnames == COLUMNS, f"columns {reader.fieldnames}, expected {COLUMNS}")
        rows = list(reader)
    keys = [(r["surface"], r["simplifier"], r["alpha"], r["weight"], r["keep"]) for r in rows]
    expected = [(s, p, a, "", "0.1") for s in SURFACES for p, a in SIMPLIFIERS]
    node_rows = any(r["simplifier"] in NODE_PEERS for r in rows)
    if node_rows:
        expected += [(s, p, "", w, "0.1") for s in SURFACES for p in NODE_PEERS for w in WEIGHTS]
    expect(sorted(keys) == sorted(expected), f"rows {sorted(keys)}, expected {sorted(expected)}")

    for r in rows:
        name = f"{r['surface']}/{r['simplifier']}/{r['alpha']}{r['weight']}"
        triangles_in = SURFACES.get(r["surface"], -1)
        expect(r["status"] in STATUSES, f"{name}: status {r['status']!r}")
        expect(r["runtime"] == ("wasm" if r["simplifier"] in NODE_PEERS else ""),
               f"{name}: runtime {r['runtime']!r}")
        expect(int(r["triangles_in"]) == triangles_in, f"{name}: triangles_in {r['triangles_in']}")
        expect(int(r["target"]) == triangles_in // 10, f"{name}: target {r['target']}")
        if r["status"] in ("crashed", "timeout"):
            continue
        out_triangles = int(r["triangles_out"])
        expect(0 < out_triangles <= triangles_in, f"{name}: triangles_out {out_triangles}")
        if r["status"] == "ok":
            expect(out_triangles <= 1.02 * int(r["target"]), f"{name}: ok but {out_triangles}")
        expect(number(r, "seconds") >= 0 and number(r, "cpu_seconds") >= 0, f"{name}: time < 0")
        expect(number(r, "peak_rss_mb") > 0, f"{name}: no peak memory")
        rms, hd = number(r, "geometric_rms"), number(r, "geometric_hausdorff")
        expect(0 <= rms <= hd + 1e-12, f"{name}: geometric RMS {rms} vs Hausdorff {hd}")
        drms, dmax = number(r, "data_rms"), number(r, "data_max")
        expect(0 <= drms <= dmax + 1e-12, f"{name}: data RMS {drms} vs max {dmax}")
        # Both inputs are one edge-connected piece with one boundary loop: Euler characteristic 1.
        expect((r["euler_in"], r["boundary_loops_in"], r["components_in"]) == ("1", "1", "1"),
               f"{name}: input topology {r['euler_in']}, {r['boundary_loops_in']}, "
               f"{r['components_in']}")
        if r["simplifier"].startswith("ddsimp"):
            # The library's promise: the target is reached here and the topology kept.
            expect(r["status"] == "ok", f"{name}: status {r['status']}")
            expect(r["topology_kept"] == "True", f"{name}: topology not kept")
            expect((r["euler_out"], r["boundary_loops_out"], r["components_out"]) ==
                   ("1", "1", "1"), f"{name}: output topology changed")

    report = open(os.path.join(out, "report.md")).read()
    if not node_rows:
        expect("meshoptimizer's attribute-aware simplifiers: not run: " in report,
               "no node peer rows, and report.md does not say why")
    for heading in ("## Goals at 10% of the triangles", "## Peers: topology and failures",
                    "## Where ddsimp still loses, and why", "### disk-cut", "### disk-temp400"):
        expect(heading in report, f"report.md has no '{heading}'")
    plot = os.path.join(out, "data-error-vs-triangles.png")
    expect(os.path.exists(plot) and open(plot, "rb").read(8) == b"\x89PNG\r\n\x1a\n",
           "no PNG data-error-vs-triangles.png")

    for f in failures:
        print("FAILED:", f)
    print(f"{len(rows)} rows checked, {len(failures)} failures")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
