#!/usr/bin/python3
"""Checks the CSV of tradeoff_mpc or tradeoff_mdpd (their --quick ctests): the columns are there,
every cost, viscosity and error of a stable run is finite, the JSON summary beside the CSV parses,
and a convergence property holds.

    check_viscosity_tradeoff.py {mpc|mdpd|mdpd_permeability} CSV

mpc (quick grid n = 3, 10, 40 at h = 0.1, double): eq. (B.3) is a large-n result, so its error
falls with n: |η/η_B3 − 1| > 10% at n = 3 (measured +26%) and < 5% at n = 40 (measured −0.05%);
the cost per τ grows with n (N = 200 n particles): more than 5× from n = 3 to n = 40.
mdpd (quick sweep dt = 0.02, 0.01, 0.005 at L/2 = 5): dt = 0.02 is unstable in 2D and is marked so;
the kinetic temperature's excess over k_BT (the half-step lag of the dissipative force) falls with
dt from 0.01 to 0.005 in both precisions (measured +0.86% → +0.19% in double, +0.55% → +0.12% in float); η of the stable runs is within
30% of the paper's 26.1 (20τ of sampling in a 10 × 10 box: ±7–10% statistical error).
mdpd_permeability (tradeoff_mdpd --observable permeability --quick: dt = 0.02, 0.01, 0.005 at
d = 2.5 and d = 2.5, 3.5, 5 at dt = 0.01, square array at ε = 0.8): dt = 0.02 is unstable and marked
so; the fluid's temperature excess falls from dt = 0.01 to 0.005 in both precisions (measured
+0.58% → −0.07% in double); κ/d² at d = 5 is within 25% of Sangani & Acrivos's exact 0.07621
(measured −6.5% double, +3.9% float after 100τ, ±5% statistical); the cost per τ grows with d
(N ∝ d²): more than 2× from d = 2.5 to d = 5 (measured 4.3×).
Exit status 1 naming the first failure.
"""
import csv
import json
import math
import sys

COLUMNS = {
    "mpc": ["precision", "n", "h", "eta_b3", "eta", "eta_stderr", "rel_err_b3", "rel_err_b3_stderr", "rel_err_ref",
            "wall_s_per_tau", "cpu_s_per_tau"],
    "mdpd": ["sweep", "precision", "dt", "half_width", "eta", "eta_stderr", "temperature", "rel_err_ref",
             "rel_err_ref_stderr", "wall_s_per_tau", "cpu_s_per_tau", "stable"],
    "mdpd_permeability": ["sweep", "precision", "dt", "diameter", "particles", "mean_u", "kappa", "kappa_stderr",
                          "kappa_over_d2", "kappa_over_d2_stderr", "temperature", "rel_err_ref", "rel_err_ref_stderr",
                          "rel_err_exact", "rel_err_exact_stderr", "wall_s_per_tau", "cpu_s_per_tau", "stable"],
}


def fail(msg):
    print(f"check_viscosity_tradeoff: FAIL: {msg}", file=sys.stderr)
    sys.exit(1)


def finite_positive(r, cols):
    for c in cols:
        v = float(r[c])
        if not (math.isfinite(v) and v > 0):
            fail(f"{c} = {r[c]} is not finite and > 0 in row {r}")


def check_mpc(rows):
    for r in rows:
        finite_positive(r, ["eta", "eta_stderr", "eta_b3", "wall_s_per_tau", "cpu_s_per_tau"])
        for c in ("rel_err_b3", "rel_err_ref"):
            if not math.isfinite(float(r[c])):
                fail(f"{c} = {r[c]} in row {r}")
    d = {int(r["n"]): r for r in rows if r["precision"] == "double" and float(r["h"]) == 0.1}
    for n in (3, 40):
        if n not in d:
            fail(f"no double row at n = {n}, h = 0.1")
    e3, e40 = abs(float(d[3]["rel_err_b3"])), abs(float(d[40]["rel_err_b3"]))
    if not e3 > 0.10:
        fail(f"|η/η_B3 − 1| at n = 3 is {e3:.3f}, expected > 0.10 (B.3 fails at small n)")
    if not e40 < 0.05:
        fail(f"|η/η_B3 − 1| at n = 40 is {e40:.3f}, expected < 0.05")
    ratio = float(d[40]["cpu_s_per_tau"]) / float(d[3]["cpu_s_per_tau"])
    if not ratio > 5:
        fail(f"cost ratio n = 40 / n = 3 is {ratio:.2f}, expected > 5 (N grows 13×)")
    print(f"check_viscosity_tradeoff: mpc: |η/η_B3 − 1| {e3:.3f} (n = 3) → {e40:.4f} (n = 40), cost ×{ratio:.1f}")


def check_mdpd_dt_sweep(rows, precision):
    """The MDPD dt sweep of one precision: dt = 0.02 blew up, and the temperature excess falls from
    dt = 0.01 to 0.005. Returns the temperature excesses at 0.01 and 0.005."""
    by_dt = {float(r["dt"]): r for r in rows if r["precision"] == precision and r["sweep"] == "dt"}
    for dt in (0.02, 0.01, 0.005):
        if dt not in by_dt:
            fail(f"no {precision} row at dt = {dt}")
    if by_dt[0.02]["stable"] != "0":
        fail(f"{precision}: dt = 0.02 ran stable; the 2D liquid was expected to blow up there")
    t1, t2 = float(by_dt[0.01]["temperature"]) - 1, float(by_dt[0.005]["temperature"]) - 1
    if not (abs(t1) > abs(t2) and t1 > 0):
        fail(f"{precision}: temperature excess does not fall with dt: {t1:+.4f} (0.01) → {t2:+.4f} (0.005)")
    return t1, t2


def check_mdpd(rows):
    for r in rows:
        finite_positive(r, ["wall_s_per_tau", "cpu_s_per_tau"])
        if r["stable"] == "1":
            finite_positive(r, ["eta", "eta_stderr", "temperature"])
            if not math.isfinite(float(r["rel_err_ref"])):
                fail(f"rel_err_ref = {r['rel_err_ref']} in row {r}")
            if abs(float(r["eta"]) / 26.1 - 1) > 0.3:
                fail(f"η = {r['eta']} is not within 30% of 26.1 in row {r}")
    for precision in ("double", "float"):
        t1, t2 = check_mdpd_dt_sweep(rows, precision)
        print(f"check_viscosity_tradeoff: mdpd {precision}: T − 1 = {t1:+.4f} (dt 0.01) → {t2:+.4f} (dt 0.005)")


def check_mdpd_permeability(rows):
    for r in rows:
        finite_positive(r, ["wall_s_per_tau", "cpu_s_per_tau"])
        if r["stable"] == "1":
            finite_positive(r, ["mean_u", "kappa", "kappa_stderr", "kappa_over_d2", "temperature"])
            for c in ("rel_err_ref", "rel_err_ref_stderr", "rel_err_exact", "rel_err_exact_stderr"):
                if not math.isfinite(float(r[c])):
                    fail(f"{c} = {r[c]} in row {r}")
    for precision in ("double", "float"):
        t1, t2 = check_mdpd_dt_sweep(rows, precision)
        by_d = {float(r["diameter"]): r for r in rows if r["precision"] == precision and r["sweep"] == "resolution"}
        for d in (2.5, 5.0):
            if d not in by_d or by_d[d]["stable"] != "1":
                fail(f"no stable {precision} row at d = {d}")
        e = float(by_d[5.0]["rel_err_exact"])
        if not abs(e) < 0.25:
            fail(f"{precision}: κ/d² at d = 5 is {by_d[5.0]['kappa_over_d2']}, {e:+.3f} from Sangani–Acrivos; "
                 f"expected within 25%")
        ratio = float(by_d[5.0]["cpu_s_per_tau"]) / float(by_d[2.5]["cpu_s_per_tau"])
        if not ratio > 2:
            fail(f"{precision}: cost ratio d = 5 / d = 2.5 is {ratio:.2f}, expected > 2 (N grows 4×)")
        print(f"check_viscosity_tradeoff: mdpd_permeability {precision}: T − 1 = {t1:+.4f} (dt 0.01) → {t2:+.4f} "
              f"(dt 0.005); κ/d² at d = 5 {e:+.3f} from Sangani–Acrivos; cost ×{ratio:.1f} from d = 2.5 to 5")


def main():
    if len(sys.argv) != 3 or sys.argv[1] not in COLUMNS:
        sys.exit(__doc__)
    model, path = sys.argv[1:]
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        rows = list(reader)
        header = reader.fieldnames or []
    for c in COLUMNS[model]:
        if c not in header:
            fail(f"{path} has no column {c} (has {', '.join(header)})")
    if not rows:
        fail(f"{path} has no rows")
    summary = path[:-4] + ".json" if path.endswith(".csv") else path + ".json"
    try:
        with open(summary) as f:
            json.load(f)  # strict JSON: an unstable run's NaN must be written as null
    except (OSError, ValueError) as e:
        fail(f"{summary} is not valid JSON: {e}")
    {"mpc": check_mpc, "mdpd": check_mdpd, "mdpd_permeability": check_mdpd_permeability}[model](rows)
    print("check_viscosity_tradeoff: OK")


if __name__ == "__main__":
    main()
