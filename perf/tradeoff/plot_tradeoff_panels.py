#!/usr/bin/env python3
"""Log-log trade-off plot of a perf/tradeoff CSV (droplet, SP and DP hopper): cost per unit physical time
against the error of the model's observable versus the converged reference, one panel per sweep,
double (filled) and float (open) marked, each point labelled with its sweep parameter.

    plot_tradeoff_panels.py CSV PNG --error COLUMN --parameter SWEEP:COLUMN:TITLE ...
                            [--error-label TEXT] [--error-sigma COLUMN] [--cost cpu_per_t0] [--cost-label TEXT]

The CSV has one row per run and sweep with at least the columns sweep, precision, COLUMN of each
--parameter, the cost column and the error column. The reference run (error exactly 0 in double)
has no place on a log axis and is named in the panel title instead (a reference outside the runs,
such as an extrapolated limit, names none); a zero error of float (float
reproduced the reference bitwise) is drawn at the panel's lower edge. Runs with a non-finite error
or cost (a float run that blew up) are listed in the title. With --error-sigma COLUMN each error
carries a horizontal bar of that statistical error, and a dotted line marks the reference's own.
"""
import argparse
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402


def label_of(column, value):
    v = float(value)
    if column == "vertices":
        return f"N_v={int(v)}"
    if column == "dt_factor":
        return f"Δt×{v:g}"
    if column == "dt":
        return f"Δt={v:.2g}"
    if column == "pair_energy":
        return f"E_sp={v:g}"
    if column == "bending_stiffness":
        return f"K_b={v:g}"
    if column == "perimeter_stiffness":
        return f"K_l={v:g}"
    return f"{column}={v:g}"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv")
    ap.add_argument("png")
    ap.add_argument("--error", required=True)
    ap.add_argument("--error-label", default=None)
    ap.add_argument("--error-sigma", default=None)
    ap.add_argument("--cost", default="cpu_per_t0")
    ap.add_argument("--cost-label", default="CPU seconds per t0 (one thread)")
    ap.add_argument("--parameter", action="append", required=True, help="SWEEP:COLUMN:TITLE")
    a = ap.parse_args()
    with open(a.csv, newline="") as f:
        rows = list(csv.DictReader(f))
    sweeps = [p.split(":", 2) for p in a.parameter]
    fig, axes = plt.subplots(1, len(sweeps), figsize=(5.8 * len(sweeps), 4.8), squeeze=False)
    for ax, (sweep, column, title) in zip(axes[0], sweeps):
        sel = [r for r in rows if r["sweep"] == sweep]
        if not sel:
            sys.exit(f"plot_tradeoff_panels: no rows of sweep {sweep} in {a.csv}")
        failed = [r for r in sel if not (math.isfinite(float(r[a.error])) and math.isfinite(float(r[a.cost])))]
        sel = [r for r in sel if r not in failed]
        positive = [float(r[a.error]) for r in sel if float(r[a.error]) > 0]
        floor = min(positive) / 3 if positive else 1e-12
        reference = [r for r in sel if r["precision"] == "double" and float(r[a.error]) == 0]
        for precision, style in (("double", dict(marker="o", color="C0")),
                                 ("float", dict(marker="s", color="C3", markerfacecolor="none"))):
            pts = [r for r in sel if r["precision"] == precision and not (precision == "double" and float(r[a.error]) == 0)]
            pts.sort(key=lambda r: float(r[column]))
            x = [float(r[a.error]) if float(r[a.error]) > 0 else floor for r in pts]
            y = [float(r[a.cost]) for r in pts]
            ax.loglog(x, y, linestyle="-", label=precision, **style)
            if a.error_sigma:
                ax.errorbar(x, y, xerr=[[min(float(r[a.error_sigma]), 0.9 * xi) for r, xi in zip(pts, x)],
                                        [float(r[a.error_sigma]) for r in pts]],
                            fmt="none", ecolor=style["color"], alpha=0.5)
            for r, xi, yi in zip(pts, x, y):
                ax.annotate(label_of(column, r[column]), (xi, yi), textcoords="offset points",
                            xytext=(5, 4) if precision == "double" else (5, -10), fontsize=7, color=style["color"])
        if a.error_sigma and reference:
            ax.axvline(float(reference[0][a.error_sigma]), color="gray", linestyle=":", label="reference's σ")
        ref = ", ".join(label_of(column, r[column]) for r in reference)
        lost = ", ".join(f"{r['precision']} {label_of(column, r[column])}" for r in failed)
        ax.set_title(title + (f"\nreference (double): {ref}" if ref else "") + (f"\nnon-finite: {lost}" if lost else ""),
                     fontsize=9)
        ax.set_xlabel(a.error_label or a.error)
        ax.set_ylabel(a.cost_label)
        ax.grid(True, which="both", alpha=0.3)
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        costs = [float(r[a.cost]) for r in sel if float(r[a.cost]) > 0]
        if costs and max(costs) < 10 * min(costs):  # less than a decade: label the minor ticks, or none shows
            ax.yaxis.set_minor_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:.2g}"))
        else:
            ax.yaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(a.png, dpi=120)
    print(f"plot_tradeoff_panels: wrote {a.png}")


if __name__ == "__main__":
    main()
