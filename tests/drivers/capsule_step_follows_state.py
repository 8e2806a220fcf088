#!/usr/bin/python3
"""The capsule driver's step follows the state (capsule.cpp, "Time step").

A small constriction run (Π = 6, level-1 mesh, Re = 0.2, c0 = 100 U: the acoustic limit C_c h/c
binds at the start, and the flow raises the largest sound speed within the first sample):
  automatic step: the series' dt starts at the smallest starting limit, never rises, and at every
    sample is the smaller of the previous sample's dt and the previous sample's running limits (the
    smallest of the five limit columns); it is lowered at least once, and standard error says so
    once, naming the largest sound speed. Samples stay --sample-every apart to within one step.
  the same run with --dt at the starting limit: dt stays what was given, and one warning names the
    term and the limit that fell below it.

usage: capsule_step_follows_state.py <capsule executable> <work dir>
"""
import csv
import os
import subprocess
import sys

exe, work = sys.argv[1], sys.argv[2]
os.makedirs(work, exist_ok=True)
sample = 0.02
base = [exe, "--threads", "2", "--resolution", "6", "--level", "1", "--eta", "0.5", "--ca", "0.25", "--c0", "100",
        "--reynolds", "0.2", "--t-max", "0.2", "--sample-every", str(sample)]
limit_columns = ["limit_viscous", "limit_acoustic", "limit_force", "limit_acoustic_viscous", "limit_bond"]


def run(name, extra):
    out = os.path.join(work, name + ".h5")
    p = subprocess.run(base + ["--output", out] + extra, check=True, capture_output=True, text=True)
    with open(os.path.join(work, name + "_ca0.25_eta0.5_series.csv")) as f:
        rows = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]
    assert len(rows) >= 8, len(rows)
    return rows, p.stderr


rows, err = run("automatic", [])
dt = [r["dt"] for r in rows]
limit = [min(r[c] for c in limit_columns) for r in rows]
assert abs(dt[0] - limit[0]) <= 1e-12 * dt[0], (dt[0], limit[0])
for k in range(1, len(rows)):
    expected = min(dt[k - 1], limit[k - 1])
    assert abs(dt[k] - expected) <= 1e-12 * expected, (k, dt[k], dt[k - 1], limit[k - 1])
    gap = rows[k]["time"] - rows[k - 1]["time"]
    assert abs(gap - sample) <= dt[k - 1] + 1e-12, (k, gap)
assert dt[-1] < dt[0], dt
lowered = [line for line in err.splitlines() if "the step follows the stability limit" in line]
assert len(lowered) == 1 and "largest sound speed c" in lowered[0], err
print(f"automatic: dt {dt[0]:.6g} -> {dt[-1]:.6g} d/U over {len(rows)} samples")

given = dt[0]
rows, err = run("given", ["--dt", repr(given)])
assert all(r["dt"] == rows[0]["dt"] for r in rows), [r["dt"] for r in rows]
assert abs(rows[0]["dt"] - given) <= 1e-12 * given, (rows[0]["dt"], given)
warnings = [line for line in err.splitlines() if line.startswith("warning: capsule:")]
assert len(warnings) == 1 and "largest sound speed c" in warnings[0] and "--dt" in warnings[0], err
print("given --dt: kept, one warning:", warnings[0])
