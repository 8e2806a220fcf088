// bench_mdpd.cpp — the MDPD liquid of the pillar study (issue 6, item 6) in a periodic box at
// ρ = 6, the paper's parameters (3D: A = −40, B = 25; 2D: B = 30; r_B = 0.75, R = 12, dt = 0.01).
// items_per_second = particle-steps/s; a step is everything MdpdSystem::step does: half kick and
// drift, neighbor-list upkeep (skin criterion, periodic memory sort), many-body densities, fused
// conservative + dissipative + random forces, second half kick.
//   BM_MdpdStep<3, double, half>/100000/20/2: target 2·10⁶/s at 2 threads (LAMMPS 1.0·10⁶ here);
//   BM_MdpdStep<2, double, half>/100000/20/2: target 4·10⁶/s.
// The `full` variants run the same physics on a full neighbor list (no scatter, two random
// numbers per pair); float variants show what single precision buys. The third argument is the
// neighbor skin in units of 0.01σ, the fourth cells per reach of the list's binning.
// Each configuration is equilibrated for 200 steps (from uniformly random positions) before timing.
#include <benchmark/benchmark.h>

#include "manual_timing.hpp"
#include "kernels/common/random.hpp"
#include "scenes/pillars/mdpd_system.hpp"

#include <cmath>

namespace mesoflow {
namespace {

using Exec = Kokkos::DefaultExecutionSpace;

template <int D, class Real, NeighborListKind Kind>
void BM_MdpdStep(benchmark::State& state) {
  const int n_target = int(state.range(0));
  mdpd::MdpdParameters par;
  if (D == 2) par.B = 30;
  const double density = 6.0;
  const double L = std::pow(n_target / density, 1.0 / D);
  const int n = int(std::lround(density * std::pow(L, D)));
  mdpd::MdpdOptions opt;
  opt.list_kind = Kind;
  opt.skin = double(state.range(1)) / 100.0;
  opt.cells_per_reach = int(state.range(2));
  mdpd::MdpdSystem<D, Real, Exec> sys(par, Box<D, Real>::cube(Real(L), true), 2023, opt);
  sys.allocate(n);
  Real lo[D], hi[D];
  for (int d = 0; d < D; ++d) {
    lo[d] = 0;
    hi[d] = Real(L);
  }
  fill_uniform_counter(sys.particles.x, lo, hi, 17, 0);
  sys.begin();
  for (int s = 0; s < 200; ++s) sys.step();
  constexpr int steps_per_iteration = 10;
  const int builds_before = sys.neighbor_list().num_builds();
  bench::timed(state, [&] {
    for (int s = 0; s < steps_per_iteration; ++s) sys.step();
  });
  const double steps = double(state.iterations()) * steps_per_iteration;
  state.SetItemsProcessed(std::int64_t(steps * n));
  state.counters["particles"] = n;
  state.counters["steps_per_rebuild"] = steps / std::max(1, sys.neighbor_list().num_builds() - builds_before);
  state.counters["kT"] = mdpd::kinetic_temperature(sys.particles);
}

constexpr auto half = NeighborListKind::half;
constexpr auto full = NeighborListKind::full;

// Defaults of MdpdOptions (skin 0.2σ, 2 cells per reach) first; then the skin and binning choices.
BENCHMARK_TEMPLATE(BM_MdpdStep, 3, double, half)->Args({100000, 20, 2})->Args({100000, 30, 2})->Args({100000, 20, 1})->Args({100000, 30, 1})->Args({100000, 40, 1})->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_MdpdStep, 3, double, full)->Args({100000, 20, 2})->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_MdpdStep, 3, float, half)->Args({100000, 20, 2})->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_MdpdStep, 2, double, half)->Args({100000, 20, 2})->Args({100000, 30, 2})->Args({100000, 20, 1})->Args({100000, 30, 1})->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_MdpdStep, 2, double, full)->Args({100000, 20, 2})->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_MdpdStep, 2, float, half)->Args({100000, 20, 2})->UseManualTime()->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace mesoflow
