#!/usr/bin/env bash
# An obstacles sweep spread over MPI ranks (docs/scale-out.md) must give the same results as one
# process, and a multi-rank sweep killed mid-way must resume, on another number of ranks, without
# recomputing a finished replica:
#   1. one process (no mpirun) and `mpirun -np 3`: HDF5 /results and the CSV table bitwise equal,
#      3 ranks in the JSON, no rank checkpoint left behind;
#   2. `mpirun -np 3` stopped once rank 0 has checkpointed two finished replicas (a deterministic
#      stop, see below), then `mpirun -np 2 ... --restart`: it resumes exactly the
#      replicas the rank checkpoints held, computes the rest, and matches the one-process sweep.
#   obstacles_mpi.sh <mpiexec> <obstacles executable> <work dir> [driver arguments...]
set -euo pipefail
mpiexec="$1"; exe="$2"; dir="$3"; shift 3
rm -rf "$dir"; mkdir -p "$dir/one" "$dir/three" "$dir/killed"
export OMP_NUM_THREADS=1 OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
args=(--quiet --threads 1 "$@")
compare="$(dirname "$0")/h5_identical.py"
json_value() { sed -n "s/.*\"$1\": \([0-9]*\).*/\1/p" "$2"; }
status=0
fail() { echo "FAIL: $*" >&2; status=1; }

"$exe" "${args[@]}" --output "$dir/one/run.h5"
total=$(json_value replicas_computed "$dir/one/run.json")

"$mpiexec" -np 3 "$exe" "${args[@]}" --output "$dir/three/run.h5"
[ "$(json_value ranks "$dir/three/run.json")" = 3 ] || fail "the 3-rank sweep does not report 3 ranks"
[ "$(json_value replicas_computed "$dir/three/run.json")" = "$total" ] || fail "the 3-rank sweep did not compute $total replicas"
"$compare" "$dir/one/run.h5" "$dir/three/run.h5" /results || fail "3 ranks: results differ from one process"
cmp "$dir/one/run.csv" "$dir/three/run.csv" || fail "3 ranks: summary tables differ from one process"
ls "$dir"/three/run.rank*.ckpt.h5 >/dev/null 2>&1 && fail "3 ranks: rank checkpoints left behind"

finished() {  # finished replicas in the rank checkpoints
  local n=0 f k
  for f in "$dir"/killed/run.rank*.ckpt.h5; do
    [ -f "$f" ] || continue
    k=$(h5dump -d /finished "$f" 2>/dev/null | sed -n 's/.*(0): \([0-9]*\).*/\1/p')
    n=$((n + ${k:-0}))
  done
  echo "$n"
}
# The stop is deterministic (no timed kill): rank 0 alone gets MESOFLOW_STOP_AFTER_CHECKPOINT=3
# (io/checkpoint_stop.hpp) and ends with exit status 75 when its third replica has finished and
# its third rank checkpoint is about to be written (it keeps two, as SIGKILL would leave them);
# mpirun then ends the other ranks, whose checkpoints hold whatever they had finished.
code=0
"$mpiexec" -np 3 bash -c 'if [ "${OMPI_COMM_WORLD_RANK:-${PMI_RANK:-0}}" = 0 ]; then export MESOFLOW_STOP_AFTER_CHECKPOINT=3; fi; exec "$@"' \
  rank0-stops "$exe" "${args[@]}" --output "$dir/killed/run.h5" >"$dir/killed/mpirun.log" 2>&1 || code=$?
[ $code -ne 0 ] || { echo "FAIL: the 3-rank sweep should end with rank 0's stop, it exited 0" >&2; exit 1; }
grep -q "stopped after checkpoint 3" "$dir/killed/mpirun.log" ||
  { cat "$dir/killed/mpirun.log" >&2; echo "FAIL: rank 0 did not stop after its third checkpoint" >&2; exit 1; }
[ -f "$dir/killed/run.json" ] && { echo "FAIL: the stopped sweep wrote its summary" >&2; exit 1; }
rank0=$(h5dump -d /finished "$dir/killed/run.rank0.ckpt.h5" 2>/dev/null | sed -n 's/.*(0): \([0-9]*\).*/\1/p')
[ "${rank0:-0}" = 2 ] || { echo "FAIL: rank 0's checkpoint should hold 2 finished replicas, holds ${rank0:-none}" >&2; exit 1; }
before=$(finished)
echo "stopped with $before of $total replicas finished in $(ls "$dir"/killed/run.rank*.ckpt.h5 | wc -l) rank checkpoints"
[ "$before" -ge 1 ] && [ "$before" -lt "$total" ] || { echo "FAIL: expected a partial checkpoint" >&2; exit 1; }

"$mpiexec" -np 2 "$exe" "${args[@]}" --output "$dir/killed/run.h5" --restart
[ "$(json_value replicas_resumed "$dir/killed/run.json")" = "$before" ] ||
  fail "resumed $(json_value replicas_resumed "$dir/killed/run.json") replicas, the rank checkpoints held $before"
[ "$(json_value replicas_computed "$dir/killed/run.json")" = $((total - before)) ] ||
  fail "computed $(json_value replicas_computed "$dir/killed/run.json") replicas after the restart, expected $((total - before))"
"$compare" "$dir/one/run.h5" "$dir/killed/run.h5" /results || fail "resumed on 2 ranks: results differ from one process"
cmp "$dir/one/run.csv" "$dir/killed/run.csv" || fail "resumed on 2 ranks: summary tables differ from one process"
ls "$dir"/killed/run.rank*.ckpt.h5 >/dev/null 2>&1 && fail "resumed on 2 ranks: rank checkpoints left behind"
[ $status -eq 0 ] && echo "3 ranks match one process; the killed 3-rank sweep resumed on 2 ranks recomputing $((total - before)) of $total replicas"
exit $status
