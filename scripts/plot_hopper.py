#!/usr/bin/python3
"""Plot the `hopper` driver's results (hopper-flows paper, Figs. 2 and 5):
  (a) Q(w): flowing widths with error bars, clogged widths at Q = 0 (crosses), the Beverloo fit
      Q = C(w - k)^beta (eq. 1) when given;
  (b) with a fit, the log-log collapse log10(Q/C) against log10(w/sigma_avg - k), with the slopes d - 3/2
      and d - 1/2 of the two limits (d read from the JSON summary beside RESULTS.csv; 2 without one);
  (c) with a profile, the mean particle speed along gravity on the hopper axis against h above the orifice.

usage: plot_hopper.py RESULTS.csv OUT.png [--profile PROFILE.csv] [--fit FIT.csv]
       plot_hopper.py --compare OUT.png LABEL RESULTS.csv FIT.csv [LABEL RESULTS.csv FIT.csv ...]
The second form overlays several sweeps (e.g. the friction and drag limits) in panels (a) and (b).
"""
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def rows(path):
    with open(path, newline="") as f:
        return [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]


def dimension(results):
    summary = os.path.splitext(results)[0] + ".json"
    try:
        with open(summary) as f:
            return int(json.load(f).get("dimension", 2))
    except (OSError, ValueError):
        return 2


def q_panel(ax, data, fit, label="", color=None):
    flowing = [r for r in data if r["clogged"] == 0]
    clogged = [r for r in data if r["clogged"] != 0]
    pts = ax.errorbar([r["w"] for r in flowing], [r["Q"] for r in flowing], yerr=[r["Q_error"] for r in flowing],
                      fmt="o", ms=4, color=color, label=label or "simulation")
    color = pts[0].get_color()
    if clogged:
        ax.plot([r["w"] for r in clogged], [0.0] * len(clogged), "x", color=color, label="clogged")
    if fit:
        w = np.linspace(fit["k"] + 1e-3, max(r["w"] for r in data), 200)
        ax.plot(w, fit["C"] * (w - fit["k"]) ** fit["beta"], color=color,
                label=f"k = {fit['k']:.2f}±{fit['k_error']:.2f}, β = {fit['beta']:.2f}±{fit['beta_error']:.2f}")
    ax.set_xlabel("w / σ_avg")
    ax.set_ylabel("Q / Q0")
    ax.legend(fontsize=7)
    return color


def collapse_panel(ax, data, fit, color=None, label=""):
    flowing = [r for r in data if r["clogged"] == 0 and r["w"] > fit["k"] and r["Q"] > 0]
    x = np.log10([r["w"] - fit["k"] for r in flowing])
    y = np.log10([r["Q"] / fit["C"] for r in flowing])
    ax.plot(x, y, "o", ms=4, color=color, label=label)
    return x


def slopes(ax, xs, d):
    x = np.linspace(min(xs) - 0.1, max(xs) + 0.1, 10)
    ax.plot(x, (d - 1.5) * x, ":", color="gray", label=f"slope {2 * d - 3}/2")
    ax.plot(x, (d - 0.5) * x, "--", color="gray", label=f"slope {2 * d - 1}/2")
    ax.set_xlabel("log10(w/σ_avg − k)")
    ax.set_ylabel("log10(Q/C)")
    ax.legend(fontsize=7)


def single(argv):
    results, out = argv[0], argv[1]
    opts = dict(zip(argv[2::2], argv[3::2]))
    data = rows(results)
    fit = rows(opts["--fit"])[0] if "--fit" in opts else None
    profile = rows(opts["--profile"]) if "--profile" in opts else []
    panels = 1 + (fit is not None) + bool(profile)
    fig, axes = plt.subplots(1, panels, figsize=(4.5 * panels, 3.8))
    axes = np.atleast_1d(axes)
    q_panel(axes[0], data, fit)
    k = 1
    if fit:
        slopes(axes[1], collapse_panel(axes[1], data, fit), dimension(results))
        k = 2
    if profile:
        for w in sorted({r["w"] for r in profile}):
            prof = [r for r in profile if r["w"] == w]
            axes[k].plot([r["h"] for r in prof], [r["vg_mean"] for r in prof], label=f"w = {w:g}")
        axes[k].set_xlabel("h / σ_avg")
        axes[k].set_ylabel("v_g / (σ_avg/t0) on the axis")
        axes[k].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out, dpi=120)


def compare(argv):
    out, rest = argv[0], argv[1:]
    if len(rest) % 3 or not rest:
        raise SystemExit(__doc__)
    fig, axes = plt.subplots(1, 2, figsize=(9, 3.8))
    xs = []
    for label, results, fitfile in zip(rest[0::3], rest[1::3], rest[2::3]):
        data, fit = rows(results), rows(fitfile)[0]
        color = q_panel(axes[0], data, fit, label)
        xs.extend(collapse_panel(axes[1], data, fit, color, label))
    slopes(axes[1], xs, dimension(rest[1]))
    fig.tight_layout()
    fig.savefig(out, dpi=120)


def main():
    argv = sys.argv[1:]
    if argv and argv[0] == "--compare":
        compare(argv[1:])
    elif len(argv) >= 2 and len(argv) % 2 == 0:
        single(argv)
    else:
        raise SystemExit(__doc__)


if __name__ == "__main__":
    main()
