#!/usr/bin/env bash
# An obstacles sweep stopped after two replicas have finished, then run again with --restart, must
# recompute none of the finished replicas and end with the same results (HDF5 /results, CSV) as an
# uninterrupted sweep.
#   obstacles_resume.sh <obstacles executable> <work dir> [driver arguments...]
#
# The stop is deterministic: the sweep writes its checkpoint once at the start (no replica finished)
# and again after each finished replica; MESOFLOW_STOP_AFTER_CHECKPOINT=3
# (io/checkpoint_stop.hpp) ends it with exit status 75, as SIGKILL would, when the third
# replica has finished and its checkpoint is about to be written: two replicas are kept, the third
# is lost work.
set -euo pipefail
exe="$1"; dir="$2"; shift 2
rm -rf "$dir"; mkdir -p "$dir/straight" "$dir/killed"
args=(--quiet --threads 2 "$@")
compare="$(dirname "$0")/h5_identical.py"

"$exe" "${args[@]}" --output "$dir/straight/run.h5"
total=$(sed -n 's/.*"replicas_computed": \([0-9]*\).*/\1/p' "$dir/straight/run.json")

finished() { h5dump -d /finished "$dir/killed/run.ckpt.h5" 2>/dev/null | sed -n 's/.*(0): \([0-9]*\).*/\1/p'; }
code=0
MESOFLOW_STOP_AFTER_CHECKPOINT=3 "$exe" "${args[@]}" --output "$dir/killed/run.h5" || code=$?
[ $code -eq 75 ] || { echo "FAIL: the sweep should stop after its third checkpoint with exit status 75, got $code" >&2; exit 1; }
[ -f "$dir/killed/run.json" ] && { echo "FAIL: the stopped sweep wrote its summary" >&2; exit 1; }
before=$(finished)
echo "stopped with $before of $total replicas finished"
[ "$before" = 2 ] && [ "$before" -lt "$total" ] || { echo "FAIL: expected a checkpoint of 2 of $total replicas" >&2; exit 1; }

"$exe" "${args[@]}" --output "$dir/killed/run.h5" --restart
computed=$(sed -n 's/.*"replicas_computed": \([0-9]*\).*/\1/p' "$dir/killed/run.json")
resumed=$(sed -n 's/.*"replicas_resumed": \([0-9]*\).*/\1/p' "$dir/killed/run.json")
status=0
[ "$resumed" -eq "$before" ] || { echo "FAIL: resumed $resumed replicas, the checkpoint held $before" >&2; status=1; }
[ "$computed" -eq $((total - before)) ] || { echo "FAIL: computed $computed replicas after the restart, expected $((total - before))" >&2; status=1; }
"$compare" "$dir/straight/run.h5" "$dir/killed/run.h5" /results || { echo "FAIL: results differ" >&2; status=1; }
cmp "$dir/straight/run.csv" "$dir/killed/run.csv" || { echo "FAIL: summary tables differ" >&2; status=1; }
cmp "$dir/straight/run.replicas.csv" "$dir/killed/run.replicas.csv" || { echo "FAIL: replica tables differ" >&2; status=1; }
[ $status -eq 0 ] && echo "resumed sweep recomputed $computed of $total replicas and matches the uninterrupted sweep"
exit $status
