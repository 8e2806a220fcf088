// obstacle_repulsion.hpp — repulsion between a soft-particle droplet and the obstacles and walls
// (capillary-droplet study, eq. 8):
//   U_w = (ε_w/2)(1 − 2d/σ)² Θ(1 − 2d/σ),
// σ the droplet diameter and d the signed distance from the droplet's centre to the nearest surface
// (d = r − σ_ob/2 for an obstacle of diameter σ_ob whose centre is r away). The droplet is a soft disk
// that overlaps the surface when d < σ/2; the force (2ε_w/σ)(1 − 2d/σ) n points along the surface
// normal n into the fluid. Add it with accumulate_surface_forces (surface_force.hpp).
#pragma once

#include "kernels/common/geometry.hpp"
#include "kernels/common/kokkos_compat.hpp"
#include "kernels/common/surface_force.hpp"
#include "kernels/common/vec.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace mesoflow::sp {

template <class Real>
struct ObstacleRepulsion {
  Real epsilon;         // ε_w
  Real two_over_sigma;  // 2/σ
  Real range;           // σ/2: no force at d ≥ σ/2

  ObstacleRepulsion(Real epsilon_w, Real droplet_diameter) {
    if (!(epsilon_w >= Real(0)) || !std::isfinite(epsilon_w))
      throw std::invalid_argument("sp_obstacle_repulsion: epsilon_w must be finite and >= 0, got " +
                                  std::to_string(epsilon_w));
    if (!(droplet_diameter > Real(0)) || !std::isfinite(droplet_diameter))
      throw std::invalid_argument("sp_obstacle_repulsion: droplet diameter must be finite and > 0, got " +
                                  std::to_string(droplet_diameter));
    epsilon = epsilon_w;
    two_over_sigma = Real(2) / droplet_diameter;
    range = Real(0.5) * droplet_diameter;
  }

  // At signed distance d: false beyond the range, otherwise the force along the normal, −dU/dd, and
  // the energy.
  KOKKOS_INLINE_FUNCTION bool contact(Real d, Real& force_along_normal, Real& energy) const {
    if (!(d < range)) return false;
    const Real overlap = Real(1) - two_over_sigma * d;
    force_along_normal = epsilon * two_over_sigma * overlap;
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

}  // namespace mesoflow::sp
