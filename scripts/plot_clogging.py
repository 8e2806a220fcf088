#!/usr/bin/python3
"""Plot the clogging decay length lambda/sigma against Gamma (DP) or E_w (SP) from an `obstacles`
summary CSV (capillary-droplets paper, Figs. 6c and 7a), one curve per obstacle gap w_ob. Points
where no replica clogged have lambda = inf: their lower confidence bound is drawn as an arrow.

usage: plot_clogging.py SUMMARY.csv OUT.png
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    if len(sys.argv) != 3:
        raise SystemExit(__doc__)
    with open(sys.argv[1], newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise SystemExit(f"{sys.argv[1]}: no rows")
    x_key = "line_tension" if "line_tension" in rows[0] else "wall_energy"
    fig, ax = plt.subplots(figsize=(5, 4))
    for gap in sorted({r["gap"] for r in rows}, key=float):
        pts = sorted((r for r in rows if r["gap"] == gap), key=lambda r: float(r[x_key]))
        finite = [r for r in pts if math.isfinite(float(r["decay_length"]))]
        xs = [float(r[x_key]) for r in finite]
        ys = [float(r["decay_length"]) for r in finite]
        lo = [y - float(r["decay_length_lower"]) for y, r in zip(ys, finite)]
        hi = [float(r["decay_length_upper"]) - y for y, r in zip(ys, finite)]
        line = ax.errorbar(xs, ys, yerr=[lo, hi], marker="o", capsize=3, label=f"$w_{{ob}}/\\sigma$ = {gap}")
        for r in pts:
            if not math.isfinite(float(r["decay_length"])):
                ax.annotate("", xy=(float(r[x_key]), 2 * float(r["decay_length_lower"])),
                            xytext=(float(r[x_key]), float(r["decay_length_lower"])),
                            arrowprops=dict(arrowstyle="->", color=line[0].get_color()))
                ax.plot(float(r[x_key]), float(r["decay_length_lower"]), "_", ms=12, color=line[0].get_color())
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(r"line tension $\Gamma$" if x_key == "line_tension" else r"stiffness $E_w$")
    ax.set_ylabel(r"$\lambda/\sigma$ (arrows: no clog, lower bound)")
    ax.legend()
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=120)


if __name__ == "__main__":
    main()
