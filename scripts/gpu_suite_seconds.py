#!/usr/bin/env python3
"""gpu_suite_seconds.py — seconds per GoogleTest suite in earlier GPU runs, the order in which
`scripts/gpu_run_tests suites` starts them (longest first; docs/portability.md).

    scripts/gpu_suite_seconds.py LOG_DIR... > suite_seconds.csv

LOG_DIR: unpacked `logs` folders of gpu_run_tests runs (each program's PROGRAM.log). A suite's seconds
are the sum of its tests' times ("[       OK ]" and "[  FAILED  ]" lines); a test that was running when
its program was cut at the time limit (a "[ RUN      ]" with no result) counts CUT_SECONDS (default
600), since it took at least the limit. A suite that ran to the end in some run keeps the largest
such figure; one that never did, its largest cut figure.
"""
import os
import re
import sys

CUT_SECONDS = float(os.environ.get("CUT_SECONDS", "600"))
done = re.compile(r"^\[ +(OK|FAILED) +\] (\S+?)\.(\S+)(?:, where .*)? \((\d+) ms\)")
run = re.compile(r"^\[ RUN +\] (\S+?)\.(\S+)")

complete = {}  # suite -> largest sum over runs in which it was not cut
cut = {}       # suite -> largest sum over runs in which it was
for top in sys.argv[1:]:
    for dirpath, _, files in os.walk(top):
        for name in files:
            if not name.endswith(".log"):
                continue
            per_suite = {}
            running = None
            with open(os.path.join(dirpath, name), errors="replace") as f:
                for line in f:
                    m = done.match(line)
                    if m:
                        per_suite[m.group(2)] = per_suite.get(m.group(2), 0.0) + int(m.group(4)) / 1000
                        running = None
                        continue
                    m = run.match(line)
                    if m:
                        running = m.group(1)
            if running is not None:
                per_suite[running] = per_suite.get(running, 0.0) + CUT_SECONDS
            for suite, s in per_suite.items():
                into = cut if suite == running else complete
                into[suite] = max(into.get(suite, 0.0), s)

seconds = dict(cut)
seconds.update(complete)

print("suite,seconds")
for suite, s in sorted(seconds.items(), key=lambda kv: -kv[1]):
    print(f"{suite},{s:.1f}")
