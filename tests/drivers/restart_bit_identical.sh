#!/usr/bin/env bash
# A run stopped after its first checkpoint and restarted with --restart must resume from that
# checkpoint (not from step 0) and end bit-identically to an uninterrupted run with the same thread
# count: same final checkpoint, same trajectory frames and observables.
#   restart_bit_identical.sh <driver executable> <work dir> [driver arguments...]
#
# The stop is deterministic: MESOFLOW_STOP_AFTER_CHECKPOINT=1 (io/checkpoint_stop.hpp)
# ends the driver with exit status 75 when it comes to write its second checkpoint, without
# destructors or closing files, as SIGKILL would. The steps it ran after the first checkpoint, and
# the frames it flushed past it, are work the restart must redo and drop; the test checks that there
# are such frames. The restarted run's summary (<out>.json) must say it resumed from the checkpoint's
# step and ran only the steps after it: resumed_from_step = that step > 0 and
# steps_run + resumed_from_step = the uninterrupted run's steps_run.
set -euo pipefail
exe="$1"; dir="$2"; shift 2
rm -rf "$dir"; mkdir -p "$dir/straight" "$dir/killed"
args=(--quiet --threads 2 "$@")
compare="$(dirname "$0")/h5_identical.py"
fail() { echo "FAIL: $*" >&2; exit 1; }
json_value() { sed -n "s/.*\"$1\": \([0-9]*\).*/\1/p" "$2"; }

"$exe" "${args[@]}" --output "$dir/straight/run.h5"

code=0
MESOFLOW_STOP_AFTER_CHECKPOINT=1 "$exe" "${args[@]}" --output "$dir/killed/run.h5" || code=$?
[ $code -eq 75 ] || fail "the run should stop after its first checkpoint with exit status 75, got $code"
[ ! -f "$dir/killed/run.json" ] || fail "the stopped run wrote its summary"
[ -f "$dir/killed/run.ckpt.h5" ] || fail "no checkpoint was written before the stop"
stopped_at=$(h5dump -d /step "$dir/killed/run.ckpt.h5" | sed -n 's/.*(0): \([0-9]*\).*/\1/p')
[ -n "$stopped_at" ] && [ "$stopped_at" -gt 0 ] || fail "the checkpoint's step is '$stopped_at', expected > 0"
flushed=$(/usr/bin/python3 - "$dir/killed/run.h5" <<'EOF'
import sys, h5py
last = []
with h5py.File(sys.argv[1], "r") as f:
    f.visititems(lambda name, obj: last.append(int(obj[-1])) if name.endswith("/step") and obj.shape and obj.shape[0] else None)
print(max(last))
EOF
)
[ "$flushed" -gt "$stopped_at" ] ||
  fail "the stopped run flushed output up to step $flushed only, not past its checkpoint (step $stopped_at)"
echo "stopped after the checkpoint of step $stopped_at, with output flushed up to step $flushed"

"$exe" "${args[@]}" --output "$dir/killed/run.h5" --restart

straight_steps=$(json_value steps_run "$dir/straight/run.json")
resumed=$(json_value resumed_from_step "$dir/killed/run.json")
restarted_steps=$(json_value steps_run "$dir/killed/run.json")
echo "uninterrupted: $straight_steps steps; restarted: resumed from step $resumed, $restarted_steps steps"
status=0
[ "$(json_value resumed_from_step "$dir/straight/run.json")" = 0 ] || { echo "FAIL: the uninterrupted run says it resumed" >&2; status=1; }
[ "$resumed" = "$stopped_at" ] || { echo "FAIL: resumed from step '$resumed', the checkpoint holds step $stopped_at" >&2; status=1; }
[ -n "$restarted_steps" ] && [ -n "$straight_steps" ] && [ $((restarted_steps + stopped_at)) -eq "$straight_steps" ] ||
  { echo "FAIL: the restarted run ran '$restarted_steps' steps, expected $straight_steps - $stopped_at" >&2; status=1; }
"$compare" "$dir/straight/run.ckpt.h5" "$dir/killed/run.ckpt.h5" / || { echo "FAIL: final checkpoints differ" >&2; status=1; }
"$compare" "$dir/straight/run.h5" "$dir/killed/run.h5" /particles /observables || { echo "FAIL: trajectories differ" >&2; status=1; }
[ $status -eq 0 ] && echo "restart from step $stopped_at is bit-identical to the uninterrupted run"
exit $status
