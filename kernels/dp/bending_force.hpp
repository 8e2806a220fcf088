// bending_force.hpp — bending U_b = (k_b / (2 N_v)) Σ_j |û_j − û_{j+1}|² / l0² per body
// (hopper-flows eq. 8, third term; the factor 1/N_v makes the shape energy independent of N_v).
//
// With C = k_b / (2 N_v l0²) and |û_j − û_{j+1}|² = 2 − 2 û_j·û_{j+1}, the energy depends on edge
// e_j through û_j only, in the corners at its two ends:
//   ∂U_b/∂e_j = (∂û_j/∂e_j)ᵀ ∂U_b/∂û_j = −(2C / l_j) (I − û_j û_jᵀ)(û_{j−1} + û_{j+1}) ≡ G_j,
// using ∂û/∂e = (I − û ûᵀ)/l. Vertex i ends e_{i−1} and starts e_i (∂e_{i−1}/∂r_i = I,
// ∂e_i/∂r_i = −I), so
//   F_i = −∂U_b/∂r_i = G_i − G_{i−1},
// which involves û_{i−2} … û_{i+1}, i.e. vertices i−2 … i+2. Each vertex carries the energy of the
// corner at it, C |û_{i−1} − û_i|².
#pragma once

#include "vertex_stencil.hpp"

namespace mesoflow::dp {

template <class Real>
struct Bending {
  Real k_b;

  KOKKOS_INLINE_FUNCTION ForceEnergy<Real> evaluate(const VertexStencil<Real>& s, const BodyShape<Real>& body) const {
    const Real c = k_b / (Real(2 * body.nv) * body.l0 * body.l0);
    ForceEnergy<Real> out;
    out.force = edge_gradient(c, s.u(0), s.l(0), s.u(-1) + s.u(1)) -
                edge_gradient(c, s.u(-1), s.l(-1), s.u(-2) + s.u(0));
    const Vec2<Real> turn = s.u(-1) - s.u(0);
    out.energy = c * norm2(turn);
    return out;
  }

 private:
  // G_j = −(2C / l_j) (I − û_j û_jᵀ) w, with w = û_{j−1} + û_{j+1}.
  KOKKOS_INLINE_FUNCTION static Vec2<Real> edge_gradient(Real c, const Vec2<Real>& u, Real l, const Vec2<Real>& w) {
    const Vec2<Real> w_perp = w - dot(u, w) * u;
    return (Real(-2) * c / l) * w_perp;
  }
};

}  // namespace mesoflow::dp
