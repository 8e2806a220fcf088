#!/usr/bin/python3
"""Summary of `scripts/reproduce_capillary overshoot` (issue 25, item 5): max v_g/v_t after the orifice
against the near-wall drag floor d_min/σ and the vertex diameter δ/l0.

usage: summarize_overshoot.py DIR   (reads DIR/*.json of the orifice runs; writes DIR/overshoot.{csv,json,png})
"""
import csv
import glob
import json
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from profile_landmarks import landmarks, read_profile  # noqa: E402  (the §4.1 landmarks, one definition)

d = sys.argv[1]
rows = []
for path in sorted(glob.glob(os.path.join(d, "*.json"))):
    name = os.path.basename(path)[:-5]
    m = re.match(r"(fig3d|fig2|fig4)(?:_gamma([0-9.]+))?_floor([0-9.]+)(?:_delta([0-9.]+))?$", name)
    if not m:
        continue
    with open(path) as f:
        js = json.load(f)
    case, gamma, floor, delta = m.group(1), m.group(2), float(m.group(3)), float(m.group(4) or 1)
    gamma = float(gamma) if gamma else {"fig3d": 1.08, "fig2": 0.16}[case]
    rows.append({"run": name, "case": case, "gamma": gamma, "drag_floor": floor, "vertex_diameter": delta,
                 "outcome": js["outcome"], "passage_time": js["time"], "dt": js["dt"],
                 "min_vg_over_vt_before": js["min_vg_over_vt_before_orifice"],
                 "max_vg_over_vt_after": js["max_vg_over_vt_after_orifice"],
                 "max_shape_parameter": js["max_shape_parameter"], "max_area_error": js["max_area_error"],
                 "wall_seconds": js["wall_seconds"]})
    prof = read_profile(os.path.join(d, name + ".csv"))  # where the maximum after the orifice and the minima lie
    after = [(h, v) for h, v in prof if h > 0]
    first, _, second, _ = landmarks(prof)
    rows[-1].update({"h_at_max_after": max(after, key=lambda p: p[1])[0] if after else "",
                     "h_first_min": first[0] if first else "", "vg_first_min": first[1] if first else "",
                     "h_second_min": second[0] if second else "", "vg_second_min": second[1] if second else ""})
if not rows:
    sys.exit("summarize_overshoot: no runs in " + d)
with open(os.path.join(d, "overshoot.csv"), "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
    w.writeheader()
    w.writerows(rows)

fig3d = [r for r in rows if r["case"] == "fig3d" and r["outcome"] == "passed"]
best = max(fig3d, key=lambda r: r["max_vg_over_vt_after"]) if fig3d else None
overshooting = [r for r in fig3d if r["max_vg_over_vt_after"] > 1]
summary = {
    "case": "Fig. 3(c,d): w = 0.7, Gamma = 1.08, b0/b_inf = 0.07, V_t = 0.032, N_v = 256",
    "runs": len(rows),
    "fig3d_runs": len(fig3d),
    "fig3d_max_vg_over_vt_after": best["max_vg_over_vt_after"] if best else None,
    "fig3d_max_at": {"drag_floor": best["drag_floor"], "vertex_diameter": best["vertex_diameter"]} if best else None,
    "fig3d_overshooting_settings": [{"drag_floor": r["drag_floor"], "vertex_diameter": r["vertex_diameter"],
                                     "max_vg_over_vt_after": r["max_vg_over_vt_after"]} for r in overshooting],
    "fig2": [{"drag_floor": r["drag_floor"], "vertex_diameter": r["vertex_diameter"],
              "max_vg_over_vt_after": r["max_vg_over_vt_after"]} for r in rows if r["case"] == "fig2"],
    "fig4": [{"gamma": r["gamma"], "drag_floor": r["drag_floor"], "vertex_diameter": r["vertex_diameter"],
              "max_vg_over_vt_after": r["max_vg_over_vt_after"]} for r in rows if r["case"] == "fig4"],
}
with open(os.path.join(d, "overshoot.json"), "w") as f:
    json.dump(summary, f, indent=1)

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

fig, (a, b) = plt.subplots(1, 2, figsize=(9, 3.6))
for delta, col in ((0.5, "b"), (1.0, "k"), (2.0, "g")):
    pts = sorted((r["drag_floor"], r["max_vg_over_vt_after"]) for r in fig3d if r["vertex_diameter"] == delta)
    if pts:
        a.plot([p[0] for p in pts], [p[1] for p in pts], "o-", color=col, label="δ = %g l0" % delta)
a.axhline(1, color="r", lw=1, ls="--", label="v_t (paper: overshoot > 1)")
a.set_xscale("log")
a.set_xlabel("near-wall drag floor d_min/σ")
a.set_ylabel("max v_g/v_t after the orifice")
a.set_title("Fig. 3(d) case: w = 0.7σ, Γ = 1.08, b0/b∞ = 0.07", fontsize=9)
a.legend(fontsize=7)
for case, gamma, col, lab in (("fig2", 0.16, "m", "Fig. 2, Γ = 0.16"), ("fig4", 1.85, "k", "Fig. 4, Γ = 1.85"),
                               ("fig4", 1.11, "b", "Fig. 4, Γ = 1.11"), ("fig4", 0.83, "r", "Fig. 4, Γ = 0.83")):
    pts = sorted((r["drag_floor"], r["max_vg_over_vt_after"]) for r in rows
                 if r["case"] == case and r["gamma"] == gamma and r["vertex_diameter"] == 1.0)
    if pts:
        b.plot([p[0] for p in pts], [p[1] for p in pts], "o-", color=col, label=lab)
    other = [(r["drag_floor"], r["max_vg_over_vt_after"]) for r in rows
             if r["case"] == case and r["gamma"] == gamma and r["vertex_diameter"] != 1.0]
    if other:
        b.plot([p[0] for p in other], [p[1] for p in other], "s", mfc="none", color=col)
b.plot([], [], "ks", mfc="none", label="open squares: δ = l0/2")
b.axhline(1, color="r", lw=1, ls="--")
b.set_xscale("log")
b.set_xlabel("near-wall drag floor d_min/σ (lines: δ = l0)")
b.set_ylabel("max v_g/v_t after the orifice")
b.legend(fontsize=7)
fig.tight_layout()
fig.savefig(os.path.join(d, "overshoot.png"), dpi=120)
for r in rows:
    print("%-32s %-7s max v_g/v_t after = %.4f  (passage %.0f t0, dt %.2g)" %
          (r["run"], r["outcome"], r["max_vg_over_vt_after"], r["passage_time"], r["dt"]))
