#!/usr/bin/python3
"""Plot Q(w) from the `hopper` driver's CSV: flowing widths with error bars, clogged widths at
Q = 0 (crosses), and the Beverloo fit Q = C(w - k)^beta (hopper-flows paper, eq. 1) when given.

usage: plot_hopper.py RESULTS.csv OUT.png [FIT.csv]
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def rows(path):
    with open(path, newline="") as f:
        return [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]


def main():
    if len(sys.argv) not in (3, 4):
        raise SystemExit(__doc__)
    data = rows(sys.argv[1])
    flowing = [r for r in data if r["clogged"] == 0]
    clogged = [r for r in data if r["clogged"] != 0]
    fig, ax = plt.subplots(figsize=(5, 4))
    ax.errorbar([r["w"] for r in flowing], [r["Q"] for r in flowing], yerr=[r["Q_error"] for r in flowing],
                fmt="o", label="simulation")
    if clogged:
        ax.plot([r["w"] for r in clogged], [0.0] * len(clogged), "x", color="red", label="clogged")
    if len(sys.argv) == 4:
        fit = rows(sys.argv[3])[0]
        w = np.linspace(fit["k"] + 1e-3, max(r["w"] for r in data), 200)
        ax.plot(w, fit["C"] * (w - fit["k"]) ** fit["beta"],
                label=f"C(w-k)^β: k = {fit['k']:.2f}±{fit['k_error']:.2f}, β = {fit['beta']:.2f}±{fit['beta_error']:.2f}")
    ax.set_xlabel("w / σ_avg")
    ax.set_ylabel("Q / Q0")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=120)


if __name__ == "__main__":
    main()
