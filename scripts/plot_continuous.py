#!/usr/bin/python3
"""Tables and plots of continuous flow through obstacle arrays (capillary-droplets Figs. 8(a,b), 9(a),
15) from the `obstacles` summary CSVs that `scripts/reproduce_capillary continuous` writes into DIR:
fig8a_dp_w<w>.csv, fig9a_sp_w<w>.csv, fig8b_dp_sob<s>.csv, fig15_dp_b0<b>.csv. For each figure it
writes DIR/<fig>.csv (one row per point, the curve's parameter in the first column) and DIR/<fig>.png:
⟨v_g⟩/v_t against Γ or E_w with the standard error over the arrays. Every point of a curve runs on
the same 10 arrays (the same seeds), so DIR/trends.csv gives each curve's paired trend: per array,
v_g/v_t at the largest Γ (E_w) minus at the smallest, its mean and standard error over the arrays.
Missing runs are left out.

usage: plot_continuous.py DIR [--terminal-speed 0.03]
"""
import csv
import glob
import math
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def curves(d, pattern, regex, terminal_speed, label):
    """[(label value, rows)] of the summaries matching pattern, the label from the file name."""
    out = []
    for path in sorted(glob.glob(os.path.join(d, pattern))):
        if path.endswith(".replicas.csv"):
            continue
        m = re.search(regex, os.path.basename(path))
        if m and os.path.exists(path[: -len(".csv")] + ".json"):
            rows = read(path)
            out.append((float(m.group(1)), rows))
            name = os.path.basename(path)[: -len(".csv")]
            paired_trend(d, name, label, float(m.group(1)), rows, terminal_speed)
    return sorted(out)


TRENDS = []


def paired_trend(d, name, label, value, summary_rows, terminal_speed):
    """v_g/v_t(largest x) − v_g/v_t(smallest x) per array (replica index), mean and standard error."""
    path = os.path.join(d, name + ".replicas.csv")
    if not os.path.exists(path):
        return
    rows = read(path)
    x_key = "line_tension" if "line_tension" in rows[0] else "wall_energy"
    xs = sorted({float(r[x_key]) for r in rows})
    lo, hi = xs[0], xs[-1]
    by = {}
    for r in rows:
        if r["clogged"] == "0":
            by.setdefault(r["replica"], {})[float(r[x_key])] = float(r["steady_speed"]) / terminal_speed
    diffs = [v[hi] - v[lo] for v in by.values() if lo in v and hi in v]
    if len(diffs) < 2:
        return
    mean = sum(diffs) / len(diffs)
    se = math.sqrt(sum((x - mean) ** 2 for x in diffs) / (len(diffs) - 1) / len(diffs))
    TRENDS.append([name, label, value, x_key, lo, hi, len(diffs), mean, se])


def figure(d, name, label_key, label_tex, series):
    if not series:
        return
    x_key = "line_tension" if "line_tension" in series[0][1][0] else "wall_energy"
    keys = [label_key, x_key, "replicas", "clogged", "flowing", "mean_speed_ratio", "mean_speed_ratio_error"]
    with open(os.path.join(d, name + ".csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(keys)
        for value, rows in series:
            for r in sorted(rows, key=lambda r: float(r[x_key])):
                w.writerow([value] + [r[k] for k in keys[1:]])
    fig, ax = plt.subplots(figsize=(5, 4))
    for value, rows in series:
        pts = sorted((r for r in rows if r["mean_speed_ratio"] not in ("", "nan")), key=lambda r: float(r[x_key]))
        xs = [float(r[x_key]) for r in pts]
        ys = [float(r["mean_speed_ratio"]) for r in pts]
        es = [float(r["mean_speed_ratio_error"] or 0) for r in pts]
        ax.errorbar(xs, ys, yerr=es, marker="o", capsize=3, label=f"{label_tex} = {value:g}")
    ax.set_xscale("log")
    ax.set_xlabel(r"line tension $\Gamma$" if x_key == "line_tension" else r"stiffness $E_w$")
    ax.set_ylabel(r"$\langle v_g\rangle / v_t$ (10 arrays, ± s.e.)")
    ax.set_title(name)
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(d, name + ".png"), dpi=120)
    plt.close(fig)


def main():
    args = sys.argv[1:]
    vt = 0.03
    if "--terminal-speed" in args:
        k = args.index("--terminal-speed")
        vt = float(args[k + 1])
        del args[k : k + 2]
    if len(args) != 1:
        raise SystemExit(__doc__)
    d = args[0]
    fig8a = curves(d, "fig8a_dp_w*.csv", r"_w([0-9.]+)\.csv$", vt, "gap")
    figure(d, "fig8a", "gap", r"$w_{ob}/\sigma$", fig8a)
    figure(d, "fig9a", "gap", r"$w_{ob}/\sigma$", curves(d, "fig9a_sp_w*.csv", r"_w([0-9.]+)\.csv$", vt, "gap"))
    base = [rows for w, rows in fig8a if w == 1.0]
    figure(d, "fig8b", "obstacle_diameter", r"$\sigma_{ob}/\sigma$",
           sorted([(0.3, r) for r in base]
                  + curves(d, "fig8b_dp_sob*.csv", r"_sob([0-9.]+)\.csv$", vt, "obstacle_diameter")))
    figure(d, "fig15", "near_wall_drag", r"$b_0/b_\infty$",
           sorted([(0.0, r) for r in base] + curves(d, "fig15_dp_b0*.csv", r"_b0([0-9.]+)\.csv$", vt, "near_wall_drag")))
    with open(os.path.join(d, "trends.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["run", "parameter", "value", "x", "x_low", "x_high", "arrays", "paired_difference",
                    "paired_difference_error"])
        w.writerows(TRENDS)


if __name__ == "__main__":
    main()
