#!/usr/bin/env python3
"""The orifice passage (capillary-droplets Fig. 2, docs/droplets.md): v_g/v_t and the shape parameter
𝒜 against the distance h from the orifice, with the droplet's outline drawn at a few moments.

    examples/orifice_profile.py [--tiny] [--plot FILE.png]

--tiny: 32 vertices and 30 t0 (seconds; what CI runs). Without it: the paper's Fig. 2 droplet.
"""
import argparse

import numpy as np

import mesoflow
from mesoflow import droplets

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--tiny", action="store_true")
parser.add_argument("--plot", help="write the profiles and outlines to this PNG")
parser.add_argument("--threads", type=int, default=0)
args = parser.parse_args()
mesoflow.initialize(threads=args.threads)

run = droplets.orifice(**(dict(vertices=32, start_h=-1.3, max_time=30.0) if args.tiny else {}))
outlines = []


def keep_outline(r):  # r.positions is the scene's memory (host backends): copy what is kept
    if r.samples % 40 == 0:
        outlines.append(np.array(r.positions))


profile = run.run(callback=keep_outline, progress=not args.tiny)
vt = run.scene.droplet.terminal_speed
print("outcome %s at t = %.4g t0 after %d steps; max shape parameter %.4g; min v_g/v_t before the orifice %.3g"
      % (profile["outcome"], profile["t"][-1], profile["steps"], profile["shape_parameter"].max(),
         (profile["vg"][(profile["h"] > -0.5) & (profile["h"] < 0)] / vt).min(initial=np.inf)))
if args.plot:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (a, b) = plt.subplots(1, 2, figsize=(9, 3.5))
    a.plot(profile["h"], profile["vg"] / vt, label="v_g/v_t")
    a.plot(profile["h"], profile["shape_parameter"], label="shape parameter A")
    a.set_xlabel("h/σ"), a.legend()
    for x in outlines:
        b.fill(x[:, 0], x[:, 1], alpha=0.3)
    w = run.scene.width
    b.plot([-2, -w / 2, None, w / 2, 2], [2 - w / 2, 0, None, 0, 2 - w / 2], "k")  # the 45° wedges' faces
    b.set_aspect("equal"), b.set_xlabel("x/σ"), b.set_ylabel("y/σ")
    fig.tight_layout()
    fig.savefig(args.plot, dpi=120)
