#!/usr/bin/python3
"""Issue 29 item 2: convergence in the speed of sound c0 of the capsule's simple-shear table
(scripts/reproduce_capsule shear_c0). For each capillary number (the network's G_s) the runs at
c0 = 10V (the driver's rule; shear_network's runs, γ̇t = 24), 20V (γ̇t = 24) and 40V (γ̇t = 12),
compared over the same windows: γ̇t ∈ [8.4, 12] (all three c0; the last 30% of the 40V run) and
[16.8, 24] (10V and 20V; the last 30% of theirs):

- D_xy: the window mean of the Taylor deformation, ± the standard deviation of its samples and ± the
  standard error from 4 consecutive blocks of the window (the samples are correlated over ~1/γ̇, so
  the block error is the one to compare differences with);
- the drift of D_xy across the window (a least-squares line's change over it);
- ΔD_xy from the previous c0 in the same window and the verdict of item 2: converged where
  |ΔD_xy| < 0.01 at the last doubling.

Only finished runs (a row in the driver's <file>_shear.csv) are used: a campaign stopped part way
gives the Ca it finished.

With --resolution the same for the resolution Π (scripts/reproduce_capsule shear_resolution): Ca = 0.3,
the rule's c0, Π = 8 (shear_network's run) against Π = 10 and 12 (<run dir>/pi<Π>_shear*.csv, γ̇t = 12)
over γ̇t ∈ [8.4, 12]; converged where the last refinement moves D_xy by less than 0.01.

usage: capsule_shear_c0_table.py [--resolution] <shear_network dir> <run dir> <out stem>
       (writes <stem>.csv and <stem>.png)
"""
import csv
import os
import sys

from capsule_diagonals_table import window_range

def finished_runs(table):
    """{Ca: driver row} of a driver's <file>_shear.csv (absent file: none)."""
    if not os.path.exists(table):
        return {}
    return {float(r["ca"]): r for r in csv.DictReader(open(table))}


def window(series_csv, start, end):
    """Mean, sample std, block standard error, drift and θ/π mean of D_xy over γ̇t ∈ [start, end]."""
    w = window_range(series_csv, start, end)
    return w["mean"], w["std"], w["block_error"], w["drift"], w["theta"], w["n"]


def write_csv(stem, rows):
    with open(stem + ".csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})


WINDOWS = ((8.4, 12.0), (16.8, 24.0))
RUN_END = {10: 24.0, 20: 24.0, 40: 12.0}


def resolution_table(network_dir, run_dir, stem):
    ca, ws, we = 0.3, 8.4, 12.0
    runs = [(8, os.path.join(network_dir, "high_shear.csv"), os.path.join(network_dir, "high_shear_ca0.3_series.csv"))]
    for pi in (10, 12):
        table = os.path.join(run_dir, f"pi{pi}_shear.csv")
        if ca in finished_runs(table):
            runs.append((pi, table, os.path.join(run_dir, f"pi{pi}_shear_ca0.3_series.csv")))
    rows = []
    for pi, table, series in runs:
        run = finished_runs(table)[ca]
        if float(run["shear_time"]) < we:
            continue
        dm, std, se, drift, thm, n = window(series, ws, we)
        rows.append({"resolution": pi, "ca_network": ca, "window_start": ws, "window_end": we, "taylor_deformation": dm,
                     "taylor_deformation_std": std, "taylor_deformation_block_error": se, "drift_over_window": drift,
                     "inclination_over_pi": thm, "window_samples": n, "particles": int(run["particles"]),
                     "dt_gamma": float(run["dt_gamma"]), "max_density_deviation": float(run["max_density_deviation"]),
                     "wall_seconds": float(run["wall_seconds"]),
                     "delta_from_previous": dm - rows[-1]["taylor_deformation"] if rows else float("nan")})
    write_csv(stem, rows)
    for r in rows:
        d = r["delta_from_previous"]
        print(f"Pi {r['resolution']} ({r['particles']} particles, dt gamma {r['dt_gamma']:.3g}, {r['wall_seconds']:.0f} s): "
              f"D_xy {r['taylor_deformation']:.4f} ± {r['taylor_deformation_block_error']:.4f} (blocks) over gamma t in "
              f"[{ws:g}, {we:g}], drift {r['drift_over_window']:+.4f}, theta/pi {r['inclination_over_pi']:.4f}"
              + ("" if d != d else f", change from the previous Pi {d:+.4f}"))
    if len(rows) == 3:
        # an error ∝ Π^-p through the three points: the ratio of the two increments fixes p, then the limit
        d1, d2 = rows[1]["delta_from_previous"], rows[2]["delta_from_previous"]
        pis = [r["resolution"] for r in rows]

        def mismatch(p):
            return (pis[0] ** -p - pis[1] ** -p) / (pis[1] ** -p - pis[2] ** -p) - d1 / d2

        lo, hi = 0.1, 10.0
        if d1 * d2 > 0 and mismatch(lo) * mismatch(hi) < 0:
            for _ in range(100):
                mid = 0.5 * (lo + hi)
                lo, hi = (mid, hi) if mismatch(lo) * mismatch(mid) > 0 else (lo, mid)
            p = 0.5 * (lo + hi)
            c = d2 / (pis[1] ** -p - pis[2] ** -p)
            print(f"error ~ Pi^-p through the three points: p = {p:.2f}, D_xy(Pi -> infinity) ~ "
                  f"{rows[2]['taylor_deformation'] + c * pis[2] ** -p:.3f} (an estimate from three points)")
    if len(rows) > 1:
        d = rows[-1]["delta_from_previous"]
        print(f"Pi {rows[-2]['resolution']} -> {rows[-1]['resolution']}: D_xy changes by {d:+.4f}: "
              + ("converged (|change| < 0.01)" if abs(d) < 0.01 else "NOT converged (|change| >= 0.01)"))
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(4.6, 3.4))
    ax.errorbar([r["resolution"] for r in rows], [r["taylor_deformation"] for r in rows],
                yerr=[r["taylor_deformation_block_error"] for r in rows], fmt="o-", capsize=3)
    ax.set_xlabel("resolution Π = d/Δx")
    ax.set_ylabel(f"D_xy, mean over γ̇t ∈ [{ws:g}, {we:g}]")
    ax.set_title("capsule in simple shear, Ca = 0.3 (network G_s), c0 = 10V", fontsize=9)
    fig.tight_layout()
    fig.savefig(stem + ".png", dpi=120)


def main():
    if sys.argv[1] == "--resolution":
        resolution_table(*sys.argv[2:5])
        return
    network_dir, run_dir, stem = sys.argv[1:4]
    # (Ca, c0/V) -> (driver's table, series file); 10V is the rule's c0 (the shear_network runs).
    sources = {}
    for ca in (0.3, 0.6):
        sources[(ca, 10)] = (os.path.join(network_dir, "high_shear.csv"),
                             os.path.join(network_dir, f"high_shear_ca{ca:g}_series.csv"))
        for c0 in (20, 40):
            table = os.path.join(run_dir, f"c0_{c0}_shear.csv")
            if ca in finished_runs(table):
                sources[(ca, c0)] = (table, os.path.join(run_dir, f"c0_{c0}_shear_ca{ca:g}_series.csv"))
    rows = []
    for ws, we in WINDOWS:
        for (ca, c0), (table, series) in sorted(sources.items()):
            run = finished_runs(table)[ca]
            if float(run["shear_time"]) != RUN_END[c0] or we > RUN_END[c0]:
                continue
            dm, std, se, drift, thm, n = window(series, ws, we)
            rows.append({"ca_network": ca, "c0_over_V": c0, "window_start": ws, "window_end": we,
                         "taylor_deformation": dm, "taylor_deformation_std": std,
                         "taylor_deformation_block_error": se, "drift_over_window": drift,
                         "inclination_over_pi": thm, "window_samples": n, "run_shear_time": RUN_END[c0],
                         "dt_gamma": float(run["dt_gamma"]),
                         "max_density_deviation": float(run["max_density_deviation"]),
                         "wall_seconds": float(run["wall_seconds"]), "delta_from_previous_c0": float("nan")})
    rows.sort(key=lambda r: (r["window_start"], r["ca_network"], r["c0_over_V"]))
    for k, r in enumerate(rows):
        p = rows[k - 1] if k else None
        if p and (p["ca_network"], p["window_start"]) == (r["ca_network"], r["window_start"]):
            r["delta_from_previous_c0"] = r["taylor_deformation"] - p["taylor_deformation"]
    write_csv(stem, rows)
    for r in rows:
        delta = r["delta_from_previous_c0"]
        print(f"Ca {r['ca_network']:g}, c0 {r['c0_over_V']}V, gamma t in [{r['window_start']:g}, {r['window_end']:g}] "
              f"(dt gamma {r['dt_gamma']:.3g}, run {r['run_shear_time']:g}, {r['wall_seconds']:.0f} s): "
              f"D_xy {r['taylor_deformation']:.4f} ± {r['taylor_deformation_block_error']:.4f} (blocks; "
              f"sample std {r['taylor_deformation_std']:.4f}), drift {r['drift_over_window']:+.4f}, "
              f"theta/pi {r['inclination_over_pi']:.4f}, max |rho-rho0|/rho0 {r['max_density_deviation']:.3f}"
              + ("" if delta != delta else f", change from the previous c0 {delta:+.4f}"))
    for ws, we in WINDOWS:
        for ca in sorted({r["ca_network"] for r in rows}):
            runs = [r for r in rows if r["ca_network"] == ca and r["window_start"] == ws]
            if len(runs) < 2:
                continue
            last, prev = runs[-1], runs[-2]
            d = last["delta_from_previous_c0"]
            e = (last["taylor_deformation_block_error"] ** 2 + prev["taylor_deformation_block_error"] ** 2) ** 0.5
            verdict = "converged (|change| < 0.01)" if abs(d) < 0.01 else "NOT converged (|change| >= 0.01)"
            print(f"Ca {ca:g}, window [{ws:g}, {we:g}]: {prev['c0_over_V']}V -> {last['c0_over_V']}V changes D_xy by "
                  f"{d:+.4f} ± {e:.4f}: {verdict}")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(5.0, 3.6))
    for k, ca in enumerate(sorted({r["ca_network"] for r in rows})):
        for ws, we in WINDOWS:
            runs = [r for r in rows if r["ca_network"] == ca and r["window_start"] == ws]
            ax.errorbar([r["c0_over_V"] for r in runs], [r["taylor_deformation"] for r in runs],
                        yerr=[r["taylor_deformation_block_error"] for r in runs],
                        fmt="o-" if ws < 10 else "s--", color=f"C{k}", capsize=3,
                        label=f"Ca = {ca:g}, γ̇t ∈ [{ws:g}, {we:g}]")
    ax.set_xscale("log", base=2)
    ax.set_xticks([10, 20, 40])
    ax.set_xticklabels(["10", "20", "40"])
    ax.set_xlabel("c0 / V")
    ax.set_ylabel("D_xy, window mean")
    ax.set_title("capsule in simple shear: c0 convergence (Π = 8, Re = 0.5)", fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(stem + ".png", dpi=120)


if __name__ == "__main__":
    main()
