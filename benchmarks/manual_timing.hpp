// manual_timing.hpp — the timed region of a UseManualTime benchmark: fence, run, fence, record.
#pragma once

#include <benchmark/benchmark.h>

#include <Kokkos_Core.hpp>

#include <chrono>

namespace mesoflow::bench {

// Times `body` once per benchmark iteration, with Kokkos fences on both sides so that only the
// kernels launched by `body` are measured.
template <class Body>
void timed(benchmark::State& state, Body&& body) {
  for (auto _ : state) {
    Kokkos::fence();
    const auto t0 = std::chrono::steady_clock::now();
    body();
    Kokkos::fence();
    state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
}

}  // namespace mesoflow::bench
