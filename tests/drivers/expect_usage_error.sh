#!/usr/bin/env bash
# Runs a driver with bad input and checks that it exits with the usage status (2) and that its
# error message matches a pattern (naming the parameter and the allowed range or the path).
#   expect_usage_error.sh <pattern> <command> [arguments...]
set -uo pipefail
pattern="$1"; shift
err=$("$@" 2>&1 >/dev/null)
code=$?
echo "exit status $code; stderr: $err"
[ $code -eq 2 ] || { echo "FAIL: expected exit status 2"; exit 1; }
grep -qE -- "$pattern" <<<"$err" || { echo "FAIL: the message does not match /$pattern/"; exit 1; }
grep -qiE "nan|inf" <<<"$pattern" || ! grep -q "Segmentation\|core dumped" <<<"$err"
