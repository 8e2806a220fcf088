#!/usr/bin/env bash
# --restart from a checkpoint written with other parameters (particle count, box) must fail with
# a message naming what differs, and must not touch the existing output.
#   restart_refuses_other_parameters.sh <lj_fluid executable> <work dir>
set -uo pipefail
exe="$1"; dir="$2"
rm -rf "$dir"; mkdir -p "$dir"
"$exe" --quiet --particles 200 --steps 20 --checkpoint-every 10 --output "$dir/run.h5" || exit 1
before=$(md5sum "$dir/run.ckpt.h5" "$dir/run.h5")
status=0
check() {
  local pattern="$1"; shift
  err=$("$exe" --quiet --steps 40 --output "$dir/run.h5" --restart "$@" 2>&1 >/dev/null)
  code=$?
  echo "$* -> exit $code: $err"
  [ $code -ne 0 ] && grep -qE -- "$pattern" <<<"$err" || { echo "FAIL: expected a failure matching /$pattern/"; status=1; }
}
check "holds 200 particles, this run has 300" --particles 300
check "box of length .* this run's box is" --particles 200 --density 0.5
check "holds a 3D double run; this run is 2D double" --particles 200 --dimension 2
[ "$before" = "$(md5sum "$dir/run.ckpt.h5" "$dir/run.h5")" ] || { echo "FAIL: the output was modified"; status=1; }
exit $status
