#!/usr/bin/python3
"""bench/report/reuse.py on the committed report: every reused result, read back the way report.py
reads its cache (row_of), must give its results.csv row again, field for field, and exactly the
rows a --rerun matches (and the rendered earth runs) must be left to run.

    check_report_reuse.py REPORT_DIR (bench/report: reuse.py, report.py and latest/) OUT_DIR
"""

import csv
import io
import json
import os
import shutil
import subprocess
import sys

report_dir, out = sys.argv[1], sys.argv[2]
sys.path.insert(0, report_dir)
import report  # noqa: E402  (row_of, run_key and the CSV columns: how the report reads its cache)

latest = os.path.join(report_dir, "latest")
shutil.rmtree(out, ignore_errors=True)
subprocess.run([sys.executable, os.path.join(report_dir, "reuse.py"), latest, out,
                "--rerun", "simplifier=ddsimp-edge alpha=0.5,1.0",
                "--rerun", "surface=scale-* simplifier=meshopt keep=scaling"], check=True)
runs = os.path.join(out, "runs")
failures = []


def as_csv(row, columns):
    """The row as report.py writes it and csv reads it back (None as "")."""
    text = io.StringIO()
    w = csv.DictWriter(text, fieldnames=columns)
    w.writeheader()
    w.writerow({k: "" if row[k] is None else row[k] for k in columns})
    return next(csv.DictReader(io.StringIO(text.getvalue())))


expected_files = set()
with open(os.path.join(latest, "results.csv"), newline="") as f:
    rows = list(csv.DictReader(f))
for row in rows:
    alpha = None if row["alpha"] == "" else float(row["alpha"])
    weight = None if row.get("weight", "") == "" else float(row["weight"])
    key = report.run_key(row["surface"], row["simplifier"], alpha, float(row["keep"]),
                         weight) + ".json"
    rerun = (row["simplifier"] == "ddsimp-edge" and row["alpha"] in ("0.5", "1.0")) or (
        row["surface"] == "earth" and row["keep"] == "0.1" and row["alpha"] in ("", "0.0")
        and weight is None)
    path = os.path.join(runs, key)
    if rerun:
        if os.path.exists(path):
            failures.append(f"{key}: cached, but its run must be made again")
        continue
    expected_files.add(key)
    if not os.path.exists(path):
        failures.append(f"{key}: not cached")
        continue
    with open(path) as j:
        again = report.row_of(row["surface"], row["simplifier"], alpha, float(row["keep"]),
                              json.load(j), weight)
    again = as_csv(again, report.COLUMNS)
    for column in report.COLUMNS:  # a column an older report has not is empty
        if again[column] != row.get(column, ""):
            failures.append(f"{key}: {column} {again[column]!r}, the report has "
                            f"{row.get(column)!r}")

with open(os.path.join(latest, "scaling.csv"), newline="") as f:
    for row in csv.DictReader(f):
        if row["simplifier"] == "meshopt" or row["simplifier"] == "ddsimp-edge":
            continue  # both --reruns match (ddsimp's scaling runs are at alpha 0.5)
        alpha = None if row["alpha"] == "" else float(row["alpha"])
        for rep in range(max(1, int(row["repetitions"]))):
            key = report.run_key(row["surface"], row["simplifier"], alpha, rep) + ".json"
            expected_files.add(key)
            path = os.path.join(runs, key)
            if not os.path.exists(path):
                failures.append(f"{key}: not cached")
                continue
            with open(path) as j:
                r = json.load(j)
            if r.get("cpu_seconds") != (float(row["median_cpu_seconds"])
                                        if row["median_cpu_seconds"] else None):
                failures.append(f"{key}: cpu_seconds {r.get('cpu_seconds')}, the report has "
                                f"{row['median_cpu_seconds']}")
            # a run that crashed or timed out has no triangles_out
            if r.get("triangles_out") != (int(row["triangles_out"]) if row["triangles_out"]
                                          else None):
                failures.append(f"{key}: triangles_out {r.get('triangles_out')}")

extra = set(os.listdir(runs)) - expected_files
if extra:
    failures.append(f"cached but not expected: {sorted(extra)[:5]}")
if len(expected_files) < 400:
    failures.append(f"only {len(expected_files)} results expected: is latest/ complete?")
for line in failures[:20]:
    print("FAIL", line)
print(f"{len(expected_files)} cached results checked, {len(failures)} failures")
sys.exit(1 if failures else 0)
