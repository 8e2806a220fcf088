#!/usr/bin/env python3
"""Beverloo's law in a 2D hopper (hopper-flows Fig. 2, docs/hopper.md): the flow rate Q against the
orifice width w and the fit Q = C (w/σ_avg − k)^β, resumable width by width.

    examples/hopper_beverloo.py [--tiny] [--drag] [--checkpoint FILE] [--plot FILE.png]

Without --tiny: the paper's 2D scene (N = 1600, W = 50σ_avg, θ_w = 90°, E_sp = 10³) in the friction
limit at μ/μ0 = √10 (where β = 3/2 holds with eq. 6 as printed, docs/hopper.md), 7 widths, 150 t0
measured per width (about 25 min on one core); --drag: the drag limit (ζ t0 = 7.3, β → 1/2).
--tiny runs 150 particles through 4 widths in seconds (what CI runs).
"""
import argparse

import mesoflow
from mesoflow import hopper

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--tiny", action="store_true")
parser.add_argument("--drag", action="store_true", help="the drag limit instead of the friction limit")
parser.add_argument("--checkpoint", help="JSON-lines file of finished widths: rerun to resume")
parser.add_argument("--plot", help="write Q(w) with the fit to this PNG")
parser.add_argument("--threads", type=int, default=0)
args = parser.parse_args()
mesoflow.initialize(threads=args.threads)

dissipation = dict(friction=0.0, drag=7.3) if args.drag else dict(friction=3.16227766, drag=0.0)
if args.tiny:
    widths = [4, 5, 6, 7]
    scene = dict(particles=150, hopper_width=15.0, seed=3)
    flow = dict(steady_windows=2, measure_windows=4, max_time=40.0)
else:
    widths = [4, 5, 6, 7, 8, 9, 10]
    scene = dict(particles=1600, hopper_width=50.0, wall_angle=90.0, pair_energy=1e3, seed=1)
    flow = dict(measure_windows=75, max_time=2000.0)
r = hopper.sweep(widths, flow=flow, checkpoint=args.checkpoint, progress=not args.tiny, **scene, **dissipation)
print("w/σ_avg   Q/Q0      ± error   steady")
for w, rec in zip(r["widths"], r["records"]):
    print("%5.1f   %8.4g  %8.2g   %s" % (w, rec["Q"], rec["Q_error"], "clogged" if rec["clogged"] else rec["steady"]))
fit = r["beverloo"]
if fit:
    print("Beverloo: C = %.3g ± %.2g, k = %.2f ± %.2f, β = %.2f ± %.2f (χ²/dof %.2f)"
          % (fit["C"], fit["C_error"], fit["k"], fit["k_error"], fit["beta"], fit["beta_error"], fit["chi2_per_dof"]))
else:
    print("Beverloo: fewer than 4 flowing widths, no fit")
if args.plot:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    ok = [not rec["clogged"] for rec in r["records"]]
    w = np.array(r["widths"])[ok]
    plt.errorbar(w, np.array(r["Q"])[ok], yerr=np.array(r["Q_error"])[ok], fmt="o", capsize=3, label="Q(w)")
    if fit:
        ws = np.linspace(max(fit["k"], 0) + 0.05, w.max(), 100)
        plt.plot(ws, fit["C"] * (ws - fit["k"]) ** fit["beta"], label="β = %.2f ± %.2f" % (fit["beta"], fit["beta_error"]))
    plt.legend()
    plt.xlabel("w/σ_avg"), plt.ylabel("Q/Q0")
    plt.savefig(args.plot, dpi=120)
