// shape_forces.hpp — the one loop over polygon vertices for the DP shape energy and gravity
// (capillary-droplets eqs. 1–2 and 4, hopper-flows eq. 8).
//
// Physics lives in the evaluators (area_force.hpp, segment_spring_force.hpp, line_tension.hpp,
// bending_force.hpp, gravity.hpp; interface in vertex_stencil.hpp); this loop owns iteration, the
// stencil and the reductions. Each vertex loads r_{i−2..i+2} and its body's shape once, derives
// the edge geometry once, and sums every term the scene passes:
//
//     update_body_state(polygons, p, state);   // AreaElasticity needs the current areas
//     double u = accumulate_shape_forces(polygons, state, p, AreaElasticity<Real>{k_a},
//                                        SegmentSprings<Real>{k_l}, LineTension<Real>{gamma},
//                                        Gravity<Real>{g});
//
// The terms are a compile-time list: a term not in the scene costs nothing, so a scene passes
// only the terms whose coefficient is non-zero (the droplet study has no bending, the hopper study
// no line tension). Each vertex writes only its own force, so forces are deterministic on every
// backend and thread count, with no atomics; energies are summed in double.
#pragma once

#include "../common/kernel_launch.hpp"
#include "polygons.hpp"
#include "vertex_stencil.hpp"

#include "kernels/common/kokkos_compat.hpp"
#include "kernels/common/particles.hpp"

#include <stdexcept>
#include <string>

namespace mesoflow::dp {

namespace shape_forces_detail {

// The terms of a scene as one device-copyable value: term(s, body) for each, in order.
template <class... Terms>
struct TermList;

template <>
struct TermList<> {
  template <class Real>
  KOKKOS_INLINE_FUNCTION void add(const VertexStencil<Real>&, const BodyShape<Real>&, Vec2<Real>&, double&) const {}
};

template <class Head, class... Tail>
struct TermList<Head, Tail...> {
  Head head;
  TermList<Tail...> tail;

  template <class Real>
  KOKKOS_INLINE_FUNCTION void add(const VertexStencil<Real>& s, const BodyShape<Real>& body, Vec2<Real>& force,
                                  double& energy) const {
    const ForceEnergy<Real> fe = head.evaluate(s, body);
    force += fe.force;
    energy += double(fe.energy);
    tail.add(s, body, force, energy);
  }
};

inline TermList<> make_term_list() { return {}; }

template <class Head, class... Tail>
TermList<Head, Tail...> make_term_list(const Head& head, const Tail&... tail) {
  return {head, make_term_list(tail...)};
}

// Σ over the polygon vertices of every term's energy; with AddForces, f_i += Σ_terms F_i as well.
template <bool AddForces, class Real, class ExecSpace, class... Terms>
double vertex_loop(const char* label, const Polygons<Real, ExecSpace>& polygons,
                   const BodyState<Real, ExecSpace>& state, const Particles<2, Real, ExecSpace>& p,
                   const Terms&... terms) {
  if (state.num_bodies() != polygons.num_bodies())
    throw std::invalid_argument(std::string(label) + ": state for " + std::to_string(state.num_bodies()) +
                                " bodies, polygons have " + std::to_string(polygons.num_bodies()));
  if (int(p.size()) < polygons.num_vertices())
    throw std::invalid_argument(std::string(label) + ": the polygons have " + std::to_string(polygons.num_vertices()) +
                                " vertices but the particle set only " + std::to_string(p.size()));
  const auto term_list = make_term_list(terms...);
  const auto offset = polygons.offset;
  const auto body_of = polygons.body;
  const auto a0 = polygons.a0;
  const auto l0 = polygons.l0;
  const auto area = state.area;
  const auto x = p.x;
  const auto f = p.f;
  const auto mass = p.mass;
  double energy = 0;
  mesoflow::launch::parallel_reduce(
      label, Kokkos::RangePolicy<ExecSpace>(0, polygons.num_vertices()),
      KOKKOS_LAMBDA(int i, double& e_acc) {
        const int b = body_of(i);
        const int begin = offset(b), n = offset(b + 1) - begin;
        VertexStencil<Real> s;
        s.pos[0] = Vec2<Real>::load(x, prev_vertex(i, 2, begin, n));
        s.pos[1] = Vec2<Real>::load(x, prev_vertex(i, 1, begin, n));
        s.pos[2] = Vec2<Real>::load(x, i);
        s.pos[3] = Vec2<Real>::load(x, next_vertex(i, 1, begin, n));
        s.pos[4] = Vec2<Real>::load(x, next_vertex(i, 2, begin, n));
        s.mass = mass(i);
        s.derive_edges();
        const BodyShape<Real> shape{area(b), a0(b), l0(b), n, b};
        Vec2<Real> fi = Vec2<Real>::zero();
        term_list.add(s, shape, fi, e_acc);
        // `if`, not `if constexpr`: nvcc rejects a KOKKOS_LAMBDA whose first use of a captured
        // variable is inside `if constexpr` (the condition is a compile-time constant all the same).
        if (AddForces)
          for (int d = 0; d < 2; ++d) f(i, d) += fi[d];
      },
      energy);
  return energy;
}

}  // namespace shape_forces_detail

// Adds F_i = −∂U/∂r_i of every term to p.f for each polygon vertex (adds, never overwrites: other
// force terms may have written first) and returns the total energy of the terms. `state` must hold
// the bodies' areas at the current positions (update_body_state).
template <class Real, class ExecSpace, class... Terms>
double accumulate_shape_forces(const Polygons<Real, ExecSpace>& polygons, const BodyState<Real, ExecSpace>& state,
                               const Particles<2, Real, ExecSpace>& p, const Terms&... terms) {
  return shape_forces_detail::vertex_loop<true>("mesoflow::dp::shape_forces", polygons, state, p, terms...);
}

// The total energy of the terms only, p.f untouched (observables, tests, line searches); `state`
// must be current as for accumulate_shape_forces.
template <class Real, class ExecSpace, class... Terms>
double shape_energy(const Polygons<Real, ExecSpace>& polygons, const BodyState<Real, ExecSpace>& state,
                    const Particles<2, Real, ExecSpace>& p, const Terms&... terms) {
  return shape_forces_detail::vertex_loop<false>("mesoflow::dp::shape_energy", polygons, state, p, terms...);
}

}  // namespace mesoflow::dp
