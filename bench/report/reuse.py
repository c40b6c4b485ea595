#!/usr/bin/python3
"""Seeds a report's cache from an earlier report, so that only the runs a change affects run again.

    reuse.py EARLIER_DIR OUT_DIR [--rerun SPEC]...
    bench/report/run.sh --resume --out OUT_DIR

EARLIER_DIR holds an earlier report's results.csv and scaling.csv (bench/report/latest is the
committed one). Every row becomes a cached result in OUT_DIR/runs, the cache that
`run.sh --resume` reads (report.py: cached_run), except the rows that a --rerun SPEC matches and
report.py's RENDER_SURFACE at GOAL_LEVEL with α = 0 and the peers, whose reductions render.py
draws (only a run writes them). A SPEC is space-separated FIELD=VALUE,VALUE... with FIELD one of
surface, simplifier, alpha (empty for a peer), weight (empty but for meshoptimizer's
attribute-aware peers) and keep ("scaling" for a scaling point); a row
matches when every field named has one of its values ("*" ends a value as a prefix). Example, a
change to edge collapse at α > 0:

    reuse.py bench/report/latest /tmp/report --rerun 'simplifier=ddsimp-edge alpha=0.5,1.0'

Use it only for rows whose output the change leaves byte for byte as it was (compare reference
outputs before and after, as changes.md describes for each version); their times are the earlier
report's, from another day. A scaling point's repetitions each carry its median (the CSV keeps no
more), so its median is unchanged.
"""

import argparse
import csv
import json
import os
import sys

import report  # run_key, GOAL_LEVEL, RENDER_SURFACE: the cache's names and what is rendered

MEASURED = ["seconds", "cpu_seconds", "geometric_rms", "geometric_hausdorff", "data_rms", "data_max"]
COUNTED = ["triangles_in", "target", "triangles_out", "triangles_seen"]
TOPOLOGY = ["euler", "boundary_loops", "components", "nonmanifold_edges"]


def parse_spec(text):
    spec = {}
    for part in text.split():
        field, _, values = part.partition("=")
        if field not in ("surface", "simplifier", "alpha", "weight", "keep"):
            sys.exit(f"reuse.py: unknown field '{field}' in --rerun '{text}'")
        spec[field] = values.split(",")
    return spec


def matches(spec, row):
    def one(value, wanted):
        return value.startswith(wanted[:-1]) if wanted.endswith("*") else value == wanted
    return all(any(one(row.get(f, ""), w) for w in wanted) for f, wanted in spec.items())


def number(text, kind=float):
    return None if text == "" else kind(float(text)) if kind is int else kind(text)


def cached_reduction(row):
    """The measurements `ddsimp_report reduce` printed for a results.csv row (what row_of reads)."""
    r = {"status": row["status"], "message": row["message"],
         "fields_lost": row["fields_lost"].split(), "runtime": row.get("runtime") or None}
    r.update({k: number(row[k], int) for k in COUNTED})
    r.update({k: number(row[k]) for k in MEASURED})
    if row["topology_kept"] != "":
        r["topology_kept"] = row["topology_kept"] == "True"
    for key in ("peak_rss", "call_rss"):
        if row[key + "_mb"] != "":
            r[key + "_bytes"] = round(float(row[key + "_mb"]) * 2**20)
    for side in ("in", "out"):
        r["topology_" + side] = {k: number(row[f"{k}_{side}"], int) for k in TOPOLOGY}
    return {k: v for k, v in r.items() if v is not None}


def cached_scaling(row):
    r = {"status": row["status"], "message": row["message"],
         "cpu_seconds": number(row["median_cpu_seconds"])}
    r.update({k: number(row[k], int) for k in ("triangles_in", "target", "triangles_out")})
    if row["peak_rss_mb"] != "":
        r["peak_rss_bytes"] = round(float(row["peak_rss_mb"]) * 2**20)
    return {k: v for k, v in r.items() if v is not None}


def alpha_of(text):
    return None if text == "" else float(text)


def rendered(row):
    """report.py writes the meshes of these runs for render.py, which only a run does."""
    return (row["surface"] == report.RENDER_SURFACE and float(row["keep"]) == report.GOAL_LEVEL
            and row["alpha"] in ("", "0.0") and row.get("weight", "") == "")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("earlier")
    ap.add_argument("out")
    ap.add_argument("--rerun", action="append", default=[], type=parse_spec)
    args = ap.parse_args()
    runs = os.path.join(args.out, "runs")
    os.makedirs(runs, exist_ok=True)

    def write(key, result):
        with open(os.path.join(runs, key + ".json"), "w") as f:
            json.dump(result, f)

    reused = rerun = 0
    with open(os.path.join(args.earlier, "results.csv"), newline="") as f:
        for row in csv.DictReader(f):
            if rendered(row) or any(matches(s, row) for s in args.rerun):
                rerun += 1
                continue
            write(report.run_key(row["surface"], row["simplifier"], alpha_of(row["alpha"]),
                                 float(row["keep"]), alpha_of(row.get("weight", ""))),
                  cached_reduction(row))
            reused += 1
    scaling = os.path.join(args.earlier, "scaling.csv")
    if os.path.exists(scaling):
        with open(scaling, newline="") as f:
            for row in csv.DictReader(f):
                if any(matches(s, dict(row, keep="scaling")) for s in args.rerun):
                    rerun += 1
                    continue
                for rep in range(max(1, int(row["repetitions"]))):  # 0: it failed, once
                    write(report.run_key(row["surface"], row["simplifier"],
                                         alpha_of(row["alpha"]), rep), cached_scaling(row))
                    reused += 1  # one result per repetition, as report.py counts them
    print(f"reuse.py: {reused} results from {args.earlier} in {runs}; {rerun} left to run",
          file=sys.stderr)


if __name__ == "__main__":
    main()
