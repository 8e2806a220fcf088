#!/usr/bin/env python3
"""compare_gpu_cpu_ensemble.py — one clogging ensemble run on the GPU and on the CPU with the same
arguments and seeds (issue 26 item 6; docs/portability.md): λ from the replicas both finished, the
ratio λ_GPU/λ_CPU with its 95% interval (independent samples: se of ln λ̂ = 1/√k for each), and the
same-seed comparison (same obstacle array and initial droplet: the same outcome, the same place).

    scripts/compare_gpu_cpu_ensemble.py GPU CPU_REPLICAS_CSV OUT.json

GPU: the obstacles driver's <out>.replicas.csv, or its checkpoint <out>.ckpt.h5 when the run was cut
(the replicas it finished). CPU_REPLICAS_CSV: <out>.replicas.csv of the CPU run.
"""
import csv
import json
import math
import sys


def read_replicas(path):
    """replica index -> (seed, clogged, distance, time)"""
    if path.endswith(".h5"):
        import h5py
        with h5py.File(path, "r") as f:
            rec = f["record"][()]
            return {int(j): (int(s) % 2**64, bool(c), float(r[0]), float(r[1]))  # stored as int64
                    for j, s, c, r in zip(f["replica"][()], f["seed"][()], f["clogged"][()], rec)}
    return {int(r["replica"]): (int(r["seed"]), r["clogged"] == "1", float(r["distance"]), float(r["time"]))
            for r in csv.DictReader(open(path))}


def mle(rows):
    """λ̂ = (Σ max(0, r)) / k with its 95% likelihood-ratio interval (analysis/droplets/clogging_statistics)."""
    k = sum(1 for c, _ in rows if c)
    total = sum(max(0.0, d) for _, d in rows)
    lam = total / k if k else math.inf

    def loglik(x):
        return -k * math.log(x) - total / x

    target = loglik(lam) - 3.841458820694124 / 2 if k else None

    def solve(lo, hi):
        f_lo = loglik(lo) - target
        for _ in range(200):
            mid = math.sqrt(lo * hi)
            if (loglik(mid) - target > 0) == (f_lo > 0):
                lo, f_lo = mid, loglik(mid) - target
            else:
                hi = mid
        return math.sqrt(lo * hi)

    if not k:
        return lam, total / (3.841458820694124 / 2), math.inf, k
    return lam, solve(lam * 1e-6, lam), solve(lam, lam * 1e6), k


def main(argv):
    if len(argv) != 4:
        print(__doc__)
        return 2
    gpu, cpu = read_replicas(argv[1]), read_replicas(argv[2])
    common = sorted(j for j in gpu if j in cpu)
    assert all(gpu[j][0] == cpu[j][0] for j in common), "the seeds differ: not the same ensemble"
    g = [(gpu[j][1], gpu[j][2]) for j in common]
    c = [(cpu[j][1], cpu[j][2]) for j in common]
    lam_g, lam_c = mle(g), mle(c)
    out = {"gpu": argv[1], "cpu": argv[2], "replicas_gpu": len(gpu), "replicas_cpu": len(cpu),
           "common": len(common),
           "gpu_decay_length": lam_g[:3], "gpu_clogged": lam_g[3],
           "cpu_decay_length": lam_c[:3], "cpu_clogged": lam_c[3]}
    if lam_g[3] and lam_c[3]:
        ratio = lam_g[0] / lam_c[0]
        se = math.sqrt(1 / lam_g[3] + 1 / lam_c[3])
        out["ratio"] = [ratio, ratio * math.exp(-1.96 * se), ratio * math.exp(1.96 * se)]
        out["consistent_at_95"] = out["ratio"][1] <= 1 <= out["ratio"][2]
    out["cpu_full_ensemble"] = dict(zip(("decay_length", "lower", "upper", "clogged"),
                                        mle([(v[1], v[2]) for v in cpu.values()])))
    same = [j for j in common if gpu[j][1] == cpu[j][1]]
    near = [j for j in common if gpu[j][1] and cpu[j][1] and abs(gpu[j][2] - cpu[j][2]) < 1.0]
    out["same_outcome"] = len(same)
    out["both_clogged_within_1_sigma"] = len(near)
    out["median_abs_distance_difference"] = sorted(abs(gpu[j][2] - cpu[j][2]) for j in common)[len(common) // 2]
    missing = sorted(j for j in cpu if j not in gpu)
    out["cpu_only"] = [{"replica": j, "clogged": cpu[j][1], "distance": cpu[j][2], "time": cpu[j][3]} for j in missing]
    if missing:  # where the replicas the GPU did not finish rank among the CPU's travel distances
        ranked = sorted(cpu, key=lambda j: -cpu[j][2])
        out["cpu_only_rank_by_distance"] = [ranked.index(j) + 1 for j in missing]
    json.dump(out, open(argv[3], "w"), indent=2)
    print(json.dumps(out, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
