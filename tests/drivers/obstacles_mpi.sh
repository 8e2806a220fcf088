#!/usr/bin/env bash
# An obstacles sweep spread over MPI ranks (docs/scale-out.md) must give the same results as one
# process, and a multi-rank sweep killed mid-way must resume, on another number of ranks, without
# recomputing a finished replica:
#   1. one process (no mpirun) and `mpirun -np 3`: HDF5 /results and the CSV table bitwise equal,
#      3 ranks in the JSON, no rank checkpoint left behind;
#   2. `mpirun -np 3` killed (SIGTERM, as a batch scheduler does at the time limit) once a rank has
#      checkpointed a finished replica, then `mpirun -np 2 ... --restart`: it resumes exactly the
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
"$mpiexec" -np 3 "$exe" "${args[@]}" --output "$dir/killed/run.h5" &
pid=$!
for _ in $(seq 1 3000); do
  [ "$(finished)" -ge 1 ] && break
  sleep 0.01
done
kill -TERM "$pid" 2>/dev/null || true
wait "$pid" 2>/dev/null || true
[ -f "$dir/killed/run.json" ] && { echo "FAIL: the sweep finished before it could be killed; give it more work" >&2; exit 1; }
before=$(finished)
echo "killed with $before of $total replicas finished in $(ls "$dir"/killed/run.rank*.ckpt.h5 | wc -l) rank checkpoints"
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
