#!/usr/bin/python3
"""Issue 29 item 2 (part): the capsule in simple shear at capillary numbers of the network's measured G_s
(scripts/reproduce_capsule shear_network), one table for the three run groups, with how steady each
run is: the driver's D_xy and θ/π (mean over the last 30% of the run, ± the standard deviation of the
samples) and the drift of D_xy across that window (a least-squares line's change over it). A run whose
|drift| exceeds its standard deviation is marked not steady. The neo-Hookean values of other codes at
Ca = 0.3 and 0.6 (see capsule_ca_network.py for the sources and the Ca conversion) are added to the plot.

usage: capsule_shear_network_table.py <run dir> <out stem> [<converted formula-Ca table csv>]
       (writes <stem>.csv and <stem>.png)
"""
import csv
import glob
import os
import sys

from capsule_ca_network import REFERENCES
from capsule_diagonals_table import window_stats


def main():
    run_dir, stem = sys.argv[1:3]
    rows = []
    for table in sorted(glob.glob(os.path.join(run_dir, "*_shear.csv"))):
        group = os.path.basename(table)[: -len("_shear.csv")]
        for r in csv.DictReader(open(table)):
            ca = float(r["ca"])
            series = os.path.join(run_dir, f"{group}_shear_ca{ca:g}_series.csv")
            _, _, _, drift, n = window_stats(series)
            d_std = float(r["taylor_deformation_std"])
            rows.append({"ca_network": ca, "shear_time": float(r["shear_time"]),
                         "taylor_deformation": float(r["taylor_deformation"]), "taylor_deformation_std": d_std,
                         "drift_over_window": drift, "steady": abs(drift) <= d_std,
                         "inclination_over_pi": float(r["inclination_over_pi"]),
                         "inclination_over_pi_std": float(r["inclination_over_pi_std"]),
                         "dt_gamma": float(r["dt_gamma"]), "max_density_deviation": float(r["max_density_deviation"]),
                         "wall_seconds": float(r["wall_seconds"]), "group": group})
    rows.sort(key=lambda r: r["ca_network"])
    with open(stem + ".csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})
    for r in rows:
        print(f"Ca {r['ca_network']:g} (gamma t {r['shear_time']:g}): D_xy {r['taylor_deformation']:.4f} ± "
              f"{r['taylor_deformation_std']:.4f}, drift {r['drift_over_window']:+.4f} "
              f"({'steady' if r['steady'] else 'NOT steady'}), theta/pi {r['inclination_over_pi']:.4f}")
    low = [r for r in rows if r["ca_network"] <= 0.05]
    print("D_xy/Ca at Ca <= 0.05: " + ", ".join(f"{r['taylor_deformation'] / r['ca_network']:.2f}" for r in low))
    for ca, ref, source in REFERENCES:
        match = [r for r in rows if abs(r["ca_network"] - ca) < 1e-12]
        if match:
            d = match[0]["taylor_deformation"]
            print(f"Ca {ca}: ours {d:.4f}, {source} {ref} (ratio {d / ref:.2f})")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(5.2, 3.8))
    ax.errorbar([r["ca_network"] for r in rows], [r["taylor_deformation"] for r in rows],
                yerr=[r["taylor_deformation_std"] for r in rows], fmt="o-", color="C0",
                label="ours, Ca of the network's G_s (direct runs)")
    if len(sys.argv) > 3:
        lines = (line for line in open(sys.argv[3]) if not line.startswith("#"))
        conv = [r for r in csv.DictReader(lines) if r.get("ca_network")]
        ax.plot([float(r["ca_network"]) for r in conv], [float(r["taylor_deformation"]) for r in conv], "s",
                mfc="none", color="0.5", label="ours, formula-Ca runs converted")
    for k, (ca, ref, source) in enumerate(REFERENCES):
        ax.plot([ca], [ref], "x^v"[k], color="C3", label=f"neo-Hookean, {source}")
    ax.set_xscale("log")
    ax.set_xlabel("Ca = μ γ̇ a / G_s (network)")
    ax.set_ylabel("D_xy")
    ax.set_title("capsule in simple shear, Π = 8, Re = 0.5", fontsize=9)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(stem + ".png", dpi=120)


if __name__ == "__main__":
    main()
