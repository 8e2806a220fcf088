#!/usr/bin/python3
"""Permeability of square pillar arrays against porosity (Soft Matter 19, 436 (2023), Fig. 7b):
simulation points from `pillars` runs (their JSON summaries; Darcy and tether-drag estimates) over
the theory curves that `pillars --mode theory` writes, and Sangani & Acrivos' exact values.

usage: plot_pillar_permeability.py THEORY.csv SA_TABLE.csv OUT.png RUN.json [RUN.json ...]
"""
import csv
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def column(rows, key):
    return [float(r[key]) for r in rows]


def main():
    theory_path, table_path, png = sys.argv[1:4]
    runs = [json.load(open(p)) for p in sys.argv[4:]]
    theory = list(csv.DictReader(open(theory_path)))
    table = list(csv.DictReader(open(table_path)))
    eps = column(theory, "porosity")
    fig, ax = plt.subplots(figsize=(6, 4.5))
    for key, label, style in [("gebart_square", "Gebart (G)", "-"),
                              ("drummond_tahir_square", "Drummond-Tahir (DT)", "--"),
                              ("sangani_acrivos_dense", "Sangani-Acrivos dense limit", ":"),
                              ("tsay_weinbaum_fit", "Tsay-Weinbaum fit (unverified)", "-.")]:
        ax.semilogy(eps, column(theory, key), style, label=label)
    ax.semilogy(column(table, "porosity"), column(table, "kappa_over_d2"), "k+", ms=9,
                label="Sangani-Acrivos exact (Table 1)")
    runs = sorted(runs, key=lambda r: r["porosity"])
    d2 = [r["diameter"] ** 2 for r in runs]
    ax.semilogy([r["porosity"] for r in runs], [r["kappa_darcy"] / s for r, s in zip(runs, d2)], "o",
                label="MDPD 2D, Darcy (eqs. 1-2)")
    ax.semilogy([r["porosity"] for r in runs], [r["kappa_drag_tether"] / s for r, s in zip(runs, d2)], "s",
                mfc="none", label="MDPD 2D, pillar drag (eq. 3, tethers)")
    ax.set_xlabel("porosity")
    ax.set_ylabel("kappa_p / d^2")
    ax.set_xlim(0.5, 1.0)
    ax.set_ylim(1e-3, 2)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(png, dpi=120)


if __name__ == "__main__":
    main()
