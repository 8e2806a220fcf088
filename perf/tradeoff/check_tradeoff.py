#!/usr/bin/env python3
"""Checks a perf/tradeoff CSV (the --quick ctests): the columns are there, every cost and error is
finite and non-negative, the reference (error 0 in double) is the finest level of its sweep, and
in double the error falls strictly from the coarsest to the finest level of each sweep.

    check_tradeoff.py CSV --error COLUMN --parameter SWEEP:COLUMN[:desc] ... [--columns a,b,...]

Levels are ordered by COLUMN ascending (finest = largest, e.g. N_v), or descending with ":desc"
(finest = smallest, e.g. the time-step factor). A sweep given as SWEEP:COLUMN:ORDER:noise is one
whose effect is expected below the statistical error of a stochastic observable (the hopper's Q
over Δt): there every error must instead lie within 4 of its error_sigma column. A sweep given as
SWEEP:COLUMN:ORDER:resolved is one with a real effect whose intermediate levels may lie within the
noise of one another (the DP hopper's Q over K_b): there only the coarsest level's error must
exceed 3 × its error_sigma. Exit status 1 naming the first failure.
"""
import argparse
import csv
import math
import sys


def fail(msg):
    print(f"check_tradeoff: FAIL: {msg}", file=sys.stderr)
    sys.exit(1)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv")
    ap.add_argument("--error", required=True)
    ap.add_argument("--parameter", action="append", required=True)
    ap.add_argument("--columns", default="sweep,precision,wall_s,cpu_s,wall_per_t0,cpu_per_t0")
    a = ap.parse_args()
    with open(a.csv, newline="") as f:
        reader = csv.DictReader(f)
        rows = list(reader)
        header = reader.fieldnames or []
    sweeps = [p.split(":") for p in a.parameter]
    needed = a.columns.split(",") + [a.error] + [s[1] for s in sweeps]
    for c in needed:
        if c not in header:
            fail(f"{a.csv} has no column {c} (has {', '.join(header)})")
    for r in rows:
        for c in ("wall_per_t0", "cpu_per_t0", a.error):
            v = float(r[c])
            if not (math.isfinite(v) and v >= 0):
                fail(f"{c} = {r[c]} in row {r}")
        if not float(r["cpu_per_t0"]) > 0:
            fail(f"zero cost in row {r}")
    for spec in sweeps:
        sweep, column = spec[0], spec[1]
        descending = len(spec) > 2 and spec[2] == "desc"
        for precision in ("double", "float"):
            if not any(r["sweep"] == sweep and r["precision"] == precision for r in rows):
                fail(f"no {precision} rows in sweep {sweep}")
        d = [r for r in rows if r["sweep"] == sweep and r["precision"] == "double"]
        d.sort(key=lambda r: float(r[column]), reverse=descending)
        if len(d) < 3:
            fail(f"sweep {sweep}: {len(d)} levels in double, need >= 3")
        if float(d[-1][a.error]) != 0:
            fail(f"sweep {sweep}: the finest level {column} = {d[-1][column]} is not the reference (error 0)")
        errors = [float(r[a.error]) for r in d[:-1]]
        if len(spec) > 3 and spec[3] == "noise":
            for r in d[:-1]:
                if not float(r[a.error]) <= 4 * float(r["error_sigma"]):
                    fail(f"sweep {sweep}: {column} = {r[column]}: error {r[a.error]} exceeds 4 × its statistical "
                         f"error {r['error_sigma']}")
            print(f"check_tradeoff: {sweep}: double errors {', '.join(f'{e:.3g}' for e in errors)} within 4σ")
            continue
        if len(spec) > 3 and spec[3] == "resolved":
            coarse = d[0]
            if not float(coarse[a.error]) > 3 * float(coarse["error_sigma"]):
                fail(f"sweep {sweep}: the coarsest level {column} = {coarse[column]} has error {coarse[a.error]}, "
                     f"not above 3 × its statistical error {coarse['error_sigma']}: the sweep resolves nothing")
            print(f"check_tradeoff: {sweep}: coarsest error {float(coarse[a.error]):.3g} > 3 × its σ "
                  f"{float(coarse['error_sigma']):.3g}")
            continue
        for k in range(len(errors) - 1):
            if not errors[k] > errors[k + 1]:
                fail(f"sweep {sweep}: the error does not fall from {column} = {d[k][column]} ({errors[k]:.4g}) "
                     f"to {d[k + 1][column]} ({errors[k + 1]:.4g})")
        if not errors[-1] > 0:
            fail(f"sweep {sweep}: the second-finest level has error 0: the sweep does not resolve anything")
        print(f"check_tradeoff: {sweep}: double errors {', '.join(f'{e:.3g}' for e in errors)} fall from coarse to fine")
    print("check_tradeoff: OK")


if __name__ == "__main__":
    main()
