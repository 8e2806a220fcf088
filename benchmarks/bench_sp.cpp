// bench_sp.cpp — the many-body contact terms of the hopper study. items_per_second =
// particle-updates/s (vertex-updates/s for DP). Neighbor-list upkeep is measured separately in
// bench_common (BM_NeighborListBuild).
//   BM_SoftParticleContactForces2D: soft-sphere repulsion (eq. 2) through the generic pair loop,
//     kinetic friction (eq. 6) and drag (eq. 5) on a dense bidisperse packing (σ_l/σ_s = 1.4,
//     packing fraction ≈ 0.85, overlapping contacts): one force evaluation of a hopper step.
//   BM_SoftParticleWallRepulsion2D: eq. 3 over the four walls of a 2D hopper, particles filling it.
//   BM_DeformablePolygonContacts: rough (eq. 9 + friction eq. 12) and smooth (Appendix A) contacts,
//     and smooth contacts with their vertex–edge friction (eq. 12, smooth_vertex_friction.hpp), of
//     bidisperse 16-gons pressed against their neighbours on a square lattice.
// Issue 24, item 3 (one pair loop): BM_PairLoop* time each contact term through the generic loop of
// kernels/common/pair_force.hpp (last argument 0) against its model-specific loop as it was before
// (1, benchmarks/reference_pair_loops.hpp), in the same run.
#include "kernels/common/geometry.hpp"
#include "kernels/common/neighbor_list.hpp"
#include "kernels/common/pair_force.hpp"
#include "kernels/dp/polygons.hpp"
#include "kernels/dp/smooth_vertex_contacts.hpp"
#include "kernels/dp/smooth_vertex_friction.hpp"
#include "kernels/dp/vertex_contacts.hpp"
#include "kernels/sp/kinetic_friction.hpp"
#include "kernels/sp/mass_proportional_drag.hpp"
#include "kernels/sp/pair_repulsion.hpp"
#include "kernels/sp/wall_repulsion.hpp"

#include "reference_pair_loops.hpp"

#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <random>

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

// n bidisperse disks (σ = 1, 1.4, alternating) at random in a periodic square at packing fraction
// 0.85, with small random velocities: most overlap several neighbours; E_sp = 100 contacts and their
// neighbor list.
struct DensePacking {
  Particles<2, double, Exec> p;
  Box<2, double> box;
  sp::SoftSphereRepulsion<double> contacts{100.0, {1.0, 1.4}};
  NeighborList<2, double, Exec> list;

  explicit DensePacking(int n)
      : p(n, "bench_sp"), box(Box<2, double>::cube(side(n), true)), list(contacts.cutoff(), 0.2) {
    const double L = side(n);
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
    list.build(p, box);
  }
  static double side(int n) { return std::sqrt(n * 0.5 * (0.25 * M_PI * (1.0 + 1.4 * 1.4)) / 0.85); }
};

// Times `evaluations` calls of `evaluate` per benchmark iteration; items = particle updates.
template <class Evaluate>
void time_evaluations(benchmark::State& state, int n, Evaluate&& evaluate) {
  const int evaluations = 20;
  for (auto _ : state) {
    Kokkos::fence();
    const auto t0 = std::chrono::steady_clock::now();
    for (int k = 0; k < evaluations; ++k) evaluate();
    Kokkos::fence();
    state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * evaluations * n);
}

void BM_SoftParticleContactForces2D(benchmark::State& state) {
  const int n = int(state.range(0));
  DensePacking s(n);
  PairForce<2, double, Exec> pair;
  time_evaluations(state, n, [&] {
    s.p.zero_forces();
    pair.accumulate(s.contacts, s.p, s.list, s.box);
    sp::accumulate_kinetic_friction(0.5, s.contacts, s.p, s.p.v, s.list, s.box);
    sp::accumulate_mass_proportional_drag(0.3, s.p, s.p.v);
  });
}

// Kinetic friction (eq. 6) alone on the same packing; range(1): 0 the full relative velocity, 1 its
// tangential part only (--friction-component tangential), measured in the same run.
void BM_SoftParticleKineticFriction2D(benchmark::State& state) {
  const int n = int(state.range(0));
  const auto component = state.range(1) == 1 ? sp::FrictionComponent::tangential : sp::FrictionComponent::full;
  DensePacking s(n);
  time_evaluations(state, n, [&] {
    s.p.zero_forces();
    sp::accumulate_kinetic_friction(0.5, s.contacts, s.p, s.p.v, s.list, s.box, component);
  });
}

void BM_SoftParticleWallRepulsion2D(benchmark::State& state) {
  const int n = int(state.range(0));
  const double W = 60.0, height = n / (0.8 * W);
  Particles<2, double, Exec> p(n, "bench_sp_walls");
  {
    std::mt19937 gen(2);
    std::uniform_real_distribution<double> ux(-0.5 * W, 0.5 * W), uy(0.0, height);
    auto x = Kokkos::create_mirror_view(p.x);
    auto type = Kokkos::create_mirror_view(p.type);
    for (int i = 0; i < n; ++i) x(i, 0) = ux(gen), x(i, 1) = uy(gen), type(i) = i % 2;
    Kokkos::deep_copy(p.x, x);
    Kokkos::deep_copy(p.type, type);
  }
  const Geometry<2, double, Exec> walls(hopper_walls_2d<double>(W, 6.0, 90.0));
  const sp::SoftSphereRepulsion<double> sizes(100.0, {1.0, 1.4});
  time_evaluations(state, n, [&] {
    p.zero_forces();
    sp::accumulate_wall_repulsion(1e4, sizes, walls, p);
  });
}

// range(0): polygons; range(1): 0 rough (eqs. 9 + 12), 1 smooth (Appendix A), 2 smooth with its
// vertex–edge friction (Appendix A + eq. 12).
void BM_DeformablePolygonContacts(benchmark::State& state) {
  const int bodies = int(state.range(0)), nv = 16;
  const bool smooth = state.range(1) >= 1, smooth_friction = state.range(1) == 2;
  const int side = int(std::ceil(std::sqrt(double(bodies))));
  const double spacing = 1.15, L = side * spacing;  // σ_avg = 1.2: neighbours press on each other
  std::vector<int> counts(bodies, nv);
  std::vector<double> a0(bodies), l0(bodies);
  for (int b = 0; b < bodies; ++b) {
    const double sigma = b % 2 ? 1.4 : 1.0;
    a0[b] = 0.25 * dp::pi * sigma * sigma;
    l0[b] = dp::regular_polygon_edge(a0[b], nv);
  }
  const auto polygons = dp::Polygons<double, Exec>::from_vertex_counts(counts, a0, l0);
  Particles<2, double, Exec> p(bodies * nv, "bench_dp_contacts");
  dp::assign_bodies(polygons, p);
  {
    std::mt19937 gen(3);
    std::uniform_real_distribution<double> w(-0.1, 0.1);
    auto x = Kokkos::create_mirror_view(p.x);
    auto v = Kokkos::create_mirror_view(p.v);
    auto type = Kokkos::create_mirror_view(p.type);
    for (int b = 0; b < bodies; ++b) {
      const double R = 0.5 * (b % 2 ? 1.4 : 1.0);
      for (int k = 0; k < nv; ++k) {
        const int i = b * nv + k;
        x(i, 0) = ((b % side) + 0.5) * spacing + R * std::cos(2 * dp::pi * k / nv);
        x(i, 1) = ((b / side) + 0.5) * spacing + R * std::sin(2 * dp::pi * k / nv);
        v(i, 0) = w(gen), v(i, 1) = w(gen);
        type(i) = b % 2;
      }
    }
    Kokkos::deep_copy(p.x, x);
    Kokkos::deep_copy(p.v, v);
    Kokkos::deep_copy(p.type, type);
  }
  const Box<2, double> box = Box<2, double>::cube(L, true);
  const double width = smooth ? 0.1 : 1.0;  // δ/l0: circulo-lines of 0.1 l0, or vertex disks of l0
  const sp::SoftSphereRepulsion<double> contacts(1e4, {width * l0[0], width * l0[1]});
  NeighborList<2, double, Exec> list(smooth ? 1.5 * l0[1] + contacts.cutoff() : contacts.cutoff(), 0.05,
                                     NeighborListKind::full, BodyExclusion::same_body);
  list.build(p, box);
  PairForce<2, double, Exec> pair;
  const int evaluations = 20;
  for (auto _ : state) {
    Kokkos::fence();
    const auto t0 = std::chrono::steady_clock::now();
    for (int k = 0; k < evaluations; ++k) {
      p.zero_forces();
      if (smooth) {
        dp::accumulate_smooth_vertex_contacts(contacts, polygons, p, list, box);
        if (smooth_friction) dp::accumulate_smooth_vertex_friction(0.5, contacts, polygons, p, p.v, list, box);
      } else {
        dp::accumulate_vertex_contacts(contacts, p, list, box, pair);
        dp::accumulate_vertex_friction(0.5, contacts, p, p.v, list, box);
      }
    }
    Kokkos::fence();
    state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * evaluations * bodies * nv);
}

// Soft-sphere repulsion (eq. 2) alone, forces only (the hopper step's call); range(1): 0 generic
// loop, 1 the pre-item-3 PairForce loop.
void BM_PairLoopSoftSphere2D(benchmark::State& state) {
  const int n = int(state.range(0));
  DensePacking s(n);
  PairForce<2, double, Exec> pair;
  ReferencePairForce<2, double, Exec> reference;
  const bool ref = state.range(1) == 1;
  time_evaluations(state, n, [&] {
    s.p.zero_forces();
    if (ref)
      reference.accumulate_forces(s.contacts, s.p, s.list, s.box);
    else
      pair.accumulate_forces(s.contacts, s.p, s.list, s.box);
  });
  auto f_ref = Kokkos::create_mirror(s.p.f);
  s.p.zero_forces();
  reference.accumulate_forces(s.contacts, s.p, s.list, s.box);
  Kokkos::deep_copy(f_ref, s.p.f);
  s.p.zero_forces();
  pair.accumulate_forces(s.contacts, s.p, s.list, s.box);
  state.counters["bitwise_equal"] = same_bits(s.p.f, f_ref);
}

// Kinetic friction (eq. 6), range(1) the component as above; range(2): 0 generic loop, 1 the
// pre-item-3 loop.
void BM_PairLoopKineticFriction2D(benchmark::State& state) {
  const int n = int(state.range(0));
  const auto component = state.range(1) == 1 ? sp::FrictionComponent::tangential : sp::FrictionComponent::full;
  const bool ref = state.range(2) == 1;
  DensePacking s(n);
  time_evaluations(state, n, [&] {
    s.p.zero_forces();
    if (ref)
      sp::reference_kinetic_friction(0.5, s.contacts, s.p, s.p.v, s.list, s.box, component);
    else
      sp::accumulate_kinetic_friction(0.5, s.contacts, s.p, s.p.v, s.list, s.box, component);
  });
  auto f_ref = Kokkos::create_mirror(s.p.f);
  s.p.zero_forces();
  sp::reference_kinetic_friction(0.5, s.contacts, s.p, s.p.v, s.list, s.box, component);
  Kokkos::deep_copy(f_ref, s.p.f);
  s.p.zero_forces();
  sp::accumulate_kinetic_friction(0.5, s.contacts, s.p, s.p.v, s.list, s.box, component);
  state.counters["bitwise_equal"] = same_bits(s.p.f, f_ref);
}

// Smooth DP contacts (Appendix A) of the polygon lattice of BM_DeformablePolygonContacts; range(1):
// 0 generic loop, 1 the pre-item-3 loop.
void BM_PairLoopSmoothVertexContacts(benchmark::State& state) {
  const int bodies = int(state.range(0)), nv = 16;
  const bool ref = state.range(1) == 1;
  const int side = int(std::ceil(std::sqrt(double(bodies))));
  const double spacing = 1.15, L = side * spacing;
  std::vector<int> counts(bodies, nv);
  std::vector<double> a0(bodies), l0(bodies);
  for (int b = 0; b < bodies; ++b) {
    const double sigma = b % 2 ? 1.4 : 1.0;
    a0[b] = 0.25 * dp::pi * sigma * sigma;
    l0[b] = dp::regular_polygon_edge(a0[b], nv);
  }
  const auto polygons = dp::Polygons<double, Exec>::from_vertex_counts(counts, a0, l0);
  Particles<2, double, Exec> p(bodies * nv, "bench_dp_smooth");
  dp::assign_bodies(polygons, p);
  {
    auto x = Kokkos::create_mirror_view(p.x);
    auto type = Kokkos::create_mirror_view(p.type);
    for (int b = 0; b < bodies; ++b) {
      const double R = 0.5 * (b % 2 ? 1.4 : 1.0);
      for (int k = 0; k < nv; ++k) {
        const int i = b * nv + k;
        x(i, 0) = ((b % side) + 0.5) * spacing + R * std::cos(2 * dp::pi * k / nv);
        x(i, 1) = ((b / side) + 0.5) * spacing + R * std::sin(2 * dp::pi * k / nv);
        type(i) = b % 2;
      }
    }
    Kokkos::deep_copy(p.x, x);
    Kokkos::deep_copy(p.type, type);
  }
  const Box<2, double> box = Box<2, double>::cube(L, true);
  const sp::SoftSphereRepulsion<double> contacts(1e4, {0.1 * l0[0], 0.1 * l0[1]});
  NeighborList<2, double, Exec> list(1.5 * l0[1] + contacts.cutoff(), 0.05, NeighborListKind::full,
                                     BodyExclusion::same_body);
  list.build(p, box);
  time_evaluations(state, bodies * nv, [&] {
    p.zero_forces();
    if (ref)
      dp::reference_smooth_vertex_contacts(contacts, polygons, p, list, box);
    else
      dp::accumulate_smooth_vertex_contacts(contacts, polygons, p, list, box);
  });
  auto f_ref = Kokkos::create_mirror(p.f);
  p.zero_forces();
  const double e_ref = dp::reference_smooth_vertex_contacts(contacts, polygons, p, list, box);
  Kokkos::deep_copy(f_ref, p.f);
  p.zero_forces();
  const double e = dp::accumulate_smooth_vertex_contacts(contacts, polygons, p, list, box);
  state.counters["bitwise_equal"] = same_bits(p.f, f_ref) * (e == e_ref ? 1.0 : 0.0);
}

BENCHMARK(BM_SoftParticleWallRepulsion2D)->Arg(20000)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DeformablePolygonContacts)->Args({1600, 0})->Args({1600, 1})->Args({1600, 2})->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SoftParticleContactForces2D)->Arg(1600)->Arg(20000)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SoftParticleKineticFriction2D)->Args({20000, 0})->Args({20000, 1})->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PairLoopSoftSphere2D)->Args({20000, 0})->Args({20000, 1})->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PairLoopKineticFriction2D)->Args({20000, 0, 0})->Args({20000, 0, 1})->Args({20000, 1, 0})->Args({20000, 1, 1})->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PairLoopSmoothVertexContacts)->Args({1600, 0})->Args({1600, 1})->UseManualTime()->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace mesoflow
