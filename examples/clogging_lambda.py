#!/usr/bin/env python3
"""λ(Γ) in obstacle arrays (capillary-droplets Fig. 13(b) scene, docs/droplets.md): the clogging decay
length of DP droplets against the line tension, with its 95% likelihood interval, resumable.

    examples/clogging_lambda.py [--tiny] [--checkpoint FILE] [--plot FILE.png]

--tiny runs a few replicas of a small scene in seconds (what CI runs); without it, the calibrated
Fig. 13(b) scene (φ = 0.0248, L = 100σ, T = 2000 t0, early clog test) at five Γ, 50 replicas each.
"""
import argparse

import mesoflow
from mesoflow import droplets

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--tiny", action="store_true")
parser.add_argument("--checkpoint", help="JSON-lines file of finished replicas: rerun to resume")
parser.add_argument("--plot", help="write λ(Γ) to this PNG")
parser.add_argument("--threads", type=int, default=0)
args = parser.parse_args()
mesoflow.initialize(threads=args.threads)

if args.tiny:
    # maximal (densest) arrays, a fast droplet: clogs within the 40 t0
    gammas, gap = [2.0, 16.0], 0.1
    scene = dict(replicas=6, vertices=16, box_length=10.0, time_limit=40.0, relax_iterations=2000,
                 obstacle_fraction=0.0, terminal_speed=0.5)
else:
    gammas, gap = [0.25, 0.5, 1.09, 2.0, 4.0], 0.2
    scene = dict(replicas=50, time_limit=2000.0, box_length=100.0, clog_test="early", batch=50)
result = droplets.clogging_sweep(gammas, [gap], seed=14, checkpoint=args.checkpoint, progress=not args.tiny, **scene)
print("Gamma   lambda/sigma  [95% interval]   clogged/replicas")
for (gamma, _), lam, lo, hi, n in zip(result["points"], result["decay_length"], result["lower"], result["upper"],
                                      result["clogged"]):
    print("%5.2f   %8.3g      [%.3g, %.3g]   %d/%d" % (gamma, lam, lo, hi, n, scene["replicas"]))
if args.plot:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    g, lam, lo, hi = np.array(gammas), result["decay_length"], result["lower"], result["upper"]
    ok = np.isfinite(lam) & np.isfinite(hi)
    plt.errorbar(g[ok], lam[ok], yerr=[lam[ok] - lo[ok], hi[ok] - lam[ok]], fmt="o", capsize=3, label="λ, 95% interval")
    if (~ok).any():  # no clog (or too few): only a lower bound
        plt.plot(g[~ok], lo[~ok], "^", label="lower bound (no upper)")
    plt.legend()
    plt.xscale("log"), plt.yscale("log"), plt.xlabel("Γ"), plt.ylabel("λ/σ")
    plt.savefig(args.plot, dpi=120)
