#!/usr/bin/env bash
# Second GPU call of 2026-11-28 (docs/portability.md): bench_mpc's cell-sum modes alone, then side by
# side: backtraces (.gpu/libsegv.so, LD_PRELOAD) of the two segfaulting suites, the ensemble's last 6 replicas (--restart), and
# the 30 test entries the first call stopped or never started.
set -u
out=$1
b=$(mktemp -d); seg=$PWD/.gpu/libsegv.so
tar -xJf .gpu/bundle.tar.xz -C "$b"
export LD_LIBRARY_PATH=$b/lib
mkdir -p "$out/bench"
(cd "$b" && timeout 40 bin/bench_mpc --benchmark_min_time=0.1 --benchmark_filter='BM_MpcStepCellSums.*/25/[12]/|BM_ChannelFlowStep' \
   --benchmark_out="$out/bench/bench_mpc.json" --benchmark_out_format=json >"$out/bench/bench_mpc.txt" 2>&1); echo "bench_mpc: $?"
for t in 'MpcGridTest/0.StreamingAppliesB1AndWrapsPeriodicAxesOnly' 'RigidDiscsTest/0.ParticleAimedAtRestingDiscReturnsReversed'; do
  (cd "$b" && LD_PRELOAD=$seg timeout 90 bin/test_mpc --gtest_filter="$t" >"$out/gdb_${t%%.*}.txt" 2>&1
   echo "exit $?" >>"$out/gdb_${t%%.*}.txt") &
done
mkdir -p "$out/obstacles" && cp .gpu/gpu.ckpt.h5 "$out/obstacles/"
(t0=$(date +%s); cd "$b" && timeout 200 bin/obstacles $OBSTACLES_ARGS --restart --output "$out/obstacles/gpu.h5" >"$out/obstacles/log.txt" 2>&1
 echo "obstacles: exit $?, $(( $(date +%s) - t0 )) s" >"$out/obstacles/status.txt") &
ENTRIES=.gpu/rerun.tsv JOBS=16 TOTAL_SECONDS=${TESTS:-240} scripts/gpu_run_tests suites .gpu/bundle.tar.xz "$out/tests" >"$out/tests.txt" 2>&1
echo "tests: $?"; tail -2 "$out/tests.txt"
wait
cat "$out/obstacles/status.txt"
