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
// Issue 24, item 3 (one pair loop): BM_MdpdDensityLoop and BM_MdpdPairForceLoop time the density and
// the fused pair force alone, through the generic loop of kernels/common/pair_force.hpp (impl 0)
// against the pre-item-3 loops (impl 1, benchmarks/reference_pair_loops.hpp), in the same run, on a
// liquid 20 steps from random positions; items = particle-evaluations. BM_MdpdPairForceLoop's third
// argument 1 sets the WCA and drag-record flags (now run-time branches; no solid particles, so only
// their cost shows).
#include "reference_pair_loops.hpp"

#include <benchmark/benchmark.h>

#include "manual_timing.hpp"
#include "kernels/common/random.hpp"
#include "scenes/pillars/mdpd_system.hpp"

#include <cmath>
#include <cstring>

namespace mesoflow {
namespace {

using Exec = Kokkos::DefaultExecutionSpace;

// 1 when two Views hold the same bits (the generic loop against the reference loop, same inputs).
template <class A, class B>
double same_bits(const A& a, const B& b) {
  auto ha = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), a);
  auto hb = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), b);
  const std::size_t bytes = ha.span() * sizeof(typename decltype(ha)::value_type);
  return ha.span() == hb.span() && std::memcmp(ha.data(), hb.data(), bytes) == 0 ? 1.0 : 0.0;
}

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

// An equilibrated liquid and the packed rows of its state (packed_state.hpp), as MdpdSystem packs them.
template <int D, class Real, NeighborListKind Kind>
struct MdpdLiquid {
  using rows_view = mdpd::PackedRows<Real, Exec>;
  mdpd::MdpdParameters par;
  mdpd::MdpdSystem<D, Real, Exec> sys;
  rows_view xr, vr, fr;
  Kokkos::View<Real*, Exec> rho;
  typename Particles<D, Real, Exec>::vector_view drag;
  int n;

  static mdpd::MdpdParameters parameters() {
    mdpd::MdpdParameters p;
    if (D == 2) p.B = 30;
    return p;
  }
  static double side(int n_target) { return std::pow(n_target / 6.0, 1.0 / D); }
  static mdpd::MdpdOptions options() {
    mdpd::MdpdOptions opt;
    opt.list_kind = Kind;
    return opt;
  }

  explicit MdpdLiquid(int n_target)
      : par(parameters()), sys(par, Box<D, Real>::cube(Real(side(n_target)), true), 2023, options()) {
    const double L = side(n_target);
    n = int(std::lround(6.0 * std::pow(L, D)));
    sys.allocate(n);
    Real lo[D], hi[D];
    for (int d = 0; d < D; ++d) {
      lo[d] = 0;
      hi[d] = Real(L);
    }
    fill_uniform_counter(sys.particles.x, lo, hi, 17, 0);
    sys.begin();
    for (int s = 0; s < 20; ++s) sys.step();
    xr = rows_view("bench::xr", n);
    vr = rows_view("bench::vr", n);
    fr = rows_view("bench::fr", n);
    rho = Kokkos::View<Real*, Exec>("bench::rho", n);
    drag = typename Particles<D, Real, Exec>::vector_view("bench::drag", n);
    mdpd::pack_vectors<D, Real, Exec>(sys.particles.x, xr);
    mdpd::pack_vectors<D, Real, Exec>(sys.particles.v, vr);
    pack_density(sys.rho, xr, n);
  }

  // Outside the constructor: CUDA needs an enclosing function whose address can be taken.
  template <class Density>
  static void pack_density(const Density& density, const rows_view& x, int n) {
    Kokkos::parallel_for(
        "bench::pack_rho", Kokkos::RangePolicy<Exec>(0, n), KOKKOS_LAMBDA(int i) { x(i, mdpd::rho_column) = density(i); });
    Kokkos::fence();
  }
};

template <int D, class Real, NeighborListKind Kind>
void BM_MdpdDensityLoop(benchmark::State& state) {
  MdpdLiquid<D, Real, Kind> s(int(state.range(0)));
  const bool ref = state.range(1) == 1;
  const mdpd::DensityWeight<D, Real> w(s.par.density_kernel, Real(s.par.r_B));
  mdpd::LocalDensity<D, Real, Exec> generic(w);
  mdpd::ReferenceLocalDensity<D, Real, Exec> reference(w);
  constexpr int evaluations = 10;
  bench::timed(state, [&] {
    for (int k = 0; k < evaluations; ++k) {
      if (ref)
        reference.compute(s.xr, s.sys.neighbor_list(), s.sys.box(), s.rho);
      else
        generic.compute(s.xr, s.sys.neighbor_list(), s.sys.box(), s.rho);
    }
  });
  state.SetItemsProcessed(std::int64_t(state.iterations()) * evaluations * s.n);
  Kokkos::View<Real*, Exec> rho_ref("bench::rho_ref", s.n);
  reference.compute(s.xr, s.sys.neighbor_list(), s.sys.box(), rho_ref);
  generic.compute(s.xr, s.sys.neighbor_list(), s.sys.box(), s.rho);
  state.counters["bitwise_equal"] = same_bits(s.rho, rho_ref);
}

template <int D, class Real, NeighborListKind Kind>
void BM_MdpdPairForceLoop(benchmark::State& state) {
  MdpdLiquid<D, Real, Kind> s(int(state.range(0)));
  const bool ref = state.range(1) == 1;
  const bool flags = state.range(2) == 1;
  mdpd::MdpdPairForce<D, Real, Exec> generic(s.par, 2023);
  mdpd::ReferenceMdpdPairForce<D, Real, Exec> reference(s.par, 2023);
  const auto drag = flags ? s.drag : typename Particles<D, Real, Exec>::vector_view();
  constexpr int evaluations = 10;
  std::uint64_t step = 0;
  bench::timed(state, [&] {
    for (int k = 0; k < evaluations; ++k, ++step) {
      if (ref)
        reference.compute(s.xr, s.vr, s.sys.particles.type, s.sys.tag, s.sys.neighbor_list(), s.sys.box(), step,
                          flags, s.fr, drag);
      else
        generic.compute(s.xr, s.vr, s.sys.particles.type, s.sys.tag, s.sys.neighbor_list(), s.sys.box(), step,
                        flags, s.fr, drag);
    }
  });
  state.SetItemsProcessed(std::int64_t(state.iterations()) * evaluations * s.n);
  typename MdpdLiquid<D, Real, Kind>::rows_view fr_ref("bench::fr_ref", s.n);
  typename Particles<D, Real, Exec>::vector_view drag_ref("bench::drag_ref", flags ? s.n : 0);
  reference.compute(s.xr, s.vr, s.sys.particles.type, s.sys.tag, s.sys.neighbor_list(), s.sys.box(), step, flags,
                    fr_ref, drag_ref);
  generic.compute(s.xr, s.vr, s.sys.particles.type, s.sys.tag, s.sys.neighbor_list(), s.sys.box(), step, flags, s.fr,
                  drag);
  state.counters["bitwise_equal"] = same_bits(s.fr, fr_ref) * (flags ? same_bits(drag, drag_ref) : 1.0);
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

// Generic (impl 0) against the pre-item-3 loops (impl 1): particles, impl[, WCA + drag flags].
// Device-sized problems (issue 26, item 6): an accelerator needs millions of items per launch before
// a step is limited by memory bandwidth rather than launch latency; these are registered in device
// builds only, so that a host run's benchmark list stays as it is.
#if defined(KOKKOS_ENABLE_CUDA) || defined(KOKKOS_ENABLE_HIP) || defined(KOKKOS_ENABLE_SYCL)
BENCHMARK_TEMPLATE(BM_MdpdStep, 3, double, half)->Args({1000000, 20, 2})->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_MdpdStep, 2, double, half)->Args({1000000, 20, 2})->UseManualTime()->Unit(benchmark::kMillisecond);
#endif

BENCHMARK_TEMPLATE(BM_MdpdDensityLoop, 3, double, half)->Args({30000, 0})->Args({30000, 1})->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_MdpdDensityLoop, 3, double, full)->Args({30000, 0})->Args({30000, 1})->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_MdpdPairForceLoop, 3, double, half)->Args({30000, 0, 0})->Args({30000, 1, 0})->Args({30000, 0, 1})->Args({30000, 1, 1})->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_MdpdPairForceLoop, 3, double, full)->Args({30000, 0, 0})->Args({30000, 1, 0})->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_MdpdPairForceLoop, 2, double, half)->Args({30000, 0, 0})->Args({30000, 1, 0})->UseManualTime()->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace mesoflow
