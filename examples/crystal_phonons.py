#!/usr/bin/env python3
"""Phonons of a 1D microfluidic crystal (mpc-microfluidic-crystal-phonons, docs/mpc.md): rigid discs
in a line along an MPC-AT+a channel flow, their transverse displacements recorded frame by frame,
and the power spectrum P(k, ω) of that field drawn over the (k, ω) plane.

    examples/crystal_phonons.py [--tiny] [--plot FILE.png]

Without --tiny: the `crystal` driver's channel (W = 15Δx, n = 40, g = 0.1, R = 5Δx) at L = 300Δx
with 27 discs (a = 11.1Δx, as the driver's 90 in 1000), 2000 frames of 1 τ after 200 τ (hours on
one core; the driver itself runs with checkpoints). --tiny: a short, dilute channel (what CI runs).
"""
import argparse

import numpy as np

import mesoflow
from mesoflow import analysis, crystal

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--tiny", action="store_true")
parser.add_argument("--plot", help="write log P(k, ω) to this PNG")
parser.add_argument("--threads", type=int, default=0)
args = parser.parse_args()
mesoflow.initialize(threads=args.threads)

if args.tiny:
    L, discs, frames, interval, before = 60.0, 5, 40, 0.5, 5.0
    channel = dict(length=L, width=15.0, density=5.0)
else:
    L, discs, frames, interval, before = 300.0, 27, 2000, 1.0, 200.0
    channel = dict(length=L, width=15.0)
a = L / discs
rng = np.random.default_rng(4)
# discs on the axis, a small random transverse kick each (the driver starts from a zigzag)
centres = [((n + 0.5) * a, 7.5 + 0.3 * rng.uniform(-1, 1)) for n in range(discs)]
c = crystal.channel(disc_centres=centres, **channel)
h = c.parameters.h
mesoflow.run(c, int(round(before / h)), every=200, progress=not args.tiny)
y = np.empty((frames, discs))
for f in range(frames):
    c.advance(int(round(interval / h)))
    y[f] = np.array(c.disc_positions)[:, 1] - 7.5  # discs keep their order in a line: index = site
P = analysis.power_spectrum(y)  # (discs, frames) on the grids below
k, w = np.array(analysis.wavenumbers(discs, a)), np.array(analysis.frequencies(frames, interval))
kmax, wmax = np.unravel_index(np.argmax(P[1:]), P[1:].shape)
print("%d discs, a = %.2f Δx, %d frames of %g τ; mean |y| = %.3f Δx" % (discs, a, frames, interval, np.abs(y).mean()))
print("strongest transverse mode: k a = %.3f, ω τ = %.4f" % (k[kmax + 1] * a, w[wmax]))
if args.plot:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    order_k, order_w = np.argsort(k), np.argsort(w)
    img = np.log10(P[np.ix_(order_k, order_w)].T + 1e-30)
    plt.imshow(img, origin="lower", aspect="auto", cmap="magma",
               extent=[k.min() * a, k.max() * a, w.min(), w.max()])
    plt.colorbar(label="log10 P(k, ω), transverse")
    plt.xlabel("k a"), plt.ylabel("ω τ")
    plt.savefig(args.plot, dpi=120)
