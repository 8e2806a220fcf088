// no_slip_walls.hpp — the velocity that fixed wall particles show in the viscous term of eq. (5).
//
// prescribed (the paper, §2.4, §3 and Fig. 1a; the default): walls are SPH particles at rest and
//   the viscous term sees their own velocity, zero. Geometry-free, but the no-slip plane is not
//   where the fluid ends: a fluid particle next to the wall sees a velocity field with a kink.
//   Plane Poiseuille flow with 10 particles across then runs 27% of U faster than the analytic
//   parabola (tests/sph/test_sph_flow.cpp measures it), the error falling only as 1/resolution.
// morris (Morris, Fox & Zhu, J. Comput. Phys. 136, 214 (1997)): for a pair of fluid particle a
//   and wall particle B the wall shows the fluid velocity extrapolated through the wall surface,
//     u_B = u_w − (d_B/d_a)(u_a − u_w),   so   u_a − u_B = β (u_a − u_w),   β = min(β_max, 1 + d_B/d_a),
//   d_a, d_B the distances of a and B from the wall surface. Exact for a linear velocity profile
//   at a plane wall. Each wall particle carries its surface: the unit normal n_B pointing from the
//   wall into the fluid and its depth d_B ≥ 0 below the surface (wall_geometry, D + 1 columns);
//   d_a = (x_a − x_B)·n_B − d_B then needs no other geometry. Used only in the viscous term; the
//   continuity eq. (4) keeps the wall's own velocity, so walls still neither move nor let fluid
//   through. Both orders of a pair give the same β: the pair forces stay antisymmetric.
//
// β_max guards fluid particles pushed close to the wall surface (d_a → 0). Morris et al. use 1.5;
// at 10 particles across (first fluid layer at d_a = Δx/2, wall layers at d_B = Δx/2, 3Δx/2, …) that
// caps every pair but the shallowest and leaves an 11% error in plane Poiseuille flow; 4 keeps the
// pairs that matter exact (1.5% error, Lucy kernel of support 3Δx). Default 8: exact up to a
// support of 4Δx. β multiplies the wall–fluid viscous coupling, so it tightens the viscous time-step
// limit (sph_time_step.hpp).
#pragma once

#include <Kokkos_Core.hpp>

#include <stdexcept>
#include <string>

namespace mesoflow::sph {

enum class WallVelocity { prescribed, morris };

inline WallVelocity parse_wall_velocity(const std::string& s) {
  if (s == "prescribed") return WallVelocity::prescribed;
  if (s == "morris") return WallVelocity::morris;
  throw std::invalid_argument("sph: wall velocity must be 'prescribed' or 'morris', got '" + s + "'");
}

// Column of the depth d_B in a wall-geometry row (the normal n_B fills columns 0…D−1).
template <int D>
constexpr int wall_depth_column = D;

template <class Real>
struct MorrisWallFactor {
  Real beta_max;

  explicit MorrisWallFactor(double beta_max_ = 8.0) {
    if (!(beta_max_ >= 1))
      throw std::invalid_argument("sph: Morris wall factor beta_max must be >= 1, got " + std::to_string(beta_max_));
    beta_max = Real(beta_max_);
  }

  // β for a fluid particle at normal distance `normal_offset` = (x_a − x_B)·n_B from wall particle B of
  // depth `depth`.
  KOKKOS_INLINE_FUNCTION Real operator()(Real normal_offset, Real depth) const {
    const Real d_fluid = normal_offset - depth;
    if (!(d_fluid > Real(0))) return beta_max;
    const Real beta = Real(1) + depth / d_fluid;
    return beta < beta_max ? beta : beta_max;
  }
};

}  // namespace mesoflow::sph
