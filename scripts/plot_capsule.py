#!/usr/bin/python3
"""Plots of the `capsule` driver (sph-microcapsules-constriction).

constriction: the measures against the centroid position x_c (Figs. 5 and 7: D_x, D_y, D_z, C_f,
C_r), one line per run of the sweep, and a snapshot of the capsule's xy mid-plane outline at
several x_c inside the channel (Figs. 6 and 10).
shear: the steady Taylor deformation D_xy and inclination θ/π against Ca (Fig. 3a, b).
resolution: D_x against x_c for one (Ca, η) at several resolutions Π (Fig. 4), and a CSV of D_x at
x_c = 3.5, 4, 4.5 d and its largest value inside the constriction for each, with the difference from the
finest Π (the runs' series interpolated linearly in x_c).

usage: plot_capsule.py constriction SWEEP.csv OUT.png SNAPSHOT.png
       plot_capsule.py shear SHEAR.csv OUT.png
       plot_capsule.py resolution OUT.png OUT.csv PI=SERIES.csv [PI=SERIES.csv ...]
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def number(text):
    try:
        return float(text)
    except ValueError:
        return math.nan


def constriction(sweep_path, png, snapshot_png):
    runs = read(sweep_path)
    names = [("Dx", "D∞,x"), ("Dy", "D∞,y"), ("Dz", "D∞,z"), ("Cf", "C_f"), ("Cr", "C_r")]
    fig, axes = plt.subplots(1, len(names), figsize=(4 * len(names), 3.6))
    for run in runs:
        rows = read(run["series_csv"])
        x = [number(r["x_c"]) for r in rows]
        label = "Ca %s, η %s (%s)" % (run["ca"], run["eta"], run["status"])
        for ax, (key, title) in zip(axes, names):
            ax.plot(x, [number(r[key]) for r in rows], label=label)
    for ax, (key, title) in zip(axes, names):
        ax.set_xlabel("x_c / d")
        ax.set_title(title)
        for edge in (3, 5):
            ax.axvline(edge, color="0.7", lw=0.8, ls="--")
    axes[3].set_ylim(-6, 6)
    axes[4].set_ylim(-6, 6)
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(png, dpi=120)

    fig, axes = plt.subplots(len(runs), 1, figsize=(10, 3.2 * len(runs)), squeeze=False)
    for ax, run in zip(axes[:, 0], runs):
        eta = number(run["eta_effective"])
        # Channel walls in the mid-plane (units of d): y = 0, 2; the constriction's blocks.
        ax.plot([0, 7], [0, 0], "k-", lw=1)
        ax.plot([0, 7], [2, 2], "k-", lw=1)
        lo, hi = 1 - eta / 2, 1 + eta / 2
        ax.fill([3, 5, 5, 3], [0, 0, lo, lo], color="0.8")
        ax.fill([3, 5, 5, 3], [hi, hi, 2, 2], color="0.8")
        sections = {}
        for r in read(run["sections_csv"]):
            sections.setdefault(r["x_c_target"], []).append((float(r["x"]), float(r["y"])))
        for target, pts in sorted(sections.items(), key=lambda kv: float(kv[0])):
            cx = sum(p[0] for p in pts) / len(pts)
            cy = sum(p[1] for p in pts) / len(pts)
            pts.sort(key=lambda p: math.atan2(p[1] - cy, p[0] - cx))
            pts.append(pts[0])
            ax.plot([p[0] for p in pts], [p[1] for p in pts], "-", lw=1.2, label="x_c = %s" % target)
        ax.set_aspect("equal")
        ax.set_xlim(0, 7)
        ax.set_ylim(-0.1, 2.1)
        ax.set_title("Ca %s, η %s: xy mid-plane outline (%s)" % (run["ca"], run["eta"], run["status"]))
        ax.set_xlabel("x / d")
        ax.set_ylabel("y / d")
    fig.tight_layout()
    fig.savefig(snapshot_png, dpi=120)


def shear(table_path, png):
    rows = read(table_path)
    ca = [number(r["ca"]) for r in rows]
    fig, (a, b) = plt.subplots(1, 2, figsize=(9, 3.6))
    a.errorbar(ca, [number(r["taylor_deformation"]) for r in rows],
               yerr=[number(r["taylor_deformation_std"]) for r in rows], fmt="o-")
    a.set_xlabel("Ca")
    a.set_ylabel("D_xy")
    b.errorbar(ca, [number(r["inclination_over_pi"]) for r in rows],
               yerr=[number(r["inclination_over_pi_std"]) for r in rows], fmt="o-")
    b.set_xlabel("Ca")
    b.set_ylabel("θ/π")
    fig.tight_layout()
    fig.savefig(png, dpi=120)


def interpolate(xs, ys, x):
    """ys at x by linear interpolation in the first crossing of x along the (monotone) series."""
    for k in range(1, len(xs)):
        if (xs[k - 1] - x) * (xs[k] - x) <= 0 and xs[k] != xs[k - 1]:
            return ys[k - 1] + (ys[k] - ys[k - 1]) * (x - xs[k - 1]) / (xs[k] - xs[k - 1])
    return math.nan


def resolution(png, table, runs):
    levels = []
    for run in runs:
        pi, path = run.split("=", 1)
        rows = read(path)
        levels.append((int(pi), [number(r["x_c"]) for r in rows], [number(r["Dx"]) for r in rows]))
    levels.sort()
    probes = (3.5, 4.0, 4.5)
    fig, ax = plt.subplots(figsize=(6, 4))
    for pi, x, dx in levels:
        ax.plot(x, dx, label="Π = %d" % pi)
    for edge in (3, 5):
        ax.axvline(edge, color="0.7", lw=0.8, ls="--")
    ax.set_xlabel("x_c / d")
    ax.set_ylabel("D∞,x")
    ax.set_title("Resolution study (Fig. 4)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(png, dpi=120)

    finest = levels[-1]
    ref = [interpolate(finest[1], finest[2], p) for p in probes]
    ref_max = max(d for x, d in zip(finest[1], finest[2]) if 3 <= x <= 5)
    with open(table, "w") as f:
        f.write("resolution,%s,max_Dx_in_constriction,%s,max_Dx_minus_finest\n" % (
            ",".join("Dx_at_%g" % p for p in probes), ",".join("Dx_at_%g_minus_finest" % p for p in probes)))
        for pi, x, dx in levels:
            at = [interpolate(x, dx, p) for p in probes]
            inside = max(d for xc, d in zip(x, dx) if 3 <= xc <= 5)
            f.write("%d,%s,%.6g,%s,%.6g\n" % (
                pi, ",".join("%.6g" % v for v in at), inside,
                ",".join("%.6g" % (v - r) for v, r in zip(at, ref)), inside - ref_max))


def main():
    if sys.argv[1] == "constriction":
        constriction(*sys.argv[2:5])
    elif sys.argv[1] == "resolution":
        resolution(sys.argv[2], sys.argv[3], sys.argv[4:])
    else:
        shear(*sys.argv[2:4])


if __name__ == "__main__":
    main()
