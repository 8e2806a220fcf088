#!/usr/bin/env python3
"""summarize_gpu_session.py — tables from one scripts/gpu_session run (docs/portability.md).

    scripts/summarize_gpu_session.py SESSION_DIR OUT_DIR [TEST_DIR ...]

TEST_DIR: further `gpu_run_tests run` OUT_DIRs of the same lease (programs rerun after they were not
run or were cut at their limit); a later run's row replaces an earlier one in tests.csv.

SESSION_DIR is the unpacked OUT_DIR of scripts/gpu_session. Writes to OUT_DIR:
  tests.csv        every test program: exit status, tests passed/failed, seconds (as gpu_run_tests wrote),
                   which run, and for a program cut at its limit the test it was in
  failures.txt     the failing tests, one per line, from the GoogleTest logs
  bench.csv        every benchmark: items/s, and for the whole-step ones the compulsory memory traffic
                   per item and that traffic as a fraction of the triad's bandwidth in the same run
  sanitizer.csv    compute-sanitizer memcheck per program and layout (as gpu_session wrote it)
  obstacles.{csv,json,replicas.csv}, obstacles_log.txt   the obstacle ensemble on the GPU, and
  obstacles_vs_cpu.json  its λ against the CPU's (CPU_REFERENCE, default the Fig. 13(b) verification
                   ensemble): the ratio λ_GPU/λ_CPU with a 95% interval from the clog counts
                   (the standard error of ln λ̂ is 1/√n_clogged for each; independent samples)
and prints a summary. The compulsory traffic is a lower bound on what a step must move: each state
array of a particle read once and written once (2D/3D, float/double), nothing for neighbors, cells
or scratch; so the fraction is a lower bound of the fraction of bandwidth a kernel uses.
"""
import csv
import io
import json
import math
import os
import re
import shutil
import sys
import tarfile

CPU_REFERENCE = os.environ.get("CPU_REFERENCE", os.path.join(
    os.path.dirname(os.path.abspath(__file__)), "..", "docs", "results", "capillary", "calibration", "runs",
    "verify_phi0.0248_L100.csv"))

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


def read_logs(test_dir):
    """program -> its GoogleTest log text, from a gpu_run_tests OUT_DIR's logs.tar.gz."""
    logs = {}
    path = os.path.join(test_dir, "logs.tar.gz")
    if os.path.exists(path):
        with tarfile.open(path) as t:
            for m in t.getmembers():
                if m.name.endswith(".log"):
                    logs[os.path.basename(m.name)[:-4]] = t.extractfile(m).read().decode("utf-8", "replace")
    return logs


def main(argv):
    if len(argv) < 3:
        print(__doc__)
        return 2
    session, out = argv[1], argv[2]
    os.makedirs(out, exist_ok=True)
    # The session's tests, then each further gpu_run_tests OUT_DIR (reruns of programs that were not
    # run or were cut at their time limit): a later run's row replaces an earlier one.
    test_dirs = [os.path.join(session, "tests")] + argv[3:]
    if os.path.exists(os.path.join(test_dirs[0], "suites.csv")):
        summarize_suites(test_dirs, out)
        test_dirs = []
    merged, logs = {}, {}
    for k, d in enumerate(test_dirs):
        run_logs = read_logs(d)
        for r in csv.DictReader(open(os.path.join(d, "summary.csv"))):
            if r["exit_status"] == "not run" and r["program"] in merged:
                continue
            r["run"] = str(k + 1)
            text = run_logs.get(r["program"], "")
            running = ""
            if r["exit_status"] == "124":  # cut at the time limit: the test it was in
                started = re.findall(r"^\[ RUN      \] (\S+)", text, re.M)
                finished = set(re.findall(r"^\[       OK \] (\S+)", text, re.M)) | set(
                    re.findall(r"^\[  FAILED  \] (\S+)", text, re.M))
                running = next((t for t in reversed(started) if t not in finished), "")
                r["passed"] = str(len(re.findall(r"^\[       OK \] ", text, re.M)))  # before the cut
            r["running_at_limit"] = running
            merged[r["program"]] = r
            logs[r["program"]] = text
    rows = [merged[p] for p in sorted(merged)]
    if not rows:
        return summarize_rest(session, out)
    with open(os.path.join(out, "tests.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    failures = []
    for program, text in logs.items():
        for line in text.splitlines():
            mt = re.match(r"\[  FAILED  \] (\S+)(, where .*)?$", line)
            if mt and "listed below" not in line and not line.rstrip().endswith("ms)"):
                failures.append("%s: %s" % (program, mt.group(1)))
    failures = sorted(set(failures))
    with open(os.path.join(out, "failures.txt"), "w") as f:
        f.write("\n".join(failures) + ("\n" if failures else ""))
    passed = sum(int(r["passed"]) for r in rows)
    failed = sum(int(r["failed"]) for r in rows)
    cut = [r["program"] + " (in " + (r["running_at_limit"] or "?") + ")" for r in rows if r["exit_status"] == "124"]
    bad = [r["program"] for r in rows if r["exit_status"] not in ("0", "124")]
    print("tests: %d programs, %d tests passed, %d failed; programs exiting non-zero: %s"
          % (len(rows), passed, failed, ", ".join(bad) or "none"))
    print("cut at their time limit (tests until then passed): %s" % (", ".join(cut) or "none"))
    for line in failures:
        print("  failed: " + line)
    return summarize_rest(session, out)


def summarize_suites(test_dirs, out):
    """tests.csv and failures.txt from `gpu_run_tests suites` folders (a later folder, e.g. a rerun of
    the entries an earlier one stopped, replaces their rows); totals per program printed."""
    merged, order = {}, []
    failures = []
    for k, test_dir in enumerate(test_dirs):
        rows = list(csv.DictReader(open(os.path.join(test_dir, "suites.csv"))))
        logs = read_logs(test_dir)  # logs/<row index>.log, 1-based in suites.csv's order
        for i, r in enumerate(rows, 1):
            key = (r["program"], r["filter"])
            if key not in merged:
                order.append(key)
            r["run"] = str(k + 1)
            merged[key] = r
            r["_failures"] = ["%s: %s" % (r["program"], mt.group(1)) for mt in
                              (re.match(r"\[  FAILED  \] (\S+)(, where .*)? \(\d+ ms\)$", line)
                               for line in logs.get(str(i), "").splitlines()) if mt]
    rows = [merged[key] for key in order]
    for r in rows:
        failures += r.pop("_failures")
    failures = sorted(set(failures))
    with open(os.path.join(out, "tests.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    with open(os.path.join(out, "failures.txt"), "w") as f:
        f.write("\n".join(failures) + ("\n" if failures else ""))
    per = {}
    for r in rows:
        a = per.setdefault(r["program"], {"entries": 0, "passed": 0, "failed": 0, "stopped": [], "not_run": 0,
                                          "bad": 0})
        a["entries"] += 1
        a["passed"] += int(r["passed"])
        a["failed"] += int(r["failed"])
        if r["exit_status"] in ("124", "137"):
            a["stopped"].append(r["running_at_stop"] or r["filter"])
        elif r["exit_status"] == "not run":
            a["not_run"] += 1
        elif r["exit_status"] != "0":
            a["bad"] += 1
            a.setdefault("crashed", []).append("%s (exit %s in %s)" % (r["filter"], r["exit_status"],
                                                                        r["running_at_stop"] or "?"))
    print("tests, one process per suite: %d entries, %d tests passed, %d failed"
          % (len(rows), sum(a["passed"] for a in per.values()), sum(a["failed"] for a in per.values())))
    for p in sorted(per):
        a = per[p]
        print("  %-28s %4d passed %3d failed  %d stopped at the deadline%s%s" % (
            p, a["passed"], a["failed"], len(a["stopped"]), " (" + ", ".join(a["stopped"]) + ")" if a["stopped"] else "",
            ", %d not started" % a["not_run"] if a["not_run"] else ""))
        for c in a.get("crashed", []):
            print("      crashed: " + c)
    for line in failures:
        print("  failed: " + line)


def bench_rows_from_text(path):
    scale = {"": 1.0, "k": 1e3, "M": 1e6, "G": 1e9, "T": 1e12}
    rows = []
    if not os.path.exists(path):
        return rows
    for line in open(path, errors="replace"):
        m = re.match(r"^(BM_\S+(?:, \S+)*)\s+[\d.]+ \w+\s+[\d.]+ \w+\s+\d+ .*?items_per_second=([\d.]+)([kMGT]?)/s", line)
        if m:
            rows.append({"name": m.group(1), "items_per_second": float(m.group(2)) * scale[m.group(3)],
                         "source": "console"})
    return rows


def summarize_rest(session, out):
    bench_rows = []
    bandwidth = None
    for name in sorted(os.listdir(session)):
        if not (name.startswith("bench_") and name.endswith(".json")):
            continue
        try:
            data = json.load(open(os.path.join(session, name)))
        except (ValueError, OSError):
            # A program that aborted leaves its JSON unfinished: the console lines it printed before
            # (bench_*.txt, "name  time  cpu  iterations ... items_per_second=5.42942G/s") are read instead.
            data = {"benchmarks": bench_rows_from_text(os.path.join(session, name[:-5] + ".txt"))}
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
    summarize_sanitizer(session, out)
    summarize_obstacles(session, out)
    return 0


def summarize_sanitizer(session, out):
    path = os.path.join(session, "sanitizer.csv")
    if not os.path.exists(path):
        return
    shutil.copy(path, os.path.join(out, "sanitizer.csv"))
    print("compute-sanitizer memcheck:")
    for r in csv.DictReader(open(path)):
        print("  %-4s %-36s exit %-8s memcheck errors %-4s failed tests %s"
              % (r["layout"], r["program"], r["exit_status"], r["memcheck_errors"], r["failed_tests"]))


def summarize_obstacles(session, out):
    d = os.path.join(session, "obstacles")
    if not os.path.isdir(d):
        return
    for src, dst in (("gpu.csv", "obstacles.csv"), ("gpu.json", "obstacles.json"),
                     ("gpu.replicas.csv", "obstacles.replicas.csv"), ("log.txt", "obstacles_log.txt"),
                     ("status.txt", "obstacles_status.txt")):
        if os.path.exists(os.path.join(d, src)):
            shutil.copy(os.path.join(d, src), os.path.join(out, dst))
    gpu_csv = os.path.join(d, "gpu.csv")
    if not os.path.exists(gpu_csv) or not os.path.exists(CPU_REFERENCE):
        print("obstacles: no GPU summary (the ensemble did not finish)" if not os.path.exists(gpu_csv)
              else "obstacles: no CPU reference at " + CPU_REFERENCE)
        return
    gpu = next(csv.DictReader(open(gpu_csv)))
    cpu = next(csv.DictReader(open(CPU_REFERENCE)))
    result = {"cpu_reference": os.path.relpath(CPU_REFERENCE, out)}
    for tag, r in (("gpu", gpu), ("cpu", cpu)):
        result[tag] = {k: float(r[k]) for k in ("replicas", "clogged", "decay_length", "decay_length_lower",
                                                  "decay_length_upper")}
    n_g, n_c = result["gpu"]["clogged"], result["cpu"]["clogged"]
    if n_g > 0 and n_c > 0:
        ratio = result["gpu"]["decay_length"] / result["cpu"]["decay_length"]
        se = math.sqrt(1 / n_g + 1 / n_c)
        result["ratio"] = ratio
        result["ratio_lower"] = ratio * math.exp(-1.96 * se)
        result["ratio_upper"] = ratio * math.exp(1.96 * se)
        result["consistent_at_95"] = result["ratio_lower"] <= 1 <= result["ratio_upper"]
    # The same seeds give the same obstacle arrays and initial droplets on both: how many of the
    # replicas both ran clog on both, and at the same place (|Δd| < 1σ).
    cpu_replicas = CPU_REFERENCE[:-4] + ".replicas.csv"
    gpu_replicas = os.path.join(d, "gpu.replicas.csv")
    if os.path.exists(cpu_replicas) and os.path.exists(gpu_replicas):
        key = lambda r: (r["line_tension"], r["gap"], r["replica"])
        c = {key(r): r for r in csv.DictReader(open(cpu_replicas))}
        g = {key(r): r for r in csv.DictReader(open(gpu_replicas))}
        common = [k for k in g if k in c and g[k]["seed"] == c[k]["seed"]]
        both = [k for k in common if g[k]["clogged"] == "1" and c[k]["clogged"] == "1"]
        same = [k for k in both if abs(float(g[k]["distance"]) - float(c[k]["distance"])) < 1.0]
        result["same_seed_replicas"] = len(common)
        result["same_seed_both_clogged"] = len(both)
        result["same_seed_clogged_within_one_sigma"] = len(same)
        result["same_seed_same_outcome"] = sum(g[k]["clogged"] == c[k]["clogged"] for k in common)
    with open(os.path.join(out, "obstacles_vs_cpu.json"), "w") as f:
        json.dump(result, f, indent=2)
    print("obstacles: GPU λ = %.3g [%.3g, %.3g]σ (%d/%d clogged), CPU λ = %.3g [%.3g, %.3g]σ (%d/%d); ratio %s"
          % (result["gpu"]["decay_length"], result["gpu"]["decay_length_lower"], result["gpu"]["decay_length_upper"],
             n_g, result["gpu"]["replicas"], result["cpu"]["decay_length"], result["cpu"]["decay_length_lower"],
             result["cpu"]["decay_length_upper"], n_c, result["cpu"]["replicas"],
             "%.3f [%.3f, %.3f]" % (result["ratio"], result["ratio_lower"], result["ratio_upper"])
             if "ratio" in result else "undefined"))
    if "same_seed_replicas" in result:
        print("  same seeds: %d replicas, same outcome in %d, both clogged in %d, %d of those within 1σ of each other"
              % (result["same_seed_replicas"], result["same_seed_same_outcome"], result["same_seed_both_clogged"],
                 result["same_seed_clogged_within_one_sigma"]))


if __name__ == "__main__":
    sys.exit(main(sys.argv))
