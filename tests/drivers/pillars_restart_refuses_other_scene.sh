#!/usr/bin/env bash
# pillars --restart from a checkpoint of another scene must fail (exit 2) naming what may change,
# and must leave the existing output untouched; --steps may change (the run is extended).
#   pillars_restart_refuses_other_scene.sh <pillars executable> <work dir>
set -uo pipefail
exe="$1"; dir="$2"
rm -rf "$dir"; mkdir -p "$dir"
args=(--quiet --threads 2 --dimension 2 --layout square --cells-x 3 --cells-y 1
      --equilibrate-steps 50 --warmup-steps 50 --sample-every 10 --output "$dir/run.h5")
"$exe" "${args[@]}" --porosity 0.8 --steps 100 || exit 1
before=$(md5sum "$dir/run.ckpt.h5" "$dir/run.h5")
status=0
err=$("$exe" "${args[@]}" --steps 200 --porosity 0.7 --restart 2>&1 >/dev/null)
code=$?
echo "--porosity 0.7 -> exit $code: $err"
[ $code -eq 2 ] && grep -qE -- "written by another scene.*only --steps, --checkpoint-every, --check-every and --threads may change" <<<"$err" ||
  { echo "FAIL: expected exit 2 naming the parameters that may change"; status=1; }
[ "$before" = "$(md5sum "$dir/run.ckpt.h5" "$dir/run.h5")" ] || { echo "FAIL: the output was modified"; status=1; }
"$exe" "${args[@]}" --porosity 0.8 --steps 200 --restart || { echo "FAIL: extending --steps was refused"; status=1; }
python3 -c "import json,sys; s=json.load(open('$dir/run.json')); sys.exit(0 if s['samples']==20 else 1)" ||
  { echo "FAIL: the extended run should hold 20 samples"; status=1; }
exit $status
