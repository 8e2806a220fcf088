#!/usr/bin/python3
"""pillar_walls_forces.py — the walls study at three driving forces per porosity, as the paper's Fig. 11
error bars for the regular lattices ("standard deviations across three driving forces"; issue 28).

    scripts/pillar_walls_forces.py OUT_STEM WALLS3D_DIR FORCES_DIR

For every 3D run <layout>_<ε>_H<h>_fb<f>.json in FORCES_DIR, the walls study's run <layout>_<ε>_H<h>.json
(WALLS3D_DIR, its own f_b) is the third force. All runs of one (layout, ε) were given the same κ_p (the
first 2D seed, as the driver's JSON has it), so their Brinkman fits differ only by the force and the
noise: per force κ_eff (Darcy over the box), B_fit/B, α, μ_eff/μ of the fit with its jackknife error;
per (layout, ε) the mean and standard deviation over the forces of μ_eff/μ and B_fit/B, and κ_eff's
spread over the forces relative to its mean against the runs' block errors (linear response: κ_eff
should not depend on f_b). Writes OUT_STEM.csv and prints the summary.
"""
import csv
import glob
import json
import os
import re
import statistics
import sys


def record(path, force=None):
    d = json.load(open(path))
    b = d["brinkman"]
    return {"run": os.path.basename(path)[:-5], "layout": d["layout"], "porosity": round(d["porosity"], 6),
            "H": d["walls_height"], "driving_force": d["driving_force"] if force is None else force,
            "kappa_p_given": b["kappa_p"], "kappa_eff": d["kappa_darcy_box"],
            "kappa_eff_error": d["kappa_darcy_box"] * d["kappa_darcy_box_relative_error"],
            "alpha": b["alpha"], "alpha_error": b["alpha_error"], "alpha_at_bound": b["alpha_at_bound"],
            "B_fit_over_B": b["B"] / b["B_theory"], "mu_eff_over_mu": b["mu_eff_over_mu"],
            "mu_eff_over_mu_error": b["mu_eff_over_mu_error_alpha"]}


def main(argv):
    if len(argv) != 4:
        print(__doc__)
        return 2
    stem, walls, forces = argv[1:]
    rows = []
    groups = {}
    for path in sorted(glob.glob(os.path.join(forces, "*_H*_fb*.json"))):
        m = re.match(r"(.+_H[0-9.]+)_fb([0-9.]+)\.json$", os.path.basename(path))
        if not m:
            continue
        groups.setdefault(m.group(1), []).append(path)
    for base, paths in sorted(groups.items()):
        ref = os.path.join(walls, base + ".json")
        group = ([record(ref)] if os.path.exists(ref) else []) + [record(p) for p in paths]
        group.sort(key=lambda r: r["driving_force"])
        rows += group
    with open(stem + ".csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})
    keys = sorted({(r["layout"], r["porosity"], r["H"]) for r in rows})
    for layout, eps, h in keys:
        g = [r for r in rows if (r["layout"], r["porosity"], r["H"]) == (layout, eps, h)]
        forces_text = ", ".join(f"f_b {r['driving_force']:g}: mu_eff/mu {r['mu_eff_over_mu']:.2f} ± "
                                f"{r['mu_eff_over_mu_error']:.2f}, B_fit/B {r['B_fit_over_B']:.3f}, "
                                f"kappa_eff {r['kappa_eff']:.4f} ± {r['kappa_eff_error']:.4f}" for r in g)
        print(f"{layout} eps {eps:g} H {h:g}: {forces_text}")
        if len(g) >= 2:
            mu = [r["mu_eff_over_mu"] for r in g]
            bb = [r["B_fit_over_B"] for r in g]
            ke = [r["kappa_eff"] for r in g]
            spread = statistics.stdev(ke) / statistics.mean(ke)
            block = statistics.mean(r["kappa_eff_error"] / r["kappa_eff"] for r in g)
            print(f"  over {len(g)} forces: mu_eff/mu {statistics.mean(mu):.2f}, SD {statistics.stdev(mu):.2f}; "
                  f"B_fit/B {statistics.mean(bb):.3f}, SD {statistics.stdev(bb):.3f}; kappa_eff spread "
                  f"{100 * spread:.1f}% against a mean block error of {100 * block:.1f}%")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
