#!/usr/bin/env python3
"""pillar_seed_spread.py — κ_p of one pillar lattice over independent seeds (issue 28, the 2D-3D gap
at ε = 0.7; docs/mdpd.md, Fig. S11).

    scripts/pillar_seed_spread.py OUT.csv RUN.json ...

One row per run (cells, seed, κ_p/d² by the chosen estimator with its block error, the difference
from Sangani & Acrivos's exact value at that porosity when it is tabulated), then per cell count the
mean, the standard deviation between seeds and the mean block error: each seed carves its own
pillar surfaces, so the seeds spread by more than one run's block error says.
"""
import csv
import json
import math
import sys

EXACT = {0.6: 0.0090114067, 0.7: 0.025442117, 0.8: 0.076207856, 0.9: 0.31631017}  # κ/d², Sangani-Acrivos


def main(argv):
    if len(argv) < 3:
        print(__doc__)
        return 2
    rows = []
    for path in argv[2:]:
        d = json.load(open(path))
        box = d["box"]
        eps = round(d["porosity"], 6)
        k = d["kappa_darcy_box"] / d["diameter"] ** 2
        rows.append({"run": path.split("/")[-1][:-5], "porosity": eps, "box_x": box[0], "box_y": box[1],
                     "particles": d["particles"], "kappa_over_d2": k,
                     "block_error": k * d["kappa_darcy_box_relative_error"],
                     "vs_exact": k / EXACT[eps] - 1 if eps in EXACT else float("nan")})
    groups = {}
    for r in rows:
        groups.setdefault((r["porosity"], round(r["box_x"], 6), round(r["box_y"], 6)), []).append(r)
    with open(argv[1], "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["run", "porosity", "box_x", "box_y", "particles", "kappa_over_d2", "block_error", "vs_exact"])
        for r in rows:
            w.writerow([r["run"], r["porosity"], f"{r['box_x']:.4f}", f"{r['box_y']:.4f}", r["particles"],
                        f"{r['kappa_over_d2']:.6g}", f"{r['block_error']:.3g}", f"{r['vs_exact']:+.4f}"])
        w.writerow([])
        w.writerow(["porosity", "box_x", "box_y", "seeds", "mean", "sd_between_seeds", "mean_block_error",
                    "mean_vs_exact", "standard_error_of_mean"])
        for (eps, bx, by), g in sorted(groups.items()):
            k = [r["kappa_over_d2"] for r in g]
            m = sum(k) / len(k)
            sd = math.sqrt(sum((x - m) ** 2 for x in k) / (len(k) - 1)) if len(k) > 1 else float("nan")
            be = sum(r["block_error"] for r in g) / len(g)
            vs = m / EXACT[eps] - 1 if eps in EXACT else float("nan")
            w.writerow([eps, f"{bx:.4f}", f"{by:.4f}", len(k), f"{m:.6g}", f"{sd:.3g}", f"{be:.3g}", f"{vs:+.4f}",
                        f"{sd / math.sqrt(len(k)):.3g}"])
            print(f"eps {eps} box {bx:.2f} x {by:.2f}: {len(k)} seeds, mean {m:.5f} ({vs:+.1%} from exact), "
                  f"SD {sd:.5f} ({sd / m:.1%}), mean block error {be:.5f} ({be / m:.1%})")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
