// Benchmarks of the deformable-polygon (DP) droplet model (capillary-droplets study): full time
// steps (velocity Verlet, body state, shape forces, wall/obstacle repulsion, near-wall drag) of
// droplets with N_v = 256 in a random obstacle array (σ_ob = 0.3σ, w_ob = σ, Fig. 1b).
//
// items_per_second = vertex-steps/s; the `steps_per_second` counter is time steps of the whole
// scene per second. The wall energy is E_w = 0.1 here, not the paper's 10⁴: with vertex diameter
// δ = l0 the paper's value is not stable at Δt = 10⁻³ t0 (docs/droplets.md), and a benchmark that
// produced NaN would time NaN arithmetic.
#include <benchmark/benchmark.h>

#include "drivers/droplets/droplet_scene.hpp"

#include <chrono>
#include <cmath>

namespace mesoflow::droplets {
namespace {

using Exec = Kokkos::DefaultExecutionSpace;

template <class Real>
Surfaces<Real, Exec> obstacle_array(double L) {
  const auto centres = poisson_disk_obstacles(L, L, 0.3, 1.0, 7);
  const Real lo[2] = {0, 0}, len[2] = {Real(L), Real(L)};
  const bool periodic[2] = {true, true};
  return Surfaces<Real, Exec>(ObstacleArray<Real, Exec>(Box<2, Real>(lo, len, periodic), centres, Real(0.3), Real(1.3)));
}

template <class Real>
void BM_DropletsInObstacleArray(benchmark::State& state) {
  const int replicas = int(state.range(0));
  DropletParameters par;
  par.wall_energy = 0.1;
  const double L = 20.0 * std::ceil(std::sqrt(double(replicas)));
  std::vector<Vec<2, double>> centres;
  const int per_row = int(std::ceil(std::sqrt(double(replicas))));
  for (int r = 0; r < replicas; ++r)
    centres.push_back(Vec<2, double>{{10.0 + 20.0 * (r % per_row), 10.0 + 20.0 * (r / per_row)}});
  DropletScene<Real, Exec> scene(par, obstacle_array<Real>(L), centres);
  scene.relax(2000);
  for (int s = 0; s < 200; ++s) scene.step();
  const int steps_per_iteration = 100;
  for (auto _ : state) {
    Kokkos::fence();
    const auto t0 = std::chrono::steady_clock::now();
    for (int s = 0; s < steps_per_iteration; ++s) scene.step();
    Kokkos::fence();
    state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  const double steps = double(state.iterations()) * steps_per_iteration;
  state.SetItemsProcessed(int64_t(steps * par.vertices * replicas));
  state.counters["steps_per_second"] = benchmark::Counter(steps, benchmark::Counter::kIsRate);
}

BENCHMARK_TEMPLATE(BM_DropletsInObstacleArray, double)->Arg(1)->Arg(256)->UseManualTime()->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace mesoflow::droplets
