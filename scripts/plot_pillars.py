#!/usr/bin/python3
"""Plot the superficial velocity profile u_s(z) of a 3D pillar run with walls (Soft Matter 19, 436
(2023), Fig. 10) and its Brinkman fit, eq. (5), with the pillar force density f_p(z) (Fig. 13a) on a
second axis. Reads the <out>_profile.csv and <out>.json that the `pillars` driver writes.

usage: plot_pillars.py PROFILE.csv SUMMARY.json OUT.png
"""
import csv
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    profile_path, summary_path, png = sys.argv[1:4]
    with open(profile_path) as f:
        rows = list(csv.DictReader(f))
    with open(summary_path) as f:
        summary = json.load(f)
    z = [float(r["z"]) for r in rows]
    u_s = [float(r["u_s"]) for r in rows]
    fit = [float(r["brinkman_fit"]) for r in rows]
    force = [float(r["pillar_force_density"]) for r in rows]
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(z, u_s, "o", label="simulation u_s(z)")
    if "brinkman" in summary:
        b = summary["brinkman"]
        label = f"Brinkman eq. (5): B = {b['B']:.3g}, alpha = {b['alpha']:.3g}"
        if "mu_eff_over_mu" in b:
            label += f", mu_eff/mu = {b['mu_eff_over_mu']:.2f}"
        ax.plot(z, fit, "-", label=label)
    ax.set_xlabel("z / sigma (0: mid-plane)")
    ax.set_ylabel("u_s / (sigma/tau)")
    ax2 = ax.twinx()
    ax2.plot(z, force, "s", color="tab:red", alpha=0.5, label="pillar force density f_p(z)")
    ax2.set_ylabel("f_p", color="tab:red")
    ax.set_title(f"{summary['layout']} pillars, porosity {summary['porosity']:.3f}, H = {summary['walls_height']}")
    ax.legend(loc="lower center", fontsize=8)
    fig.tight_layout()
    fig.savefig(png, dpi=120)


if __name__ == "__main__":
    main()
