#!/usr/bin/python3
"""Plot an orifice profile CSV (from the `orifice` driver): v_g/v_t and the shape parameter
against the distance h/sigma of the droplet's centre of mass from the orifice (capillary-droplets
paper, Fig. 2c-d). Extra CSVs (--compare) are overlaid, e.g. a measured profile or another run.

usage: plot_orifice_profile.py PROFILE.csv OUT.png [--label LABEL] [--compare OTHER.csv LABEL]...
"""
import argparse
import csv

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise SystemExit(f"{path}: no rows")
    return {k: [float(r[k]) for r in rows] for k in rows[0]}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("profile")
    ap.add_argument("png")
    ap.add_argument("--label", default="simulation", help="legend label of PROFILE.csv")
    ap.add_argument("--compare", nargs=2, action="append", default=[], metavar=("CSV", "LABEL"))
    args = ap.parse_args()
    runs = [(read(args.profile), args.label)] + [(read(p), label) for p, label in args.compare]
    fig, (ax_v, ax_a) = plt.subplots(2, 1, sharex=True, figsize=(5, 6))
    for data, label in runs:
        if "vg_over_vt" in data:
            ax_v.plot(data["h"], data["vg_over_vt"], label=label)
        if "shape_parameter" in data:
            ax_a.plot(data["h"], data["shape_parameter"], label=label)
    ax_v.axhline(1.0, color="grey", lw=0.5)
    ax_v.axvline(0.0, color="grey", lw=0.5)
    ax_a.axvline(0.0, color="grey", lw=0.5)
    ax_v.set_ylabel(r"$v_g / v_t$")
    ax_a.set_ylabel(r"shape parameter $\mathcal{A}$")
    ax_a.set_xlabel(r"$h/\sigma$")
    ax_v.set_xlim(-1.5, 1.0)
    if len(runs) > 1:
        ax_v.legend()
    fig.tight_layout()
    fig.savefig(args.png, dpi=120)


if __name__ == "__main__":
    main()
