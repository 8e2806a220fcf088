#!/usr/bin/env bash
# Runs a driver and checks that it succeeded (exit status 0) and that its output, stdout and stderr
# together, matches a pattern (an extended regular expression over the whole output: `.` matches
# newlines too, so "a.*b" means a, then later b). ctest's PASS_REGULAR_EXPRESSION would check the
# pattern only and ignore the exit status.
#   expect_output.sh <pattern> <command> [arguments...]
set -uo pipefail
pattern="$1"; shift
out=$("$@" 2>&1)
code=$?
printf '%s\n' "$out"
echo "exit status $code"
[ $code -eq 0 ] || { echo "FAIL: expected exit status 0"; exit 1; }
printf '%s' "$out" | grep -qEz -- "$pattern" || { echo "FAIL: the output does not match /$pattern/"; exit 1; }
