#!/usr/bin/env python3
"""Merge, compare and check Google Benchmark JSON results (see perf/run).

  compare.py merge OUT IN...          concatenate the benchmarks of several runs into OUT
  compare.py compare BASELINE CURRENT  ratio-to-reference comparison, flags > 10% slowdowns
  compare.py targets RUN...            throughput targets and thread scaling of the issues
"""
import json
import sys

REFERENCE = "BM_ReferenceTriad"
TOLERANCE = 0.10

# (benchmark name prefix, minimum items_per_second at 2 threads) — from the project's issues.
TARGETS = [
    ("BM_NeighborListBuild<3, double, full>/1000000/1/0", 3.0e6),      # issue 2
    ("BM_DropletsInObstacleArray<double>/1/", 2.0e4 * 256),            # issue 3: 2·10⁴ steps/s at N_v = 256
    ("BM_DropletsInObstacleArray<double>/256/", 2.0e7),                # issue 3: vertex-steps/s
    ("BM_HopperStepSP<2>/1600/", 1.5e7),                               # issue 4: particle-steps/s
    ("BM_HopperStepSP<2>/20000/", 1.3e7),
    ("BM_HopperStepSP<3>/6400/", 5.0e6),
    ("BM_HopperStepDP/", 5.0e6),                                       # issue 4: vertex-steps/s
    ("BM_MpcStep<2, double, at_plus_a>/600000/40/25/", 2.0e7),         # issue 5: particle-updates/s, sorted every 25 steps
    ("BM_MpcStep<3, double, srd>/1000000/10/25/", 5.0e7),
    ("BM_MdpdStep<3, double, half>/100000/20/2/", 2.0e6),             # issue 6: particle-steps/s
    ("BM_MdpdStep<2, double, half>/100000/20/2/", 4.0e6),
    ("BM_SphStep<double, half>/100000/10/1/", 3.0e6),                  # issue 7: particle-steps/s
]
# Benchmarks whose 2-thread rate must be at least this multiple of the 1-thread rate.
SCALING = [("BM_NeighborListBuild<3, double, full>/1000000/1/0", 1.5)]


def load(path):
    with open(path) as f:
        return json.load(f)


def rates(run):
    out = {}
    for b in run["benchmarks"]:
        if b.get("run_type", "iteration") == "iteration" and "items_per_second" in b:
            out[b["name"]] = b["items_per_second"]
    return out


def threads(run):
    return int(run["context"].get("omp_threads", run["context"].get("threads", "0")))


def merge(out, inputs):
    runs = [load(p) for p in inputs]
    merged = runs[0]
    for r in runs[1:]:
        merged["benchmarks"].extend(r["benchmarks"])
    with open(out, "w") as f:
        json.dump(merged, f, indent=1)
    return 0


def compare(baseline_path, current_path):
    base, cur = rates(load(baseline_path)), rates(load(current_path))
    ref = [k for k in cur if k.startswith(REFERENCE)]
    if not ref or not any(k.startswith(REFERENCE) for k in base):
        print(f"compare: reference kernel {REFERENCE} missing from a run", file=sys.stderr)
        return 1
    ref_base = base[[k for k in base if k.startswith(REFERENCE)][0]]
    ref_cur = cur[ref[0]]
    flagged = 0
    print(f"{'benchmark':62s} {'baseline':>11s} {'current':>11s} {'ratio/ref':>9s}")
    for name in sorted(cur):
        if name.startswith(REFERENCE) or name not in base:
            continue
        change = (cur[name] / ref_cur) / (base[name] / ref_base)
        mark = "  SLOWER" if change < 1.0 - TOLERANCE else ""
        flagged += bool(mark)
        print(f"{name:62s} {base[name]:11.4g} {cur[name]:11.4g} {change:9.3f}{mark}")
    print(f"reference {REFERENCE}: baseline {ref_base:.4g}/s, current {ref_cur:.4g}/s")
    if flagged:
        print(f"compare: {flagged} kernel(s) more than {TOLERANCE:.0%} slower relative to the reference")
    return 1 if flagged else 0


def targets(paths):
    runs = {threads(load(p)): rates(load(p)) for p in paths}
    failed = 0
    two = runs.get(2)
    for prefix, minimum in TARGETS:
        if two is None:
            break
        for name, rate in two.items():
            if name.startswith(prefix):
                ok = rate >= minimum
                failed += not ok
                print(f"target  {name}: {rate:.3g}/s at 2 threads (target {minimum:.3g}) {'ok' if ok else 'MISSED'}")
    if 1 in runs and 2 in runs:
        for prefix, factor in SCALING:
            for name, rate in runs[2].items():
                if name.startswith(prefix) and name in runs[1]:
                    s = rate / runs[1][name]
                    ok = s >= factor
                    failed += not ok
                    print(f"scaling {name}: 2 threads / 1 thread = {s:.2f} (target {factor}) {'ok' if ok else 'MISSED'}")
    return 1 if failed else 0


def main(argv):
    if len(argv) >= 3 and argv[1] == "merge":
        return merge(argv[2], argv[3:])
    if len(argv) == 4 and argv[1] == "compare":
        return compare(argv[2], argv[3])
    if len(argv) >= 3 and argv[1] == "targets":
        return targets(argv[2:])
    print(__doc__, file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv))
