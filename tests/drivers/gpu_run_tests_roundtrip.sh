#!/usr/bin/env bash
# scripts/gpu_run_tests on the host: packs one test program (and its libraries) and runs it from the
# bundle, as on a GPU machine; the summary names it with exit status 0 and its passed count, and the
# closing line counts its tests. A program that fails makes the run fail.
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
echo "gpu_run_tests round trip: ok"
