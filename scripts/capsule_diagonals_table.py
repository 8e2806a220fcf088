#!/usr/bin/python3
"""Issue 29 item 4: the two membrane networks side by side (scripts/reproduce_capsule diagonals).

Reads, per network (one diagonal per quad: the paper's 25 602-bond count; both: the crossed network
with §4's E and ν), the shear run's summary JSON (its "membrane" block: G_s and K_A per k_b measured
on a patch at the mesh's h_t/δ_ave, and §4's formula) and its series CSV, and writes one row per
network: the moduli, the driver's steady D_xy and θ/π (mean over the last 30% of the run, ± the standard
deviation of the samples, from <name>_shear.csv), and the drift of D_xy over that window (a
least-squares line's change across γ̇t ∈ [0.7, 1] t_max of the series), which says whether the run is
steady at the level of the difference.

usage: capsule_diagonals_table.py <run dir> <out.csv>
"""
import csv
import json
import os
import sys


def window_range(series_csv, start=None, end=None, fraction=0.3, blocks=4):
    """D_xy of a series over γ̇t ∈ [start, end] (default: the last `fraction` of the run): mean, sample
    std, drift (a least-squares line's change across the window), θ/π mean, sample count, and the
    standard error from `blocks` consecutive blocks of the window (the samples are correlated)."""
    rows = list(csv.DictReader(open(series_csv)))
    t = [float(r["shear_time"]) for r in rows]
    d = [float(r["taylor_deformation"]) for r in rows]
    theta = [float(r["inclination_over_pi"]) for r in rows]
    start = (1 - fraction) * t[-1] if start is None else start
    end = t[-1] if end is None else end
    w = [(a, b, c) for a, b, c in zip(t, d, theta) if start - 1e-9 <= a <= end + 1e-9]
    n = len(w)
    tm = sum(a for a, _, _ in w) / n
    dm = sum(b for _, b, _ in w) / n
    thm = sum(c for _, _, c in w) / n
    d_std = (sum((b - dm) ** 2 for _, b, _ in w) / (n - 1)) ** 0.5
    slope = sum((a - tm) * (b - dm) for a, b, _ in w) / sum((a - tm) ** 2 for a, _, _ in w)
    size = n // blocks
    means = [sum(b for _, b, _ in w[k * size:(k + 1) * size]) / size for k in range(blocks)]
    mb = sum(means) / blocks
    block_error = (sum((m - mb) ** 2 for m in means) / (blocks - 1) / blocks) ** 0.5
    return {"mean": dm, "std": d_std, "drift": slope * (w[-1][0] - w[0][0]), "theta": thm, "n": n,
            "block_error": block_error}


def window_stats(series_csv, fraction=0.3):
    w = window_range(series_csv, fraction=fraction)
    return w["mean"], w["std"], w["theta"], w["drift"], w["n"]


def main():
    run_dir, out_csv = sys.argv[1:3]
    with open(out_csv, "w", newline="") as f:
        out = csv.writer(f)
        out.writerow(["diagonals", "thickness_over_spacing", "shear_modulus_network_over_k_b",
                      "area_modulus_network_over_k_b", "shear_modulus_paper_formula_over_k_b", "ca_network",
                      "ca_paper_formula", "taylor_deformation", "taylor_deformation_std", "drift_over_window",
                      "inclination_over_pi", "window_samples"])
        for name in ("one", "both"):
            m = json.load(open(os.path.join(run_dir, name + ".json")))["membrane"]
            row = next(csv.DictReader(open(os.path.join(run_dir, name + "_shear.csv"))))
            ca = float(row["ca"])
            _, _, _, drift, n = window_stats(os.path.join(run_dir, f"{name}_shear_ca{ca:g}_series.csv"))
            dm, d_std, thm = float(row["taylor_deformation"]), float(row["taylor_deformation_std"]), \
                float(row["inclination_over_pi"])
            ca_formula = ca * m["ca_paper_formula_over_ca_network"]
            out.writerow([name, f"{m['thickness_over_spacing']:.5g}", f"{m['shear_modulus_network_over_k_b']:.5g}",
                          f"{m['area_modulus_network_over_k_b']:.5g}",
                          f"{m['shear_modulus_paper_formula_over_k_b']:.5g}", f"{ca:g}", f"{ca_formula:.4g}",
                          f"{dm:.4f}", f"{d_std:.4f}", f"{drift:+.4f}", f"{thm:.4f}", n])
            print(f"{name}: G_s = {m['shear_modulus_network_over_k_b']:.4f} k_b, K_A = "
                  f"{m['area_modulus_network_over_k_b']:.4f} k_b; at Ca = {ca:g} (network) D_xy = {dm:.4f} ± "
                  f"{d_std:.4f}, drift {drift:+.4f} over the window, theta/pi = {thm:.4f}")


if __name__ == "__main__":
    main()
