#!/usr/bin/env python3
"""Checks the SPH capsule trade-off output (perf/tradeoff/run_sph --quick, the ctest): the CSV holds
its columns, every run finished finite with finite costs, D_xy, errors and density deviations, each
sweep has float and double rows and its reference (double, finest level) has error 0, the JSON is
valid and names both references; and three properties that a broken run would fail:

  - the capsule deforms: D_xy over the window lies in (0.02, 0.6) (an undriven or uncoupled
    capsule stays at D_xy ≈ 0, a torn one runs off),
  - the fluid's largest density deviation falls as c0 rises, in each precision, by more than
    --min-ratio per step of the c0 sweep (weak compressibility: |ρ − ρ0|/ρ0 ~ (U/c0)²),
  - float and double agree: |D_float − D_double| < --float-tolerance at every setting.

    check_sph_tradeoff.py CSV JSON [--min-ratio 1.5] [--float-tolerance 0.005]

Exit status 1 naming the first failure.
"""
import argparse
import csv
import json
import math
import sys

COLUMNS = ("sweep,precision,resolution,c0_factor,c0,dt_gamma,particles,steps,shear_time,taylor_deformation,"
           "taylor_deformation_std,inclination_over_pi,error,rel_error,error_vs_double,max_density_deviation,"
           "max_density_deviation_fluid,mean_density_deviation_fluid,wall_s,cpu_s,wall_per_shear_time,"
           "cpu_per_shear_time,finite").split(",")
FINITE = ("c0", "dt_gamma", "taylor_deformation", "error", "rel_error", "error_vs_double", "max_density_deviation",
          "max_density_deviation_fluid", "mean_density_deviation_fluid", "wall_per_shear_time", "cpu_per_shear_time")


def fail(msg):
    print(f"check_sph_tradeoff: FAIL: {msg}", file=sys.stderr)
    sys.exit(1)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv")
    ap.add_argument("json")
    ap.add_argument("--min-ratio", type=float, default=1.5)
    ap.add_argument("--float-tolerance", type=float, default=0.005)
    a = ap.parse_args()
    with open(a.csv, newline="") as f:
        reader = csv.DictReader(f)
        rows = list(reader)
        header = reader.fieldnames or []
    for c in COLUMNS:
        if c not in header:
            fail(f"{a.csv} has no column {c} (has {', '.join(header)})")
    if not rows:
        fail(f"{a.csv} has no rows")
    for r in rows:
        where = f"{r['sweep']} {r['precision']} Pi = {r['resolution']}, c0 x {r['c0_factor']}"
        if r["finite"] != "1":
            fail(f"{where}: the run did not stay finite")
        for c in FINITE:
            v = float(r[c])
            if not (math.isfinite(v) and v >= 0):
                fail(f"{where}: {c} = {r[c]}")
        if not float(r["cpu_per_shear_time"]) > 0:
            fail(f"{where}: zero cost")
        if not 0.02 < float(r["taylor_deformation"]) < 0.6:
            fail(f"{where}: D_xy = {r['taylor_deformation']} outside (0.02, 0.6): the capsule does not deform as sheared")
        if not float(r["error_vs_double"]) < a.float_tolerance:
            fail(f"{where}: float differs from double by {r['error_vs_double']} in D_xy (tolerance {a.float_tolerance})")
    for sweep, column in (("resolution", "resolution"), ("c0", "c0_factor")):
        for precision in ("double", "float"):
            if not any(r["sweep"] == sweep and r["precision"] == precision for r in rows):
                fail(f"no {precision} rows in sweep {sweep}")
        d = sorted((r for r in rows if r["sweep"] == sweep and r["precision"] == "double"), key=lambda r: float(r[column]))
        if len(d) < 2:
            fail(f"sweep {sweep}: {len(d)} levels in double, need >= 2")
        if float(d[-1]["error"]) != 0:
            fail(f"sweep {sweep}: the finest level {column} = {d[-1][column]} is not the reference (error 0)")
    for precision in ("double", "float"):
        c = sorted((r for r in rows if r["sweep"] == "c0" and r["precision"] == precision), key=lambda r: float(r["c0"]))
        if len(c) < 3:
            fail(f"c0 sweep: {len(c)} levels in {precision}, need >= 3")
        dev = [float(r["max_density_deviation_fluid"]) for r in c]
        for k in range(len(c) - 1):
            if not dev[k] > a.min_ratio * dev[k + 1]:
                fail(f"c0 sweep, {precision}: the fluid's max |drho|/rho0 does not fall by > {a.min_ratio}x from "
                     f"c0 = {c[k]['c0']} ({dev[k]:.4g}) to {c[k + 1]['c0']} ({dev[k + 1]:.4g})")
        print(f"check_sph_tradeoff: c0 sweep, {precision}: max |drho|/rho0 of the fluid "
              f"{', '.join(f'{v:.3g}' for v in dev)} at c0 = {', '.join(r['c0'] for r in c)}")
    try:
        with open(a.json) as f:
            summary = json.load(f)
    except (OSError, ValueError) as e:
        fail(f"{a.json}: {e}")
    sweeps = {ref.get("sweep") for ref in summary.get("references", [])}
    if sweeps != {"resolution", "c0"}:
        fail(f"{a.json}: references for {sorted(s for s in sweeps if s)}, expected resolution and c0")
    for entry in summary.get("float_vs_double", []):
        if not (isinstance(entry.get("cpu_speedup"), (int, float)) and entry["cpu_speedup"] > 0):
            fail(f"{a.json}: float_vs_double entry {entry} has no positive cpu_speedup")
    if not summary.get("float_vs_double"):
        fail(f"{a.json}: no float_vs_double entries")
    print("check_sph_tradeoff: OK")


if __name__ == "__main__":
    main()
