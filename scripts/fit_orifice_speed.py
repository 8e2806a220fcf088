#!/usr/bin/python3
"""The speed at the orifice against its width (hopper-flows Fig. 5): from `hopper` profile CSVs
(<name>_profile.csv: w, h, n, vg_sum, vg_mean on the axis), v_g(0) = Σ v_g,i φ at h = 0 (the paper's
coarse-grained v_g, column vg_sum) and the mean speed vg_mean there, for each width; a least-squares
fit log v_g(0) = a log w + b per limit, a with its standard error from the scatter of the widths
(each width its own seed, so independent); the same for v_g far above the orifice (the largest h
of each profile that every width has). Writes OUT.csv (limit, w, v_g(0), mean speed, v_g(h_far)),
OUT.json (exponents, errors, the paper's +1/2 and −1/2 and how many errors away) and OUT.png.

usage: fit_orifice_speed.py OUT LABEL=PROFILE.csv:EXPECTED [LABEL=PROFILE.csv:EXPECTED ...]
"""
import csv
import json
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def fit(xs, ys):
    """Slope and intercept of y = a x + b, the slope's standard error from the residuals."""
    n = len(xs)
    mx, my = sum(xs) / n, sum(ys) / n
    sxx = sum((x - mx) ** 2 for x in xs)
    a = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx
    b = my - a * mx
    res = [y - (a * x + b) for x, y in zip(xs, ys)]
    s2 = sum(r * r for r in res) / (n - 2) if n > 2 else float("nan")
    return a, b, math.sqrt(s2 / sxx)


def main():
    if len(sys.argv) < 3:
        raise SystemExit(__doc__)
    out = sys.argv[1]
    summary, table = {}, []
    fig, axes = plt.subplots(1, 2, figsize=(9, 4))
    for spec in sys.argv[2:]:
        label, rest = spec.split("=", 1)
        path, expected = rest.rsplit(":", 1)
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
        widths = sorted({float(r["w"]) for r in rows})
        h_far = min(max(float(r["h"]) for r in rows if float(r["w"]) == w) for w in widths)
        pts = []
        for w in widths:
            at0 = [r for r in rows if float(r["w"]) == w and float(r["h"]) == 0.0]
            far = [r for r in rows if float(r["w"]) == w and abs(float(r["h"]) - h_far) < 1e-9]
            if not at0 or float(at0[0]["vg_sum"]) <= 0:
                continue  # clogged: no flow at the orifice
            pts.append((w, float(at0[0]["vg_sum"]), float(at0[0]["vg_mean"]), float(far[0]["vg_sum"])))
        for w, v0, m0, vfar in pts:
            table.append([label, w, v0, m0, h_far, vfar])
        lx = [math.log(p[0]) for p in pts]
        a0, b0, e0 = fit(lx, [math.log(p[1]) for p in pts])
        af, bf, ef = fit(lx, [math.log(p[3]) for p in pts])
        target = float(expected)
        summary[label] = {"widths": [p[0] for p in pts], "exponent_vg0": a0, "exponent_vg0_error": e0,
                          "paper_exponent_vg0": target, "deviation_in_errors": (a0 - target) / e0,
                          "h_far": h_far, "exponent_vg_far": af, "exponent_vg_far_error": ef}
        line = axes[0].loglog([p[0] for p in pts], [p[1] for p in pts], "o",
                              label=f"{label}: $w^{{{a0:.2f} \\pm {e0:.2f}}}$ (paper {target:+g})")
        ws = [min(p[0] for p in pts), max(p[0] for p in pts)]
        axes[0].loglog(ws, [math.exp(b0) * w ** a0 for w in ws], "-", color=line[0].get_color())
        axes[1].loglog([p[0] for p in pts], [p[3] for p in pts], "s", color=line[0].get_color(),
                       label=f"{label}: $w^{{{af:.2f} \\pm {ef:.2f}}}$")
    axes[0].set_xlabel(r"$w/\sigma_{avg}$")
    axes[0].set_ylabel(r"$v_g(h=0)$ (coarse-grained, $\sigma_{avg}/t_0$)")
    axes[1].set_xlabel(r"$w/\sigma_{avg}$")
    axes[1].set_ylabel(r"$v_g$ far above the orifice")
    for ax in axes:
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out + ".png", dpi=120)
    with open(out + ".csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["limit", "w", "vg0", "mean_speed0", "h_far", "vg_far"])
        w.writerows(table)
    with open(out + ".json", "w") as f:
        json.dump(summary, f, indent=2)
    for label, s in summary.items():
        print(f"  {label}: v_g(0) ~ w^{s['exponent_vg0']:.3f} ± {s['exponent_vg0_error']:.3f} "
              f"(paper {s['paper_exponent_vg0']:+g}, {s['deviation_in_errors']:+.1f} errors); "
              f"v_g(h = {s['h_far']:g}) ~ w^{s['exponent_vg_far']:.3f} ± {s['exponent_vg_far_error']:.3f}")


if __name__ == "__main__":
    main()
