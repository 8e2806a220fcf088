// bench_sp.cpp — the soft-particle many-body terms of the hopper study on a dense bidisperse 2D
// packing (σ_l/σ_s = 1.4, packing fraction ≈ 0.85, overlapping contacts): the soft-sphere repulsion
// (eq. 2) through the generic pair loop, kinetic friction (eq. 6) and drag (eq. 5), as one force
// evaluation of a hopper time step. items_per_second = particle-updates/s. Neighbor-list upkeep is
// measured separately in bench_common (BM_NeighborListBuild).
#include "kernels/common/neighbor_list.hpp"
#include "kernels/common/pair_force.hpp"
#include "kernels/sp/kinetic_friction.hpp"
#include "kernels/sp/mass_proportional_drag.hpp"
#include "kernels/sp/pair_repulsion.hpp"

#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <random>

namespace mesoflow {
namespace {

using Exec = Kokkos::DefaultExecutionSpace;

void BM_SoftParticleContactForces2D(benchmark::State& state) {
  const int n = int(state.range(0));
  const double mean_area = 0.5 * (0.25 * M_PI * (1.0 + 1.4 * 1.4));
  const double L = std::sqrt(n * mean_area / 0.85);
  Particles<2, double, Exec> p(n, "bench_sp");
  {
    std::mt19937 gen(1);
    std::uniform_real_distribution<double> u(0, L), w(-0.1, 0.1);
    auto x = Kokkos::create_mirror_view(p.x);
    auto v = Kokkos::create_mirror_view(p.v);
    auto type = Kokkos::create_mirror_view(p.type);
    for (int i = 0; i < n; ++i) {
      for (int d = 0; d < 2; ++d) {
        x(i, d) = u(gen);
        v(i, d) = w(gen);
      }
      type(i) = i % 2;
    }
    Kokkos::deep_copy(p.x, x);
    Kokkos::deep_copy(p.v, v);
    Kokkos::deep_copy(p.type, type);
  }
  const Box<2, double> box = Box<2, double>::cube(L, true);
  const sp::SoftSphereRepulsion<double> contacts(100.0, {1.0, 1.4});
  NeighborList<2, double, Exec> list(contacts.cutoff(), 0.2);
  list.build(p, box);
  PairForce<2, double, Exec> pair;
  const int evaluations = 20;
  for (auto _ : state) {
    Kokkos::fence();
    const auto t0 = std::chrono::steady_clock::now();
    for (int k = 0; k < evaluations; ++k) {
      p.zero_forces();
      pair.accumulate(contacts, p, list, box);
      sp::accumulate_kinetic_friction(0.5, contacts, p, p.v, list, box);
      sp::accumulate_mass_proportional_drag(0.3, p, p.v);
    }
    Kokkos::fence();
    state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * evaluations * n);
}

BENCHMARK(BM_SoftParticleContactForces2D)->Arg(1600)->Arg(20000)->UseManualTime()->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace mesoflow
