// near_wall_drag.hpp — viscous drag on the vertices of a deformable polygon, stronger near walls and
// obstacles (capillary-droplet study, eqs. 5–6):
//   F_i = −(ζ_i/N_v) v_i,   ζ_i = b∞ (1 + (b0/b∞)(σ/d_i)^α) = b∞ + b0 (σ/d_i)^α,
// d_i the distance from vertex i to the nearest surface, σ the droplet diameter, α = 4/3 as calibrated
// in the paper's Appendix A. d_i is floored at d_floor (default 0.01σ): at contact (d_i → 0) and for a
// vertex pushed inside a wall (d_i < 0) ζ_i stays finite, b∞ + b0 (σ/d_floor)^α. b0 = 0 (the
// obstacle-array runs of §4.3) skips the power: the drag is then −(b∞/N_v) v_i at no extra cost.
// v_i is the integrator's velocity for velocity-dependent forces (velocity_verlet.hpp). The force
// dissipates: F_i · v_i = −(ζ_i/N_v)|v_i|² ≤ 0.
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
struct NearWallDrag {
  Real far_coefficient;   // b∞/N_v
  Real near_coefficient;  // b0/N_v
  Real sigma;             // σ
  Real alpha;             // α
  Real d_floor;           // smallest d_i used in eq. 6
  bool four_thirds;       // α = 4/3 exactly

  NearWallDrag() = default;  // for per-body Views (per_body.hpp); assign a constructed value before use
  // b∞ ≥ 0, b0 ≥ 0, σ > 0, N_v ≥ 1 vertices per droplet, α > 0, d_floor = d_floor_over_sigma · σ > 0.
  NearWallDrag(Real b_inf, Real b0, Real sigma_, int num_vertices, Real alpha_ = Real(4) / Real(3),
               Real d_floor_over_sigma = Real(0.01)) {
    require(b_inf >= Real(0) && std::isfinite(b_inf), "b_inf must be finite and >= 0", b_inf);
    require(b0 >= Real(0) && std::isfinite(b0), "b0 must be finite and >= 0", b0);
    require(sigma_ > Real(0) && std::isfinite(sigma_), "sigma must be finite and > 0", sigma_);
    require(num_vertices >= 1, "the number of vertices must be >= 1", Real(num_vertices));
    require(alpha_ > Real(0) && std::isfinite(alpha_), "alpha must be finite and > 0", alpha_);
    require(d_floor_over_sigma > Real(0) && std::isfinite(d_floor_over_sigma),
            "d_floor / sigma must be finite and > 0", d_floor_over_sigma);
    far_coefficient = b_inf / Real(num_vertices);
    near_coefficient = b0 / Real(num_vertices);
    sigma = sigma_;
    alpha = alpha_;
    d_floor = d_floor_over_sigma * sigma_;
    four_thirds = alpha_ == Real(4) / Real(3);
  }

  // ζ_i/N_v at distance d (eq. 6 over N_v).
  KOKKOS_INLINE_FUNCTION Real coefficient(Real d) const {
    if (near_coefficient == Real(0)) return far_coefficient;
    const Real gap = d > d_floor ? d : d_floor;
    const Real ratio = sigma / gap;
    // The paper's α = 4/3 as x·∛x: several times cheaper than pow() in the hottest loop.
    return far_coefficient + near_coefficient * (four_thirds ? ratio * kmath::cbrt(ratio) : kmath::pow(ratio, alpha));
  }

  KOKKOS_INLINE_FUNCTION void evaluate(const SurfacePoint<2, Real>& s, const Vec<2, Real>& v, Vec<2, Real>& force,
                                       double&) const {
    force += (-coefficient(s.distance)) * v;
  }

 private:
  static void require(bool ok, const std::string& what, Real value) {
    if (!ok) throw std::invalid_argument("near_wall_drag: " + what + ", got " + std::to_string(value));
  }
};

}  // namespace mesoflow::dp
