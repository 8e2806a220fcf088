// surface_force.hpp — the one loop for forces between particles and the surfaces of a scene (walls and
// obstacles): one pass over the surfaces near each particle, handed to every per-particle term.
//
// Physics lives in small terms (dp/vertex_wall_repulsion.hpp, dp/near_wall_drag.hpp,
// sp/obstacle_repulsion.hpp, sp/viscous_drag.hpp); this loop owns the query, the per-particle sum
// and the energy reduction (accumulated in double). Terms come in two kinds:
//   - nearest-surface terms (drag: eq. 6 takes the minimum distance) provide
//       KOKKOS_INLINE_FUNCTION void evaluate(const SurfacePoint<2, Real>& s, const Vec<2, Real>& v,
//                                            Vec<2, Real>& force, double& energy) const;
//     adding the force on a particle at signed distance s.distance from the nearest surface (normal
//     s.normal, into the fluid), moving with velocity v, to `force` and its energy to `energy`;
//   - pairwise terms (a pair potential between the particle and each surface: eq. 3) declare
//       static constexpr bool pairwise = true;  Real reach() const;  (no action at d ≥ reach)
//       KOKKOS_INLINE_FUNCTION void evaluate_pair(const SurfacePoint<2, Real>& s, Vec<2, Real>& force,
//                                                 double& energy) const;
//     and are called once for every wall shape and every obstacle within reach of the particle, so
//     their energy is a sum of smooth pair terms (the nearest alone would make the force jump where
//     the nearest of two overlapping surfaces changes).
// A term that declares `static constexpr bool per_particle = true` takes the particle index first,
// evaluate(i, s, v, force, energy) / evaluate_pair(i, s, force, energy): per-body coefficients
// (dp/per_body.hpp).
// The query of a call with pairwise terms, nearest_within(i, x, reach, visit), returns the nearest
// surface and calls visit(s) for every surface at distance < reach, in a fixed order. Each particle
// writes only its own force: deterministic at any thread count, no atomics.
#pragma once

#include "kernel_launch.hpp"
#include "kokkos_compat.hpp"
#include "obstacle_array.hpp"
#include "particles.hpp"
#include "vec.hpp"

#include <type_traits>

namespace mesoflow {

namespace surface_force_detail {

// The terms of one call, evaluated in order (a device-copyable list; std::tuple is not usable in
// device code with every compiler mesoflow supports).
template <class... Terms>
struct TermList;

// Whether Term is a pairwise term (declares `static constexpr bool pairwise = true`).
template <class Term, class = void>
struct IsPairwise {
  static constexpr bool value = false;
};
template <class Term>
struct IsPairwise<Term, std::enable_if_t<Term::pairwise>> {
  static constexpr bool value = true;
};

// Whether Term takes the particle index (declares `static constexpr bool per_particle = true`).
template <class Term, class = void>
struct IsPerParticle {
  static constexpr bool value = false;
};
template <class Term>
struct IsPerParticle<Term, std::enable_if_t<Term::per_particle>> {
  static constexpr bool value = true;
};

template <>
struct TermList<> {
  static constexpr bool any_pairwise = false;
  template <class Real>
  KOKKOS_INLINE_FUNCTION void evaluate(int, const SurfacePoint<2, Real>&, const Vec<2, Real>&, Vec<2, Real>&,
                                       double&) const {}
  template <class Real>
  KOKKOS_INLINE_FUNCTION void evaluate_pair(int, const SurfacePoint<2, Real>&, Vec<2, Real>&, double&) const {}
  template <class Real>
  Real reach() const {
    return Real(0);
  }
};

template <class Head, class... Tail>
struct TermList<Head, Tail...> {
  static constexpr bool head_pairwise = IsPairwise<Head>::value;
  static constexpr bool head_per_particle = IsPerParticle<Head>::value;
  static constexpr bool any_pairwise = head_pairwise || TermList<Tail...>::any_pairwise;
  Head head;
  TermList<Tail...> tail;

  // The nearest-surface terms, for particle i.
  template <class Real>
  KOKKOS_INLINE_FUNCTION void evaluate(int i, const SurfacePoint<2, Real>& s, const Vec<2, Real>& v,
                                       Vec<2, Real>& force, double& energy) const {
    if constexpr (!head_pairwise) {
      if constexpr (head_per_particle)
        head.evaluate(i, s, v, force, energy);
      else
        head.evaluate(s, v, force, energy);
    }
    tail.evaluate(i, s, v, force, energy);
  }

  // The pairwise terms, for one surface within reach of particle i.
  template <class Real>
  KOKKOS_INLINE_FUNCTION void evaluate_pair(int i, const SurfacePoint<2, Real>& s, Vec<2, Real>& force,
                                            double& energy) const {
    if constexpr (head_pairwise) {
      if constexpr (head_per_particle)
        head.evaluate_pair(i, s, force, energy);
      else
        head.evaluate_pair(s, force, energy);
    }
    tail.evaluate_pair(i, s, force, energy);
  }

  // Largest reach of the pairwise terms (host).
  template <class Real>
  Real reach() const {
    const Real rest = tail.template reach<Real>();
    if constexpr (head_pairwise) return head.reach() > rest ? head.reach() : rest;
    return rest;
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
  Real reach;  // largest reach of the pairwise terms

  KOKKOS_INLINE_FUNCTION void operator()(int i, double& energy) const {
    const Vec<2, Real> xi = Vec<2, Real>::load(x, i);
    Vec<2, Real> fi = Vec<2, Real>::zero();
    if constexpr (Terms::any_pairwise) {
      const SurfacePoint<2, Real> s =
          surfaces.nearest_within(i, xi, reach, [&](const SurfacePoint<2, Real>& near) {
            terms.evaluate_pair(i, near, fi, energy);
          });
      terms.evaluate(i, s, Vec<2, Real>::load(v, i), fi, energy);
    } else {
      terms.evaluate(i, surfaces.nearest(i, xi), Vec<2, Real>::load(v, i), fi, energy);
    }
    for (int d = 0; d < 2; ++d) f(i, d) += fi[d];
  }
};

}  // namespace surface_force_detail

// Adds the forces of `terms` on every particle of p to p.f and returns their total energy. `velocity`
// is the velocity that velocity-dependent terms (drag) must see: the integrator's
// velocity_for_forces(p) (p.v itself for λ = ½, see velocity_verlet.hpp).
//
// `surfaces` is any query with KOKKOS_INLINE_FUNCTION nearest(int particle, Vec x) and, for pairwise
// terms, nearest_within(int particle, Vec x, Real reach, Visit visit): Surfaces (walls and the
// obstacle grid), BodySurfaces (walls and per-body obstacle candidates) or ParticleArraySurfaces.
template <class Query, class Real, class ExecSpace, class... Terms>
double accumulate_surface_forces(const Query& surfaces, const Particles<2, Real, ExecSpace>& p,
                                 const typename Particles<2, Real, ExecSpace>::vector_view& velocity,
                                 const Terms&... terms) {
  using Kernel =
      surface_force_detail::SurfaceForceKernel<Real, ExecSpace, Query, surface_force_detail::TermList<Terms...>>;
  const auto term_list = surface_force_detail::make_term_list(terms...);
  const Kernel kernel{surfaces, p.x, velocity, p.f, term_list, term_list.template reach<Real>()};
  double energy = 0;
  mesoflow::launch::parallel_reduce("mesoflow::surface_force::accumulate", Kokkos::RangePolicy<ExecSpace>(0, p.size()), kernel,
                          energy);
  return energy;
}

}  // namespace mesoflow
