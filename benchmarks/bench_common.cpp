// Benchmarks of the common kernels: cell binning, neighbor-list build, the generic pair loop, and
// the reference kernel (a streaming triad) that perf/compare divides every figure by, so that
// results from noisy or different machines compare as ratios.
//
// items_per_second: particles/s for binning and list builds, pair-updates/s for the pair loop,
// particle-updates/s for the triad.
#include <benchmark/benchmark.h>

#include <cstdint>

#include "manual_timing.hpp"
#include "kernels/common/langevin.hpp"
#include "kernels/common/lennard_jones.hpp"
#include "kernels/common/neighbor_list.hpp"
#include "kernels/common/pair_force.hpp"

#include <cmath>
#include <algorithm>
#include <array>
#include <random>
#include <vector>

namespace mesoflow {
namespace {

using Exec = Kokkos::DefaultExecutionSpace;
constexpr double kPi = 3.14159265358979323846;

// n particles uniformly at random in a periodic cube at unit density: a reach r gives on average
// (4/3)π r³ neighbors in 3D (π r² in 2D).
template <int D, class Real>
struct Scene {
  Particles<D, Real, Exec> p;
  Box<D, Real> box;
};

template <int D, class Real>
Scene<D, Real> random_scene(int n, unsigned seed, bool sorted = false) {
  const double L = std::pow(double(n), 1.0 / D);
  Scene<D, Real> s{Particles<D, Real, Exec>(n), Box<D, Real>::cube(Real(L), true)};
  auto x = Kokkos::create_mirror_view(s.p.x);
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(0.0, L);
  std::vector<std::array<double, D>> pos(n);
  for (auto& r : pos)
    for (int d = 0; d < D; ++d) r[d] = u(gen);
  if (sorted) {
    const double w = 1.0;  // sort key: cells of unit width, axis 0 fastest
    auto key = [&](const std::array<double, D>& r) {
      long long k = 0;
      for (int d = D - 1; d >= 0; --d) k = k * 1000 + (long long)(r[d] / w);
      return k;
    };
    std::sort(pos.begin(), pos.end(), [&](const auto& a, const auto& b) { return key(a) < key(b); });
  }
  for (int i = 0; i < n; ++i)
    for (int d = 0; d < D; ++d) x(i, d) = Real(pos[i][d]);
  Kokkos::deep_copy(s.p.x, x);
  return s;
}

// Reach giving `neighbors` neighbors per particle at unit density.
template <int D>
double reach_for(double neighbors) {
  return D == 3 ? std::cbrt(neighbors * 3.0 / (4.0 * kPi)) : std::sqrt(neighbors / kPi);
}

using bench::timed;

template <int D, class Real>
void BM_CellBinning(benchmark::State& state) {
  const int n = int(state.range(0));
  auto s = random_scene<D, Real>(n, 1);
  CellList<D, Real, Exec> cells;
  const Real width = Real(reach_for<D>(25.0));
  cells.build(s.p.x, s.box, width);
  timed(state, [&] { cells.build(s.p.x, s.box, width); });
  state.SetItemsProcessed(state.iterations() * n);
}

template <int D, class Real, NeighborListKind Kind>
void BM_NeighborListBuild(benchmark::State& state) {
  const int n = int(state.range(0));
  auto s = random_scene<D, Real>(n, 2, state.range(2));
  const double reach = reach_for<D>(25.0);
  const int cells_per_reach = state.range(1);
  NeighborList<D, Real, Exec> list(Real(0.9 * reach), Real(0.1 * reach), Kind, BodyExclusion::none, cells_per_reach);
  list.build(s.p, s.box);
  timed(state, [&] { list.build(s.p, s.box); });
  state.SetItemsProcessed(state.iterations() * n);
  state.counters["neighbors_per_particle"] = double(list.num_entries()) / n;
}

template <int D, class Real, NeighborListKind Kind>
void BM_PairForceLJ(benchmark::State& state) {
  const int n = int(state.range(0));
  auto s = random_scene<D, Real>(n, 3);
  const double reach = reach_for<D>(25.0);
  // Unit density random points overlap strongly: a small σ keeps the forces finite and tame.
  const LennardJones<Real> lj(Real(1), Real(0.3), Real(0.9 * reach));
  NeighborList<D, Real, Exec> list(Real(0.9 * reach), Real(0.1 * reach), Kind);
  list.build(s.p, s.box);
  PairForce<D, Real, Exec> pair;
  timed(state, [&] {
    Kokkos::deep_copy(s.p.f, Real(0));
    benchmark::DoNotOptimize(pair.accumulate(lj, s.p, list, s.box));
  });
  state.SetItemsProcessed(state.iterations() * list.num_entries());
}

// Langevin thermostat forces (one Philox stream per particle): particle-updates/s.
void BM_LangevinForces(benchmark::State& state) {
  const int n = int(state.range(0));
  Particles<3, double, Exec> p(n);
  const LangevinThermostat<double> thermostat(1.0, 1.0, 1);
  std::int64_t step = 0;
  timed(state, [&] { thermostat.accumulate(p, p.v, 0.005, step++); });
  state.SetItemsProcessed(state.iterations() * n);
}

// Reference kernel: x ← x + dt·v over the same SoA storage (memory-bound, ~48 bytes per particle).
void BM_ReferenceTriad(benchmark::State& state) {
  const int n = int(state.range(0));
  Particles<3, double, Exec> p(n);
  const auto x = p.x, v = p.v;
  timed(state, [&] {
    Kokkos::parallel_for(
        "mesoflow::bench::reference_triad", Kokkos::RangePolicy<Exec>(0, n), KOKKOS_LAMBDA(int i) {
          for (int d = 0; d < 3; ++d) x(i, d) += 1e-3 * v(i, d);
        });
  });
  state.SetItemsProcessed(state.iterations() * n);
  state.SetBytesProcessed(state.iterations() * std::int64_t(n) * 72);  // x, v read, x written: 3 doubles each
}

constexpr auto full = NeighborListKind::full;
constexpr auto half = NeighborListKind::half;

// 2^20 rows (48 MB): the machine-local reference for the kernels beside it; 2^24 rows (805 MB): the
// memory bandwidth of a device whose last-level cache holds the small one (an H200's 60 MB L2).
BENCHMARK(BM_ReferenceTriad)->Arg(1 << 20)->Arg(1 << 24)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LangevinForces)->Arg(1 << 20)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_CellBinning, 3, double)->Arg(1000000)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_CellBinning, 2, double)->Arg(1000000)->UseManualTime()->Unit(benchmark::kMillisecond);
// Arguments: particles; cells per reach (1: 27 cells, 2: 125 cells of half the width);
// particle order (0: random, 1: sorted by cell, as after a spatial sort).
BENCHMARK_TEMPLATE(BM_NeighborListBuild, 3, double, full)
    ->Args({100000, 1, 0})->Args({1000000, 1, 0})->Args({1000000, 2, 0})->Args({1000000, 1, 1})
    ->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_NeighborListBuild, 3, double, half)->Args({1000000, 1, 0})->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_NeighborListBuild, 3, float, full)->Args({1000000, 1, 0})->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_NeighborListBuild, 2, double, full)->Args({1000000, 1, 0})->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_PairForceLJ, 3, double, full)->Arg(1000000)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_PairForceLJ, 3, double, half)->Arg(1000000)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_PairForceLJ, 3, float, full)->Arg(1000000)->UseManualTime()->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace mesoflow
