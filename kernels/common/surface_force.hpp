// surface_force.hpp — the one loop for forces between particles and the surfaces of a scene (walls and
// obstacles): one nearest-surface query per particle, handed to every per-particle term.
//
// Physics lives in small terms (dp/vertex_wall_repulsion.hpp, dp/near_wall_drag.hpp,
// sp/obstacle_repulsion.hpp, sp/viscous_drag.hpp); this loop owns the query, the per-particle sum
// and the energy reduction (accumulated in double). A term provides
//     KOKKOS_INLINE_FUNCTION void evaluate(const SurfacePoint<2, Real>& s, const Vec<2, Real>& v,
//                                          Vec<2, Real>& force, double& energy) const;
// adding its force on a particle at signed distance s.distance from the nearest surface (normal
// s.normal, into the fluid), moving with velocity v, to `force` and its energy to `energy`.
// Each particle writes only its own force: deterministic at any thread count, no atomics.
#pragma once

#include "kokkos_compat.hpp"
#include "obstacle_array.hpp"
#include "particles.hpp"
#include "vec.hpp"

namespace mesoflow {

namespace surface_force_detail {

// The terms of one call, evaluated in order (a device-copyable list; std::tuple is not usable in
// device code with every compiler mesoflow supports).
template <class... Terms>
struct TermList;

template <>
struct TermList<> {
  template <class Real>
  KOKKOS_INLINE_FUNCTION void evaluate(const SurfacePoint<2, Real>&, const Vec<2, Real>&, Vec<2, Real>&,
                                       double&) const {}
};

template <class Head, class... Tail>
struct TermList<Head, Tail...> {
  Head head;
  TermList<Tail...> tail;

  template <class Real>
  KOKKOS_INLINE_FUNCTION void evaluate(const SurfacePoint<2, Real>& s, const Vec<2, Real>& v,
                                       Vec<2, Real>& force, double& energy) const {
    head.evaluate(s, v, force, energy);
    tail.evaluate(s, v, force, energy);
  }
};

inline TermList<> make_term_list() { return {}; }

template <class Head, class... Tail>
TermList<Head, Tail...> make_term_list(const Head& head, const Tail&... tail) {
  return {head, make_term_list(tail...)};
}

template <class Real, class ExecSpace, class Query, class Terms>
struct SurfaceForceKernel {
  using vector_view = typename Particles<2, Real, ExecSpace>::vector_view;

  Query surfaces;
  vector_view x, v, f;
  Terms terms;

  KOKKOS_INLINE_FUNCTION void operator()(int i, double& energy) const {
    const SurfacePoint<2, Real> s = surfaces.nearest(i, Vec<2, Real>::load(x, i));
    Vec<2, Real> fi = Vec<2, Real>::zero();
    terms.evaluate(s, Vec<2, Real>::load(v, i), fi, energy);
    for (int d = 0; d < 2; ++d) f(i, d) += fi[d];
  }
};

}  // namespace surface_force_detail

// Adds the forces of `terms` on every particle of p to p.f and returns their total energy. `velocity`
// is the velocity that velocity-dependent terms (drag) must see: the integrator's
// velocity_for_forces(p) (p.v itself for λ = ½, see velocity_verlet.hpp).
//
// `surfaces` is any query with KOKKOS_INLINE_FUNCTION nearest(int particle, Vec x): Surfaces (walls
// and the obstacle grid) or BodySurfaces (walls and per-body obstacle candidates).
template <class Query, class Real, class ExecSpace, class... Terms>
double accumulate_surface_forces(const Query& surfaces, const Particles<2, Real, ExecSpace>& p,
                                 const typename Particles<2, Real, ExecSpace>::vector_view& velocity,
                                 const Terms&... terms) {
  using Kernel =
      surface_force_detail::SurfaceForceKernel<Real, ExecSpace, Query, surface_force_detail::TermList<Terms...>>;
  const Kernel kernel{surfaces, p.x, velocity, p.f, surface_force_detail::make_term_list(terms...)};
  double energy = 0;
  Kokkos::parallel_reduce("mesoflow::surface_force::accumulate", Kokkos::RangePolicy<ExecSpace>(0, p.size()), kernel,
                          energy);
  return energy;
}

}  // namespace mesoflow
