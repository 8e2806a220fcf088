// gravity.hpp — uniform gravity on the vertices, U_g = −Σ_i M_i g·r_i = −M g·r_com
// (capillary-droplets eq. 4, U_g = −M g h; hopper-flows eq. 4; M_i = M/N_v, eq. 7).
//
// g is a vector: (0, −g) for the hopper, along the channel axis for the orifice. F_i = M_i g, and
// vertex i carries −M_i g·r_i. M_i is the vertex's Particles::mass.
#pragma once

#include "vertex_stencil.hpp"

namespace mesoflow::dp {

template <class Real>
struct Gravity {
  Vec2<Real> g;

  KOKKOS_INLINE_FUNCTION ForceEnergy<Real> evaluate(const VertexStencil<Real>& s, const BodyShape<Real>&) const {
    ForceEnergy<Real> out;
    out.force = s.mass * g;
    out.energy = -s.mass * dot(g, s.r(0));
    return out;
  }
};

}  // namespace mesoflow::dp
