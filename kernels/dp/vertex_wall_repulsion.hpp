// vertex_wall_repulsion.hpp — repulsion between the vertices of a deformable polygon and the walls and
// obstacles (capillary-droplet study, eq. 3: "pairwise purely repulsive forces between the droplet
// vertices and walls"):
//   U_w = Σ_i Σ_s (ε_w/2)(1 − 2d_is/δ)² Θ(1 − 2d_is/δ),
// d_is the signed distance from vertex i to surface s (each wall shape, each obstacle), δ the vertex
// diameter. A pairwise term of the surface-force loop (surface_force.hpp): a vertex in a gap
// narrower than δ overlaps two obstacles and feels both. With the nearest surface alone the force
// jumps where the nearest of the two changes, energy is not conserved and a droplet held in such a
// gap never comes to rest (docs/droplets.md, finding 6). The harmonic contact law is shared with the
// SP model (kernels/common/harmonic_surface_repulsion.hpp).
#pragma once

#include "kernels/common/harmonic_surface_repulsion.hpp"

namespace mesoflow::dp {

template <class Real>
struct VertexWallRepulsion {
  static constexpr bool pairwise = true;
  HarmonicSurfaceRepulsion<Real> law;

  // ε_w ≥ 0, vertex diameter δ > 0.
  VertexWallRepulsion(Real epsilon, Real diameter) : law(epsilon, diameter) {}

  Real reach() const { return law.range; }  // δ/2

  KOKKOS_INLINE_FUNCTION void evaluate_pair(const SurfacePoint<2, Real>& s, Vec<2, Real>& force,
                                            double& energy) const {
    Real f_n, u;
    if (law.contact(s.distance, f_n, u)) {
      force += f_n * s.normal;
      energy += double(u);
    }
  }
};

}  // namespace mesoflow::dp
