// vertex_wall_repulsion.hpp — repulsion between the vertices of a deformable polygon and the walls and
// obstacles (capillary-droplet study, eq. 3):
//   U_w = Σ_i (ε_w/2)(1 − 2d_i/δ)² Θ(1 − 2d_i/δ),
// d_i the signed distance from vertex i to the nearest surface, δ the vertex diameter. The force on
// vertex i, −∇U_w = (2ε_w/δ)(1 − 2d_i/δ) n_i, points along the surface normal n_i into the fluid; it
// keeps growing past contact (d_i < 0: the vertex is inside a wall). Add it with
// accumulate_surface_forces (surface_force.hpp), which queries the nearest surface once per vertex.
#pragma once

#include "kernels/common/geometry.hpp"
#include "kernels/common/kokkos_compat.hpp"
#include "kernels/common/surface_force.hpp"
#include "kernels/common/vec.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace mesoflow::dp {

template <class Real>
struct VertexWallRepulsion {
  Real epsilon;         // ε_w
  Real two_over_delta;  // 2/δ
  Real range;           // δ/2: no force at d ≥ δ/2

  VertexWallRepulsion(Real epsilon_w, Real vertex_diameter) {
    if (!(epsilon_w >= Real(0)) || !std::isfinite(epsilon_w))
      throw std::invalid_argument("vertex_wall_repulsion: epsilon_w must be finite and >= 0, got " +
                                  std::to_string(epsilon_w));
    if (!(vertex_diameter > Real(0)) || !std::isfinite(vertex_diameter))
      throw std::invalid_argument("vertex_wall_repulsion: vertex diameter must be finite and > 0, got " +
                                  std::to_string(vertex_diameter));
    epsilon = epsilon_w;
    two_over_delta = Real(2) / vertex_diameter;
    range = Real(0.5) * vertex_diameter;
  }

  // At signed distance d: false beyond the range, otherwise the force along the normal, −dU/dd, and
  // the energy.
  KOKKOS_INLINE_FUNCTION bool contact(Real d, Real& force_along_normal, Real& energy) const {
    if (!(d < range)) return false;
    const Real overlap = Real(1) - two_over_delta * d;
    force_along_normal = epsilon * two_over_delta * overlap;
    energy = Real(0.5) * epsilon * overlap * overlap;
    return true;
  }

  KOKKOS_INLINE_FUNCTION void evaluate(const SurfacePoint<2, Real>& s, const Vec<2, Real>&, Vec<2, Real>& force,
                                       double& energy) const {
    Real f_n, u;
    if (contact(s.distance, f_n, u)) {
      force += f_n * s.normal;
      energy += double(u);
    }
  }
};

}  // namespace mesoflow::dp
