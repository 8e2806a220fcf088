// line_tension.hpp — line tension U_γ = γ P, P = Σ_i l_i the perimeter (capillary-droplets eq. 2).
//
// Eq. 2 reads U_γ = γ_so l_so + γ_sw (L − l_so) + γ_ow l_ow, with l_so the oil–solid contact length,
// l_ow the oil–water interface length and L the wall length. In the oil-in-water experiments a thin
// water film separates the droplet from the walls, so the droplet never touches the solid
// (l_so = 0, l_ow = P) and all three tensions equal γ (§2.2):
//   U_γ = γ · 0 + γ (L − 0) + γ P = γ P + γ L.
// γ L is a constant of the geometry and is dropped; what acts on the vertices is γ P.
//
// ∂P/∂r_i = û_{i−1} − û_i, so F_i = γ (û_i − û_{i−1}): the turn of the boundary at vertex i, which
// for a convex counter-clockwise polygon points inward (2γ sin(π/N) towards the centre of a regular
// N-gon). Each vertex carries γ l_i, the energy of the edge it starts.
#pragma once

#include "vertex_stencil.hpp"

namespace mesoflow::dp {

template <class Real>
struct LineTension {
  Real gamma;

  KOKKOS_INLINE_FUNCTION ForceEnergy<Real> evaluate(const VertexStencil<Real>& s, const BodyShape<Real>&) const {
    ForceEnergy<Real> out;
    out.force = gamma * (s.u(0) - s.u(-1));
    out.energy = gamma * s.l(0);
    return out;
  }
};

}  // namespace mesoflow::dp
