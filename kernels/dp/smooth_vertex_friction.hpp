// smooth_vertex_friction.hpp — kinetic friction between nearly smooth deformable polygons (hopper
// study, eq. 12 on the circulo-line contacts of Appendix A): a vertex r_nj of particle n in contact
// with edge i of particle m (smooth_vertex_contacts.hpp: distance below δ_mn, foot of the
// perpendicular at edge parameter t, t = 0 at the cap of the edge's first vertex) moves relative to
// the edge's material point at t with
//   Δv = v_nj − [(1 − t) v_mi + t v_m,i+1],
// and eq. 12 damps it: −μ Δv on the vertex, +(1 − t) μ Δv on r_mi and +t μ Δv on r_m,i+1. The three
// forces sum to zero exactly in the weights, so the friction exchanges momentum within each contact;
// it dissipates, Σ F·v = −μ Σ_contacts |Δv|² ≤ 0. At t = 0 or a cap it is eq. 12 between two
// vertices, as the rough model's vertex friction (vertex_contacts.hpp).
//
// FrictionComponent::tangential damps only the part of Δv along the edge (perpendicular to the
// contact normal u of smooth_vertex_contacts.hpp), as kinetic_friction.hpp does for disks; it
// dissipates −μ Σ |Δv_t|².
//
// Same loop as the contacts: a full neighbor list of vertices excluding pairs of the same particle,
// each vertex summing its own forces in its three roles (point; first vertex of its edge i → i+1;
// second vertex of its edge i−1 → i), deterministic, no atomics. The list must cover the longest
// edge plus the widest δ_mn, as for the contacts (checked there: the scene evaluates both).
#pragma once

#include "kernels/common/box.hpp"
#include "kernels/common/kokkos_compat.hpp"
#include "kernels/common/neighbor_list.hpp"
#include "kernels/common/pair_force.hpp"
#include "kernels/common/particles.hpp"
#include "kernels/dp/polygons.hpp"
#include "kernels/dp/smooth_vertex_contacts.hpp"
#include "kernels/sp/kinetic_friction.hpp"
#include "kernels/sp/pair_repulsion.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace mesoflow::dp {

template <class Real, class ExecSpace>
struct SmoothVertexFrictionEvaluator : PairEvaluatorTraits {
  static constexpr MinimumImage image = MinimumImage::none;
  using vector_view = typename Particles<2, Real, ExecSpace>::vector_view;
  Real mu;
  sp::SoftSphereRepulsion<Real> widths;
  Kokkos::View<int*, ExecSpace> offset, body;
  vector_view x, v, f;
  Kokkos::View<int*, ExecSpace> type;
  Box<2, Real> box;
  bool tangential;

  // Row i: as the contacts' row (its own two edges once per row), with the velocities of i and of
  // its two edge neighbours.
  struct Row {
    Vec<2, Real> xi, x_prev, l_next, l_prev;
    Real l2_next, l2_prev;
    Vec<2, Real> vi, v_next, v_prev;
    int ti;
    Vec<2, Real> fi;
  };
  KOKKOS_INLINE_FUNCTION Row begin(FullList, int i) const {
    using smooth_contact_detail::edge;
    const int bi = body(i), begin_i = offset(bi), n_i = offset(bi + 1) - begin_i;
    const int next = next_vertex(i, 1, begin_i, n_i), prev = prev_vertex(i, 1, begin_i, n_i);
    const Vec<2, Real> xi = Vec<2, Real>::load(x, i), x_prev = Vec<2, Real>::load(x, prev);
    const Vec<2, Real> l_next = edge(xi, Vec<2, Real>::load(x, next), box), l_prev = edge(x_prev, xi, box);
    return {xi,
            x_prev,
            l_next,
            l_prev,
            norm2(l_next),
            norm2(l_prev),
            Vec<2, Real>::load(v, i),
            Vec<2, Real>::load(v, next),
            Vec<2, Real>::load(v, prev),
            type(i),
            Vec<2, Real>::zero()};
  }
  // The damped part of the relative velocity: all of it, or its part perpendicular to the normal u.
  KOKKOS_INLINE_FUNCTION Vec<2, Real> damped(Vec<2, Real> dv, const Vec<2, Real>& u) const {
    if (tangential) dv -= dot(dv, u) * u;
    return dv;
  }
  KOKKOS_INLINE_FUNCTION void operator()(FullList, Row& s, int, int j, const Vec<2, Real>&, Real, double&) const {
    using smooth_contact_detail::contact;
    using smooth_contact_detail::contact_along;
    const Real width = widths.contact[s.ti][type(j)];
    const Vec<2, Real> xj = Vec<2, Real>::load(x, j), vj = Vec<2, Real>::load(v, j);
    Real fm, t, e;
    Vec<2, Real> u;
    // (a) i the point, against the edge j → next(j) of the other particle.
    const int bj = body(j), begin_j = offset(bj), n_j = offset(bj + 1) - begin_j;
    const int jn = next_vertex(j, 1, begin_j, n_j);
    if (contact(s.xi, xj, Vec<2, Real>::load(x, jn), box, width, widths.epsilon, fm, u, t, e))
      s.fi += (-mu) * damped(s.vi - ((Real(1) - t) * vj + t * Vec<2, Real>::load(v, jn)), u);
    // (b) i the first vertex of its edge i → next(i), against the point j.
    if (contact_along(xj, s.xi, s.l_next, s.l2_next, box, width, widths.epsilon, fm, u, t, e))
      s.fi += ((Real(1) - t) * mu) * damped(vj - ((Real(1) - t) * s.vi + t * s.v_next), u);
    // (c) i the second vertex of its edge prev(i) → i, against the point j (no share at a cap).
    if (contact_along(xj, s.x_prev, s.l_prev, s.l2_prev, box, width, widths.epsilon, fm, u, t, e))
      s.fi += (t * mu) * damped(vj - ((Real(1) - t) * s.v_prev + t * s.vi), u);
  }
  KOKKOS_INLINE_FUNCTION void end(FullList, Row& s, int i, double&) const {
    for (int d = 0; d < 2; ++d) f(i, d) += s.fi[d];
  }
};

// Adds eq. 12 between vertices and circulo-line edges to p.f (skipped at μ = 0). `velocity`: the
// integrator's velocity for velocity-dependent forces (velocity_verlet.hpp). Throws if the list
// does not exclude pairs of the same body or is not full.
template <class Real, class ExecSpace>
void accumulate_smooth_vertex_friction(Real mu, const sp::SoftSphereRepulsion<Real>& widths,
                                       const Polygons<Real, ExecSpace>& polygons,
                                       const Particles<2, Real, ExecSpace>& p,
                                       const typename Particles<2, Real, ExecSpace>::vector_view& velocity,
                                       const NeighborList<2, Real, ExecSpace>& list, const Box<2, Real>& box,
                                       sp::FrictionComponent component = sp::FrictionComponent::full) {
  if (list.exclusion() != BodyExclusion::same_body)
    throw std::invalid_argument("dp smooth friction: the neighbor list must exclude pairs of the same body");
  if (list.kind() != NeighborListKind::full) throw std::invalid_argument("dp smooth friction: needs a full neighbor list");
  if (!(mu >= Real(0)) || !std::isfinite(double(mu)))
    throw std::invalid_argument("dp smooth friction: mu must be finite and >= 0, got " + std::to_string(double(mu)));
  if (mu == Real(0)) return;  // a term whose coefficient is zero costs nothing
  const SmoothVertexFrictionEvaluator<Real, ExecSpace> ev{
      {},  mu,  widths, polygons.offset, polygons.body, p.x, velocity, p.f, p.type, box,
      component == sp::FrictionComponent::tangential};
  for_each_pair<Kokkos::Dynamic>("mesoflow::dp::smooth_vertex_friction", FullList{}, list, box, p.x, ev);
}

}  // namespace mesoflow::dp
