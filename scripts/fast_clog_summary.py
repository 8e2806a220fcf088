#!/usr/bin/env python3
"""Summary of scripts/validate_fast_clog (standard library only).

Reads <dir>/runs/{both,early}_<point>.{replicas.csv,json} and writes <dir>/fast_clog_replicas.csv
(one row per replica of the `both` runs: the full criterion's and the early test's classification,
r and t) and <dir>/fast_clog.json (per point and overall: replicas, disagreements, max |Δr| over the
replicas both call clogged, simulated time to the decision under each test, wall time of the `both`
run (= the full criterion) and of the `early` run, and whether the `early` run reproduced the early
decisions of the `both` run)."""
import csv
import json
import os
import sys


def read_rows(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def main(directory):
    runs = os.path.join(directory, "runs")
    names = sorted({f[len("both_"):-len(".json")] for f in os.listdir(runs) if f.startswith("both_") and f.endswith(".json")})
    order = lambda n: (0 if n.startswith("sp") else 1, -float(n.split("ew" if n.startswith("sp") else "gamma")[1]))
    names.sort(key=order)
    rows, points = [], []
    for name in names:
        model = "sp" if name.startswith("sp") else "dp"
        both = read_rows(os.path.join(runs, f"both_{name}.replicas.csv"))
        both_json = json.load(open(os.path.join(runs, f"both_{name}.json")))
        early_path = os.path.join(runs, f"early_{name}.replicas.csv")
        early = {r["replica"]: r for r in read_rows(early_path)} if os.path.exists(early_path) else None
        early_json = json.load(open(os.path.join(runs, f"early_{name}.json"))) if early is not None else None
        key = "wall_energy" if model == "sp" else "line_tension"
        p = dict(point=name, model=model, strength=float(both[0][key]), replicas=len(both), clogged_full=0, clogged_early=0,
                 decided_by_early_test=0, disagreements=0, max_abs_dr=0.0, time_full=0.0, time_early=0.0,
                 clog_time_full=0.0, clog_time_early=0.0, wall_full=both_json["wall_seconds"])
        reproduced = 0
        for r in both:
            full_c, early_c = int(r["clogged"]), int(r["early_clogged"])
            dr = abs(float(r["distance"]) - float(r["early_distance"]))
            row = dict(model=model, strength=r[key], gap=r["gap"], replica=r["replica"], seed=r["seed"],
                       full_clogged=full_c, full_distance=r["distance"], full_time=r["time"], early_clogged=early_c,
                       early_decision=r["early_decision"], early_distance=r["early_distance"], early_time=r["early_time"],
                       early_rate=r["early_rate"], early_crossing=r["early_crossing"], abs_dr=f"{dr:.6g}",
                       agree=int(full_c == early_c))
            rows.append(row)
            p["clogged_full"] += full_c
            p["clogged_early"] += early_c
            p["decided_by_early_test"] += int(r["early_decision"] == "1")
            p["disagreements"] += int(full_c != early_c)
            if full_c and early_c:
                p["max_abs_dr"] = max(p["max_abs_dr"], dr)
                p["clog_time_full"] += float(r["time"])
                p["clog_time_early"] += float(r["early_time"])
            p["time_full"] += float(r["time"])
            p["time_early"] += float(r["early_time"])
            if early is not None:
                e = early[r["replica"]]
                reproduced += int(int(e["clogged"]) == early_c and e["distance"] == r["early_distance"] and e["time"] == r["early_time"])
        p["simulated_speedup"] = p["time_full"] / p["time_early"]
        p["clogged_simulated_speedup"] = p["clog_time_full"] / p["clog_time_early"] if p["clog_time_early"] > 0 else None
        if early is not None:
            p["wall_early"] = early_json["wall_seconds"]
            p["wall_speedup"] = p["wall_full"] / p["wall_early"]
            p["early_run_reproduces_both"] = reproduced
        points.append(p)
    with open(os.path.join(directory, "fast_clog_replicas.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    total = lambda k, ps: sum(p[k] for p in ps)
    summary = dict(
        definition="clogged: E_k/E_t < 1e-17 (full); early test of scenes/droplets/clog_detection.hpp",
        replicas=total("replicas", points),
        replicas_sp=total("replicas", [p for p in points if p["model"] == "sp"]),
        replicas_dp=total("replicas", [p for p in points if p["model"] == "dp"]),
        clogged_full=total("clogged_full", points),
        clogged_early=total("clogged_early", points),
        decided_by_early_test=total("decided_by_early_test", points),
        disagreements=total("disagreements", points),
        max_abs_dr=max(p["max_abs_dr"] for p in points),
        simulated_time_full=total("time_full", points),
        simulated_time_early=total("time_early", points),
        simulated_speedup=total("time_full", points) / total("time_early", points),
        clogged_simulated_speedup=total("clog_time_full", points) / total("clog_time_early", points),
        points=points,
    )
    walled = [p for p in points if "wall_early" in p]
    if walled:
        summary["wall_points"] = len(walled)
        summary["wall_full"] = total("wall_full", walled)
        summary["wall_early"] = total("wall_early", walled)
        summary["wall_speedup"] = summary["wall_full"] / summary["wall_early"]
        summary["early_runs_reproduce_both"] = f"{total('early_run_reproduces_both', walled)}/{total('replicas', walled)}"
    with open(os.path.join(directory, "fast_clog.json"), "w") as f:
        json.dump(summary, f, indent=2)
    print(f"replicas {summary['replicas']} (SP {summary['replicas_sp']}, DP {summary['replicas_dp']}), "
          f"clogged full {summary['clogged_full']} / early {summary['clogged_early']}, disagreements {summary['disagreements']}, "
          f"max |dr| {summary['max_abs_dr']:.3g} sigma, simulated speed-up {summary['simulated_speedup']:.2f} "
          f"(clogged replicas {summary['clogged_simulated_speedup']:.2f})"
          + (f", wall speed-up {summary['wall_speedup']:.2f} over {len(walled)} points" if walled else ""))
    for p in points:
        print(f"  {p['point']}: {p['replicas']} replicas, clogged {p['clogged_full']}/{p['clogged_early']} "
              f"(early test {p['decided_by_early_test']}), disagree {p['disagreements']}, max |dr| {p['max_abs_dr']:.3g}, "
              f"sim speed-up {p['simulated_speedup']:.2f}" + (f", wall {p['wall_full']:.1f}/{p['wall_early']:.1f} s" if "wall_early" in p else f", wall {p['wall_full']:.1f} s"))


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "docs/results/capillary/fast_clog")
