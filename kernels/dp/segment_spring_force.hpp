// segment_spring_force.hpp — segment springs U_l = (k_l N_v / 2) Σ_i (l_i − l0)² per body
// (capillary-droplets eq. 1 and hopper-flows eq. 8, second term; the factor N_v makes the shape
// energy independent of N_v).
//
// Vertex i ends edge e_{i−1} and starts edge e_i: ∂l_{i−1}/∂r_i = û_{i−1}, ∂l_i/∂r_i = −û_i, so
//   F_i = k_l N_v [(l_i − l0) û_i − (l_{i−1} − l0) û_{i−1}]:
// a stretched edge pulls its two ends together. Each vertex carries the energy of the edge it starts.
#pragma once

#include "vertex_stencil.hpp"

namespace mesoflow::dp {

template <class Real>
struct SegmentSprings {
  Real k_l;

  KOKKOS_INLINE_FUNCTION ForceEnergy<Real> evaluate(const VertexStencil<Real>& s, const BodyShape<Real>& body) const {
    const Real k = k_l * Real(body.nv);
    const Real stretch_prev = s.l(-1) - body.l0;
    const Real stretch = s.l(0) - body.l0;
    ForceEnergy<Real> out;
    out.force = (k * stretch) * s.u(0) - (k * stretch_prev) * s.u(-1);
    out.energy = Real(0.5) * k * stretch * stretch;
    return out;
  }
};

}  // namespace mesoflow::dp
