#!/usr/bin/env bash
# Runs a driver forced above its stability limit (--force-dt) and checks that the NaN watchdog (or the
# capsule driver's divergence guard) stops it: exit status 1, a message matching the pattern (the
# non-finite field, the step and a force term; or the diverged density), and no result file
# written from the bad state.
#   expect_watchdog_stop.sh <pattern> <result file that must not exist> <command> [arguments...]
set -uo pipefail
pattern="$1"; shift
result="$1"; shift
rm -f "$result"
err=$("$@" 2>&1 >/dev/null)
code=$?
echo "exit status $code; stderr: $err"
[ $code -eq 1 ] || { echo "FAIL: expected exit status 1"; exit 1; }
grep -qE -- "$pattern" <<<"$err" || { echo "FAIL: the message does not match /$pattern/"; exit 1; }
[ ! -e "$result" ] || { echo "FAIL: $result was written"; exit 1; }
