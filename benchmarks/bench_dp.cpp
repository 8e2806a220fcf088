// Benchmarks of the deformable-polygon (DP) droplet model (capillary-droplets study): full time
// steps (velocity Verlet, body state, shape forces, wall/obstacle repulsion, near-wall drag) of
// droplets with N_v = 256 in a random obstacle array (σ_ob = 0.3σ, w_ob = σ, Fig. 1b).
//
// items_per_second = vertex-steps/s; the `steps_per_second` counter is time steps of the whole
// scene per second. The wall energy is E_w = 0.1 here, not the paper's 10⁴: with vertex diameter
// δ = l0 the paper's value is not stable at Δt = 10⁻³ t0 (docs/droplets.md), and a benchmark that
// produced NaN would time NaN arithmetic.
#include <benchmark/benchmark.h>

#include "scenes/droplets/droplet_scene.hpp"
#include "scenes/droplets/obstacles_ensemble.hpp"
#include "kernels/common/geometry.hpp"
#include "kernels/dp/bending_force.hpp"
#include "kernels/sp/obstacle_repulsion.hpp"
#include "kernels/sp/viscous_drag.hpp"

#include <chrono>
#include <cmath>
#include <optional>
#include <numeric>
#include <random>

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
void droplets_in_obstacle_array(benchmark::State& state, bool edge_contacts) {
  const int replicas = int(state.range(0));
  DropletParameters par;
  par.edge_obstacle_contacts = edge_contacts;
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

// Droplets in obstacle arrays, one per 20σ × 20σ cell (the Fig. 2 droplet, N_v = 256): vertex-steps/s
// with eq. 3's vertex contacts, and with the edge contacts (dp/edge_obstacle_repulsion.hpp: a second
// loop over the vertices, each edge queried twice) — the pair's ratio is the edge contacts' cost.
template <class Real>
void BM_DropletsInObstacleArray(benchmark::State& state) {
  droplets_in_obstacle_array<Real>(state, false);
}
template <class Real>
void BM_DropletsInObstacleArrayEdgeContacts(benchmark::State& state) {
  droplets_in_obstacle_array<Real>(state, true);
}

// The fused DP shape loop with all five terms (bending included, which the droplet scene omits):
// vertex-updates/s, 256 droplets of 256 vertices.
void BM_ShapeForcesAllTerms(benchmark::State& state) {
  const int bodies = 256, nv = 256;
  const double l0 = dp::regular_polygon_edge(droplet_area, nv);
  const auto polygons = dp::Polygons<double, Exec>::uniform(bodies, nv, droplet_area, l0);
  dp::BodyState<double, Exec> body_state(bodies);
  Particles<2, double, Exec> p(std::size_t(bodies) * nv);
  dp::assign_bodies(polygons, p);
  auto x = Kokkos::create_mirror_view(p.x);
  for (int b = 0; b < bodies; ++b) dp::place_regular_polygon(polygons, b, x, Vec<2, double>{{2.0 * b, 0.0}}, 0.1 * b);
  Kokkos::deep_copy(p.x, x);
  for (auto _ : state) {
    Kokkos::fence();
    const auto t0 = std::chrono::steady_clock::now();
    dp::update_body_state(polygons, p, body_state);
    benchmark::DoNotOptimize(dp::accumulate_shape_forces(
        polygons, body_state, p, dp::AreaElasticity<double>{1e4}, dp::SegmentSprings<double>{1e-4},
        dp::LineTension<double>{0.16}, dp::Bending<double>{0.1}, dp::Gravity<double>{Vec<2, double>{{0.0, -1.0}}}));
    Kokkos::fence();
    state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  state.SetItemsProcessed(state.iterations() * bodies * nv);
}

// Soft-particle droplets (eqs. 8, 10) in an obstacle array: repulsion and drag, particle-updates/s.
void BM_SoftParticleSurfaceForces(benchmark::State& state) {
  const int n = int(state.range(0));
  const double L = std::sqrt(double(n)) * 4.0;
  const auto surfaces = obstacle_array<double>(L);
  Particles<2, double, Exec> p(n);
  auto x = Kokkos::create_mirror_view(p.x);
  std::mt19937_64 gen(3);
  std::uniform_real_distribution<double> u(0.0, L);
  for (int i = 0; i < n; ++i) {
    x(i, 0) = u(gen);
    x(i, 1) = u(gen);
  }
  Kokkos::deep_copy(p.x, x);
  const sp::ObstacleRepulsion<double> repulsion(1.0, 1.0);
  const sp::ViscousDrag<double> drag(droplet_mass / 0.08);
  for (auto _ : state) {
    Kokkos::fence();
    const auto t0 = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(accumulate_surface_forces(surfaces, p, p.v, repulsion, drag));
    Kokkos::fence();
    state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  state.SetItemsProcessed(state.iterations() * n);
}

// The orifice scene of Fig. 2 (N_v = 256, two wedges) composed four ways (issue 8, item 4), in
// vertex-steps/s:
//   0 only its terms: shape loop (K_a, K_l, Γ, gravity) + one surface loop (E_w, b∞, b0);
//   1 every other DP term present with coefficient zero: bending K_b = 0 and an empty obstacle
//     array — the scene drops both, so this must run as fast as 0;
//   2 bending switched on with a negligible coefficient (K_b = 10⁻¹²): what the fused loop costs
//     when it evaluates a term (an obstacle array cannot be switched on harmlessly: its obstacles
//     cover the box; tests/common/test_zero_coefficient_terms.cpp counts its kernels instead);
//   3 as 0, with the NaN watchdog checking every 100 steps (scenes/common/nan_watchdog.hpp).
void BM_OrificeSceneTerms(benchmark::State& state) {
  const int mode = int(state.range(0));
  DropletParameters par;
  if (mode == 2) par.bending_stiffness = 1e-12;
  const auto wedges = orifice_wedges<double>(0.4, 0.0, 0.0);
  const std::vector<Shape<2, double>> walls{wedges[0], wedges[1]};
  const auto surfaces =
      mode == 1 ? Surfaces<double, Exec>(walls, ObstacleArray<double, Exec>()) : Surfaces<double, Exec>(walls);
  DropletScene<double, Exec> scene(par, surfaces, {Vec<2, double>{{0.0, 2.0}}});
  scene.relax(2000);
  std::optional<watchdog::NanWatchdog> watch;
  if (mode == 3) watch.emplace(scene.watched(), 100);
  const int steps_per_iteration = 200;
  for (auto _ : state) {
    Kokkos::fence();
    const auto t0 = std::chrono::steady_clock::now();
    for (int s = 0; s < steps_per_iteration; ++s) {
      scene.step();
      if (watch) watch->after_step();
    }
    Kokkos::fence();
    state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  const double steps = double(state.iterations()) * steps_per_iteration;
  state.SetItemsProcessed(int64_t(steps * par.vertices));
  state.counters["steps_per_second"] = benchmark::Counter(steps, benchmark::Counter::kIsRate);
  const char* names[] = {"only_its_terms", "zero_coefficient_terms", "negligible_bending",
                         "only_its_terms+watchdog"};
  state.SetLabel(names[mode]);
}

// A clogging sweep (issue 25 item 3) in the regime of the paper's sweeps: most replicas clog at
// exponentially spread distances, some run to the time limit. `points` values of Γ from 1 to 10
// (log-spaced, K_l/Γ = 0.1) at w_ob = 0.2σ, σ_ob = 0.3σ, φ = 0.05 (L = 20σ), `replicas` replicas
// each, N_v = 256, V_t = 0.25 and T = 100 t0 (time-scaled: mean clog times 25–40 t0, where the
// paper's λ = 24σ takes ~400 t0 of T = 2000 t0), the early clog test with a 1 t0 window.
// Mode 0 runs the points one after another (a batch of `replicas` per point, each batch ending with
// its slowest replica); mode 1 runs the whole sweep in one batch of `replicas` slots, refilled and
// compacted (run_sweep_batched). Both give the same records (one w_ob), so items = the useful
// vertex-steps (each replica's steps to its end × N_v) compare the schedules directly; the
// `stepped_fraction` counter is useful / stepped vertex-steps (the relaxations are timed too).
// Minutes per mode: perf/run leaves it out; run it with --benchmark_filter=BM_ObstacleSweep.
void BM_ObstacleSweep(benchmark::State& state) {
  const bool batched = state.range(0) == 1;
  const int points = int(state.range(1)), replicas = int(state.range(2)), vertices = int(state.range(3));
  std::vector<ObstacleEnsembleParameters> scenes;
  for (int p = 0; p < points; ++p) {
    const double gamma = points > 1 ? std::pow(10.0, double(p) / (points - 1)) : 1.0;
    ObstacleEnsembleParameters par;
    par.droplet.vertices = vertices;
    par.droplet.line_tension = gamma;
    par.droplet.perimeter_stiffness = 0.1 * gamma;
    par.droplet.near_wall_drag = 0;
    par.droplet.terminal_speed = 0.25;
    par.box_length = 20;
    par.obstacle_fraction = 0.05;
    par.gap = 0.2;
    par.time_limit = 100;
    par.clog_test = ClogTest::early;
    par.early.sample_interval = 0.05;
    par.early.window = 1;
    par.relax_iterations = 2000;
    scenes.push_back(par);
  }
  std::vector<int> all(static_cast<std::size_t>(replicas));
  std::iota(all.begin(), all.end(), 0);
  double useful = 0, stepped = 0;
  for (auto _ : state) {
    useful = stepped = 0;
    const auto count = [&](std::size_t p, int, std::uint64_t, const ReplicaRecord& r) {
      useful += std::round(r.time / ObstacleSweep::time_step(scenes[p])) * vertices;
    };
    Kokkos::fence();
    const auto t0 = std::chrono::steady_clock::now();
    if (batched) {
      const auto stats = run_sweep_batched<double>(scenes, std::vector<std::vector<int>>(std::size_t(points), all), 3,
                                                   replicas, count, [](long long) {});
      stepped += double(stats.replica_steps) * vertices;
    } else {
      for (int p = 0; p < points; ++p) {
        std::vector<std::uint64_t> seeds;
        for (const int j : all) seeds.push_back(replica_seed(3, j));
        long long last = 0;
        run_obstacle_batch<double>(
            scenes[std::size_t(p)], seeds, [&](int k, const ReplicaRecord& r) { count(std::size_t(p), k, 0, r); },
            [&](long long s) { last = s; });
        stepped += double(last) * replicas * vertices;
      }
    }
    Kokkos::fence();
    state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  state.SetItemsProcessed(int64_t(useful) * int64_t(state.iterations()));
  state.counters["stepped_fraction"] = stepped > 0 ? useful / stepped : 0.0;
  state.SetLabel(batched ? "one batch, refilled" : "point by point");
}

BENCHMARK(BM_ObstacleSweep)
    ->ArgNames({"batched", "points", "replicas", "Nv"})
    ->Args({0, 10, 50, 256})
    ->Args({1, 10, 50, 256})
    ->Iterations(1)
    ->UseManualTime()
    ->Unit(benchmark::kSecond);
BENCHMARK(BM_ShapeForcesAllTerms)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_OrificeSceneTerms)->DenseRange(0, 3)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SoftParticleSurfaceForces)->Arg(65536)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_DropletsInObstacleArray, double)->Arg(1)->Arg(256)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_DropletsInObstacleArrayEdgeContacts, double)
    ->Arg(256)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);

// Device-sized problems (issue 26, item 6): an accelerator needs millions of items per launch before
// a step is limited by memory bandwidth rather than launch latency; these are registered in device
// builds only, so that a host run's benchmark list stays as it is.
#if defined(KOKKOS_ENABLE_CUDA) || defined(KOKKOS_ENABLE_HIP) || defined(KOKKOS_ENABLE_SYCL)
BENCHMARK_TEMPLATE(BM_DropletsInObstacleArray, double)->Arg(1024)->UseManualTime()->Unit(benchmark::kMillisecond);
#endif

}  // namespace
}  // namespace mesoflow::droplets
