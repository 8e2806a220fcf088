#!/usr/bin/env bash
# Runs a build command that must FAIL (a deliberate compile error) and checks that it did (non-zero
# exit status) and that its output matches a pattern (the error the check is about, not any error).
#   expect_build_failure.sh <pattern> <command> [arguments...]
set -uo pipefail
pattern="$1"; shift
out=$("$@" 2>&1)
code=$?
printf '%s\n' "$out" | grep -E "error|static assert|kernel_closure_size" | head -20
echo "exit status $code"
[ $code -ne 0 ] || { echo "FAIL: the build succeeded; it must not"; exit 1; }
printf '%s' "$out" | grep -qE -- "$pattern" || { echo "FAIL: the output does not match /$pattern/"; exit 1; }
