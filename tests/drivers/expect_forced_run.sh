#!/usr/bin/env bash
# Runs a driver with a --dt above its stability limit and --force-dt, and checks that it ran
# (exit status 0) and warned on stderr with a message matching a pattern (the limiting term and
# the limit).
#   expect_forced_run.sh <pattern> <command> [arguments...]
set -uo pipefail
pattern="$1"; shift
err=$("$@" 2>&1 >/dev/null)
code=$?
echo "exit status $code; stderr: $err"
[ $code -eq 0 ] || { echo "FAIL: expected exit status 0"; exit 1; }
grep -qE -- "warning: .*$pattern" <<<"$err" || { echo "FAIL: no warning matching /$pattern/"; exit 1; }
