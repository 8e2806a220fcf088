// bench_hopper.cpp — whole time steps of the hopper study (hopper-flows paper), as the `hopper`
// driver takes them: velocity Verlet halves, neighbor-list upkeep, gravity, pair repulsion (eq. 2),
// wall repulsion (eq. 3), kinetic friction (eq. 6), drag (eq. 5), crossing detection and recycling
// (§2.4). items_per_second = particle-steps/s.
//   BM_HopperStepSP<D>/N/W: N bidisperse soft particles in a hopper of width W (2D: θ_w = 90°,
//     w = 8σ_avg; 3D: flat base, circular orifice w = 6σ_avg), E_sp = 100, E_w = 10⁴, both
//     dissipations on (μ/μ0 = 10√10, ζ/ζ0 = 1/√10) so every term of the step is timed. The scene is
//     relaxed by FIRE and flows for 20 t0 (2D) / 10 t0 (3D) before timing, so the orifice is
//     discharging and particles are being recycled while it is measured.
#include "drivers/hopper/hopper_scene.hpp"

#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>

namespace mesoflow {
namespace {

template <int D>
void BM_HopperStepSP(benchmark::State& state) {
  hopper::HopperParameters par;
  par.particles = int(state.range(0));
  par.hopper_width = double(state.range(1));
  par.orifice = D == 2 ? 8.0 : 6.0;
  par.friction = 10 * std::sqrt(10.0);
  par.drag = 1 / std::sqrt(10.0);
  par.seed = 3;
  hopper::HopperScene<D> scene(par);
  scene.relax();
  const int warmup = int((D == 2 ? 20.0 : 10.0) / par.dt);
  for (int s = 0; s < warmup; ++s) scene.step();
  const int steps = 200;
  const long long insertions_before = scene.insertions();
  for (auto _ : state) {
    Kokkos::fence();
    const auto t0 = std::chrono::steady_clock::now();
    for (int s = 0; s < steps; ++s) scene.step();
    Kokkos::fence();
    state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * steps * par.particles);
  state.counters["insertions_per_step"] =
      double(scene.insertions() - insertions_before) / double(int64_t(state.iterations()) * steps);
}

BENCHMARK_TEMPLATE(BM_HopperStepSP, 2)->Args({1600, 50})->Args({20000, 150})->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_HopperStepSP, 3)->Args({6400, 25})->UseManualTime()->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace mesoflow
