#!/usr/bin/python3
"""Log–log plot of a trade-off CSV (perf/tradeoff/tradeoff_{mpc,mdpd}): CPU seconds per τ against
the relative error of the observable, double filled and float open, colour by one setting and
marker by the other. Errors within 2 standard errors of zero are drawn at 2σ as upper limits (▼);
unstable runs (no finite error) and MDPD's references (error 0 by definition) are left out.

    plot_viscosity_tradeoff.py {mpc|mdpd|mdpd_permeability} CSV PNG
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

MODELS = {
    # model: (colour key, colour label, marker key, marker label, [(error, stderr, title)])
    "mpc": ("n", "n", "h", "h", [("rel_err_b3", "rel_err_b3_stderr", "η against eq. (B.3)"),
                                 ("rel_err_ref", "rel_err_b3_stderr", "η/η_B3 against the finest double run")]),
    "mdpd": ("half_width", "L/2 (r_A)", "dt", "dt", [("rel_err_ref", "rel_err_ref_stderr",
                                                      "η against the finest double run")]),
    "mdpd_permeability": ("diameter", "d (r_A)", "dt", "dt",
                          [("rel_err_ref", "rel_err_ref_stderr", "κ/d² against the finest double run"),
                           ("rel_err_exact", "rel_err_exact_stderr", "κ/d² against Sangani–Acrivos (exact Stokes)")]),
}
MARKERS = "osD^P*Xh"  # (▼ marks upper limits)


def main():
    if len(sys.argv) != 4 or sys.argv[1] not in MODELS:
        sys.exit(__doc__)
    model, path, png = sys.argv[1:]
    ckey, clabel, mkey, mlabel, errors = MODELS[model]
    with open(path) as f:
        rows = list(csv.DictReader(f))
    rows = [r for r in rows if all(math.isfinite(float(r[e])) for e, _, _ in errors)]  # unstable runs left out
    cvals = sorted({float(r[ckey]) for r in rows})
    mvals = sorted({float(r[mkey]) for r in rows})
    cmap = plt.get_cmap("viridis")
    fig, axes = plt.subplots(1, len(errors), figsize=(6.2 * len(errors), 4.8), squeeze=False)
    for ax, (ecol, scol, title) in zip(axes[0], errors):
        for r in rows:
            ci = cvals.index(float(r[ckey]))
            mi = mvals.index(float(r[mkey]))
            colour = cmap(ci / max(1, len(cvals) - 1))
            err, se = abs(float(r[ecol])), float(r[scol])
            if not math.isfinite(err) or (err == 0 and se == 0):
                continue  # an unstable run (MDPD: the CSV's `stable` column), or a sweep's reference
            cost = float(r["cpu_s_per_tau"])
            upper = err < 2 * se
            y = 2 * se if upper else err
            ax.errorbar(cost, y, yerr=None if upper else se, fmt=("v" if upper else MARKERS[mi % len(MARKERS)]),
                        color=colour, mfc=colour if r["precision"] == "double" else "none", ms=7, capsize=2)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("cost: CPU seconds per τ (1 thread)")
        ax.set_ylabel("|relative error|")
        ax.set_title(title)
        ax.grid(True, which="both", alpha=0.3)
    handles = [plt.Line2D([], [], color=cmap(i / max(1, len(cvals) - 1)), marker="o", ls="", label=f"{clabel} = {v:g}")
               for i, v in enumerate(cvals)]
    handles += [plt.Line2D([], [], color="k", marker=MARKERS[i % len(MARKERS)], ls="", mfc="none",
                           label=f"{mlabel} = {v:g}") for i, v in enumerate(mvals)]
    handles += [plt.Line2D([], [], color="k", marker="o", ls="", label="double (filled)"),
                plt.Line2D([], [], color="k", marker="o", mfc="none", ls="", label="float (open)"),
                plt.Line2D([], [], color="k", marker="v", ls="", label="|error| < 2σ: drawn at 2σ")]
    axes[0][-1].legend(handles=handles, fontsize=7, loc="best", ncol=2)
    fig.tight_layout()
    fig.savefig(png, dpi=120)
    print(f"plot_viscosity_tradeoff: wrote {png}")


if __name__ == "__main__":
    main()
