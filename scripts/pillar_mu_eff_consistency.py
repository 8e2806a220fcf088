#!/usr/bin/python3
"""pillar_mu_eff_consistency.py — why the Brinkman profile fit's μ_eff lies above the flux's (eq. 7) in the
walls study (issue 28, docs/mdpd.md "Pillar lattices between walls over ε").

    scripts/pillar_mu_eff_consistency.py WALLS3D.csv SEED_SPREAD.csv S11_3D.json OUT_STEM [EXACT_TABLE.csv]

For every run of WALLS3D.csv (scripts/summarize_pillar_walls.py) whose fit is interior:
- flux_ratio: the fitted profile's mean, B_fit g(α_fit) with g(α) = 1 − tanh(αH/2)/(αH/2), over the
  measured superficial velocity B κ_eff/κ_p. Near 1 means the fit and eq. 7 describe the same flux, so
  the two μ_eff can differ only through the plateau B_fit against B = κ_p Δp/(μ L).
- mu_eff_eq7_midplane_kappa: eq. 7 solved with the mid-plane pillar permeability κ_p B_fit/B in place of
  the 2D κ_p: how much of the fit's μ_eff that plateau alone explains.
- mu_eff_fit_midplane_kappa: the fit's μ_eff with that same κ_p B_fit/B, μ/(α_fit² κ_p B_fit/B).
- sensitivity: d ln μ_eff / d ln κ_p of eq. 7 at the measured κ_eff (μ_eff = μ/(α²κ_p), g(α) = κ_eff/κ_p):
  the factor by which an error of κ_p is amplified in μ_eff from fluxes.
Then the mean B_fit/B over ε ≤ 0.8 against the 3D-periodic over 2D κ_p of Fig. S11 at ε = 0.7
(S11_3D.json, the 3D periodic run, over the mean of the SEED_SPREAD.csv runs with its box: 4 × 2 cells,
scripts/pillar_seed_spread.py), and the means per lattice at ε ≤ 0.8.
With EXACT_TABLE.csv (the Sangani–Acrivos exact κ/d² of the square lattice, sangani_acrivos_table.csv):
the pillar radius changes those κ_p offsets amount to. At fixed cell, κ = f(ε) d² with ε = 1 − πR²/L²,
so d ln κ/d ln R = 2 − 2(1 − ε) d ln f/dε (d ln f/dε from the table's neighbours of ε, a central
difference of ln f), and an offset κ/κ_ref = r is a radius change δR/R = ln r / (d ln κ/d ln R).
Writes OUT_STEM.csv and prints the summary.
"""
import csv
import json
import math
import statistics
import sys


def g(a, h):
    x = a * h / 2
    return 1 - math.tanh(x) / x


def solve_alpha(target, h):
    """α with g(α, h) = target (0 < target < 1; g rises monotonically from 0 to 1)."""
    lo, hi = 1e-6, 1e3
    for _ in range(200):
        mid = math.sqrt(lo * hi)
        if g(mid, h) < target:
            lo = mid
        else:
            hi = mid
    return math.sqrt(lo * hi)


def sensitivity(kappa_eff, kappa_p, h):
    a = solve_alpha(kappa_eff / kappa_p, h)
    da = 1e-6 * a
    dg = (g(a + da, h) - g(a - da, h)) / (2 * da)
    dlna_dlnkp = -(kappa_eff / kappa_p) / (a * dg)
    return -2 * dlna_dlnkp - 1


def main(argv):
    if len(argv) not in (5, 6):
        print(__doc__)
        return 2
    walls, spread, s11_3d, stem = argv[1:5]
    out = []
    for r in csv.DictReader(open(walls)):
        if r["alpha_at_bound"] == "True" or not r["alpha"]:
            continue
        h, kp, a = float(r["H"]), float(r["kappa_p"]), float(r["alpha"])
        bb, ke = float(r["B_fit_over_B"]), float(r["kappa_eff"])
        flux_ratio = bb * g(a, h) / (ke / kp)
        kp_mid = kp * bb
        mid = 1 / (solve_alpha(ke / kp_mid, h) ** 2 * kp_mid) if ke < kp_mid else float("nan")
        out.append({"run": r["run"], "layout": r["layout"], "porosity": float(r["porosity"]), "H": h,
                    "B_fit_over_B": bb, "B_fit_over_B_error": float(r["B_fit_over_B_error"]),
                    "flux_ratio": flux_ratio, "mu_eff_over_mu_fit": float(r["mu_eff_over_mu"]),
                    "mu_eff_over_mu_eq7": float(r["mu_eff_over_mu_eq7"]), "mu_eff_eq7_midplane_kappa": mid,
                    "mu_eff_fit_midplane_kappa": float(r["mu_eff_over_mu"]) / bb,
                    "sensitivity": sensitivity(ke, kp, h)})
    with open(stem + ".csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(out[0].keys()))
        w.writeheader()
        for r in out:
            w.writerow({k: (f"{v:.5g}" if isinstance(v, float) else v) for k, v in r.items()})
    band = [r for r in out if r["porosity"] <= 0.8 + 1e-9]
    fr = [r["flux_ratio"] for r in out]
    print(f"fitted profile's flux over the measured flux: {min(fr):.3f} to {max(fr):.3f} over {len(out)} runs")
    bbs = [r["B_fit_over_B"] for r in band]
    m, sd = statistics.mean(bbs), statistics.stdev(bbs)
    print(f"B_fit/B at eps <= 0.8: mean {m:.3f}, SD {sd:.3f}, standard error {sd / math.sqrt(len(bbs)):.3f} "
          f"({len(bbs)} runs)")
    ratio = [r["mu_eff_over_mu_fit"] / r["mu_eff_over_mu_eq7"] for r in band]
    rmid = [r["mu_eff_over_mu_fit"] / r["mu_eff_eq7_midplane_kappa"] for r in band]
    print(f"mu_eff fit / eq7 at eps <= 0.8: mean {statistics.mean(ratio):.2f} (SD {statistics.stdev(ratio):.2f}); "
          f"with kappa_p B_fit/B in eq. 7: mean {statistics.mean(rmid):.2f} (SD {statistics.stdev(rmid):.2f})")
    sens = [r["sensitivity"] for r in band]
    print(f"d ln mu_eff / d ln kappa_p of eq. 7 at eps <= 0.8: {min(sens):.1f} to {max(sens):.1f}, "
          f"median {statistics.median(sens):.1f}")
    for layout in sorted({r["layout"] for r in band}):
        sel = [r for r in band if r["layout"] == layout]
        for key in ("mu_eff_over_mu_fit", "mu_eff_over_mu_eq7", "mu_eff_eq7_midplane_kappa", "mu_eff_fit_midplane_kappa"):
            v = [r[key] for r in sel]
            print(f"{layout}, eps <= 0.8 ({len(v)} runs): {key} mean {statistics.mean(v):.2f} "
                  f"± {statistics.stdev(v) / math.sqrt(len(v)):.2f} (standard error)")
    d3 = json.load(open(s11_3d))
    k3 = d3["kappa_darcy_box"] / d3["diameter"] ** 2
    two_d = []
    for line in open(spread):  # the per-run rows (the file's summary block below them has other columns)
        f = line.strip().split(",")
        if not line.strip():
            break
        if f[0] != "run" and abs(float(f[2]) - d3["box"][0]) < 1e-3 and abs(float(f[3]) - d3["box"][1]) < 1e-3:
            two_d.append(float(f[5]))
    m2, s2 = statistics.mean(two_d), statistics.stdev(two_d)
    err = math.hypot(s2 / math.sqrt(len(two_d)) / m2, s2 / m2) * k3 / m2
    print(f"Fig. S11 at eps = {d3['porosity']:g}: 3D periodic kappa_p over the mean of {len(two_d)} 2D seeds of its cell "
          f"= {k3 / m2:.3f} ± {err:.3f} (the 2D seed spread for the 3D run too)")
    if len(argv) == 6:
        table = sorted((float(r["porosity"]), float(r["kappa_over_d2"])) for r in csv.DictReader(open(argv[5])))
        eps = d3["porosity"]
        i = min(range(1, len(table) - 1), key=lambda j: abs(table[j][0] - eps))
        if abs(table[i][0] - eps) > 1e-9:
            raise SystemExit(f"pillar_mu_eff_consistency: eps = {eps} is not a row of {argv[5]}")
        (e0, f0), (_, f1), (e2, f2) = table[i - 1], table[i], table[i + 1]
        dlnf = (math.log(f2) - math.log(f0)) / (e2 - e0)
        slope = 2 - 2 * (1 - eps) * dlnf
        radius = d3["diameter"] / 2
        se2 = s2 / math.sqrt(len(two_d)) / m2  # relative standard error of the 2D mean

        def line(what, ratio, rel_err):
            dr = math.log(ratio) / slope
            dr_err = rel_err / abs(slope)
            return (f"{what}: kappa ratio {ratio:.3f} ± {rel_err * ratio:.3f} = a radius change dR/R = "
                    f"{100 * dr:+.1f}% ± {100 * dr_err:.1f}% ({dr * radius:+.3f} ± {dr_err * radius:.3f} r_c)")
        print(f"effective radius at eps = {eps:g} (R = {radius:.3f} r_c, d ln kappa/d ln R = {slope:.2f}, "
              f"d ln f/d eps = {dlnf:.2f} from the exact table):")
        print("  " + line("2D mean of its cell against exact", m2 / f1, se2))
        print("  " + line("3D periodic against the 2D mean", k3 / m2, err / (k3 / m2)))
        print("  " + line("3D periodic against exact", k3 / f1, d3["kappa_darcy_box_relative_error"]))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
