// harmonic_surface_repulsion.hpp — purely repulsive harmonic contact between a particle of
// diameter δ and every surface of a scene it overlaps (a pair potential particle–surface),
//   U = Σ_s (ε/2)(1 − 2d_s/δ)² Θ(1 − 2d_s/δ),
// d_s the signed distance from the particle's centre to surface s (a wall shape or one obstacle).
// Each term's force (2ε/δ)(1 − 2d_s/δ) n_s points along that surface's normal into the fluid and
// keeps growing past contact (d_s < 0: the centre is inside a wall). Summed over every surface in
// reach, not the nearest alone: a particle in a gap narrower than δ overlaps two obstacles, and with
// the nearest alone the force would jump where the nearer of the two changes, so energy would not be
// conserved and a particle held in such a gap would never come to rest (docs/droplets.md,
// deviation 3). The same law is the DP vertex–wall repulsion (capillary-droplets eq. 3, δ the
// vertex diameter; dp/vertex_wall_repulsion.hpp) and the SP droplet–obstacle repulsion (eq. 8,
// δ = σ the droplet diameter; sp/obstacle_repulsion.hpp). A pairwise term of
// accumulate_surface_forces (surface_force.hpp).
#pragma once

#include "geometry.hpp"
#include "kokkos_compat.hpp"
#include "surface_force.hpp"
#include "vec.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace mesoflow {

template <class Real>
struct HarmonicSurfaceRepulsion {
  static constexpr bool pairwise = true;
  Real epsilon;        // ε
  Real two_over_size;  // 2/δ
  Real range;          // δ/2: no force at d ≥ δ/2

  HarmonicSurfaceRepulsion(Real epsilon_, Real diameter) {
    if (!(epsilon_ >= Real(0)) || !std::isfinite(epsilon_))
      throw std::invalid_argument("surface repulsion: epsilon_w must be finite and >= 0, got " +
                                  std::to_string(epsilon_));
    if (!(diameter > Real(0)) || !std::isfinite(diameter))
      throw std::invalid_argument("surface repulsion: diameter must be finite and > 0, got " +
                                  std::to_string(diameter));
    epsilon = epsilon_;
    two_over_size = Real(2) / diameter;
    range = Real(0.5) * diameter;
  }

  // At signed distance d: false beyond the range, otherwise the force along the normal, −dU/dd, and
  // the energy.
  KOKKOS_INLINE_FUNCTION bool contact(Real d, Real& force_along_normal, Real& energy) const {
    if (!(d < range)) return false;
    const Real overlap = Real(1) - two_over_size * d;
    force_along_normal = epsilon * two_over_size * overlap;
    energy = Real(0.5) * epsilon * overlap * overlap;
    return true;
  }

  Real reach() const { return range; }

  // The contact with one surface in reach.
  KOKKOS_INLINE_FUNCTION void evaluate_pair(const SurfacePoint<2, Real>& s, Vec<2, Real>& force, double& energy) const {
    Real f_n, u;
    if (contact(s.distance, f_n, u)) {
      force += f_n * s.normal;
      energy += double(u);
    }
  }
};

}  // namespace mesoflow
