#!/usr/bin/env python3
"""fit_walls_profile.py — the walls-only channel of the pillar study (issue 28, item 1): a parabola
fitted to the bin means u(z) of a `pillars --layout none` run (each bin the average of A − Bz² over
its width), its no-slip planes ±√(A/B) against ±H/2 (the slip), the viscosity from its curvature
(−dp/dx = 2μB, −dp/dx = f_b ρ L_d/L_x), and κ = μ⟨u⟩L_x/Δp against H²/12 for a given μ, with the
run's block error.

    scripts/fit_walls_profile.py RUN.json RUN_profile.csv MU OUT.json
"""
import csv
import json
import math
import sys


def fit_parabola(z, u, half_bin):
    """Least squares of u = A − B(z² + h²/3) (the bin average of A − Bz² over ±h): (A, B)."""
    x = [-(zi * zi + half_bin * half_bin / 3) for zi in z]
    n, sx, sxx = len(x), sum(x), sum(xi * xi for xi in x)
    sy, sxy = sum(u), sum(xi * ui for xi, ui in zip(x, u))
    B = (n * sxy - sx * sy) / (n * sxx - sx * sx)
    A = (sy - B * sx) / n
    return A, B


def main(argv):
    if len(argv) != 5:
        print(__doc__)
        return 2
    run = json.load(open(argv[1]))
    rows = list(csv.DictReader(open(argv[2])))
    mu = float(argv[3])
    z = [float(r["z"]) for r in rows]
    u = [float(r["mean_ux"]) for r in rows]
    half_bin = 0.5 * (z[1] - z[0])
    H = run["walls_height"]
    gradient = run["pressure_difference"] / run["box"][0]
    out = {"run": argv[1], "H": H, "viscosity": mu, "fits": []}
    for excluded in (0, 1):  # all bins; without the bin at each wall
        s = slice(excluded, len(z) - excluded)
        A, B = fit_parabola(z[s], u[s], half_bin)
        w = math.sqrt(A / B)
        out["fits"].append({"bins_excluded_at_each_wall": excluded, "no_slip_half_width": w,
                            "slip": w - H / 2, "viscosity_from_curvature": gradient / (2 * B)})
    kappa = mu * run["mean_ux"] * run["box"][0] / run["pressure_difference"]
    out["kappa"] = kappa
    out["kappa_relative_error"] = run["kappa_darcy_relative_error"]
    out["kappa_walls_theory"] = H * H / 12
    out["kappa_over_theory"] = kappa / (H * H / 12)
    out["kappa_volume_average_over_theory"] = mu * (sum(u) / len(u)) * run["box"][0] / run["pressure_difference"] / (H * H / 12)
    json.dump(out, open(argv[4], "w"), indent=2)
    print(json.dumps(out, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
