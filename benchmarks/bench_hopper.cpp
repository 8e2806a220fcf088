// bench_hopper.cpp — whole time steps of the hopper study (hopper-flows paper), as the `hopper`
// driver takes them: velocity Verlet halves, neighbor-list upkeep, gravity, pair repulsion (eq. 2),
// wall repulsion (eq. 3), kinetic friction (eq. 6), drag (eq. 5), crossing detection and recycling
// (§2.4). items_per_second = particle-steps/s.
//   BM_HopperStepSP<D>/N/W: N bidisperse soft particles in a hopper of width W (2D: θ_w = 90°,
//     w = 8σ_avg; 3D: flat base, circular orifice w = 6σ_avg), E_sp = 100, E_w = 10⁴, both
//     dissipations on (μ/μ0 = 10√10, ζ/ζ0 = 1/√10) so every term of the step is timed. The scene is
//     relaxed by FIRE and flows for 20 t0 (2D) / 10 t0 (3D) before timing, so the orifice is
//     discharging and particles are being recycled while it is measured.
//   BM_HopperStepDP: the deformable-polygon hopper (scenes/hopper/dp_hopper_scene.hpp), 1600
//     bidisperse rough 16-gons (eq. 9), W = 50, w = 8, θ_w = 90°, defaults of DpHopperParameters
//     (K_a = 10⁴, K_l = 10, K_b = 0.1, E_c = E_w = 100), both dissipations on (μ/μ0 = 10√10,
//     ζ/ζ0 = 1/√10; Δt automatic, friction-limited), so every term of the step is timed: shape
//     forces and gravity, contacts, friction, walls, drag, neighbor upkeep, crossing detection and
//     recycling. Relaxed by FIRE, then flows for 5 t0 before timing (the first polygons cross at
//     ≈ 2 t0 and are re-inserted from ≈ 3 t0 on, so it is discharging and recycling while timed; the
//     pile is still settling). Setup ≈ 17 s at 1 thread (counter setup_s). items_per_second = vertex-steps/s.
#include "scenes/hopper/dp_hopper_scene.hpp"
#include "scenes/hopper/hopper_scene.hpp"

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

void BM_HopperStepDP(benchmark::State& state) {
  hopper::DpHopperParameters par;
  par.particles = 1600;
  par.vertices = 16;
  par.hopper_width = 50;
  par.orifice = 8;
  par.friction = 10 * std::sqrt(10.0);
  par.drag = 1 / std::sqrt(10.0);
  par.dt = 0;
  par.seed = 3;
  const auto setup = std::chrono::steady_clock::now();
  hopper::DpHopperScene<> scene(par);
  const auto fire = scene.relax();
  const int warmup = int(std::lround(5.0 / scene.dt()));
  for (int s = 0; s < warmup; ++s) scene.step();
  const double setup_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - setup).count();
  const int steps = 200;
  const long long insertions_before = scene.insertions();
  const int builds_before = scene.neighbor_builds();
  for (auto _ : state) {
    Kokkos::fence();
    const auto t0 = std::chrono::steady_clock::now();
    for (int s = 0; s < steps; ++s) scene.step();
    Kokkos::fence();
    state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  const double timed_steps = double(int64_t(state.iterations()) * steps);
  state.SetItemsProcessed(int64_t(state.iterations()) * steps * par.particles * par.vertices);
  state.counters["dt"] = scene.dt();
  state.counters["insertions_per_step"] = double(scene.insertions() - insertions_before) / timed_steps;
  state.counters["builds_per_step"] = double(scene.neighbor_builds() - builds_before) / timed_steps;
  state.counters["fire_iterations"] = fire.iterations;
  state.counters["setup_s"] = setup_seconds;
}

BENCHMARK(BM_HopperStepDP)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_HopperStepSP, 2)->Args({1600, 50})->Args({20000, 150})->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_HopperStepSP, 3)->Args({6400, 25})->UseManualTime()->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace mesoflow
