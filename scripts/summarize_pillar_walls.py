#!/usr/bin/env python3
"""summarize_pillar_walls.py — pillar arrays between walls against their 2D permeability
(pillar paper, Figs. 9-12; issue 28, items 3-4; docs/mdpd.md).

    scripts/summarize_pillar_walls.py OUT.csv OUT.png RUN_3D.json ... [--also-2d=RUN_2D.json ...]

Each 3D run NAME_H<h>.json (or NAME_3d.json) is paired with the 2D run NAME_2d.json beside it (the
κ_p the 3D run was given) and the 2D runs NAME_2d_s<seed>.json of other seeds: κ_p is the mean of
their chosen estimator (Darcy over the box, kappa_darcy_box), its error the spread between seeds
pooled over all configurations over √n (each seed carves its own pillar surfaces, which the block
errors of one run do not see); the 3D run's κ_eff is given that spread too, as an upper estimate. One CSV row per 3D run:
κ_p, κ_eff (the same estimator in 3D), κ_w = H²/12, κ_eff/κ_w (Fig. 9a), κ_eff/κ_p (Fig. 9b), the
Brinkman fit's α and B (eq. 5) against B = κ_p Δp/(μ L_x) (Fig. 11a), μ_eff/μ = 1/(κ_p α²)
(Fig. 11b), eq. 7's κ_eff from the fitted α, and μ_eff/μ from the fluxes alone (eq. 7 solved for the
measured κ_eff/κ_p: the value whose Brinkman profile carries the measured flux), each with its error: the block errors of the two
fluxes and the fit's delete-one-block jackknife (10 blocks), combined in quadrature (independent
runs). Where a configuration ran at H = 7.5 and at another height, μ_eff(H)/μ_eff(7.5) (Fig. 12).

The plot: (a)-(d) as Figs. 9a, 9b, 11a, 11b, with eq. 7's κ_eff for μ_eff = 2.1μ (the paper's
regular-lattice value) and μ_eff = μ from each run's κ_p; (e) the profiles u_s(z)/u_s(0) with their
Brinkman fits at the lowest, a middle and the highest porosity of the first layout (Fig. 10);
(f) Fig. 12 when other heights ran. A summary JSON (OUT.csv with .json) holds, per layout, the mean
μ_eff/μ over 0.6 ≤ ε ≤ 0.8 (the paper leaves out its lowest and highest porosity) with the standard
error of that mean from the runs' spread.
"""
import csv
import glob
import json
import math
import os
import re
import sys

PAPER_REGULAR = 2.1              # μ_eff/μ, square and rotated-square lattices (Fig. 11b, text)
PAPER_IRREGULAR = (3.0, 0.4)     # ε ≤ 0.7; above: 6.52 − 5.14 ε (section 3.2.2)


def brinkman_factor(x):
    return x * x / 3 - 2 * x ** 4 / 15 if x < 1e-3 else 1 - math.tanh(x) / x


def kappa_eq7(kappa_p, mu_ratio, H):
    alpha = 1 / math.sqrt(kappa_p * mu_ratio)
    return kappa_p * brinkman_factor(0.5 * alpha * H)


def mu_eff_from_ratio(ratio, kappa_p, H):
    """μ_eff/μ for which eq. 7 gives κ_eff/κ_p = ratio (bisection in ln μ_eff; NaN outside (0, 1))."""
    if not 0 < ratio < 1:
        return float("nan")
    lo, hi = -12.0, 12.0  # ln(μ_eff/μ); eq. 7's ratio falls as μ_eff grows
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if kappa_eq7(kappa_p, math.exp(mid), H) / kappa_p > ratio:
            lo = mid
        else:
            hi = mid
    return math.exp(0.5 * (lo + hi))


def pair_2d(path):
    base = os.path.basename(path)[:-5]
    stem = re.sub(r"_(H[0-9.]+|3d)$", "", base)
    return os.path.join(os.path.dirname(path), stem + "_2d.json"), stem


ALSO_2D = []  # --also-2d=PATH: more 2D runs, each joining the configuration with its layout, ε, box and f_b


def same_configuration(a, b):
    return (a["layout"] == b["layout"] and abs(a["porosity"] - b["porosity"]) < 1e-9 and
            all(abs(x - y) < 1e-9 for x, y in zip(a["box"], b["box"])) and a["driving_force"] == b["driving_force"])


def seeds_2d(path):
    """The 2D runs of a 3D run's configuration: NAME_2d.json (the one whose κ_p the 3D run was given),
    any NAME_2d_s<seed>.json beside it, and the --also-2d runs of the same configuration."""
    path2, stem = pair_2d(path)
    paths = [path2] + sorted(glob.glob(os.path.join(os.path.dirname(path), stem + "_2d_s*.json")))
    base = json.load(open(path2))
    return paths + [q for q in ALSO_2D if same_configuration(json.load(open(q)), base)]


def pooled_seed_spread(paths_3d):
    """The relative spread of κ_p between 2D seeds, pooled over every configuration with two or more:
    s² = Σ_configurations Σ_seeds (κ/κ̄ − 1)² / Σ (n − 1). Each seed carves its own pillar surfaces (a
    quenched difference the block errors of one run cannot see). NaN without any second seed."""
    ss, dof = 0.0, 0
    groups = {tuple(seeds_2d(p)) for p in paths_3d}  # once per configuration (a 3D run at two heights shares it)
    for g in sorted(groups):
        k = [json.load(open(q))["kappa_darcy_box"] for q in g]
        if len(k) >= 2:
            m = sum(k) / len(k)
            ss += sum((x / m - 1) ** 2 for x in k)
            dof += len(k) - 1
    return (math.sqrt(ss / dof), dof) if dof else (float("nan"), 0)


def row_of(path, seed_spread):
    d3 = json.load(open(path))
    paths2 = seeds_2d(path)
    _, stem = pair_2d(path)
    d2 = json.load(open(paths2[0]))
    H = d3["walls_height"]
    b = d3["brinkman"]
    if abs(b["kappa_p"] / d2["kappa_darcy_box"] - 1) > 1e-6:
        raise SystemExit(f"{path}: ran with kappa_p = {b['kappa_p']}, but {paths2[0]} gives {d2['kappa_darcy_box']}")
    # κ_p: the mean over the 2D seeds; its error from the pooled seed spread (or, with no second seed
    # anywhere, the one run's block error)
    k2 = [json.load(open(q))["kappa_darcy_box"] for q in paths2]
    kp = sum(k2) / len(k2)
    kp_rel = seed_spread / math.sqrt(len(k2)) if seed_spread == seed_spread else d2["kappa_darcy_box_relative_error"]
    ke, ke_rel = d3["kappa_darcy_box"], d3["kappa_darcy_box_relative_error"]
    # the 3D run's own carved pillars: assumed to spread as much as a 2D seed's (an upper estimate: a
    # column averages its surface over the height)
    ke_rel_total = math.hypot(ke_rel, seed_spread) if seed_spread == seed_spread else ke_rel
    kw = H * H / 12
    alpha, a_err = b["alpha"], b.get("alpha_error", float("nan"))
    B, B_err = b["B"], b.get("B_error", float("nan"))
    B_th = b["B_theory"] * kp / b["kappa_p"]
    mu = 1 / (kp * alpha * alpha)
    mu_rel = math.hypot(2 * a_err / alpha, kp_rel)
    # μ_eff from the flux instead of the profile's shape: eq. 7 solved for the measured κ_eff/κ_p;
    # its error from the ratio's ±1σ (both fluxes' block errors in quadrature)
    ratio, ratio_rel = ke / kp, math.hypot(ke_rel_total, kp_rel)
    mu7 = mu_eff_from_ratio(ratio, kp, H)
    mu7_err = 0.5 * abs(mu_eff_from_ratio(ratio * (1 - ratio_rel), kp, H) -
                        mu_eff_from_ratio(ratio * (1 + ratio_rel), kp, H))
    return {
        "run": stem, "layout": d3["layout"], "porosity": d3["porosity"], "H": H,
        "driving_force": d3["driving_force"], "particles": d3["particles"],
        "kappa_p": kp, "kappa_p_error": kp * kp_rel, "kappa_p_seeds": len(k2),
        "kappa_eff": ke, "kappa_eff_error": ke * ke_rel, "kappa_eff_error_with_pillars": ke * ke_rel_total,
        "kappa_w": kw, "kappa_eff_over_kappa_w": ke / kw, "kappa_eff_over_kappa_w_error": ke * ke_rel / kw,
        "kappa_eff_over_kappa_p": ke / kp, "kappa_eff_over_kappa_p_error": ke / kp * ratio_rel,
        "alpha": alpha, "alpha_error": a_err, "alpha_at_bound": b["alpha_at_bound"],
        "B_fit": B, "B_fit_error": B_err, "B_theory": B_th,
        "B_fit_over_B": B / B_th, "B_fit_over_B_error": B / B_th * math.hypot(B_err / B, kp_rel),
        "mu_eff_over_mu": mu, "mu_eff_over_mu_error": mu * mu_rel,
        "mu_eff_over_mu_eq7": mu7, "mu_eff_over_mu_eq7_error": mu7_err,
        "kappa_eff_eq7": kappa_eq7(kp, mu, H), "kappa_eff_eq7_over_kappa_eff": kappa_eq7(kp, mu, H) / ke,
        "kappa_eff_eq7_mu2.1": kappa_eq7(kp, PAPER_REGULAR, H), "kappa_eff_eq7_mu1": kappa_eq7(kp, 1.0, H),
        "profile": os.path.join(os.path.dirname(path), os.path.basename(path)[:-5] + "_profile.csv"),
    }


def mean_and_error(values):
    n = len(values)
    m = sum(values) / n
    if n < 2:
        return m, float("nan")
    return m, math.sqrt(sum((v - m) ** 2 for v in values) / (n - 1) / n)


def main(argv):
    if len(argv) < 4:
        print(__doc__)
        return 2
    out_csv, out_png = argv[1], argv[2]
    runs = [a for a in argv[3:] if not a.startswith("--also-2d=")]
    ALSO_2D.extend(a.split("=", 1)[1] for a in argv[3:] if a.startswith("--also-2d="))
    spread, dof = pooled_seed_spread(runs)
    rows = sorted((row_of(p, spread) for p in runs), key=lambda r: (r["layout"], r["H"], r["porosity"]))
    # Fig. 12: the same configuration at another height over H = 7.5
    base = {(r["layout"], round(r["porosity"], 6)): r for r in rows if abs(r["H"] - 7.5) < 1e-9}
    for r in rows:
        ref = base.get((r["layout"], round(r["porosity"], 6)))
        if ref is not None and r is not ref:
            q = r["mu_eff_over_mu"] / ref["mu_eff_over_mu"]
            r["mu_eff_over_mu_H7.5_ratio"] = q
            r["mu_eff_over_mu_H7.5_ratio_error"] = q * math.hypot(
                r["mu_eff_over_mu_error"] / r["mu_eff_over_mu"], ref["mu_eff_over_mu_error"] / ref["mu_eff_over_mu"])
    fields = [k for k in rows[0] if k != "profile"] + ["mu_eff_over_mu_H7.5_ratio", "mu_eff_over_mu_H7.5_ratio_error"]
    with open(out_csv, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})
    summary = {"pooled_2d_seed_spread": spread, "pooled_2d_seed_spread_dof": dof, "paper": {"mu_eff_over_mu_regular": PAPER_REGULAR, "mu_eff_over_mu_irregular": PAPER_IRREGULAR,
                         "irregular_linear_fit_above_0.7": "6.52 - 5.14 eps"}, "layouts": {}}
    for layout in sorted({r["layout"] for r in rows}):
        for H in sorted({r["H"] for r in rows if r["layout"] == layout}):
            sel = [r for r in rows if r["layout"] == layout and r["H"] == H and 0.6 - 1e-9 <= r["porosity"] <= 0.8 + 1e-9]
            if not sel:
                continue
            m, e = mean_and_error([r["mu_eff_over_mu"] for r in sel])
            m7, e7 = mean_and_error([r["mu_eff_over_mu_eq7"] for r in sel])
            summary["layouts"][f"{layout}_H{H:g}"] = {
                "porosities": [r["porosity"] for r in sel], "mu_eff_over_mu_mean": m, "mu_eff_over_mu_mean_error": e,
                "mu_eff_over_mu_eq7_mean": m7, "mu_eff_over_mu_eq7_mean_error": e7,
                "B_fit_over_B_mean": mean_and_error([r["B_fit_over_B"] for r in sel])[0]}
    with open(out_csv[:-4] + ".json", "w") as f:
        json.dump(summary, f, indent=1)
    for r in rows:
        print(f"{r['run']:>24s} H={r['H']:<5g} eps={r['porosity']:.3f} k_p={r['kappa_p']:.4g} "
              f"k_eff/k_w={r['kappa_eff_over_kappa_w']:.4f}±{r['kappa_eff_over_kappa_w_error']:.4f} "
              f"k_eff/k_p={r['kappa_eff_over_kappa_p']:.3f}±{r['kappa_eff_over_kappa_p_error']:.3f} "
              f"B/B={r['B_fit_over_B']:.3f}±{r['B_fit_over_B_error']:.3f} "
              f"mu_eff/mu={r['mu_eff_over_mu']:.2f}±{r['mu_eff_over_mu_error']:.2f} "
              f"(eq.7: {r['mu_eff_over_mu_eq7']:.2f}±{r['mu_eff_over_mu_eq7_error']:.2f})")
    print(f"2D seeds: relative spread of κ_p {spread:.3f} (pooled, {dof} degrees of freedom)")
    for k, v in summary["layouts"].items():
        print(f"{k}: mean mu_eff/mu over 0.6-0.8 = {v['mu_eff_over_mu_mean']:.2f} ± {v['mu_eff_over_mu_mean_error']:.2f} "
              f"(fit), {v['mu_eff_over_mu_eq7_mean']:.2f} ± {v['mu_eff_over_mu_eq7_mean_error']:.2f} (eq. 7)")
    plot(rows, out_png)
    return 0


def plot(rows, out_png):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(2, 3, figsize=(14, 8))
    ax = ax.ravel()
    markers = {"square": "s", "rotated-square": "D", "irregular": "o"}
    colours = {7.5: "C0", 10.0: "C1", 12.5: "C2"}
    panels = [("kappa_eff_over_kappa_w", "κ_eff/κ_w (Fig. 9a)", True), ("kappa_eff_over_kappa_p", "κ_eff/κ_p (Fig. 9b)", False),
              ("B_fit_over_B", "B_fit/B (Fig. 11a)", False), ("mu_eff_over_mu", "μ_eff/μ (Fig. 11b)", False)]
    for i, (key, label, logy) in enumerate(panels):
        a = ax[i]
        for layout in sorted({r["layout"] for r in rows}):
            for H in sorted({r["H"] for r in rows if r["layout"] == layout}):
                sel = [r for r in rows if r["layout"] == layout and r["H"] == H]
                a.errorbar([r["porosity"] for r in sel], [r[key] for r in sel], yerr=[r[key + "_error"] for r in sel],
                           marker=markers.get(layout, "^"), color=colours.get(H, "k"), ls="none", capsize=3,
                           mfc="none" if layout == "rotated-square" else None, label=f"{layout}, H = {H:g}")
                if key in ("kappa_eff_over_kappa_w", "kappa_eff_over_kappa_p") and layout == "square":
                    norm = [r["kappa_w"] if key.endswith("w") else r["kappa_p"] for r in sel]
                    for mu, ls in ((PAPER_REGULAR, "-"), (1.0, ":")):
                        a.plot([r["porosity"] for r in sel],
                               [kappa_eq7(r["kappa_p"], mu, H) / n for r, n in zip(sel, norm)],
                               color=colours.get(H, "k"), ls=ls, lw=1,
                               label=f"eq. 7, μ_eff = {mu:g}μ (H = {H:g})")
        if key == "mu_eff_over_mu":
            for layout in sorted({r["layout"] for r in rows}):
                sel = [r for r in rows if r["layout"] == layout and abs(r["H"] - 7.5) < 1e-9]
                a.errorbar([r["porosity"] + 0.004 for r in sel], [r["mu_eff_over_mu_eq7"] for r in sel],
                           yerr=[r["mu_eff_over_mu_eq7_error"] for r in sel], marker=markers.get(layout, "^"),
                           color="C3", ls="none", capsize=3, mfc="none" if layout == "rotated-square" else None,
                           label=f"{layout}, H = 7.5: eq. 7 from κ_eff/κ_p")
            a.axhline(PAPER_REGULAR, color="k", ls="--", lw=1, label="paper, regular: 2.1")
            a.axhspan(PAPER_IRREGULAR[0] - PAPER_IRREGULAR[1], PAPER_IRREGULAR[0] + PAPER_IRREGULAR[1], color="0.85",
                      label="paper, irregular: 3.0 ± 0.4")
        if key == "B_fit_over_B":
            a.axhline(1, color="k", lw=0.8)
        if logy:
            a.set_yscale("log")
        a.set_xlabel("ε")
        a.set_ylabel(label)
        a.legend(fontsize=7)
    # (e) Fig. 10: normalised profiles of the first layout at H = 7.5
    a = ax[4]
    first = [r for r in rows if abs(r["H"] - 7.5) < 1e-9 and os.path.exists(r["profile"])]
    if first:
        layout = "square" if any(r["layout"] == "square" for r in first) else first[0]["layout"]
        sel = [r for r in first if r["layout"] == layout]
        picks = [sel[0], sel[len(sel) // 2], sel[-1]] if len(sel) >= 3 else sel
        for k, r in enumerate(picks):
            with open(r["profile"]) as f:
                prof = list(csv.DictReader(f))
            z = [float(p["z"]) for p in prof]
            us = [float(p["u_s"]) for p in prof]
            fit = [float(p["brinkman_fit"]) for p in prof]
            mid = max(fit)
            a.plot(z, [u / mid for u in us], marker="o", ls="none", color=f"C{k}",
                   label=f"ε = {r['porosity']:.2f}, α = {r['alpha']:.2f}")
            a.plot(z, [u / mid for u in fit], color=f"C{k}")
        a.set_xlabel("z/σ")
        a.set_ylabel("u_s/u_s,fit(0)")
        a.set_title(f"{layout}, H = 7.5 (Fig. 10)", fontsize=9)
        a.legend(fontsize=7)
    # (f) Fig. 12
    a = ax[5]
    other = [r for r in rows if "mu_eff_over_mu_H7.5_ratio" in r]
    if other:
        for r in other:
            a.errorbar(r["porosity"], r["mu_eff_over_mu_H7.5_ratio"], yerr=r["mu_eff_over_mu_H7.5_ratio_error"],
                       marker=markers.get(r["layout"], "^"), color=colours.get(r["H"], "k"), capsize=3,
                       mfc="none" if r["layout"] == "rotated-square" else None)
        a.axhline(1, color="k", lw=0.8)
        a.set_xlabel("ε")
        a.set_ylabel("μ_eff(H)/μ_eff(H = 7.5) (Fig. 12)")
    else:
        a.set_axis_off()
    fig.tight_layout()
    fig.savefig(out_png, dpi=110)


if __name__ == "__main__":
    sys.exit(main(sys.argv))
