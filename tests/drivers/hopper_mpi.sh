#!/usr/bin/env bash
# A hopper sweep spread over MPI ranks (docs/scale-out.md) must write the same files as one process:
# every HDF5 file bitwise (observables, profiles, parameters), the result and profile tables, the
# same list of files (only rank 0 writes), and a JSON that says how many ranks ran:
#   - the width sweep given by the arguments on 2 ranks (uneven shares: widths 0, 2 and 1 of 3);
#   - a --vary drag sweep over 2 values × its first 2 widths on 3 ranks (items across the values).
#   hopper_mpi.sh <mpiexec> <hopper executable> <work dir> [driver arguments...]
set -euo pipefail
mpiexec="$1"; exe="$2"; dir="$3"; shift 3
rm -rf "$dir"; mkdir -p "$dir"/{one,two,vary_one,vary_three}
export OMP_NUM_THREADS=1 OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
args=(--quiet --threads 1 --no-plot --output run.h5 "$@")  # the same relative --output: equal /parameters
compare="$(realpath "$(dirname "$0")/h5_identical.py")"
status=0
fail() { echo "FAIL: $*" >&2; status=1; }

# same_files <one-process dir> <multi-rank dir> <ranks>
same_files() {
  local a="$1" b="$2" n="$3" f
  [ "$(ls "$b")" = "$(ls "$a")" ] || fail "$n ranks: other files than one process: $(ls "$b" | tr '\n' ' ')"
  for f in "$a"/*.json; do
    [ "$(basename "$f")" = run_vary.json ] && continue
    grep -q "\"ranks\": $n," "$b/$(basename "$f")" || fail "$n ranks: $(basename "$f") does not report $n ranks"
  done
  for f in "$a"/*.h5; do
    "$compare" "$f" "$b/$(basename "$f")" / || fail "$n ranks: $(basename "$f") differs from one process"
  done
  for f in "$a"/*.csv; do
    cmp "$f" "$b/$(basename "$f")" || fail "$n ranks: $(basename "$f") differs from one process"
  done
}

(cd "$dir/one" && "$exe" "${args[@]}")
(cd "$dir/two" && "$mpiexec" -np 2 "$exe" "${args[@]}")
same_files "$dir/one" "$dir/two" 2

vary=(); after_widths=""  # the arguments with the first 2 widths only, and the --vary sweep
for a in "${args[@]}"; do
  [ -n "$after_widths" ] && { a=$(cut -d, -f1-2 <<<"$a"); after_widths=""; }
  [ "$a" = --widths ] && after_widths=yes
  vary+=("$a")
done
vary+=(--vary drag --values 0.3,3)
(cd "$dir/vary_one" && "$exe" "${vary[@]}")
(cd "$dir/vary_three" && "$mpiexec" -np 3 "$exe" "${vary[@]}")
[ -f "$dir/vary_three/run_drag3.h5" ] || fail "the --vary sweep wrote no run_drag3.h5"
same_files "$dir/vary_one" "$dir/vary_three" 3

[ $status -eq 0 ] && echo "hopper sweeps on 2 ranks and a --vary sweep on 3 ranks write the same files as one process"
exit $status
