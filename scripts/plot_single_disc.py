#!/usr/bin/python3
"""Plots the single-disc runs of docs/mpc.md ("K of a single disc"): (left) the oil speed profile
u_x(y) far from the disc, normalised by its axis value, with the no-slip parabola; (right) K per
block against all solvent and against the far oil speed on the axis, with the disc's height.

usage: plot_single_disc.py <results dir> <out.png> NAME [NAME...]
NAME: a run whose <NAME>_check.json (scripts/crystal_single_disc_check.py) lies in the results
directory, with <NAME>_far_profile.csv where the run recorded the far field.
"""
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

results, png, names = sys.argv[1], sys.argv[2], sys.argv[3:]
if not names:
    sys.exit(__doc__)
fig, (ax_p, ax_k) = plt.subplots(1, 2, figsize=(11, 4.2))
colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
for i, name in enumerate(names):
    c = colors[i % len(colors)]
    with open(os.path.join(results, name + "_check.json")) as f:
        check = json.load(f)
    label = name.replace("single_", "").replace("_", " ")
    profile = os.path.join(results, name + "_far_profile.csv")
    if os.path.exists(profile):
        rows = list(csv.DictReader(open(profile)))
        y = np.array([float(r["y"]) for r in rows])
        u = np.array([float(r["u_x"]) for r in rows])
        axis = np.abs(y - 0.5 * check["width"]) < 0.5
        ax_p.plot(y / check["width"], u / u[axis].mean(), ".-", color=c, label=label)
    mid = [0.5 * (b["t0"] + b["t1"]) for b in check["blocks"]]
    ax_k.plot(mid, [b["K"] for b in check["blocks"]], "o-", color=c, label=label + ": all solvent")
    if check["blocks"] and "K_axis" in check["blocks"][0]:
        ax_k.plot(mid, [b["K_axis"] for b in check["blocks"]], "s--", color=c, label=label + ": far, axis")
    elif check.get("K_axis") is None:
        pass
    off = [abs(b["disc_y"] - 0.5 * check["width"]) for b in check["blocks"]]
    for t, k, d in zip(mid, [b["K"] for b in check["blocks"]], off):
        if d > 1.0:
            ax_k.annotate("off axis", (t, k), textcoords="offset points", xytext=(0, -12), fontsize=7, color=c,
                          ha="center")
s = np.linspace(0, 1, 101)
ax_p.plot(s, 4 * s * (1 - s), "k:", label="no-slip parabola")
ax_p.set_xlabel("y / W (far from the disc)")
ax_p.set_ylabel("u_x / u_x(axis)")
ax_p.legend(fontsize=7)
ax_k.axhline(0.62, color="gray", lw=0.8)
ax_k.text(ax_k.get_xlim()[0], 0.63, " paper: K ≈ 0.62", fontsize=7, color="gray")
ax_k.set_xlabel("time / τ (block centres)")
ax_k.set_ylabel("K = u_d / u_oil")
ax_k.legend(fontsize=6, ncol=1)
fig.suptitle("One disc at the paper's parameters (W = 3R): K against which oil speed", fontsize=10)
fig.tight_layout()
fig.savefig(png, dpi=120)
print("wrote", png)
