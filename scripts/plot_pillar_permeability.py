#!/usr/bin/python3
"""Permeability of regular pillar arrays against porosity (Soft Matter 19, 436 (2023), Fig. 7b and
Fig. S11): `pillars` runs (their JSON summaries) over the theory curves that `pillars --mode theory`
writes and Sangani & Acrivos' exact values; a CSV of every run beside the plot.

usage: plot_pillar_permeability.py THEORY.csv SA_TABLE.csv OUT.png OUT.csv RUN.json [RUN.json ...]

κ_p is the chosen estimator (docs/mdpd.md, issue 28 item 1): Darcy over the whole period with the box
flux, `kappa_darcy_box`, with its block error (`kappa_darcy_box_relative_error`); the tether drag of
eq. (3) is drawn beside it. Runs are grouped by (dimension, layout): 2D square lattices are Fig. 7b;
3D square lattices periodic in z are Fig. S11, which the paper shows to agree with 2D. For each 3D run
with 2D runs of the same layout and porosity, the CSV gives the ratio κ_p(3D)/⟨κ_p(2D)⟩ over those
runs and its error (the 3D block error in quadrature with the 2D mean's: the standard error over the
2D runs' seeds where there are several, else the one run's block error) — the S11 check.
"""
import csv
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def column(rows, key):
    return [float(r[key]) for r in rows]


def sangani_acrivos(table, eps):
    """The exact value at this porosity, if the table has it."""
    for r in table:
        if abs(float(r["porosity"]) - eps) < 1e-9:
            return float(r["kappa_over_d2"])
    return None


def main():
    if len(sys.argv) < 6:
        print(__doc__)
        return 2
    theory_path, table_path, png, out_csv = sys.argv[1:5]
    runs = []
    for p in sys.argv[5:]:
        d = json.load(open(p))
        d["_name"] = os.path.basename(p)[:-5]
        runs.append(d)
    theory = list(csv.DictReader(open(theory_path)))
    table = list(csv.DictReader(open(table_path)))

    rows = []
    for d in sorted(runs, key=lambda r: (r["dimension"], r["layout"], r["porosity"])):
        d2 = d["diameter"] ** 2
        k = d["kappa_darcy_box"] / d2
        row = {"run": d["_name"], "dimension": d["dimension"], "layout": d["layout"], "porosity": d["porosity"],
               "box": " x ".join(f"{x:.3f}" for x in d["box"] if x > 0), "particles": d["particles"],
               "driving_force": d["driving_force"], "samples": d["samples"],
               "kappa_p_over_d2": k, "kappa_p_relative_error": d["kappa_darcy_box_relative_error"],
               "kappa_drag_tether_over_d2": d["kappa_drag_tether"] / d2,
               "tether_over_darcy_box": d["kappa_drag_tether"] / d["kappa_darcy_box"],
               "momentum_balance": d["tether_force_all_pillars"] / d["driving_force_total"] - 1}
        sa = sangani_acrivos(table, d["porosity"]) if d["layout"] == "square" else None
        row["sangani_acrivos_exact"] = sa if sa is not None else ""
        row["deviation_from_exact"] = k / sa - 1 if sa is not None else ""
        row["ratio_to_2d"] = row["ratio_to_2d_error"] = row["runs_2d"] = ""
        if d["dimension"] == 3:
            twins = [r for r in runs if r["dimension"] == 2 and r["layout"] == d["layout"]
                     and abs(r["porosity"] - d["porosity"]) < 1e-9]
            if twins:
                k2 = [t["kappa_darcy_box"] for t in twins]
                mean2 = sum(k2) / len(k2)
                if len(k2) >= 2:  # independent seeds: the standard error of their mean
                    rel2 = math.sqrt(sum((k - mean2) ** 2 for k in k2) / (len(k2) - 1) / len(k2)) / mean2
                else:  # one run: its block error
                    rel2 = twins[0]["kappa_darcy_box_relative_error"]
                row["runs_2d"] = len(k2)
                row["ratio_to_2d"] = d["kappa_darcy_box"] / mean2
                row["ratio_to_2d_error"] = row["ratio_to_2d"] * math.hypot(d["kappa_darcy_box_relative_error"], rel2)
        rows.append(row)
    with open(out_csv, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})

    fig, ax = plt.subplots(figsize=(6.4, 4.8))
    eps = column(theory, "porosity")
    for key, label, style in [("gebart_square", "Gebart (G)", "-"),
                              ("drummond_tahir_square", "Drummond-Tahir (DT)", "--"),
                              ("sangani_acrivos_dense", "Sangani-Acrivos dense limit", ":")]:
        ax.semilogy(eps, column(theory, key), style, lw=1, label=label)
    ax.semilogy(column(table, "porosity"), column(table, "kappa_over_d2"), "k+", ms=9,
                label="Sangani-Acrivos exact (Table 1)")
    styles = {(2, "square"): ("o", "C0", "MDPD 2D square"), (3, "square"): ("D", "C3", "MDPD 3D square, periodic z (S11)"),
              (2, "rotated-square"): ("^", "C2", "MDPD 2D rotated square"),
              (2, "hexagonal"): ("h", "C4", "MDPD 2D hexagonal")}
    for (dim, layout), (marker, color, label) in styles.items():
        sel = [r for r in rows if r["dimension"] == dim and r["layout"] == layout]
        if not sel:
            continue
        x = [r["porosity"] + (0.004 if dim == 3 else 0) for r in sel]
        y = [r["kappa_p_over_d2"] for r in sel]
        ax.errorbar(x, y, yerr=[v * r["kappa_p_relative_error"] for v, r in zip(y, sel)], fmt=marker, color=color,
                    mfc="none" if dim == 3 else color, ms=6, capsize=2, label=label + ", Darcy (box flux)")
        if dim == 2 and layout == "square":
            ax.semilogy([r["porosity"] for r in sel], [r["kappa_drag_tether_over_d2"] for r in sel], "s", color=color,
                        mfc="none", ms=8, label="MDPD 2D square, tether drag (eq. 3)")
    ax.set_xlabel("porosity ε")
    ax.set_ylabel("κ_p / d²")
    ax.set_xlim(0.5, 1.0)
    ax.set_ylim(3e-3, 1)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(png, dpi=120)
    return 0


if __name__ == "__main__":
    sys.exit(main())
