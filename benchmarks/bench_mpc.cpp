// bench_mpc.cpp — the MPC solvent in a periodic box (issue 5, item 6). items_per_second =
// particle-updates/s (particles × steps); one step is streaming (eq. B.1) + grid shift + binning +
// collision, as MpcCollision::stream_and_collide runs it.
//   BM_MpcStep<2, Real, at+a>/600000/40/25: the paper's solvent, MPC-AT+a (eq. B.2) at 40 particles
//     per cell (target 2·10⁷/s in double at 2 threads).
//   BM_MpcStep<3, Real, srd>/1000000/10/25: SRD at 10 particles per cell (target 5·10⁷/s).
//   BM_MpcStepSeparate: the same step as three calls (stream, shift_grid, collide), to show what
//     the fused streaming saves.
//   BM_ChannelFlowStep<rule>: one step of the paper's crystal scene (ChannelFlow: L × W =
//     1000Δx × 15Δx, n = 40, walls, 90 discs on the axis, AT+a), with the walls' cut cells filled
//     by the mirror images (rule 0, the default) or by Appendix B's Maxwell–Boltzmann particles
//     (rule 1): what the mirror images' selection pass costs. items = solvent particles × steps.
//   BM_MpcStepCellSums<2, double, at+a>/…/mode: the paper's solvent with each cell-sum mode (chunked,
//     atomic, sorted = the deterministic-sum mode of issue 26 item 4): what determinism costs.
// perf/run normalises these rates by bench_common's BM_ReferenceTriad (x ← x + h v over 2²⁰ 3D
// double particles) measured in the same run.
// Particles start at uniformly random positions in random memory order; the third argument sorts
// them by cell every so many steps (0: never).
#include <benchmark/benchmark.h>

#include "manual_timing.hpp"
#include "kernels/common/random.hpp"
#include "scenes/crystal/channel_flow.hpp"
#include "kernels/mpc/maxwell_boltzmann.hpp"
#include "kernels/mpc/mpc_collision.hpp"

#include <array>
#include <chrono>
#include <cmath>
#include <string>
#include <vector>

namespace mesoflow {
namespace {

using Exec = Kokkos::DefaultExecutionSpace;
using mpc::CollisionRule;

template <int D, class Real>
struct MpcBox {
  using vector_view = typename mpc::MpcCollision<D, Real, Exec>::vector_view;
  mpc::CollisionGrid<D, Real> grid;
  vector_view x, v;
};

// A periodic box of about n / per_cell unit cells (the first axis adjusted to fit), k_BT = m = 1.
template <int D, class Real>
MpcBox<D, Real> make_box(int n, int per_cell) {
  const int cells = n / per_cell;
  const int side = int(std::floor(std::pow(double(cells), 1.0 / D)));
  Kokkos::Array<int, D> count;
  Kokkos::Array<Real, D> lo, length;
  Kokkos::Array<int, D> periodic;
  int rest = cells;
  for (int d = D - 1; d >= 1; --d) {
    count[d] = side;
    rest /= side;
  }
  count[0] = rest;
  for (int d = 0; d < D; ++d) {
    lo[d] = Real(0);
    length[d] = Real(count[d]);
    periodic[d] = 1;
  }
  MpcBox<D, Real> box{mpc::make_collision_grid<D, Real>(Real(1), lo, length, periodic),
                      typename MpcBox<D, Real>::vector_view("mesoflow::bench::x", n),
                      typename MpcBox<D, Real>::vector_view("mesoflow::bench::v", n)};
  Real low[D], high[D];
  for (int d = 0; d < D; ++d) {
    low[d] = Real(0);
    high[d] = length[d];
  }
  fill_uniform_counter(box.x, low, high, 1);
  mpc::fill_maxwell_boltzmann(box.v, Real(1), Real(1), 1);
  return box;
}

using bench::timed;

// Arguments: particles, particles per cell, sort interval (MpcCollision::sort_by_cell every that
// many steps, its cost included; 0: never, the particles stay in random memory order).
template <int D, class Real, CollisionRule Rule, bool Fused>
void mpc_step(benchmark::State& state, mpc::CellSums sums = mpc::CellSums::automatic) {
  const int n = int(state.range(0)), per_cell = int(state.range(1)), sort_every = int(state.range(2));
  auto box = make_box<D, Real>(n, per_cell);
  mpc::CollisionParameters<Real> p;
  p.rule = Rule;
  p.cell_sums = sums;
  mpc::MpcCollision<D, Real, Exec> collision(box.grid, p, std::size_t(n));
  Kokkos::Array<Real, D> g;
  for (int d = 0; d < D; ++d) g[d] = Real(0);
  g[0] = Real(0.001);
  const Real h = Real(0.1);
  const int steps = 25;
  std::uint64_t step = 0;
  auto one_step = [&] {
    if constexpr (Fused) {
      collision.stream_and_collide(box.x, box.v, h, g, step);
    } else {
      mpc::stream(box.x, box.v, h, g, collision.grid());
      collision.shift_grid(step);
      collision.collide(box.x, box.v, step);
    }
    ++step;
    if (sort_every > 0 && step % sort_every == 0) collision.sort_by_cell(box.x, box.v);
  };
  for (int s = 0; s < steps; ++s) one_step();  // warm-up (and the first sort)
  timed(state, [&] {
    for (int s = 0; s < steps; ++s) one_step();
  });
  state.SetItemsProcessed(state.iterations() * std::int64_t(steps) * n);
  state.counters["cells"] = double(box.grid.num_cells());
}

template <int D, class Real, CollisionRule Rule>
void BM_MpcStep(benchmark::State& state) {
  mpc_step<D, Real, Rule, true>(state);
}

template <int D, class Real, CollisionRule Rule>
void BM_MpcStepSeparate(benchmark::State& state) {
  mpc_step<D, Real, Rule, false>(state);
}

// The cost of the deterministic-sum mode (issue 26 item 4): the fused step with the cell sums of
// mode state.range(3): 0 chunked (per-thread copies, the host default), 1 atomic (the device
// default), 2 sorted (index-ordered segments after a BinSort: the same bits on every backend).
template <int D, class Real, CollisionRule Rule>
void BM_MpcStepCellSums(benchmark::State& state) {
  const mpc::CellSums modes[] = {mpc::CellSums::chunked, mpc::CellSums::atomic, mpc::CellSums::sorted};
  const char* names[] = {"chunked", "atomic", "sorted"};
  if (modes[state.range(3)] == mpc::CellSums::chunked &&
      !Kokkos::SpaceAccessibility<Kokkos::HostSpace, Kokkos::DefaultExecutionSpace::memory_space>::accessible) {
    // per-thread copies need a host execution space (MpcCollision refuses them); the first H200 run
    // of this benchmark aborted here
    state.SkipWithError("chunked cell sums need a host execution space");
    return;
  }
  mpc_step<D, Real, Rule, true>(state, modes[state.range(3)]);
  state.SetLabel(names[state.range(3)]);
}

// Argument: 0 mirror images, 1 Appendix B's Maxwell–Boltzmann wall particles, 2 mirror images in
// the deterministic-sum mode (sorted cell sums and disc impulses).
template <class Real>
void BM_ChannelFlowStep(benchmark::State& state) {
  mpc::ChannelFlowParameters<Real> p;  // the paper's scene (Appendix B)
  p.wall_virtual = state.range(0) == 1 ? mpc::WallVirtualRule::maxwell : mpc::WallVirtualRule::mirror;
  p.deterministic = state.range(0) == 2;
  const int discs = 90;
  std::vector<std::array<Real, 2>> centres;
  for (int k = 0; k < discs; ++k) centres.push_back({Real((k + 0.5) * double(p.length) / discs), Real(0.5) * p.width});
  mpc::ChannelFlow<Real, Exec> flow(p, centres);
  const int steps = 10;
  for (int s = 0; s < 2 * p.sort_interval; ++s) flow.step();  // warm-up, past the first sort
  timed(state, [&] {
    for (int s = 0; s < steps; ++s) flow.step();
  });
  state.SetItemsProcessed(state.iterations() * std::int64_t(steps) * std::int64_t(flow.num_solvent()));
  state.SetLabel(mpc::to_string(p.wall_virtual) + (p.deterministic ? " deterministic" : ""));
}

constexpr auto srd = CollisionRule::srd;
constexpr auto at_plus_a = CollisionRule::at_plus_a;
constexpr auto at_minus_a = CollisionRule::at_minus_a;

BENCHMARK_TEMPLATE(BM_MpcStep, 2, double, at_plus_a)->Args({600000, 40, 25})->Args({600000, 40, 0})->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_MpcStep, 2, float, at_plus_a)->Args({600000, 40, 25})->Args({600000, 40, 0})->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_MpcStep, 3, double, srd)->Args({1000000, 10, 25})->Args({1000000, 10, 0})->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_MpcStep, 3, float, srd)->Args({1000000, 10, 25})->Args({1000000, 10, 0})->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_MpcStep, 2, double, at_minus_a)->Args({600000, 40, 25})->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_MpcStep, 3, double, at_plus_a)->Args({1000000, 10, 25})->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_MpcStepSeparate, 2, double, at_plus_a)->Args({600000, 40, 25})->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_MpcStepSeparate, 3, double, srd)->Args({1000000, 10, 25})->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_ChannelFlowStep, double)->Arg(0)->Arg(1)->Arg(2)->UseManualTime()->Unit(benchmark::kMillisecond);
// Device-sized problems (issue 26, item 6): an accelerator needs millions of items per launch before
// a step is limited by memory bandwidth rather than launch latency; these are registered in device
// builds only, so that a host run's benchmark list stays as it is.
#if defined(KOKKOS_ENABLE_CUDA) || defined(KOKKOS_ENABLE_HIP) || defined(KOKKOS_ENABLE_SYCL)
BENCHMARK_TEMPLATE(BM_MpcStep, 2, double, at_plus_a)->Args({8000000, 40, 25})->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_MpcStep, 3, double, srd)->Args({8000000, 10, 25})->UseManualTime()->Unit(benchmark::kMillisecond);
#endif

BENCHMARK_TEMPLATE(BM_MpcStepCellSums, 2, double, at_plus_a)
    ->Args({600000, 40, 25, 0})
    ->Args({600000, 40, 25, 1})
    ->Args({600000, 40, 25, 2})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace mesoflow
