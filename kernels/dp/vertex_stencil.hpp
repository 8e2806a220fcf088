// vertex_stencil.hpp — what a shape-energy evaluator sees of one polygon vertex i: the positions
// r_{i−2..i+2} of its neighbours along the polygon, the edge geometry derived from them once, its
// mass, and its body's area and reference shape (a0, l0, N_v).
//
// Conventions (capillary-droplets §2.2, hopper-flows §2.3): the vertices of a body run
// counter-clockwise, edge e_j = r_{j+1} − r_j has length l_j and direction û_j = e_j / l_j, indices
// wrap around within the body. Vertex i touches the edges e_{i−1} and e_i; the bending term couples
// it to û_{i−2} and û_{i+1} as well, hence five positions.
//
// An evaluator (a term of the shape energy) is a small struct with
//     KOKKOS_INLINE_FUNCTION ForceEnergy<Real> evaluate(const VertexStencil<Real>&,
//                                                      const BodyShape<Real>&) const;
// returning F_i = −∂U/∂r_i and vertex i's share of U (the shares of a body's vertices sum to the
// body's energy). shape_forces.hpp owns the loop that builds stencils and sums the terms.
#pragma once

#include "kernels/common/kokkos_compat.hpp"
#include "kernels/common/vec.hpp"

namespace mesoflow::dp {

template <class Real>
using Vec2 = Vec<2, Real>;

template <class Real>
KOKKOS_INLINE_FUNCTION Vec2<Real> make_vec2(Real x, Real y) {
  Vec2<Real> v;
  v[0] = x;
  v[1] = y;
  return v;
}

// v rotated by −90° (clockwise): for a counter-clockwise polygon, the outward normal of an edge is
// the clockwise rotation of its direction.
template <class Real>
KOKKOS_INLINE_FUNCTION Vec2<Real> rotate_cw(const Vec2<Real>& v) {
  return make_vec2(v[1], -v[0]);
}

// z-component of a × b.
template <class Real>
KOKKOS_INLINE_FUNCTION Real cross(const Vec2<Real>& a, const Vec2<Real>& b) {
  return a[0] * b[1] - a[1] * b[0];
}

template <class Real>
struct VertexStencil {
  Vec2<Real> pos[5];   // r_{i−2}, …, r_{i+2}
  Vec2<Real> unit[4];  // û_{i−2}, …, û_{i+1}
  Real len[4];         // l_{i−2}, …, l_{i+1}
  Real mass;           // M_i

  // Relative indexing: r(k) = r_{i+k} for k ∈ [−2, 2]; u(k) = û_{i+k}, l(k) = l_{i+k} for k ∈ [−2, 1].
  KOKKOS_INLINE_FUNCTION const Vec2<Real>& r(int k) const { return pos[k + 2]; }
  KOKKOS_INLINE_FUNCTION const Vec2<Real>& u(int k) const { return unit[k + 2]; }
  KOKKOS_INLINE_FUNCTION Real l(int k) const { return len[k + 2]; }

  // Edges, lengths and unit vectors from the five positions (vertices of a body never coincide:
  // the segment springs keep l_j near l0).
  KOKKOS_INLINE_FUNCTION void derive_edges() {
    for (int k = 0; k < 4; ++k) {
      const Vec2<Real> e = pos[k + 1] - pos[k];
      len[k] = kmath::sqrt(norm2(e));
      // Two vertices can coincide in float when weak segment springs let line tension crowd them
      // (K_l/Γ = 10⁻³): a zero-length edge has no direction, and its unit vector is taken as zero
      // (the subgradient of |e| at 0) instead of 0/0 (found by the NaN watchdog, docs/tradeoff.md).
      unit[k] = len[k] > Real(0) ? (Real(1) / len[k]) * e : Vec2<Real>::zero();
    }
  }
};

// The body of vertex i: current area a (from update_body_state), preferred area a0, preferred edge
// length l0, number of vertices N_v, and the body's index (per-body coefficients, per_body.hpp).
template <class Real>
struct BodyShape {
  Real area;
  Real a0;
  Real l0;
  int nv;
  int index = 0;
};

template <class Real>
struct ForceEnergy {
  Vec2<Real> force;  // F_i = −∂U/∂r_i
  Real energy;       // vertex i's share of U
};

}  // namespace mesoflow::dp
