// area_force.hpp — area elasticity U_a = (k_a/2)(a − a0)² per body (capillary-droplets eq. 1 and
// hopper-flows eq. 8, first term).
//
// With the shoelace area a = ½ Σ_j (x_j y_{j+1} − x_{j+1} y_j),
//   ∂a/∂r_i = ½ (y_{i+1} − y_{i−1}, x_{i−1} − x_{i+1}) = ½ R_cw(r_{i+1} − r_{i−1}),
// R_cw the clockwise rotation by 90° (outward for a counter-clockwise polygon), so
//   F_i = −k_a (a − a0) · ½ R_cw(r_{i+1} − r_{i−1}):
// an over-full body (a > a0) pulls its vertices in, an under-full one pushes them out. The area a
// is the body's, from update_body_state at the current positions; each vertex carries U_a / N_v.
#pragma once

#include "vertex_stencil.hpp"

namespace mesoflow::dp {

template <class Real>
struct AreaElasticity {
  Real k_a;

  KOKKOS_INLINE_FUNCTION ForceEnergy<Real> evaluate(const VertexStencil<Real>& s, const BodyShape<Real>& body) const {
    const Real excess = body.area - body.a0;
    ForceEnergy<Real> out;
    out.force = (Real(-0.5) * k_a * excess) * rotate_cw(s.r(1) - s.r(-1));
    out.energy = Real(0.5) * k_a * excess * excess / Real(body.nv);
    return out;
  }
};

}  // namespace mesoflow::dp
