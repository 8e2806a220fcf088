#!/usr/bin/env bash
# A run killed (SIGKILL) after its first checkpoint and restarted with --restart must end
# bit-identically to an uninterrupted run with the same thread count: same final checkpoint,
# same trajectory frames and observables.
#   restart_bit_identical.sh <driver executable> <work dir> [driver arguments...]
set -euo pipefail
exe="$1"; dir="$2"; shift 2
rm -rf "$dir"; mkdir -p "$dir/straight" "$dir/killed"
args=(--quiet --threads 2 "$@")

"$exe" "${args[@]}" --output "$dir/straight/run.h5"

"$exe" "${args[@]}" --output "$dir/killed/run.h5" &
pid=$!
for _ in $(seq 1 1200); do
  [ -f "$dir/killed/run.ckpt.h5" ] && break
  sleep 0.01
done
sleep 0.1
kill -9 "$pid" 2>/dev/null || true
wait "$pid" 2>/dev/null || true
if [ -f "$dir/killed/run.json" ]; then
  echo "FAIL: the run finished before it could be killed; give it more steps" >&2
  exit 1
fi
[ -f "$dir/killed/run.ckpt.h5" ] || { echo "FAIL: no checkpoint was written before the kill" >&2; exit 1; }
killed_at=$(h5dump -d /step "$dir/killed/run.ckpt.h5" | sed -n 's/.*(0): \([0-9]*\).*/\1/p')
echo "killed after the checkpoint of step $killed_at"

"$exe" "${args[@]}" --output "$dir/killed/run.h5" --restart

compare="$(dirname "$0")/h5_identical.py"
status=0
"$compare" "$dir/straight/run.ckpt.h5" "$dir/killed/run.ckpt.h5" / || { echo "FAIL: final checkpoints differ" >&2; status=1; }
"$compare" "$dir/straight/run.h5" "$dir/killed/run.h5" /particles /observables || { echo "FAIL: trajectories differ" >&2; status=1; }
[ $status -eq 0 ] && echo "restart is bit-identical to the uninterrupted run"
exit $status
