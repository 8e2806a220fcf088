#!/usr/bin/env bash
# scripts/gpu_run_tests on the host: packs one test program (and its libraries) and runs it from the
# bundle, as on a GPU machine; the summary names it with exit status 0 and its passed count, and the
# closing line counts its tests. A program that fails makes the run fail. Then the suites mode: one
# process per suite, and per test for a suite whose earlier time (SUITE_SECONDS) exceeds the split
# threshold; every test of the program runs exactly once, and all pass.
# usage: gpu_run_tests_roundtrip.sh <gpu_run_tests> <test program> <work dir>
set -euo pipefail
script=$1 program=$2 work=$3
rm -rf "$work" && mkdir -p "$work/build/tests"
cp "$program" "$work/build/tests/"
name=$(basename "$program")
"$script" pack "$work/build" "$work/bundle.tar.gz"
tar -tzf "$work/bundle.tar.gz" >"$work/contents.txt"
grep -qx "bin/$name" "$work/contents.txt"
"$script" run "$work/bundle.tar.gz" "$work/out" "$name" | tee "$work/table.txt"
grep -Eq "^$name,0,[1-9][0-9]*,0," "$work/out/summary.csv"
grep -Eq "^[1-9][0-9]* passed, 0 failed$" "$work/table.txt"
[ -s "$work/out/logs.tar.gz" ]
status=0
"$script" run "$work/bundle.tar.gz" "$work/out2" "$name" --no-such-program >/dev/null 2>&1 || status=$?
[ "$status" -ne 0 ] || { echo "a program that fails must fail the run"; exit 1; }
# suites mode: BoxTest/1 is "slow" (split into its tests), the others run as whole suites
tests=$(grep -c '^  ' < <("$program" --gtest_list_tests))
printf 'suite,seconds\nBoxTest/1,100\n' >"$work/seconds.csv"
SUITE_SECONDS="$work/seconds.csv" SPLIT_SECONDS=60 JOBS=2 TOTAL_SECONDS=50 \
  "$script" suites "$work/bundle.tar.gz" "$work/suites" "$name" | tee "$work/suites.txt"
grep -Eq "^$tests tests passed, 0 failed; 0 entries exited non-zero, 0 stopped at the deadline, 0 not started$" "$work/suites.txt"
grep -Eq "^$name,BoxTest/0\.\*,0,[1-9][0-9]*,0," "$work/suites/suites.csv"
grep -Eq "^$name,BoxTest/1\.[A-Za-z]+,0,1,0," "$work/suites/suites.csv"
[ "$(grep -c "^$name,BoxTest/1\.[A-Za-z]" "$work/suites/suites.csv")" -eq "$(grep -A99 '^BoxTest/1\.' < <("$program" --gtest_list_tests) | sed -n '2,$p' | grep -m1 -n '^[^ ]' | cut -d: -f1 | awk '{print $1 - 1}')" ]
echo "gpu_run_tests round trip: ok"
