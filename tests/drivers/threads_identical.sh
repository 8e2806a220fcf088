#!/usr/bin/env bash
# The deterministic-sum mode (issue 26 item 4) at the driver level: a run with --deterministic gives
# bitwise the same HDF5 data under <path> on 1 and on 2 threads, and the same run without the flag
# does not (so the comparison can fail).
#   threads_identical.sh <driver> <work dir> <path> [driver arguments...]
set -euo pipefail
exe="$1"; dir="$2"; path="$3"; shift 3
rm -rf "$dir"; mkdir -p "$dir"
compare="$(dirname "$0")/h5_identical.py"
for t in 1 2; do
  OMP_NUM_THREADS=$t "$exe" --quiet --threads $t "$@" --deterministic --output "$dir/det_t$t.h5"
  OMP_NUM_THREADS=$t "$exe" --quiet --threads $t "$@" --output "$dir/default_t$t.h5"
done
status=0
"$compare" "$dir/det_t1.h5" "$dir/det_t2.h5" "$path" || { echo "FAIL: --deterministic differs between 1 and 2 threads" >&2; status=1; }
if "$compare" "$dir/default_t1.h5" "$dir/default_t2.h5" "$path" > /dev/null 2>&1; then
  echo "FAIL: the default mode agrees between 1 and 2 threads too: the test cannot tell the modes apart" >&2
  status=1
fi
[ $status -eq 0 ] && echo "--deterministic: $path bitwise identical on 1 and 2 threads (the default mode differs)"
exit $status
