#!/usr/bin/env python3
"""summarize_gpu_session.py — tables from one scripts/gpu_session run (docs/portability.md).

    scripts/summarize_gpu_session.py SESSION_DIR OUT_DIR

SESSION_DIR is the unpacked OUT_DIR of scripts/gpu_session. Writes to OUT_DIR:
  tests.csv        every test program: exit status, tests passed/failed, seconds (as gpu_run_tests wrote)
  failures.txt     the failing tests, one per line, from the GoogleTest logs
  bench.csv        every benchmark: items/s, and for the whole-step ones the compulsory memory traffic
                   per item and that traffic as a fraction of the triad's bandwidth in the same run
and prints a summary. The compulsory traffic is a lower bound on what a step must move: each state
array of a particle read once and written once (2D/3D, float/double), nothing for neighbors, cells
or scratch; so the fraction is a lower bound of the fraction of bandwidth a kernel uses.
"""
import csv
import io
import json
import os
import re
import sys
import tarfile

# Whole-step benchmarks: name prefix -> (state doubles read, written) per item, dimension-aware.
# MPC: x, v read and written (streaming and collision). SPH: x, v, ρ read and written, mass read.
# MDPD: x, v read and written, f written. DP droplets: x, v read and written per vertex.
def compulsory_words(name):
    dim = 3 if "<3" in name or ", 3," in name else 2
    if name.startswith("BM_MpcStep"):
        return 2 * dim, 2 * dim
    if name.startswith("BM_SphStep"):
        return 2 * 3 + 2, 2 * 3 + 1
    if name.startswith("BM_MdpdStep"):
        return 2 * dim, 3 * dim
    if name.startswith("BM_DropletsInObstacleArray"):
        return 2 * 2, 2 * 2
    return None


def word_bytes(name):
    return 4 if "float" in name else 8


def main(argv):
    if len(argv) != 3:
        print(__doc__)
        return 2
    session, out = argv[1], argv[2]
    os.makedirs(out, exist_ok=True)
    rows = list(csv.DictReader(open(os.path.join(session, "tests", "summary.csv"))))
    with open(os.path.join(out, "tests.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    failures = []
    logs = os.path.join(session, "tests", "logs.tar.gz")
    if os.path.exists(logs):
        with tarfile.open(logs) as t:
            for m in t.getmembers():
                if not m.name.endswith(".log"):
                    continue
                text = t.extractfile(m).read().decode("utf-8", "replace")
                for line in text.splitlines():
                    mt = re.match(r"\[  FAILED  \] (\S+)(, where .*)?$", line)
                    if mt and "listed below" not in line and not line.rstrip().endswith("ms)"):
                        failures.append("%s: %s" % (os.path.basename(m.name)[:-4], mt.group(1)))
    failures = sorted(set(failures))
    with open(os.path.join(out, "failures.txt"), "w") as f:
        f.write("\n".join(failures) + ("\n" if failures else ""))
    passed = sum(int(r["passed"]) for r in rows)
    failed = sum(int(r["failed"]) for r in rows)
    bad = [r["program"] for r in rows if r["exit_status"] not in ("0",)]
    print("tests: %d programs, %d tests passed, %d failed; programs not exiting 0: %s"
          % (len(rows), passed, failed, ", ".join(bad) or "none"))
    for line in failures:
        print("  failed: " + line)

    bench_rows = []
    bandwidth = None
    for name in sorted(os.listdir(session)):
        if not (name.startswith("bench_") and name.endswith(".json")):
            continue
        try:
            data = json.load(open(os.path.join(session, name)))
        except (ValueError, OSError):
            continue
        for b in data.get("benchmarks", []):
            if b.get("run_type", "iteration") != "iteration":
                continue
            if b["name"].startswith("BM_ReferenceTriad") and "bytes_per_second" in b:
                if "/16777216" in b["name"] or bandwidth is None:
                    bandwidth = b["bytes_per_second"]
            bench_rows.append({"program": name[:-5], "benchmark": b["name"],
                               "items_per_second": b.get("items_per_second", ""),
                               "bytes_per_second": b.get("bytes_per_second", "")})
    for r in bench_rows:
        words = compulsory_words(r["benchmark"])
        r["compulsory_bytes_per_item"] = ""
        r["fraction_of_triad_bandwidth"] = ""
        if words and r["items_per_second"] and bandwidth:
            per_item = (words[0] + words[1]) * word_bytes(r["benchmark"])
            r["compulsory_bytes_per_item"] = per_item
            r["fraction_of_triad_bandwidth"] = "%.3f" % (float(r["items_per_second"]) * per_item / bandwidth)
    if bench_rows:
        with open(os.path.join(out, "bench.csv"), "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(bench_rows[0].keys()))
            w.writeheader()
            w.writerows(bench_rows)
        print("triad bandwidth: %s GB/s" % ("%.0f" % (bandwidth / 1e9) if bandwidth else "not measured"))
        for r in bench_rows:
            if r["fraction_of_triad_bandwidth"] or r["benchmark"].startswith("BM_ReferenceTriad"):
                print("  %-60s %12.3g items/s  %s" % (r["benchmark"], float(r["items_per_second"] or 0),
                                                      r["fraction_of_triad_bandwidth"]))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
