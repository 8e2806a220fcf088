// viscous_drag.hpp — drag on a soft-particle droplet from the background fluid (capillary-droplet
// study, eq. 10): F = −ζ_sp v with ζ_sp = b∞, independent of the distance to the walls (the SP model
// has no near-wall drag). v is the integrator's velocity for velocity-dependent forces
// (velocity_verlet.hpp). A per-particle term for accumulate_surface_forces (surface_force.hpp), so the
// droplet's repulsion and drag cost one pass; it ignores the surface query.
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
struct ViscousDrag {
  Real coefficient;  // ζ_sp = b∞

  explicit ViscousDrag(Real b_inf) : coefficient(b_inf) {
    if (!(b_inf >= Real(0)) || !std::isfinite(b_inf))
      throw std::invalid_argument("sp_viscous_drag: b_inf must be finite and >= 0, got " + std::to_string(b_inf));
  }

  KOKKOS_INLINE_FUNCTION void evaluate(const SurfacePoint<2, Real>&, const Vec<2, Real>& v, Vec<2, Real>& force,
                                       double&) const {
    force += (-coefficient) * v;
  }
};

}  // namespace mesoflow::sp
