#!/usr/bin/env python3
"""Plot a deformation CSV (from the `deformation` driver): the deformation delta_s/sigma of a droplet
under its own weight (capillary-droplets paper, Fig. 7b) against the swept parameter, line tension
Gamma (DP) or wall stiffness E_w (SP, with the exact pi/(16 E_w)).

usage: plot_deformation.py DEFORMATION.csv OUT.png
"""
import argparse
import csv

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("csv")
    ap.add_argument("png")
    args = ap.parse_args()
    with open(args.csv, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise SystemExit(f"{args.csv}: no rows")
    dp = "line_tension" in rows[0]
    key = "line_tension" if dp else "sp_wall_energy"
    x = [float(r[key]) for r in rows]
    fig, ax = plt.subplots(figsize=(5, 4))
    ax.plot(x, [float(r["sinking_depth"]) for r in rows], "o-", label=r"centre of mass")
    if dp:
        ax.plot(x, [float(r["centroid_sinking"]) for r in rows], "s--", label="area centroid")
        ax.set_xlabel(r"line tension $\Gamma$")
    else:
        ax.plot(x, [float(r["sinking_depth_exact"]) for r in rows], "k:", label=r"exact $\pi/(16E_w)$")
        ax.set_xlabel(r"wall stiffness $E_w$")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_ylabel(r"$\delta_s/\sigma$")
    ax.set_title("DP" if dp else "SP")
    ax.legend()
    fig.tight_layout()
    fig.savefig(args.png, dpi=120)


if __name__ == "__main__":
    main()
