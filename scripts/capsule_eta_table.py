#!/usr/bin/python3
"""Issue 29 item 3: the constriction sweeps at η = 0.5, 0.75, 1 side by side (scripts/reproduce_capsule
sweep_eta), against what the paper's text states about Figs. 9-11 and Table 1
(sph-microcapsules-constriction §4.3-5):
  - D∞,y "varies only between 0.42 and 0.44 (η = 0.5) and 0.52 and 0.70 (η = 0.75)" over Ca;
  - D∞,x is larger at narrower constrictions and D∞,y larger at wider ones (larger Ca);
  - C_f rises with Ca at x_c = 3.5 and 4 for η = 0.75 and 1, and is larger at η = 0.75 than at 1;
  - "almost all parameters represent better correlation in η = 0.5" (Pearson r, Table 1).
Writes one row per (η, Ca) with the measures at x_c = 3.5 / 4 / 4.5, the Pearson r per η (eq. 17,
from each sweep's JSON) and a plot of D∞,x, D∞,y, D∞,z against x_c for every run (Fig. 9's panels).
Sweeps that have not finished (no JSON yet) are listed from their finished runs' result files.

usage: capsule_eta_table.py <run dir> <out stem>   (writes <stem>.csv, <stem>_pearson.csv, <stem>.png)
"""
import csv
import glob
import json
import os
import sys

ETAS = ("0.5", "0.75", "1")
COLUMNS = ["ca", "eta", "eta_effective", "status", "passage_time", "inverse_passage_time", "Dx_at_4", "Dy_at_4",
           "Dz_at_4", "Cf_at_3.5", "Cf_at_4", "Cf_at_4.5", "Cr_at_3.5", "Cr_at_4", "Cr_at_4.5",
           "max_density_deviation", "steps", "wall_seconds"]


def runs_of(run_dir, eta):
    table = os.path.join(run_dir, f"eta{eta}_sweep.csv")
    if os.path.exists(table):
        return list(csv.DictReader(open(table))), True
    rows = []
    for path in sorted(glob.glob(os.path.join(run_dir, f"eta{eta}_ca*_eta{eta}_result.csv"))):
        rows += list(csv.DictReader(open(path)))
    rows.sort(key=lambda r: float(r["ca"]))
    return rows, False


def main():
    run_dir, stem = sys.argv[1:3]
    all_rows, pearson = [], []
    for eta in ETAS:
        rows, complete = runs_of(run_dir, eta)
        for r in rows:
            all_rows.append({k: r.get(k, "") for k in COLUMNS} | {"sweep_complete": complete,
                                                                   "series_csv": r["series_csv"]})
        summary = os.path.join(run_dir, f"eta{eta}.json")
        if complete and os.path.exists(summary):
            for p in json.load(open(summary))["pearson_r"]:
                pearson.append(p)
    with open(stem + ".csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=COLUMNS + ["sweep_complete"], extrasaction="ignore")
        w.writeheader()
        w.writerows(all_rows)
    if pearson:
        keys = ["eta"] + [k for k in pearson[0] if k != "eta"]
        with open(stem + "_pearson.csv", "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=keys)
            w.writeheader()
            w.writerows(pearson)
    for eta in ETAS:
        rows = [r for r in all_rows if r["eta"] and float(r["eta"]) == float(eta)]
        if not rows:
            print(f"eta {eta}: no finished run")
            continue
        dy = [float(r["Dy_at_4"]) for r in rows if r["Dy_at_4"] not in ("", "nan")]
        status = ", ".join(f"Ca {float(r['ca']):g}: {r['status']}" for r in rows)
        rng = f"{min(dy):.3f}-{max(dy):.3f}" if dy else "n/a"
        print(f"eta {eta}: {len(rows)} runs ({status}); D_inf,y(4) {rng}")
    for p in pearson:
        values = [v for k, v in p.items() if k != "eta"]
        print("Pearson r, eta " + f"{p['eta']:g}: " + ", ".join(f"{k} {v:+.2f}" for k, v in p.items() if k != "eta")
              + f"; mean |r| {sum(abs(v) for v in values) / len(values):.2f}")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 3, figsize=(12, 3.6))
    styles = {"0.5": "-", "0.75": "--", "1": ":"}
    cas = sorted({float(r["ca"]) for r in all_rows})
    colours = {ca: f"C{k}" for k, ca in enumerate(cas)}
    for r in all_rows:
        series = os.path.join(run_dir, os.path.basename(r["series_csv"]))
        if not os.path.exists(series):
            continue
        s = list(csv.DictReader(open(series)))
        xc = [float(q["x_c"]) for q in s]
        eta = str(float(r["eta"])).rstrip("0").rstrip(".")
        for ax, key in zip(axes, ("Dx", "Dy", "Dz")):
            ax.plot(xc, [float(q[key]) for q in s], styles.get(eta, "-"), color=colours[float(r["ca"])],
                    label=f"Ca {float(r['ca']):g}, η {eta}" if key == "Dx" else None)
    for ax, key in zip(axes, ("D∞,x", "D∞,y", "D∞,z")):
        ax.set_xlabel("x_c / d")
        ax.set_ylabel(key)
        ax.axvspan(3, 5, color="0.92")
    axes[0].legend(fontsize=6, ncol=2)
    fig.suptitle("capsule through the constriction, Π = 8 (Ca of §4's formula): η = 0.5 solid, 0.75 dashed, 1 dotted",
                 fontsize=9)
    fig.tight_layout()
    fig.savefig(stem + ".png", dpi=110)


if __name__ == "__main__":
    main()
