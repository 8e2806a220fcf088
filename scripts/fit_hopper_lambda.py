#!/usr/bin/env python3
"""β(λ) from the runs of scripts/hopper_lambda_sweep (hopper paper, Fig. 4; issue 27 item 1).

    fit_hopper_lambda.py <out-dir> <label>=<runs-dir>[@<prefix>] [...]

<prefix> (default "lam") selects the runs <prefix><λ>_s<seed>.csv: "sp_lam" and "dp_lam" for the
reduced DP check (`hopper_lambda_sweep dp`), which has one seed: there the errors of Q are the
runs' own block errors, not a spread over seeds.

For each runs directory (one E_sp) and each λ: the flow rate Q(w) of every seed (lam<λ>_s<seed>.csv),
their mean per width with the standard error from the spread of the seeds (σ/√n, n seeds), and
Beverloo's eq. 1 fitted to the means with those errors (the C++ fit, mesoflow.analysis.fit_beverloo).
A width where any seed clogged is left out of the fit and counted. Then, over the finite λ > 0:
eq. 14 with the paper's plateaus d − 1/2 and d − 3/2 (mesoflow.analysis.fit_beta_sigmoid), and a
sigmoid with free plateaus (the same tanh in log10 λ, SciPy), because our limits need not be the
paper's. Writes <out-dir>/beta_lambda.csv (one row per label and λ), <out-dir>/q_w.csv (the seed
means), <out-dir>/beta_lambda.json (fits) and <out-dir>/beta_lambda.png; where the runs directory
holds the friction-limit μ scan (mu<μ>_s<seed>, `hopper_lambda_sweep mu`), <out-dir>/beta_mu.csv
with β against μ/μ0 at ζ = 0 (the sweep's λ = 0 runs are its μ/μ0 = 10√10 point).
"""
import csv
import glob
import json
import math
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "build", "release", "python"))
from mesoflow import analysis  # noqa: E402


def lam_value(text):
    return math.inf if text == "inf" else float(text)


def read_runs(runs, prefix="lam"):
    """{value text: {seed: [(w, Q, clogged)]}} from <prefix><value>_s<seed>.csv whose JSON exists
    (the driver writes it last: a run without it did not finish)."""
    out = {}
    for path in sorted(glob.glob(os.path.join(runs, prefix + "*_s*.csv"))):
        m = re.match(prefix + r"(.+)_s(\d+)\.csv$", os.path.basename(path))
        if not m or m.group(1).endswith("_profile") or not os.path.exists(path[:-4] + ".json"):
            continue
        rows = []
        with open(path) as f:
            for r in csv.DictReader(f):
                rows.append((float(r["w"]), float(r["Q"]), int(r["clogged"]), float(r["Q_error"])))
        out.setdefault(m.group(1), {})[int(m.group(2))] = rows
    return out


def run_dimension(runs, prefix="lam"):
    """The spatial dimension the runs were made in (the driver's JSON), 2 where none says."""
    for path in sorted(glob.glob(os.path.join(runs, prefix + "*_s*.json"))):
        with open(path) as f:
            return int(json.load(f).get("dimension", 2))
    return 2


def seed_mean_fit(label, key, value, seeds, qrows):
    """Q(w) averaged over the seeds (error σ/√n from their spread), Beverloo's eq. 1 fitted to it."""
    widths = sorted({r[0] for rs in seeds.values() for r in rs})
    ws, qs, es, clogged_widths = [], [], [], 0
    for w in widths:
        vals = [(q, c, e) for rs in seeds.values() for ww, q, c, e in rs if ww == w]
        n = len(vals)
        if any(c for _, c, _ in vals):
            clogged_widths += 1
            qrows.append([label, key, value, w, n, "", "", sum(c for _, c, _ in vals)])
            continue
        q = np.array([v for v, _, _ in vals])
        err = q.std(ddof=1) / math.sqrt(n) if n > 1 else vals[0][2]  # one seed: its block error
        qrows.append([label, key, value, w, n, q.mean(), err, 0])
        ws.append(w), qs.append(q.mean()), es.append(err)
    nseeds = len(seeds)
    row = {"set": label, key: value, "seeds": nseeds, "widths_fitted": len(ws), "widths_clogged": clogged_widths}
    if len(ws) >= 4:
        fit = analysis.fit_beverloo(ws, qs, es)
        row.update(C=fit["C"], C_error=fit["C_error"], k=fit["k"], k_error=fit["k_error"], beta=fit["beta"],
                   beta_error=fit["beta_error"], chi2_per_dof=fit["chi2_per_dof"], converged=int(fit["converged"]))
    return row


def free_sigmoid(x, lo, hi, logc, s):
    # β = (lo + hi)/2 − (lo − hi)/2 · tanh(s (log10 λ − log10 λ_c)): lo at λ → 0, hi at λ → ∞
    return 0.5 * (lo + hi) - 0.5 * (lo - hi) * np.tanh(s * (x - logc))


def main():
    if len(sys.argv) < 3:
        print(__doc__, file=sys.stderr)
        return 2
    out_dir = sys.argv[1]
    os.makedirs(out_dir, exist_ok=True)
    summary = {"design": "mu = mu_f (1 - f), zeta = zeta_d f, f = lambda mu_f / (zeta_d + lambda mu_f); "
                         "mu_f/mu0 = 10 sqrt(10), zeta_d t0 = 7.3 (scripts/hopper_lambda_sweep)",
               "sets": {}}
    rows, mu_rows, qrows, curves = [], [], [], {}
    for arg in sys.argv[2:]:
        label, runs = arg.rsplit("=", 1)
        runs, _, prefix = runs.partition("@")
        data = read_runs(runs, prefix or "lam")
        dim = run_dimension(runs, prefix or "lam")
        pts = []
        for lam_text in sorted(data, key=lam_value):
            row = seed_mean_fit(label, "lambda", lam_text, data[lam_text], qrows)
            if "beta" in row:
                pts.append((lam_value(lam_text), row["beta"], row["beta_error"]))
            rows.append(row)
        # the friction limit at other μ (hopper_lambda_sweep mu): β against μ at ζ = 0
        mus = read_runs(runs, "mu") if not prefix else {}
        if mus:
            if "0" in data:
                mus["31.6227766"] = data["0"]
            for mu_text in sorted(mus, key=float):
                mu_rows.append(seed_mean_fit(label, "mu", mu_text, mus[mu_text], qrows))
        s = {"points": len(pts), "dimension": dim}
        finite = [(l, b, e) for l, b, e in pts if 0 < l < math.inf]
        if len(finite) >= 3:
            lam, beta, err = (list(v) for v in zip(*finite))
            sig = analysis.fit_beta_sigmoid(lam, beta, err, dim)
            s["eq14_fixed_plateaus"] = sig
            try:
                from scipy.optimize import curve_fit
                p0 = [max(beta), min(beta), math.log10(lam[len(lam) // 2]), 1.0]
                x = np.log10(lam)
                popt, pcov = curve_fit(free_sigmoid, x, beta, p0=p0, sigma=err, absolute_sigma=True, maxfev=20000)
                perr = np.sqrt(np.diag(pcov))
                s["free_plateaus"] = {"beta_lambda_to_0": popt[0], "beta_lambda_to_0_error": perr[0],
                                      "beta_lambda_to_inf": popt[1], "beta_lambda_to_inf_error": perr[1],
                                      "log10_lambda_c": popt[2], "log10_lambda_c_error": perr[2],
                                      "lambda_c": 10 ** popt[2], "stretch": popt[3], "stretch_error": perr[3],
                                      "chi2": float(np.sum(((free_sigmoid(x, *popt) - beta) / err) ** 2)),
                                      "dof": len(lam) - 4}
                curves[label] = (popt, sig, dim)
            except Exception as e:  # too few points or no convergence: reported, not hidden
                s["free_plateaus"] = {"error": str(e)}
                curves[label] = (None, sig, dim)
        summary["sets"][label] = s
    keys = ["set", "lambda", "seeds", "widths_fitted", "widths_clogged", "C", "C_error", "k", "k_error", "beta",
            "beta_error", "chi2_per_dof", "converged"]
    with open(os.path.join(out_dir, "beta_lambda.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        for r in rows:
            w.writerow({k: (("%.6g" % v) if isinstance(v, float) else v) for k, v in r.items()})
    if mu_rows:
        with open(os.path.join(out_dir, "beta_mu.csv"), "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=["mu"] + [k for k in keys if k != "lambda"])
            w.writeheader()
            for r in mu_rows:
                w.writerow({k: (("%.6g" % v) if isinstance(v, float) else v) for k, v in r.items()})
        summary["friction_limit_mu_scan"] = mu_rows
    with open(os.path.join(out_dir, "q_w.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["set", "scan", "value", "w", "seeds", "Q_mean", "Q_error", "seeds_clogged"])
        for r in qrows:
            w.writerow([("%.6g" % v) if isinstance(v, float) else v for v in r])
    with open(os.path.join(out_dir, "beta_lambda.json"), "w") as f:
        json.dump(summary, f, indent=2, default=float)
    plot(out_dir, rows, curves)
    print(json.dumps(summary, indent=1, default=float))
    return 0


def plot(out_dir, rows, curves):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4.2))
    markers = "^Dos*"
    labels = sorted({r["set"] for r in rows})
    lo_x, hi_x = 3e-4, 3e2  # where the λ = 0 and ∞ limits are drawn
    for i, label in enumerate(labels):
        rs = [r for r in rows if r["set"] == label and "beta" in r]
        x = [lo_x if lam_value(r["lambda"]) == 0 else hi_x if math.isinf(lam_value(r["lambda"]))
             else lam_value(r["lambda"]) for r in rs]
        line = ax.errorbar(x, [r["beta"] for r in rs], yerr=[r["beta_error"] for r in rs], fmt=markers[i % 5],
                           capsize=2, label=label)
        popt, sig, dim = curves.get(label, (None, None, 2))
        xs = np.logspace(-3, 2, 200)
        if popt is not None:
            ax.plot(xs, free_sigmoid(np.log10(xs), *popt), color=line[0].get_color(), lw=1)
        if sig is not None:
            ax.plot(xs, [analysis.beta_sigmoid(v, dim, sig["lambda_c"], sig["stretch"]) for v in xs],
                    color=line[0].get_color(), lw=1, ls=":")
    dims = sorted({c[2] for c in curves.values()}) or [2]
    for b in sorted({v for d in dims for v in (d - 0.5, d - 1.5)}):
        ax.axhline(b, color="gray", ls="--", lw=0.8)
    ax.set_xscale("log")
    ax.set_xlabel("λ = ζ/μ   (λ = 0 drawn at 3·10⁻⁴, ∞ at 3·10²)")
    ax.set_ylabel("β (eq. 1)")
    ax.set_title("β(λ), %s hopper (θ_w = 90°): solid, sigmoid with free plateaus; dotted, eq. 14"
                 % " and ".join("%dD" % d for d in dims), fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, "beta_lambda.png"), dpi=120)


if __name__ == "__main__":
    sys.exit(main())
