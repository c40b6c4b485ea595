#!/usr/bin/python3
"""The fidelity and speed report: runs every reduction, one process each, and writes the report.

    report.py --build DIR --surfaces DIR --out DIR [--quick] [--scaling DIR] [--no-images]
              [--baseline OLD/results.csv] [--notes FILE]

For every surface in --surfaces, every level and every simplifier (ddsimp edge collapse and vertex
removal at each alpha, meshoptimizer, vtkQuadricDecimation with attributes, vtkDecimatePro with
the topology preserved, OpenMesh's Decimater, and meshoptimizer's attribute-aware simplifiers from
npm at each attribute weight), `ddsimp_report reduce` runs the reduction in a fresh process and
prints its measurements. This script gathers them into results.csv, writes
report.md with the tables and the goals checked, and the plots; with --scaling it times the
simplifiers on surfaces of growing size (scaling.csv, time-vs-size.png). Rendered images come from
render.py (run under Xvfb by run.sh). Needs python3-matplotlib; the attribute-aware peers need node
and `npm ci` in bench/report (run.sh does it), else they are left out and the report says why.
With --baseline (the results.csv of an earlier report) the goals are also counted on it, before
and after, for the section that says what a library change gained; --notes adds a Markdown file
(what was changed) to that section.
"""

import argparse
import csv
import datetime
import json
import math
import os
import platform
import shutil
import subprocess
import sys
import time

from goals import (DDSIMP, FLOAT_NOISE, GOAL_LEVEL, GOAL_LEVELS, HAUSDORFF_GOAL,
                   NODE_HAUSDORFF_FILTER, NODE_PEERS, PEERS, RENDER_SURFACE, WEIGHTS, check_goals,
                   fmt, goal_counts, label, losses_text, node_peer_choices, node_peer_text)

ALPHAS = [0.0, 0.5, 1.0]
LEVELS = [0.5, 0.25, 0.1, 0.05]
COLUMNS = [
    "surface", "simplifier", "alpha", "weight", "keep", "status", "message", "triangles_in",
    "target", "triangles_out", "triangles_seen", "seconds", "cpu_seconds", "runtime",
    "peak_rss_mb", "call_rss_mb",
    "geometric_rms", "geometric_hausdorff", "data_rms", "data_max", "fields_lost", "topology_kept",
    "euler_in", "euler_out", "boundary_loops_in", "boundary_loops_out", "components_in",
    "components_out", "nonmanifold_edges_in", "nonmanifold_edges_out",
]
SCALING_COLUMNS = ["surface", "simplifier", "alpha", "triangles_in", "target", "triangles_out",
                   "status", "message", "repetitions", "median_cpu_seconds", "peak_rss_mb"]


def configurations(node_peers=True):
    """(simplifier, alpha, weight) triples; alpha is None for the peers (they have none), weight
    None for all but the node peers."""
    out = [(d, a, None) for d in DDSIMP for a in ALPHAS] + [(p, None, None) for p in PEERS]
    if node_peers:
        out += [(p, None, w) for p in NODE_PEERS for w in WEIGHTS]
    return out


def node_peers_missing():
    """Why the node peers cannot run here, or None."""
    if not shutil.which("node"):
        return "node is not installed (Debian's nodejs)"
    if not os.path.exists(os.path.join(HERE, "node_modules", "meshoptimizer", "package.json")):
        return ("the npm package meshoptimizer is not installed in bench/report/node_modules "
                "(`npm ci` in bench/report installs it; bench/report/run.sh does)")
    return None


def node_peers_version():
    """'meshoptimizer 1.3.0 (npm) under node v20.x', for the report."""
    with open(os.path.join(HERE, "node_modules", "meshoptimizer", "package.json")) as f:
        version = json.load(f)["version"]
    node = subprocess.run(["node", "--version"], capture_output=True, text=True).stdout.strip()
    return f"meshoptimizer {version} (npm, WebAssembly) under node {node}"


HERE = os.path.dirname(os.path.abspath(__file__))


def run_one(tool, surface, simplifier, alpha, keep, timeout, output=None, compare=True,
            weight=None):
    """One reduction in its own process; a dict of its measurements (status says what happened)."""
    cmd = [tool, "reduce", surface, "--peer", simplifier, "--keep", str(keep)]
    if alpha is not None:
        cmd += ["--alpha", str(alpha)]
    if weight is not None:
        cmd += ["--weight", str(weight)]
    if output:
        cmd += ["-o", output]
    if not compare:
        cmd.append("--no-compare")
    try:
        done = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return {"status": "timeout", "message": f"no result within {timeout:.0f} s"}
    if done.returncode != 0 or not done.stdout.strip():
        last = (done.stderr.strip().splitlines() or ["no output"])[-1]
        how = (f"killed by signal {-done.returncode}" if done.returncode < 0
               else f"exit status {done.returncode}")
        return {"status": "crashed", "message": f"{how}: {last}"[:300]}
    return json.loads(done.stdout.strip().splitlines()[-1])


def row_of(surface, simplifier, alpha, keep, r, weight=None):
    t_in, t_out = r.get("topology_in", {}), r.get("topology_out", {})
    mb = lambda key: r[key] / 2**20 if key in r else None
    return {
        "surface": surface, "simplifier": simplifier,
        "alpha": "" if alpha is None else alpha, "weight": "" if weight is None else float(weight),
        "keep": keep,
        "status": r.get("status"), "message": r.get("message", ""),
        "triangles_in": r.get("triangles_in"), "target": r.get("target"),
        "triangles_out": r.get("triangles_out"), "triangles_seen": r.get("triangles_seen"),
        "seconds": r.get("seconds"), "cpu_seconds": r.get("cpu_seconds"),
        "runtime": r.get("runtime", ""), "peak_rss_mb": mb("peak_rss_bytes"), "call_rss_mb": mb("call_rss_bytes"),
        "geometric_rms": r.get("geometric_rms"), "geometric_hausdorff": r.get("geometric_hausdorff"),
        "data_rms": r.get("data_rms"), "data_max": r.get("data_max"),
        "fields_lost": " ".join(r.get("fields_lost", [])),
        "topology_kept": r.get("topology_kept"),
        "euler_in": t_in.get("euler"), "euler_out": t_out.get("euler"),
        "boundary_loops_in": t_in.get("boundary_loops"),
        "boundary_loops_out": t_out.get("boundary_loops"),
        "components_in": t_in.get("components"), "components_out": t_out.get("components"),
        "nonmanifold_edges_in": t_in.get("nonmanifold_edges"),
        "nonmanifold_edges_out": t_out.get("nonmanifold_edges"),
    }


def load_rows(path):
    """The rows of an earlier results.csv, typed like row_of's."""
    rows = []
    for r in csv.DictReader(open(path)):
        for k in ("keep", "data_rms", "geometric_hausdorff", "data_max", "geometric_rms"):
            r[k] = float(r[k]) if r[k] not in ("", None) else None
        r["alpha"] = float(r["alpha"]) if r["alpha"] not in ("", None) else ""
        r["weight"] = float(r["weight"]) if r.get("weight") not in ("", None) else ""
        r["topology_kept"] = r["topology_kept"] == "True"
        rows.append(r)
    return rows


# --- plots ------------------------------------------------------------------------------------

def plot_data_error(rows, out_dir, surfaces):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    n = len(surfaces)
    cols = min(4, n)
    nrows = math.ceil(n / cols)
    fig, axes = plt.subplots(nrows, cols, figsize=(4 * cols, 3.2 * nrows), squeeze=False)
    styles = {"ddsimp-edge": ("tab:blue", "o"), "ddsimp-vertex": ("tab:orange", "s"),
              "meshopt": ("tab:green", "^"), "vtk-quadric": ("tab:red", "v"),
              "vtk-decimatepro": ("tab:purple", "D"), "openmesh": ("tab:brown", "x"),
              "meshopt-attributes": ("tab:olive", "<"), "meshopt-update": ("tab:cyan", ">")}
    choices = node_peer_choices(rows)
    for ax, surface in zip(axes.flat, surfaces):
        for simplifier, alpha, weight in configurations():
            if alpha not in (None, 0.0) or weight not in (None, WEIGHTS[0]):
                continue  # ddsimp at alpha = 0 (data only); a node peer once, at its chosen weight
            if simplifier in NODE_PEERS:
                chosen = [c["chosen"] for (s, _, p), c in choices.items()
                          if s == surface and p == simplifier and c["chosen"]]
                pts = sorted((r["triangles_out"], r["data_rms"]) for r in chosen)
            else:
                pts = sorted((r["triangles_out"], r["data_rms"]) for r in rows
                             if r["surface"] == surface and r["simplifier"] == simplifier
                             and (alpha is None or r["alpha"] == alpha)
                             and r["data_rms"] is not None and r["triangles_out"])
            if not pts:
                continue
            colour, marker = styles[simplifier]
            name = simplifier + (" α=0" if alpha is not None else "")
            ax.plot([p[0] for p in pts], [p[1] for p in pts], marker=marker, color=colour,
                    label=name, linewidth=1, markersize=4)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(surface, fontsize=9)
        ax.set_xlabel("triangles", fontsize=8)
        ax.set_ylabel("data error RMS (of range)", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.grid(True, which="both", alpha=0.3)
    for ax in list(axes.flat)[n:]:
        ax.axis("off")
    handles, labels = axes.flat[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=8, fontsize=8)
    fig.tight_layout(rect=(0, 0.04, 1, 1))
    path = os.path.join(out_dir, "data-error-vs-triangles.png")
    fig.savefig(path, dpi=70)
    plt.close(fig)
    return path


def plot_scaling(scaling, out_dir):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for name in sorted({s["simplifier"] for s in scaling}):
        pts = sorted((s["triangles_in"], s["median_cpu_seconds"]) for s in scaling
                     if s["simplifier"] == name and s["median_cpu_seconds"] is not None
                     and s["status"] in ("ok", "not reached"))
        if pts:
            ax.plot([p[0] for p in pts], [p[1] for p in pts], marker="o", label=name)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("input triangles (carotid isosurfaces, resampled volume)")
    ax.set_ylabel("CPU seconds to 10% (median)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    path = os.path.join(out_dir, "time-vs-size.png")
    fig.savefig(path, dpi=80)
    plt.close(fig)
    return path


# --- the report -------------------------------------------------------------------------------

def write_report(rows, surfaces, goals, scaling, out_dir, quick, images, elapsed, baseline=None,
                 notes=None, node_note=""):
    commit = os.environ.get("DDSIMP_REPORT_COMMIT") or subprocess.run(
        ["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
        cwd=os.path.dirname(os.path.abspath(__file__))).stdout.strip()
    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo")
                if l.startswith("model name")), platform.processor())
    load = open("/proc/loadavg").read().split()[:3]
    L = []
    L.append("# ddsimp against its peers: fidelity and speed\n")
    L.append(f"Generated {datetime.date.today()} at commit {commit or 'unknown'} on "
             f"{os.cpu_count()} × {cpu} (load average {' '.join(load)} at the end), "
             f"{'quick mode, ' if quick else ''}in {elapsed / 60:.1f} min by "
             "`bench/report/run.sh" + (" --quick" if quick else "") + "`.\n")
    L.append("Every reduction ran in its own process (`ddsimp_report reduce`); time is the "
             "CPU time (user + system) of the simplifier's call on the loaded surface, one thread, "
             "since the machine may be shared (results.csv also has the wall clock), conversion to "
             "and from a peer's own mesh type included (for ddsimp: its validation and adjacency), memory the process's peak RSS "
             "(`ru_maxrss`, loaded surface included) and the rise of the RSS during the call. "
             "Errors are measured by the same code for every simplifier (`ddsimp/io/compare.h`, as "
             "`ddsimp compare`): geometric RMS and Hausdorff distance both ways, relative to the "
             "bounding-box diagonal; data error RMS and max at the closest points, relative to the "
             "field's range, of the worst field. Topology kept: Euler characteristic, boundary "
             "loops and components equal to the input's, no new non-manifold edge, no degenerate "
             "or duplicate triangle. A run counts only if its status is `ok` (it reached the "
             "target within 2% and reported no error); the others are listed, not hidden.\n")
    L.append(f"meshoptimizer's attribute-aware simplifiers: {node_note}. `meshopt-attributes` "
             "(simplifyWithAttributes) keeps a subset of the input's vertices, as vertex removal "
             "does; `meshopt-update` (simplifyWithUpdate) moves positions and data to their "
             "least-error values, as edge collapse does, and its moved data values are the "
             "output's. Their attributes are the continuous fields, each scaled by its range as "
             "the data error is measured (a vector field's components by the diagonal of their "
             "bounding box), every component with the same weight w, swept over "
             f"{', '.join(map(str, WEIGHTS))}; no vertex lock, no flags, no error bound. Of the "
             "weights, the one that counts at a level has the least data RMS among those whose "
             f"Hausdorff distance is at most {NODE_HAUSDORFF_FILTER:g}× ddsimp's at α = 0 (the "
             "better strategy's); for the Hausdorff goal the least Hausdorff over the weights "
             "counts. Their time is the WebAssembly call's as node measures it (marked wasm), "
             "their memory node's peak.\n")
    if RUNS["reused"]:
        L.append(f"{RUNS['reused']} of {RUNS['all']} results were read from the cache of earlier "
                 "invocations (`--resume`, `OUT/runs`); the time above is the sum over the invocations "
                 "that used this cache. The notes below, if any, say where the results came from.\n")
    if baseline is not None or notes:
        L.append("## What changed in the library, and what it gained\n")
        if notes:
            L.append(open(notes).read().strip() + "\n")
        if baseline is not None:
            before, after = goal_counts(check_goals(baseline)), goal_counts(goals)
            L.append("| goal at 10% and 5% | before | after |")
            L.append("|---|---|---|")
            for key, name in [("all", "both strategies"), ("ddsimp-edge", "edge collapse"),
                              ("ddsimp-vertex", "vertex removal")]:
                b, a = before[key], after[key]
                L.append(f"| data RMS at α=0 lowest ({name}) | {b[0]} of {b[2]} | "
                         f"{a[0]} of {a[2]} |")
                L.append(f"| Hausdorff at α=1 within {HAUSDORFF_GOAL}× ({name}) | "
                         f"{b[1]} of {b[2]} | {a[1]} of {a[2]} |")
            L.append("")

    levels = sorted({g["level"] for g in goals}, reverse=True)
    L.append(f"## Goals at {' and '.join(f'{l:.0%}' for l in levels)} of the triangles\n")
    L.append("| surface | level | strategy | data RMS at α=0 | best peer (data RMS) | data goal | "
             "topology | Hausdorff at α=1 | best peer (Hausdorff) | ratio | Hausdorff goal | "
             "peers not counted |")
    L.append("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for g in goals:
        d0, d1, bd, bh = g["d0"], g["d1"], g["best_data"], g["best_hd"]
        ratio = (d1["geometric_hausdorff"] / bh["geometric_hausdorff"]
                 if d1 and bh and d1.get("geometric_hausdorff") is not None
                 and bh["geometric_hausdorff"] > FLOAT_NOISE else None)
        nc = ", ".join(f"{p['simplifier']} ({p['status']})" for p in g["not_counted"]) or "—"
        L.append("| {} | {:.0%} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |".format(
            g["surface"], g["level"], g["strategy"].replace("ddsimp-", ""),
            fmt(d0 and d0["data_rms"]), f"{label(bd)} {fmt(bd['data_rms'])}" if bd else "—",
            "**met**" if g["data_ok"] else "**missed**",
            "kept" if d0 and d0["topology_kept"] else "changed",
            fmt(d1 and d1["geometric_hausdorff"]),
            f"{label(bh)} {fmt(bh['geometric_hausdorff'])}" if bh else "—",
            fmt(ratio, 3), "**met**" if g["hd_ok"] else "**missed**", nc))
    met_d = sum(g["data_ok"] for g in goals)
    met_h = sum(g["hd_ok"] for g in goals)
    L.append(f"\nData goal met in {met_d} of {len(goals)} (surface, level, strategy) triples; "
             f"Hausdorff goal in {met_h} of {len(goals)}.\n")
    L.append("## Where ddsimp still loses, and why\n")
    L += losses_text(goals, surfaces)
    L.append("")
    choices = node_peer_choices(rows)
    if choices:
        L.append("## meshoptimizer's attribute-aware simplifiers, weight by weight\n")
        L += node_peer_text(choices, lambda s, k: [r for r in rows if r["surface"] == s
                                                   and r["keep"] == k])
        L.append("")

    L.append("## Peers: topology and failures\n")
    L.append("| simplifier | runs | ok | not reached | failed / crashed / timeout | not run "
             "(budget) | topology kept (of runs with output) | what went wrong (first) |")
    L.append("|---|---|---|---|---|---|---|---|")
    for name in DDSIMP + PEERS + NODE_PEERS:
        rs = [r for r in rows if r["simplifier"] == name]
        if not rs:
            continue
        bad = [r for r in rs if r["status"] in ("failed", "crashed", "timeout")]
        with_out = [r for r in rs if r["topology_kept"] is not None]
        msg = next((f"{r['surface']}: {r['message']}" for r in rs
                    if r["status"] not in ("ok", "not run") and r["message"]), "")
        L.append(f"| {name} | {len(rs)} | {sum(r['status'] == 'ok' for r in rs)} | "
                 f"{sum(r['status'] == 'not reached' for r in rs)} | {len(bad)} | "
                 f"{sum(r['status'] == 'not run' for r in rs)} | "
                 f"{sum(bool(r['topology_kept']) for r in with_out)} / {len(with_out)} | "
                 f"{msg[:160]} |")
    L.append("")

    if scaling:
        L.append("## Time against input size (10%, carotid isosurfaces)\n")
        sizes = sorted({s["triangles_in"] for s in scaling if s["triangles_in"]})
        names = sorted({s["simplifier"] for s in scaling})
        L.append("| simplifier | " + " | ".join(f"{n:,}" for n in sizes) + " |")
        L.append("|---|" + "---|" * len(sizes))
        for name in names:
            cells = []
            for n in sizes:
                s = next((s for s in scaling if s["simplifier"] == name
                          and s["triangles_in"] == n), None)
                if not s:
                    cells.append("—")
                elif s["status"] in ("ok", "not reached") and s["median_cpu_seconds"] is not None:
                    extra = "" if s["status"] == "ok" else f" (stops at {s['triangles_out'] / n:.0%})"
                    cells.append(f"{s['median_cpu_seconds']:.2f} s{extra}")
                else:
                    cells.append(s["status"])
            L.append(f"| {name} | " + " | ".join(cells) + " |")
        L.append("\nMedian CPU seconds of the simplifier's call (repetitions: 3 below 200 k "
                 "triangles, 1 above); ddsimp at α = 0.5. ![time against size](time-vs-size.png)\n")

    L.append("## Plots and images\n")
    L.append("![data error against triangles](data-error-vs-triangles.png)\n")
    for caption, path in images:
        L.append(f"![{caption}]({os.path.basename(path)})\n")

    L.append("## Every surface and level\n")
    for surface in surfaces:
        rs = [r for r in rows if r["surface"] == surface]
        L.append(f"### {surface} ({fmt(rs[0]['triangles_in'])} triangles)\n")
        L.append("| simplifier | keep | status | triangles | CPU s | peak MB | geo RMS | Hausdorff | "
                 "data RMS | data max | topology |")
        L.append("|---|---|---|---|---|---|---|---|---|---|---|")
        for r in rs:
            topo = ("kept" if r["topology_kept"] else
                    "—" if r["topology_kept"] is None else
                    f"χ {r['euler_in']}→{r['euler_out']}, loops {r['boundary_loops_in']}→"
                    f"{r['boundary_loops_out']}, comp. {r['components_in']}→{r['components_out']}, "
                    f"nm {r['nonmanifold_edges_in']}→{r['nonmanifold_edges_out']}")
            status = r["status"] + (f": {r['message']}" if r["message"] else "")
            wasm = " (wasm)" if r.get("runtime") == "wasm" else ""
            L.append(f"| {label(r)} | {r['keep']:g} | {status[:120]} | {fmt(r['triangles_out'])} | "
                     f"{fmt(r['cpu_seconds'], 3)}{wasm} | {fmt(r['peak_rss_mb'], 4)} | "
                     f"{fmt(r['geometric_rms'], 3)} | {fmt(r['geometric_hausdorff'], 3)} | "
                     f"{fmt(r['data_rms'], 3)} | {fmt(r['data_max'], 3)} | {topo} |")
        L.append("")
    with open(os.path.join(out_dir, "report.md"), "w") as f:
        f.write("\n".join(L) + "\n")


RUNS = {"all": 0, "reused": 0}  # runs asked for, and those taken from the cache (--resume)


def run_key(surface, simplifier, alpha, level, weight=None):
    """A run's name in the cache: `level` is the keep fraction, or a scaling run's repetition;
    alpha is None for a peer, weight None for all but the node peers (reuse.py writes the cache
    under the same names)."""
    if weight is not None:
        return f"{surface}__{simplifier}__w{float(weight):g}__{level}"
    return f"{surface}__{simplifier}__{alpha}__{level}"


def cached_run(cache_dir, key, deadline, run):
    """run() unless its result is cached (an interrupted report resumes) or the budget is spent."""
    path = os.path.join(cache_dir, key + ".json")
    RUNS["all"] += 1
    if os.path.exists(path):
        RUNS["reused"] += 1
        with open(path) as f:
            return json.load(f)
    if deadline and time.time() > deadline:
        return {"status": "not run", "message": "time budget spent"}
    r = run()
    with open(path + ".partial", "w") as f:
        json.dump(r, f)
    os.replace(path + ".partial", path)
    return r


def surface_sizes(directory, names):
    """Triangle counts from the surfaces' .vtp headers (NumberOfPolys), to order the work."""
    sizes = {}
    for name in names:
        with open(os.path.join(directory, name + ".vtp"), "rb") as f:
            head = f.read(4096).decode("latin-1")
        found = head.split('NumberOfPolys="', 1)
        sizes[name] = int(found[1].split('"', 1)[0]) if len(found) > 1 else 0
    return sizes


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--build", required=True)
    ap.add_argument("--surfaces", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--quick", action="store_true", help="one level (10%%), 60 s per run at most")
    ap.add_argument("--scaling", help="directory of the scaling surfaces (scale-*.vtp)")
    ap.add_argument("--render-surface", default=RENDER_SURFACE,
                    help="surface whose reductions at 10%% are written for render.py")
    ap.add_argument("--budget-minutes", type=float,
                    help="start no run after this; the rest is reported as 'not run'")
    ap.add_argument("--baseline", help="results.csv of an earlier report: goals before and after")
    ap.add_argument("--notes", help="Markdown file: what changed in the library since the baseline")
    ap.add_argument("--resume", action="store_true",
                    help="reuse the results of an earlier (interrupted) run in OUT/runs")
    args = ap.parse_args()

    tool = os.path.join(args.build, "bench", "report", "ddsimp_report")
    meshes = os.path.join(args.out, "meshes")
    cache = os.path.join(args.out, "runs")
    if not args.resume:
        shutil.rmtree(cache, ignore_errors=True)
    os.makedirs(meshes, exist_ok=True)
    os.makedirs(cache, exist_ok=True)
    levels = [GOAL_LEVEL] if args.quick else LEVELS
    timeout = 60 if args.quick else 600
    start = time.time()
    deadline = start + 60 * args.budget_minutes if args.budget_minutes else None
    names = [f[:-4] for f in os.listdir(args.surfaces) if f.endswith(".vtp")
             and not f.endswith(".partial.vtp") and not f.startswith("scale-")]
    sizes = surface_sizes(args.surfaces, names)
    names.sort(key=lambda n: (sizes[n], n))
    missing = node_peers_missing()
    if missing:
        node_note = "not run: " + missing
        print(f"report.py: meshoptimizer's attribute-aware peers left out: {missing}",
              file=sys.stderr)
    else:
        node_note = node_peers_version()
    configs = configurations(node_peers=not missing)

    def reduce(surface, keep, simplifier, alpha, weight):
        out_mesh = None
        if (surface == args.render_surface and keep == GOAL_LEVEL and alpha in (None, 0.0)
                and weight is None):
            out_mesh = os.path.join(meshes, f"{surface}-{simplifier}.vtp")
        key = run_key(surface, simplifier, alpha, keep, weight)
        r = cached_run(cache, key, deadline,
                       lambda: run_one(tool, os.path.join(args.surfaces, surface + ".vtp"),
                                       simplifier, alpha, keep, timeout, out_mesh, weight=weight))
        print(f"{surface} {keep:g} {simplifier} {alpha} {weight}: {r.get('status')} "
              f"{r.get('triangles_out', '')} {r.get('seconds', 0):.2f}s data "
              f"{r.get('data_rms', '—')}", file=sys.stderr, flush=True)
        return row_of(surface, simplifier, alpha, keep, r, weight)

    def scale(path, simplifier):
        alpha = 0.5 if simplifier in DDSIMP else None
        runs = []
        for rep in range(3):
            key = run_key(os.path.basename(path)[:-4], simplifier, alpha, rep)
            r = cached_run(cache, key, deadline,
                           lambda: run_one(tool, path, simplifier, alpha, GOAL_LEVEL, 420,
                                           compare=False))
            runs.append(r)
            if r.get("status") not in ("ok", "not reached") or r.get("triangles_in", 0) > 200_000:
                break
        times = sorted(r["cpu_seconds"] for r in runs if "cpu_seconds" in r)
        last = runs[-1]
        s = {"surface": os.path.basename(path)[:-4], "simplifier": simplifier,
             "alpha": "" if alpha is None else alpha,
             "triangles_in": last.get("triangles_in"), "target": last.get("target"),
             "triangles_out": last.get("triangles_out"), "status": last.get("status"),
             "message": last.get("message", ""), "repetitions": len(times),
             "median_cpu_seconds": times[len(times) // 2] if times else None,
             "peak_rss_mb": last["peak_rss_bytes"] / 2**20 if "peak_rss_bytes" in last else None}
        print(f"scaling {s['surface']} {simplifier}: {s['status']} {s['median_cpu_seconds']}",
              file=sys.stderr, flush=True)
        return s

    # Most important first, so that a spent budget leaves out the least: every surface at the
    # goal levels, then the scaling, then the other levels.
    results = {}
    for keep in (l for l in GOAL_LEVELS if l in levels):
        for surface in names:
            for config in configs:
                results[(surface, keep) + config] = reduce(surface, keep, *config)
    scaling = []
    if args.scaling:
        files = [f[:-4] for f in os.listdir(args.scaling) if f.startswith("scale-")
                 and f.endswith(".vtp") and not f.endswith(".partial.vtp")]
        scale_sizes = surface_sizes(args.scaling, files)
        for f in sorted(files, key=lambda n: scale_sizes[n]):
            for simplifier in DDSIMP + PEERS:
                scaling.append(scale(os.path.join(args.scaling, f + ".vtp"), simplifier))
    for surface in names:
        for keep in levels:
            for config in configs:
                if (surface, keep) + config not in results:
                    results[(surface, keep) + config] = reduce(surface, keep, *config)
    rows = [results[(s, k) + c] for s in names for k in levels for c in configs]

    with open(os.path.join(args.out, "results.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=COLUMNS)
        w.writeheader()
        for r in rows:
            w.writerow({k: ("" if r[k] is None else r[k]) for k in COLUMNS})
    if scaling:
        with open(os.path.join(args.out, "scaling.csv"), "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=SCALING_COLUMNS)
            w.writeheader()
            for s in scaling:
                w.writerow({k: ("" if s[k] is None else s[k]) for k in SCALING_COLUMNS})
        plot_scaling(scaling, args.out)

    plot_data_error(rows, args.out, names)
    goals = check_goals(rows)
    images = []
    if not args.quick:
        picture = os.path.join(args.out, f"{args.render_surface}-10pct.png")
        images.append((f"{args.render_surface} at 10%, coloured by its data", picture))
    # Time spent on this report over all its sessions (an interrupted run resumed counts both).
    spent_file = os.path.join(cache, "elapsed-seconds")
    spent = time.time() - start
    if os.path.exists(spent_file):
        spent += float(open(spent_file).read())
    with open(spent_file, "w") as f:
        f.write(f"{spent:.0f}\n")
    baseline = load_rows(args.baseline) if args.baseline else None
    write_report(rows, names, goals, scaling, args.out, args.quick, images, spent, baseline,
                 args.notes, node_note)
    print(f"report.py: wrote {args.out}/report.md, results.csv", file=sys.stderr)


if __name__ == "__main__":
    main()
