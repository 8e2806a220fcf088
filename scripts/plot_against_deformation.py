#!/usr/bin/python3
"""λ/σ (capillary-droplets Fig. 7(c)) or ⟨v_g⟩/v_t (Fig. 9(b)) against the sinking depth δ_s/σ of the
droplet under its own weight (Fig. 7(b)), SP and DP on one plot. Each SERIES is
LABEL=SUMMARY.csv:DEFORMATION.csv: an `obstacles` summary (one w_ob) and a `deformation` table at the
same Γ (DP, column line_tension) or E_w (SP, column sp_wall_energy), matched row by row on that value.
Writes OUT.csv (label, Γ or E_w, δ_s/σ, the quantity and its interval or error) and OUT.png.

usage: plot_against_deformation.py lambda|speed OUT SERIES...
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def close(a, b):
    return abs(a - b) <= 1e-6 * max(abs(a), abs(b))


def series_rows(spec):
    label, paths = spec.split("=", 1)
    summary_path, deformation_path = paths.split(":")
    summary, deformation = read(summary_path), read(deformation_path)
    x_key = "line_tension" if "line_tension" in summary[0] else "wall_energy"
    d_key = "line_tension" if x_key == "line_tension" else "sp_wall_energy"
    depth = {float(r[d_key]): float(r["sinking_depth"]) for r in deformation}
    out = []
    for r in summary:
        x = float(r[x_key])
        match = [v for k, v in depth.items() if close(k, x)]
        if not match:
            raise SystemExit(f"plot_against_deformation: no δ_s at {x_key} = {x} in {deformation_path}")
        out.append((x, match[0], r))
    return label, x_key, sorted(out, key=lambda t: t[1])


def main():
    if len(sys.argv) < 4 or sys.argv[1] not in ("lambda", "speed"):
        raise SystemExit(__doc__)
    what, out = sys.argv[1], sys.argv[2]
    series = [series_rows(s) for s in sys.argv[3:]]
    fig, ax = plt.subplots(figsize=(5, 4))
    with open(out + ".csv", "w", newline="") as f:
        w = csv.writer(f)
        if what == "lambda":
            w.writerow(["model", "parameter", "value", "sinking_depth", "replicas", "clogged", "decay_length",
                        "decay_length_lower", "decay_length_upper"])
        else:
            w.writerow(["model", "parameter", "value", "sinking_depth", "replicas", "flowing", "mean_speed_ratio",
                        "mean_speed_ratio_error"])
        for label, x_key, rows in series:
            xs, ys, lo, hi = [], [], [], []
            for x, ds, r in rows:
                if what == "lambda":
                    w.writerow([label, x_key, x, ds, r["replicas"], r["clogged"], r["decay_length"],
                                r["decay_length_lower"], r["decay_length_upper"]])
                    lam = float(r["decay_length"])
                    if math.isfinite(lam):
                        xs.append(ds)
                        ys.append(lam)
                        lo.append(lam - float(r["decay_length_lower"]))
                        hi.append(float(r["decay_length_upper"]) - lam)
                    else:
                        ax.plot(ds, float(r["decay_length_lower"]), "^", color="gray")
                else:
                    w.writerow([label, x_key, x, ds, r["replicas"], r["flowing"], r["mean_speed_ratio"],
                                r["mean_speed_ratio_error"]])
                    if r["mean_speed_ratio"] not in ("", "nan"):
                        xs.append(ds)
                        ys.append(float(r["mean_speed_ratio"]))
                        e = float(r["mean_speed_ratio_error"] or 0)
                        lo.append(e)
                        hi.append(e)
            ax.errorbar(xs, ys, yerr=[lo, hi], marker="o", capsize=3, label=label)
    ax.set_xscale("log")
    ax.set_xlabel(r"sinking depth $\delta_s/\sigma$")
    if what == "lambda":
        ax.set_yscale("log")
        ax.set_ylabel(r"$\lambda/\sigma$ (triangles: no clog, lower bound)")
    else:
        ax.set_ylabel(r"$\langle v_g\rangle / v_t$")
    ax.legend()
    fig.tight_layout()
    fig.savefig(out + ".png", dpi=120)


if __name__ == "__main__":
    main()
