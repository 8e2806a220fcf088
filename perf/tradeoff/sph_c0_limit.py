#!/usr/bin/env python3
"""The SPH report's c0 sweep against the c0 limit of its observable (docs/tradeoff.md, "SPH capsule").

The window mean of D_xy stops falling at c0 × 4 of the driver's rule; above it the runs scatter by
the transient's run-to-run spread. The limit is the mean of the double runs with c0 factor
>= --limit-from (from tradeoff_sph.csv and the double-only checks given after it), its uncertainty
their sample standard deviation. Writes a CSV of the c0 sweep's runs (both precisions, checks
included) with error_vs_limit = |D_xy − limit| and limit_sigma, for plot_tradeoff_panels.py.

    sph_c0_limit.py OUT_CSV TRADEOFF_CSV [CHECK_CSV ...] [--limit-from 4]
"""
import argparse
import csv
import math
import statistics


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out")
    ap.add_argument("tradeoff")
    ap.add_argument("checks", nargs="*")
    ap.add_argument("--limit-from", type=float, default=4.0)
    a = ap.parse_args()
    rows = []
    for path in [a.tradeoff] + a.checks:
        with open(path, newline="") as f:
            rows += [r for r in csv.DictReader(f) if r["sweep"] == "c0"]
    seen, runs = set(), []
    for r in rows:  # one row per (precision, c0 factor): the checks repeat no sweep level
        key = (r["precision"], float(r["c0_factor"]))
        if key not in seen:
            seen.add(key)
            runs.append(r)
    band = [float(r["taylor_deformation"]) for r in runs
            if r["precision"] == "double" and float(r["c0_factor"]) >= a.limit_from]
    if len(band) < 2:
        raise SystemExit(f"sph_c0_limit: need two or more double runs with c0 factor >= {a.limit_from}, got {len(band)}")
    limit, sigma = statistics.mean(band), statistics.stdev(band)
    with open(a.out, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["sweep", "precision", "c0_factor", "taylor_deformation", "cpu_per_shear_time", "limit",
                    "limit_sigma", "error_vs_limit"])
        for r in sorted(runs, key=lambda r: (r["precision"], float(r["c0_factor"]))):
            d = float(r["taylor_deformation"])
            w.writerow(["c0", r["precision"], r["c0_factor"], r["taylor_deformation"], r["cpu_per_shear_time"],
                        f"{limit:.9g}", f"{sigma:.9g}", f"{abs(d - limit):.9g}" if math.isfinite(d) else "nan"])
    print(f"sph_c0_limit: limit {limit:.4f} +- {sigma:.4f} from {len(band)} runs; wrote {a.out}")


if __name__ == "__main__":
    main()
