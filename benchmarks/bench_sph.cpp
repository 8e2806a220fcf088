// bench_sph.cpp — a weakly compressible SPH water box (issue 7): ~10⁵ particles on a simple cubic
// lattice of spacing Δx in a periodic cube, ρ0 = 1, random velocities of amplitude U = 0.1, Tait
// equation of state with c0 = 10U (eq. 6), ν = 0.01, Lucy kernel of support 2.5Δx (the paper's
// kernel; ~80 neighbours within the support on the lattice, ~65 once disordered), dt from the
// limits of sph_time_step.hpp (the acoustic–viscous one, 2ν/c0² = 0.02, binds here; before it
// existed the acoustic 0.31 did, and particles crossed the skin 16 times as often per step).
// items_per_second = particle-steps/s; a step is
// everything SphSystem::step does: half kick, half density update, extrapolated velocity and drift
// (eqs. 11–14); neighbor-list upkeep (skin criterion, periodic memory sort); packed rows with the
// pressures of eq. (6); the fused density-rate + pressure + viscous pair loop (eqs. 4–5) over a full
// list; second half kick and density update (eqs. 15–16).
// Arguments: particles, neighbor skin in % of the support, cells per reach of the list's binning.
// The half-list variants (the default, each pair once, SphOptions) against the full-list ones
// (each row sums its own particle: the same bits on any thread count).
// Each configuration runs 100 steps before timing.
// Issue 24, item 3 (one pair loop): BM_SphPairLoop times the pair interactions alone (eqs. 4–5 on
// packed rows, 20 steps into the run), through the generic loop of kernels/common/pair_force.hpp
// (impl 0) against the pre-item-3 loop (impl 1, benchmarks/reference_pair_loops.hpp), in the same
// run; items = particle-evaluations.
#include "reference_pair_loops.hpp"

#include <benchmark/benchmark.h>

#include "manual_timing.hpp"
#include "kernels/common/random.hpp"
#include "scenes/capsule/sph_system.hpp"

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

// Mean number of neighbours within the kernel support.
template <class Real, class Sys>
double mean_neighbors(const Sys& sys) {
  const auto nbr = sys.neighbor_list().data();
  const auto x = sys.particles.x;
  const auto box = sys.box();
  const Real support2 = sys.kernel().support2;
  long long total = 0;
  Kokkos::parallel_reduce(
      "mesoflow::bench::sph_neighbors", Kokkos::RangePolicy<Exec>(0, x.extent(0)),
      KOKKOS_LAMBDA(int row, long long& acc) {
        const int i = nbr.particle(row);
        const Vec<3, Real> xi = Vec<3, Real>::load(x, i);
        for (int k = 0; k < nbr.num_neighbors(row); ++k) {
          Vec<3, Real> dr = xi - Vec<3, Real>::load(x, nbr.neighbor(row, k));
          box.minimum_image(dr);
          acc += norm2(dr) < support2;
        }
      },
      total);
  const double per_pair = sys.neighbor_list().kind() == NeighborListKind::half ? 2.0 : 1.0;
  return per_pair * double(total) / double(x.extent(0));
}

template <class Real, NeighborListKind Kind>
void BM_SphStep(benchmark::State& state) {
  const int side = int(std::lround(std::cbrt(double(state.range(0)))));
  const int n = side * side * side;
  const double rho0 = 1, u = 0.1, nu = 0.01, support = 2.5;
  const double c0 = sph::speed_of_sound_for_velocity(u);
  const sph::LucyKernel<3, Real> kernel{Real(support)};
  const double dt = sph::sph_time_step_limits(sph::time_step_length(kernel), nu, c0, 0.0).dt();
  sph::SphOptions opt;
  opt.list_kind = Kind;
  opt.skin_fraction = double(state.range(1)) / 100.0;
  opt.cells_per_reach = int(state.range(2));
  sph::SphSystem<3, Real, Exec> sys(kernel, sph::TaitEquationOfState<Real>(rho0, c0),
                                    Box<3, Real>::cube(Real(side), true), Real(dt), opt);
  sys.allocate(n);
  {
    auto x = Kokkos::create_mirror_view(sys.particles.x);
    for (int a = 0, i = 0; a < side; ++a)
      for (int b = 0; b < side; ++b)
        for (int c = 0; c < side; ++c, ++i) {
          x(i, 0) = Real(a + 0.5);
          x(i, 1) = Real(b + 0.5);
          x(i, 2) = Real(c + 0.5);
        }
    Kokkos::deep_copy(sys.particles.x, x);
  }
  const Real lo[3] = {Real(-u), Real(-u), Real(-u)}, hi[3] = {Real(u), Real(u), Real(u)};
  fill_uniform_counter(sys.particles.v, lo, hi, 7, 1);
  Kokkos::deep_copy(sys.particles.mass, Real(rho0));
  Kokkos::deep_copy(sys.mu, Real(nu * rho0));
  sys.begin();
  for (int s = 0; s < 100; ++s) sys.step();
  constexpr int steps_per_iteration = 10;
  const int builds_before = sys.neighbor_list().num_builds();
  bench::timed(state, [&] {
    for (int s = 0; s < steps_per_iteration; ++s) sys.step();
  });
  const double steps = double(state.iterations()) * steps_per_iteration;
  state.SetItemsProcessed(std::int64_t(steps * n));
  state.counters["particles"] = n;
  state.counters["neighbors"] = mean_neighbors<Real>(sys);
  state.counters["steps_per_rebuild"] = steps / std::max(1, sys.neighbor_list().num_builds() - builds_before);
}

template <class Real, NeighborListKind Kind>
void BM_SphPairLoop(benchmark::State& state) {
  const int side = int(std::lround(std::cbrt(double(state.range(0)))));
  const int n = side * side * side;
  const bool ref = state.range(1) == 1;
  const double rho0 = 1, u = 0.1, nu = 0.01, support = 2.5;
  const double c0 = sph::speed_of_sound_for_velocity(u);
  const sph::LucyKernel<3, Real> kernel{Real(support)};
  const double dt = sph::sph_time_step_limits(sph::time_step_length(kernel), nu, c0, 0.0).dt();
  sph::SphOptions opt;
  opt.list_kind = Kind;
  const sph::TaitEquationOfState<Real> eos(rho0, c0);
  sph::SphSystem<3, Real, Exec> sys(kernel, eos, Box<3, Real>::cube(Real(side), true), Real(dt), opt);
  sys.allocate(n);
  {
    auto x = Kokkos::create_mirror_view(sys.particles.x);
    for (int a = 0, i = 0; a < side; ++a)
      for (int b = 0; b < side; ++b)
        for (int c = 0; c < side; ++c, ++i) {
          x(i, 0) = Real(a + 0.5);
          x(i, 1) = Real(b + 0.5);
          x(i, 2) = Real(c + 0.5);
        }
    Kokkos::deep_copy(sys.particles.x, x);
  }
  const Real lo[3] = {Real(-u), Real(-u), Real(-u)}, hi[3] = {Real(u), Real(u), Real(u)};
  fill_uniform_counter(sys.particles.v, lo, hi, 7, 1);
  Kokkos::deep_copy(sys.particles.mass, Real(rho0));
  Kokkos::deep_copy(sys.mu, Real(nu * rho0));
  sys.begin();
  for (int s = 0; s < 20; ++s) sys.step();
  sph::SphRows<3, Real, Exec> rows("bench::sph_rows", n);
  Kokkos::View<Real*, Exec> pressure("bench::pressure", n), drho("bench::drho", n);
  typename Particles<3, Real, Exec>::vector_view f("bench::f", n);
  sph::pack_sph_rows(sys.particles, sys.u_bar, sys.rho, sys.mu, eos, rows, pressure);
  sph::SphPairInteractions<3, Real, Exec, sph::LucyKernel<3, Real>> generic(kernel, sph::BodyForce<3, Real>{});
  sph::ReferenceSphPairInteractions<3, Real, Exec, sph::LucyKernel<3, Real>> reference(kernel, sph::BodyForce<3, Real>{});
  constexpr int evaluations = 10;
  bench::timed(state, [&] {
    for (int k = 0; k < evaluations; ++k) {
      if (ref)
        reference.compute(rows, sys.particles.type, sys.neighbor_list(), sys.box(), f, drho);
      else
        generic.compute(rows, sys.particles.type, sys.neighbor_list(), sys.box(), f, drho);
    }
  });
  state.SetItemsProcessed(std::int64_t(state.iterations()) * evaluations * n);
  typename Particles<3, Real, Exec>::vector_view f_ref("bench::f_ref", n);
  Kokkos::View<Real*, Exec> drho_ref("bench::drho_ref", n);
  reference.compute(rows, sys.particles.type, sys.neighbor_list(), sys.box(), f_ref, drho_ref);
  generic.compute(rows, sys.particles.type, sys.neighbor_list(), sys.box(), f, drho);
  state.counters["bitwise_equal"] = same_bits(f, f_ref) * same_bits(drho, drho_ref);
}

constexpr auto half = NeighborListKind::half;
constexpr auto full = NeighborListKind::full;

BENCHMARK_TEMPLATE(BM_SphStep, double, half)->Args({100000, 10, 1})->Args({100000, 20, 1})->Args({100000, 10, 2})->Args({100000, 20, 2})->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_SphStep, double, full)->Args({100000, 10, 1})->Args({100000, 20, 1})->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_SphStep, float, half)->Args({100000, 10, 1})->UseManualTime()->Unit(benchmark::kMillisecond);

// Generic (impl 0) against the pre-item-3 loop (impl 1): particles, impl.
// Device-sized problems (issue 26, item 6): an accelerator needs millions of items per launch before
// a step is limited by memory bandwidth rather than launch latency; these are registered in device
// builds only, so that a host run's benchmark list stays as it is.
#if defined(KOKKOS_ENABLE_CUDA) || defined(KOKKOS_ENABLE_HIP) || defined(KOKKOS_ENABLE_SYCL)
BENCHMARK_TEMPLATE(BM_SphStep, double, half)->Args({1000000, 10, 1})->UseManualTime()->Unit(benchmark::kMillisecond);
#endif

BENCHMARK_TEMPLATE(BM_SphPairLoop, double, half)->Args({27000, 0})->Args({27000, 1})->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_SphPairLoop, double, full)->Args({27000, 0})->Args({27000, 1})->UseManualTime()->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace mesoflow
