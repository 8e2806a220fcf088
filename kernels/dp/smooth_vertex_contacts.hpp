// smooth_vertex_contacts.hpp — contacts between nearly smooth (frictionless) deformable polygons
// (hopper study, §2.3 and Appendix A): each edge i of particle m, from vertex r_mi to r_m,i+1, is a
// circulo-line of width δ_m = 0.1 l_m,0, and a vertex j of another particle n repels it by eq. 9,
//   U = (ε_c/2)(1 − δ/δ_mn)² Θ(1 − δ/δ_mn),   δ_mn = (δ_m + δ_n)/2,
// with δ the contact distance of Appendix A: if the foot P of the perpendicular from r_nj on the
// edge's line lies between r_mi and r_m,i+1 (0 ≤ t ≤ 1), δ is the distance from r_nj to the line
// (Fig. 9a), otherwise δ = |r_nj − r_mi|, the distance to the edge's first vertex (Fig. 9b; the cap
// at r_m,i+1 belongs to edge i + 1). The force on r_nj is along the edge normal (or along
// r_nj − r_mi at a cap): frictionless. Its reaction is shared by the edge's vertices, (1 − t) and t
// of it (envelope theorem), so each contact exchanges no net force.
//
// An evaluator of the generic pair loop (kernels/common/pair_force.hpp) over a full neighbor list of
// vertices excluding pairs of the same particle, each vertex
// summing its own force in its three roles (deterministic, no atomics): as the point against the
// edges starting at its neighbours, as the first vertex of its own edge i → i+1, and as the second
// vertex of its edge i−1 → i, against neighbouring points. The list's cutoff must cover the longest
// edge plus the widest δ_mn (checked: `smooth_contact_reach`). Returns the energy.
#pragma once

#include "../common/kernel_launch.hpp"
#include "kernels/common/box.hpp"
#include "kernels/common/kokkos_compat.hpp"
#include "kernels/common/neighbor_list.hpp"
#include "kernels/common/pair_force.hpp"
#include "kernels/common/particles.hpp"
#include "kernels/dp/polygons.hpp"
#include "kernels/sp/pair_repulsion.hpp"

#include <stdexcept>
#include <string>

namespace mesoflow::dp {

namespace smooth_contact_detail {

// Contact of point q with the edge from a along l (l = b − a, minimum image, |l|² = l2: the pair
// loop computes a row's own two edges once per row, not once per pair) (Appendix A): returns false
// without contact; otherwise the magnitude f = −dU/dδ, the unit direction u = ∂δ/∂q, the edge
// parameter t (0 at a cap) and U.
template <class Real>
KOKKOS_FORCEINLINE_FUNCTION bool contact_along(const Vec<2, Real>& q, const Vec<2, Real>& a, const Vec<2, Real>& l,
                                               Real l2, const Box<2, Real>& box, Real width, Real epsilon, Real& f,
                                               Vec<2, Real>& u, Real& t, Real& energy) {
  Vec<2, Real> aq = q - a;
  box.minimum_image(aq);
  t = l2 > Real(0) ? dot(aq, l) / l2 : Real(-1);
  Vec<2, Real> gap = aq;
  if (t >= Real(0) && t <= Real(1))
    gap -= t * l;
  else
    t = Real(0);
  const Real d2 = norm2(gap);
  if (!(d2 < width * width) || d2 == Real(0)) return false;
  const Real d = kmath::sqrt(d2);
  const Real overlap = Real(1) - d / width;
  f = epsilon * overlap / width;
  u = (Real(1) / d) * gap;
  energy = Real(0.5) * epsilon * overlap * overlap;
  return true;
}

// The edge vector b − a, minimum image.
template <class Real>
KOKKOS_FORCEINLINE_FUNCTION Vec<2, Real> edge(const Vec<2, Real>& a, const Vec<2, Real>& b, const Box<2, Real>& box) {
  Vec<2, Real> l = b - a;
  box.minimum_image(l);
  return l;
}

// Contact of point q with the edge a → b: contact_along with l = b − a.
template <class Real>
KOKKOS_FORCEINLINE_FUNCTION bool contact(const Vec<2, Real>& q, const Vec<2, Real>& a, const Vec<2, Real>& b,
                                         const Box<2, Real>& box, Real width, Real epsilon, Real& f, Vec<2, Real>& u,
                                         Real& t, Real& energy) {
  const Vec<2, Real> l = edge(a, b, box);
  return contact_along(q, a, l, norm2(l), box, width, epsilon, f, u, t, energy);
}

}  // namespace smooth_contact_detail

// The neighbor-list cutoff smooth contacts need: the longest edge plus the widest contact width.
template <class Real, class ExecSpace>
Real smooth_contact_reach(const Polygons<Real, ExecSpace>& polygons, const Particles<2, Real, ExecSpace>& p,
                          const Box<2, Real>& box, const sp::SoftSphereRepulsion<Real>& widths) {
  const auto offset = polygons.offset;
  const auto body = polygons.body;
  const auto x = p.x;
  Real longest = 0;
  mesoflow::launch::parallel_reduce(
      "mesoflow::dp::smooth_contact_reach", Kokkos::RangePolicy<ExecSpace>(0, polygons.num_vertices()),
      KOKKOS_LAMBDA(int i, Real& acc) {
        const int b = body(i), begin = offset(b), n = offset(b + 1) - begin;
        Vec<2, Real> l = Vec<2, Real>::load(x, next_vertex(i, 1, begin, n)) - Vec<2, Real>::load(x, i);
        box.minimum_image(l);
        const Real len = kmath::sqrt(norm2(l));
        acc = len > acc ? len : acc;
      },
      Kokkos::Max<Real>(longest));
  return longest + widths.cutoff();
}

// The three roles of vertex i against a neighbouring vertex j, as an evaluator of the generic pair
// loop (full list): the contact geometry takes its own separations, so the loop applies no image
// convention and no screen; `sum` receives the energy of role (a).
template <class Real, class ExecSpace>
struct SmoothVertexContactEvaluator : PairEvaluatorTraits {
  static constexpr MinimumImage image = MinimumImage::none;
  using vector_view = typename Particles<2, Real, ExecSpace>::vector_view;
  sp::SoftSphereRepulsion<Real> widths;
  Kokkos::View<int*, ExecSpace> offset, body;
  vector_view x, f;
  Kokkos::View<int*, ExecSpace> type;
  Box<2, Real> box;

  // Row i: its position, its own two edges i → next(i) and prev(i) → i with their squared lengths
  // (computed once per row), its type and its force.
  struct Row {
    Vec<2, Real> xi, x_prev, l_next, l_prev;
    Real l2_next, l2_prev;
    int ti;
    Vec<2, Real> fi;
  };
  KOKKOS_INLINE_FUNCTION Row begin(FullList, int i) const {
    using smooth_contact_detail::edge;
    const int bi = body(i), begin_i = offset(bi), n_i = offset(bi + 1) - begin_i;
    const Vec<2, Real> xi = Vec<2, Real>::load(x, i), x_prev = Vec<2, Real>::load(x, prev_vertex(i, 1, begin_i, n_i));
    const Vec<2, Real> l_next = edge(xi, Vec<2, Real>::load(x, next_vertex(i, 1, begin_i, n_i)), box);
    const Vec<2, Real> l_prev = edge(x_prev, xi, box);
    return {xi, x_prev, l_next, l_prev, norm2(l_next), norm2(l_prev), type(i), Vec<2, Real>::zero()};
  }
  KOKKOS_INLINE_FUNCTION void operator()(FullList, Row& s, int, int j, const Vec<2, Real>&, Real, double& acc) const {
    using smooth_contact_detail::contact;
    using smooth_contact_detail::contact_along;
    const Real width = widths.contact[s.ti][type(j)];
    const Vec<2, Real> xj = Vec<2, Real>::load(x, j);
    Real fm, t, e;
    Vec<2, Real> u;
    // (a) i the point, against the edge j → next(j) of the other particle.
    const int bj = body(j), begin_j = offset(bj), n_j = offset(bj + 1) - begin_j;
    if (contact(s.xi, xj, Vec<2, Real>::load(x, next_vertex(j, 1, begin_j, n_j)), box, width, widths.epsilon, fm, u,
                t, e)) {
      s.fi += fm * u;
      acc += double(e);
    }
    // (b) i the first vertex of its edge i → next(i), against the point j.
    if (contact_along(xj, s.xi, s.l_next, s.l2_next, box, width, widths.epsilon, fm, u, t, e))
      s.fi += (-(Real(1) - t) * fm) * u;
    // (c) i the second vertex of its edge prev(i) → i, against the point j (no share at a cap).
    if (contact_along(xj, s.x_prev, s.l_prev, s.l2_prev, box, width, widths.epsilon, fm, u, t, e)) s.fi += (-t * fm) * u;
  }
  KOKKOS_INLINE_FUNCTION void end(FullList, Row& s, int i, double&) const {
    for (int d = 0; d < 2; ++d) f(i, d) += s.fi[d];
  }
};

// Adds the contact forces to p.f and returns the energy. `widths`: ε_c and δ of each vertex type
// (the particle's size class), as a SoftSphereRepulsion. Throws if the list does not exclude pairs of
// the same body or its cutoff (plus skin) is shorter than smooth_contact_reach.
template <class Real, class ExecSpace>
double accumulate_smooth_vertex_contacts(const sp::SoftSphereRepulsion<Real>& widths,
                                         const Polygons<Real, ExecSpace>& polygons,
                                         const Particles<2, Real, ExecSpace>& p,
                                         const NeighborList<2, Real, ExecSpace>& list, const Box<2, Real>& box) {
  if (list.exclusion() != BodyExclusion::same_body)
    throw std::invalid_argument("dp smooth contacts: the neighbor list must exclude pairs of the same body");
  if (list.kind() != NeighborListKind::full)
    throw std::invalid_argument("dp smooth contacts: needs a full neighbor list");
  const Real reach = smooth_contact_reach(polygons, p, box, widths);
  if (reach > list.cutoff())
    throw std::invalid_argument("dp smooth contacts: an edge plus the contact width (" + std::to_string(double(reach)) +
                                ") exceeds the neighbor-list cutoff " + std::to_string(double(list.cutoff())));
  const SmoothVertexContactEvaluator<Real, ExecSpace> ev{{}, widths, polygons.offset, polygons.body, p.x, p.f, p.type, box};
  return reduce_pairs("mesoflow::dp::smooth_vertex_contacts", FullList{}, list, box, p.x, ev);
}

}  // namespace mesoflow::dp
