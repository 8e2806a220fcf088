#!/usr/bin/python3
"""Figs. 7(a) and 13(a) of the hopper paper: Beverloo's offset k and prefactor C (eq. 1) against the
SP stiffness E_sp in the two limits λ = 0 (friction) and λ → ∞ (drag), 2D SP hopper (N = 1600,
W = 50, θ_w = 90°), from the beta_lambda.csv that scripts/fit_hopper_lambda.py wrote for the sets
"SP E_sp=<E>" (three seeds per point, the errors of the fit to the seed means); plus Fig. 13(b, c):
Q/C against w/σ_avg − k for every E_sp in each limit (q_w.csv), which collapse if eq. 1 holds with one β.

    plot_hopper_esp.py <beta_lambda.csv> <q_w.csv> <out stem>      → <stem>.csv, <stem>.png

The paper (§3.3 and App. C): k rises with E_sp for λ → ∞ (k ≈ 1.5 at E_sp ≈ 10²) and much less for
λ → 0; C depends weakly on E_sp for λ → ∞ and falls with E_sp to a plateau C ≈ 0.15 for λ = 0.
"""
import csv
import math
import re
import sys


def main(argv):
    if len(argv) != 4:
        print(__doc__)
        return 2
    fits, qw, stem = argv[1:]
    rows = []
    for r in csv.DictReader(open(fits)):
        m = re.fullmatch(r"SP E_sp=([0-9.e+]+)", r["set"])
        if not m or r["lambda"] not in ("0", "inf"):
            continue
        rows.append({"E_sp": float(m.group(1)), "limit": "friction (lambda=0)" if r["lambda"] == "0" else "drag (lambda=inf)",
                     "lambda": r["lambda"], "seeds": int(r["seeds"]), "widths_fitted": int(r["widths_fitted"]),
                     "k": float(r["k"]), "k_error": float(r["k_error"]), "C": float(r["C"]),
                     "C_error": float(r["C_error"]), "beta": float(r["beta"]), "beta_error": float(r["beta_error"]),
                     "set": r["set"]})
    rows.sort(key=lambda r: (r["lambda"], r["E_sp"]))
    with open(stem + ".csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})
    for r in rows:
        print(f"{r['limit']:20s} E_sp {r['E_sp']:>7g} ({r['seeds']} seeds): k = {r['k']:.2f} ± {r['k_error']:.2f}, "
              f"C = {r['C']:.3f} ± {r['C_error']:.3f}, beta = {r['beta']:.2f} ± {r['beta_error']:.2f}")
    for lam in ("0", "inf"):
        sel = [r for r in rows if r["lambda"] == lam]
        if sel:
            c = [r["C"] for r in sel]
            k = [r["k"] for r in sel]
            print(f"{sel[0]['limit']:20s} over {len(sel)} E_sp: C {min(c):.3f}-{max(c):.3f}, mean {sum(c) / len(c):.3f}; "
                  f"k {min(k):.2f}-{max(k):.2f}")
    q = [r for r in csv.DictReader(open(qw))]
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(2, 2, figsize=(9, 7))
    for lam, mk, color in (("0", "o", "C0"), ("inf", "*", "C3")):
        sel = [r for r in rows if r["lambda"] == lam]
        label = "λ = 0 (friction)" if lam == "0" else "λ → ∞ (drag)"
        ax[0, 0].errorbar([r["E_sp"] for r in sel], [r["k"] for r in sel], yerr=[r["k_error"] for r in sel],
                          fmt=mk + "-", color=color, capsize=3, label=label)
        ax[0, 1].errorbar([r["E_sp"] for r in sel], [r["C"] for r in sel], yerr=[r["C_error"] for r in sel],
                          fmt=mk + "-", color=color, capsize=3, label=label)
        a = ax[1, 0] if lam == "inf" else ax[1, 1]
        for n, r in enumerate(sel):
            pts = [p for p in q if p["set"] == r["set"] and p["scan"] == "lambda" and p["value"] == lam]
            x = [float(p["w"]) - r["k"] for p in pts]
            y = [float(p["Q_mean"]) / r["C"] for p in pts]
            a.plot(x, y, "o", ms=4, color=f"C{n}", label=f"E_sp = {r['E_sp']:g}")
        if sel:
            beta = sum(r["beta"] for r in sel) / len(sel)
            xs = [0.5 + 0.1 * i for i in range(100)]
            a.plot(xs, [x ** beta for x in xs], "k--", lw=0.8, label=f"(w − k)^{beta:.2f}")
            a.set_xscale("log")
            a.set_yscale("log")
            a.set_xlabel("w/σ_avg − k")
            a.set_ylabel("Q/C")
            a.set_title(f"Fig. 13({'b' if lam == 'inf' else 'c'}): {label}", fontsize=9)
            a.legend(fontsize=7)
    ax[0, 0].axhline(1.5, color="0.6", ls=":", lw=0.8)
    ax[0, 1].axhline(0.15, color="0.6", ls=":", lw=0.8)
    for a, name in ((ax[0, 0], "offset k (Fig. 7a)"), (ax[0, 1], "prefactor C (Fig. 13a)")):
        a.set_xscale("log")
        a.set_xlabel("E_sp")
        a.set_ylabel(name)
        a.legend(fontsize=8)
    fig.suptitle("2D SP hopper (N = 1600, W = 50, θ_w = 90°): Beverloo's k and C against E_sp", fontsize=10)
    fig.tight_layout()
    fig.savefig(stem + ".png", dpi=110)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
