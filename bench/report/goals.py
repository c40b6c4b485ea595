"""The report's goals, checked on its rows: which simplifiers it compares, which run counts, the
data-error goal at alpha = 0 and the Hausdorff goal at alpha = 1 (per surface, at 10% and 5%), the
weight of meshoptimizer's attribute-aware peers that counts, and where ddsimp still loses and why.
Used by report.py (which runs and writes) and reuse.py.
"""

PEERS = ["meshopt", "vtk-quadric", "vtk-decimatepro", "openmesh"]
DDSIMP = ["ddsimp-edge", "ddsimp-vertex"]
# npm's meshoptimizer under node (WebAssembly), one run per attribute weight; each is compared
# with the ddsimp strategy that works the same way (a subset of the vertices, or moved points).
NODE_PEERS = ["meshopt-attributes", "meshopt-update"]
WEIGHTS = [1, 2, 4, 8, 16, 32]
COUNTERPART = {"meshopt-attributes": "ddsimp-vertex", "meshopt-update": "ddsimp-edge"}
# Of a node peer's weights only those whose Hausdorff distance is within this factor of ddsimp's
# at alpha = 0 (the better strategy's) count: data error bought by dropping parts of the surface
# does not.
NODE_HAUSDORFF_FILTER = 1.5
MOVES_DATA = ["vtk-quadric", "meshopt-update"]  # the peers whose data values are new ones
GOAL_LEVEL = 0.1  # the level rendered and shown first
GOAL_LEVELS = [0.1, 0.05]  # the levels whose goals are checked
RENDER_SURFACE = "earth"  # default of --render-surface: its reductions at GOAL_LEVEL are drawn
HAUSDORFF_GOAL = 1.5  # alpha = 1: within this factor of the best peer
FLOAT_NOISE = 1e-6  # relative distances below this are float rounding, not error


def label(row):
    a, w = row["alpha"], row.get("weight")
    if w not in ("", None):
        return f"{row['simplifier']} w={float(w):g}"
    return row["simplifier"] if a in ("", None) else f"{row['simplifier']} α={float(a):g}"


def fmt(x, digits=4):
    if x is None or x == "":
        return "—"
    if isinstance(x, float):
        return f"{x:.{digits}g}" if abs(x) < 1e4 else f"{x:,.0f}"
    return f"{x:,}" if isinstance(x, int) else str(x)


def counts(row):
    """Usable for comparison: it ran, reached its target, and its errors were measured."""
    return row["status"] == "ok" and row["data_rms"] is not None


# --- goals ----------------------------------------------------------------------------------

def node_peer_choices(rows):
    """Per (surface, level, node peer): its runs over the weights, the best data error among
    them ("best"), the best among the weights whose Hausdorff distance is within
    NODE_HAUSDORFF_FILTER of ddsimp's at alpha = 0 ("chosen", the one that counts), the least
    Hausdorff distance ("best_hd") and that ddsimp reference ("reference")."""
    out = {}
    for surface, keep in sorted({(r["surface"], r["keep"]) for r in rows}):
        at = [r for r in rows if r["surface"] == surface and r["keep"] == keep]
        refs = [r["geometric_hausdorff"] for r in at
                if r["simplifier"] in DDSIMP and r["alpha"] == 0.0 and counts(r)]
        reference = min(refs) if refs else None
        for peer in NODE_PEERS:
            runs = [r for r in at if r["simplifier"] == peer]
            if not runs:
                continue
            usable = [r for r in runs if counts(r)]
            within = [r for r in usable if reference is not None and r["geometric_hausdorff"]
                      <= NODE_HAUSDORFF_FILTER * reference + FLOAT_NOISE]
            out[(surface, keep, peer)] = {
                "runs": runs, "reference": reference,
                "best": min(usable, key=lambda r: r["data_rms"], default=None),
                "chosen": min(within, key=lambda r: r["data_rms"], default=None),
                "best_hd": min(usable, key=lambda r: r["geometric_hausdorff"], default=None)}
    return out


def check_goals(rows):
    """Per surface and goal level: the data-error goal (alpha = 0) and the Hausdorff goal
    (alpha = 1). The node peers count with their chosen weight for data and their least
    Hausdorff distance for geometry."""
    out = []
    choices = node_peer_choices(rows)
    for surface in sorted({r["surface"] for r in rows}):
        for level in GOAL_LEVELS:
            at = [r for r in rows if r["surface"] == surface and r["keep"] == level]
            if not at:
                continue
            peers = [r for r in at if r["simplifier"] in PEERS]
            usable = [p for p in peers if counts(p)]
            not_counted = [p for p in peers if not counts(p)]
            data_rivals, hd_rivals = list(usable), list(usable)
            for peer in NODE_PEERS:
                c = choices.get((surface, level, peer))
                if not c:
                    continue
                if c["chosen"]:
                    data_rivals.append(c["chosen"])
                else:
                    not_counted.append({"simplifier": peer, "status": "no weight within "
                                        f"{NODE_HAUSDORFF_FILTER:g}× ddsimp's Hausdorff"
                                        if c["best"] else "no weight ok"})
                if c["best_hd"]:
                    hd_rivals.append(c["best_hd"])
            best_data = min(data_rivals, key=lambda p: p["data_rms"], default=None)
            best_hd = min(hd_rivals, key=lambda p: p["geometric_hausdorff"], default=None)
            for strategy in DDSIMP:
                d0 = next((r for r in at if r["simplifier"] == strategy and r["alpha"] == 0.0),
                          None)
                d1 = next((r for r in at if r["simplifier"] == strategy and r["alpha"] == 1.0),
                          None)
                g = {"surface": surface, "level": level, "strategy": strategy, "d0": d0, "d1": d1,
                     "best_data": best_data, "best_hd": best_hd, "not_counted": not_counted,
                     "data_losses": [p for p in data_rivals if d0 and counts(d0)
                                     and p["data_rms"] <= d0["data_rms"]]}
                g["data_ok"] = bool(d0 and counts(d0) and d0["topology_kept"] and
                                    all(d0["data_rms"] < p["data_rms"] for p in data_rivals))
                # Distances below FLOAT_NOISE (of the diagonal) are rounding: a plane stays a plane.
                g["hd_ok"] = bool(d1 and counts(d1) and (
                    best_hd is None or d1["geometric_hausdorff"]
                    <= HAUSDORFF_GOAL * best_hd["geometric_hausdorff"] + FLOAT_NOISE))
                out.append(g)
    return out


def goal_counts(goals):
    """(data goals met, Hausdorff goals met, pairs) over both strategies, and per strategy."""
    out = {"all": (sum(g["data_ok"] for g in goals), sum(g["hd_ok"] for g in goals), len(goals))}
    for strategy in DDSIMP:
        gs = [g for g in goals if g["strategy"] == strategy]
        out[strategy] = (sum(g["data_ok"] for g in gs), sum(g["hd_ok"] for g in gs), len(gs))
    return out


def node_peer_text(choices, level_rows):
    """The node peers' section: per surface and goal level, the best data error over the weights
    and the best within the Hausdorff filter, each with its weight."""
    def run(r):
        if not r:
            return "—"
        return (f"{fmt(r['data_rms'], 3)} (w={float(r['weight']):g}, Hausdorff "
                f"{fmt(r['geometric_hausdorff'], 3)}, topology "
                f"{'kept' if r['topology_kept'] else 'changed'})")
    L = ["| surface | level | peer | best data RMS over the weights | best within the filter "
         "(counts) | ddsimp Hausdorff α=0 | ddsimp counterpart data RMS α=0 | CPU s (wasm) |",
         "|---|---|---|---|---|---|---|---|"]
    for (surface, keep, peer), c in sorted(choices.items(), key=lambda kv: (kv[0][0], -kv[0][1],
                                                                             kv[0][2])):
        if keep not in GOAL_LEVELS:
            continue
        mine = next((r for r in level_rows(surface, keep) if r["simplifier"] == COUNTERPART[peer]
                     and r["alpha"] == 0.0), None)
        times = [r["cpu_seconds"] for r in c["runs"] if r["cpu_seconds"] is not None]
        L.append(f"| {surface} | {keep:.0%} | {peer} | {run(c['best'])} | {run(c['chosen'])} | "
                 f"{fmt(c['reference'], 3)} | {fmt(mine and mine['data_rms'], 3)} "
                 f"({COUNTERPART[peer].replace('ddsimp-', '')}) | "
                 f"{fmt(min(times), 3) + '–' + fmt(max(times), 3) if times else '—'} |")
    return L


def topology_change(r):
    return (f"χ {r['euler_in']}→{r['euler_out']}, boundary loops {r['boundary_loops_in']}→"
            f"{r['boundary_loops_out']}, components {r['components_in']}→{r['components_out']}, "
            f"non-manifold edges {r['nonmanifold_edges_in']}→{r['nonmanifold_edges_out']}")


def losses_text(goals, surfaces):
    """Per surface: every goal ddsimp misses, against whom, by how much, and what the winner did
    differently (moved data values where vertex removal keeps the input's, changed the topology,
    or neither)."""
    L = []
    for surface in surfaces:
        lines = []
        for g in (g for g in goals if g["surface"] == surface):
            strategy = g["strategy"].replace("ddsimp-", "")
            where = f"{g['level']:.0%}, {strategy}"
            d0 = g["d0"]
            if not g["data_ok"]:
                if not (d0 and counts(d0)):
                    lines.append(f"{where}: no usable ddsimp run at α = 0 "
                                 f"({d0['status'] if d0 else 'missing'}).")
                elif not d0["topology_kept"]:
                    lines.append(f"{where}: ddsimp changed the topology at α = 0.")
                for p in sorted(g["data_losses"], key=lambda p: p["data_rms"]):
                    why = []
                    if not p["topology_kept"]:
                        why.append("it changed the topology (" + topology_change(p) + ")")
                    if p["simplifier"] in MOVES_DATA:
                        why.append("it places new points with the data quadric's least-squares "
                                   "values" + ("; vertex removal keeps a subset of the input's "
                                               "values" if strategy == "vertex" else
                                               "; edge collapse chooses its point for the "
                                               "interpolated data and fits the data there "
                                               "afterwards"))
                    else:
                        why.append("it keeps a subset of the input's vertices and their "
                                   "values: its error measure chose them better than ddsimp's "
                                   "weights chose the " + ("removals" if strategy == "vertex"
                                                           else "collapses"))
                    hd = (p["geometric_hausdorff"] / d0["geometric_hausdorff"]
                          if d0["geometric_hausdorff"] > FLOAT_NOISE else None)
                    hd = (f"{hd:.2f}× ddsimp's" if hd else
                          f"{fmt(p['geometric_hausdorff'], 3)} of the diagonal")
                    lines.append(
                        f"{where}: data RMS {fmt(d0['data_rms'], 3)} against {label(p)}'s "
                        f"{fmt(p['data_rms'], 3)} (ddsimp ×{d0['data_rms'] / max(p['data_rms'], 1e-30):.3g}"
                        f"; its Hausdorff {hd}): " + "; ".join(why) + ".")
            if not g["hd_ok"] and g["d1"] and counts(g["d1"]) and g["best_hd"]:
                b = g["best_hd"]
                lines.append(f"{where}: Hausdorff at α = 1 {fmt(g['d1']['geometric_hausdorff'], 3)}"
                             f" against {label(b)}'s {fmt(b['geometric_hausdorff'], 3)} "
                             f"(topology {'kept' if b['topology_kept'] else 'changed'} by it).")
        L.append(f"- **{surface}**: " + ("every goal met." if not lines else lines[0]))
        L += [f"  - {line}" for line in lines[1:]] if len(lines) > 1 else []
    return L
