#!/usr/bin/env python3
"""A capsule squeezed through a constriction (sph-microcapsules-constriction, docs/sph-capsules.md,
Figs. 5-8): the `capsule` driver's runs at a few capillary numbers, the deformation indices D_x,y,z
against the centroid's position x_c, and the passage time against Ca.

    examples/capsule_constriction.py [--tiny] [--plot FILE.png] [--checkpoint FILE.jsonl]

Without --tiny: Π = 12 lattice spacings per diameter, η = t_c/d = 0.75, Ca = 0.05, 0.1, 0.25 (about
10 min per Ca on 2 cores; --checkpoint keeps each finished run). --tiny: Π = 6, a level-1
membrane and 1 d/U of flow, which is what CI runs: the capsule does not reach the constriction.
"""
import argparse

import numpy as np

import mesoflow
from mesoflow import capsule

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--tiny", action="store_true")
parser.add_argument("--plot", help="write D(x_c) per Ca to this PNG")
parser.add_argument("--checkpoint", help="JSON-lines file keeping the finished runs (resume)")
parser.add_argument("--threads", type=int, default=0)
args = parser.parse_args()
mesoflow.initialize(threads=args.threads)

if args.tiny:
    cas, eta, run = [0.1, 0.25], 0.75, dict(resolution=6, level=1, t_max=1.0, sample_every=0.1)
else:
    cas, eta, run = [0.05, 0.1, 0.25], 0.75, dict(resolution=12, t_max=25.0)
sweep = capsule.sweep(cas, etas=[eta], checkpoint=args.checkpoint, progress=not args.tiny, **run)
for r in sweep["runs"]:
    print("Ca = %.3g: %s, passage time %.3g d/U, D_x at x_c = 4d: %.3g; x_c reached %.2f d" %
          (r["ca"], r["status"], r["passage_time"], r["Dx_at_4"], max(r["x_c"])))
print("Pearson r of 1/passage time against Ca at eta = %g: %.3f" % (eta, sweep["pearson_r"][0]["inverse_passage_time"]))

if args.plot:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4))
    for r, colour in zip(sweep["runs"], ("C0", "C1", "C2", "C3")):
        x = np.array(r["x_c"])
        for key, style in (("Dx", "-"), ("Dy", "--"), ("Dz", ":")):
            ax.plot(x, r[key], style, color=colour, label="Ca = %g, %s" % (r["ca"], key) if key == "Dx" else None)
    ax.axvspan(3.0, 5.0, color="0.9")  # the constriction, x = 3d to 5d along the channel
    ax.set_xlabel("x_c / d")
    ax.set_ylabel("deformation index D (- Dx, -- Dy, : Dz)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(args.plot, dpi=120)
