#!/usr/bin/env python3
"""summarize_pillar_estimators.py — the permeability estimators of pillar runs side by side
(issue 28, item 1; docs/mdpd.md, "One permeability estimator").

    scripts/summarize_pillar_estimators.py OUT.csv RUN.json ...

One row per run: the region's fluid fraction and pillar count, the three superficial velocities
(the paper's ε⟨u⟩, the region's flux Σu/(ρV_r), the box's flux Σu/(ρV)), Darcy with the paper's U_s
and with the box flux (the chosen estimator), eq. (3) as printed and over the region with its own
pillar density, the momentum balance (tethers on all pillars against the driving force), and the
ratios of each to the chosen estimator. For irregular layouts, a last row with the mean and its
standard error over the configurations (independent seeds).
"""
import csv
import json
import math
import os
import sys

FIELDS = ["region_fluid_fraction", "measured_pillars", "superficial_velocity", "superficial_velocity_region",
          "superficial_velocity_box", "kappa_darcy", "kappa_darcy_box", "kappa_drag_tether",
          "kappa_drag_tether_region", "tether_force_all_pillars", "driving_force_total",
          "kappa_darcy_relative_error", "kappa_drag_tether_relative_error"]


def main(argv):
    if len(argv) < 3:
        print(__doc__)
        return 2
    rows = []
    for path in argv[2:]:
        d = json.load(open(path))
        r = {"run": os.path.basename(path)[:-5], "layout": d["layout"], "porosity": d["porosity"]}
        r.update({k: d[k] for k in FIELDS})
        ref = d["kappa_darcy_box"]
        for k in ("kappa_darcy", "kappa_drag_tether", "kappa_drag_tether_region"):
            r[k + "_over_box"] = d[k] / ref
        r["momentum_balance"] = d["tether_force_all_pillars"] / d["driving_force_total"] - 1
        rows.append(r)
    irregular = [r for r in rows if r["layout"] == "irregular"]
    if len(irregular) > 1:
        mean = {"run": "mean of %d configurations" % len(irregular), "layout": "irregular",
                "porosity": irregular[0]["porosity"]}
        for k in rows[0]:
            if k in mean or not isinstance(irregular[0][k], (int, float)):
                continue
            xs = [r[k] for r in irregular]
            m = sum(xs) / len(xs)
            se = math.sqrt(sum((x - m) ** 2 for x in xs) / (len(xs) - 1) / len(xs))
            mean[k] = m
            mean[k + "_se"] = se
        rows.append(mean)
    keys = []
    for r in rows:
        keys += [k for k in r if k not in keys]
    with open(argv[1], "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        for r in rows:
            w.writerow({k: ("%.6g" % v if isinstance(v, float) else v) for k, v in r.items()})
    for r in rows:
        print("%-28s box %.4g  darcy(ε⟨u⟩) %.4g  eq3 %.4g  eq3 region %.4g  balance %+.2e" % (
            r["run"], r["kappa_darcy_box"], r["kappa_darcy"], r["kappa_drag_tether"], r["kappa_drag_tether_region"],
            r["momentum_balance"]))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
