#!/usr/bin/env python3
"""D_xy(γ̇t) of every run of a tradeoff_sph series CSV (and optional further ones, e.g. the double-only
convergence checks), one panel per sweep: Π at c0 = the rule, and c0 at the c0 sweep's Π; double
solid, float dashed; the averaging window shaded. Shows whether the window sits on the plateau.

    plot_sph_series.py PNG SERIES_CSV [SERIES_CSV ...] (--summary JSON | --window START END [--c0-resolution PI])

--summary reads the window and the c0 sweep's Π from tradeoff_sph's JSON.
"""
import argparse
import csv
import json

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("png")
    ap.add_argument("series", nargs="+")
    ap.add_argument("--summary")
    ap.add_argument("--window", nargs=2, type=float)
    ap.add_argument("--c0-resolution", type=int, default=8)
    a = ap.parse_args()
    if a.summary:
        with open(a.summary) as f:
            summary = json.load(f)
        a.window = summary["scene"]["window"]
        a.c0_resolution = next(r["resolution"] for r in summary["references"] if r["sweep"] == "c0")
    if not a.window:
        ap.error("give --summary or --window")
    runs = {}
    for path in a.series:
        with open(path, newline="") as f:
            for r in csv.DictReader(f):
                key = (r["precision"], int(r["resolution"]), float(r["c0_factor"]), path)
                runs.setdefault(key, []).append((float(r["shear_time"]), float(r["taylor_deformation"])))
    fig, axes = plt.subplots(1, 2, figsize=(11.5, 4.4), sharey=True)
    seen = set()
    for (precision, pi, factor, path), pts in sorted(runs.items()):
        if (precision, pi, factor) in seen:  # the same setting in two files (e.g. a repeated Π = 8, × 1)
            continue
        seen.add((precision, pi, factor))
        t, d = zip(*pts)
        style = "-" if precision == "double" else "--"
        if factor == 1:
            axes[0].plot(t, d, style, lw=1, label=f"Π={pi} {precision}")
        if pi == a.c0_resolution:
            axes[1].plot(t, d, style, lw=1, label=f"c0×{factor:g} {precision}")
    for ax, title in zip(axes, ("Π sweep (c0 = driver rule)", f"c0 sweep (Π = {a.c0_resolution})")):
        ax.axvspan(a.window[0], a.window[1], color="gray", alpha=0.15, label="window")
        ax.set_title(title, fontsize=9)
        ax.set_xlabel("γ̇t")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, ncol=2)
    axes[0].set_ylabel("D_xy")
    fig.tight_layout()
    fig.savefig(a.png, dpi=110)
    print(f"plot_sph_series: wrote {a.png}")


if __name__ == "__main__":
    main()
