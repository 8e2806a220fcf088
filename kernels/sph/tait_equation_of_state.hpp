// tait_equation_of_state.hpp — the Tait equation of state of weakly compressible SPH, eq. (6):
//
//   p = (c0² ρ0 / γ) [ (ρ/ρ0)^γ − 1 ],     γ = 7,
//
// (Monaghan & Kos 1999; Monaghan 1994). The paper's text drops the value of γ ("γ is a coefficient
// taken equal to (Monaghan 1994; Shadloo et al. 2013)"); both references, and LAMMPS'
// `sph/taitwater` pair styles that the paper's DMP simulations run on, use γ = 7, the default here.
// c0 is the reference speed of sound: the sound speed at ρ = ρ0, c² = dp/dρ = c0² (ρ/ρ0)^{γ−1}.
//
// The bracket is evaluated as δ (1 + s + … + s^{γ−1}) with δ = (ρ − ρ0)/ρ0 and s = ρ/ρ0, so the
// pressure of a density within round-off of ρ0 keeps its relative precision in float too.
//
// Choosing c0 (the paper: "at least one order of magnitude larger than the maximum velocity in the
// domain, which ensures keeping the density variations below 1%"): the density varies by
// δρ/ρ0 ≈ Ma² = (U_max/c0)², so c0 ≥ 10 U_max keeps it ≤ 1% (Monaghan 1994),
// speed_of_sound_for_velocity(). Where viscous stresses or body forces rather than inertia set the
// pressure (creeping and pressure-driven flows), Morris, Fox & Zhu, J. Comput. Phys. 136, 214
// (1997), ask for c0² ≥ max(U²/δ, ν U/(L δ), F L/δ) with δ = 0.01:
// morris_speed_of_sound().
#pragma once

#include "kernels/common/kokkos_compat.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace mesoflow::sph {

template <class Real>
struct TaitEquationOfState {
  Real rho0, inv_rho0, c0;
  Real B;     // c0² ρ0 / γ
  int gamma;

  TaitEquationOfState(double rho0_, double c0_, int gamma_ = 7) {
    if (!(std::isfinite(rho0_) && rho0_ > 0))
      throw std::invalid_argument("sph: Tait reference density rho0 must be > 0, got " + std::to_string(rho0_));
    if (!(std::isfinite(c0_) && c0_ > 0))
      throw std::invalid_argument("sph: Tait reference speed of sound c0 must be > 0, got " + std::to_string(c0_));
    if (gamma_ < 1 || gamma_ > 15)
      throw std::invalid_argument("sph: Tait exponent gamma must be an integer in [1, 15], got " +
                                  std::to_string(gamma_));
    rho0 = Real(rho0_);
    inv_rho0 = Real(1.0 / rho0_);
    c0 = Real(c0_);
    B = Real(c0_ * c0_ * rho0_ / gamma_);
    gamma = gamma_;
  }

  // p(ρ), eq. (6).
  KOKKOS_INLINE_FUNCTION Real pressure(Real rho) const {
    const Real s = rho * inv_rho0;
    Real sum = Real(1);
    for (int k = 1; k < gamma; ++k) sum = Real(1) + s * sum;
    return B * ((rho - rho0) * inv_rho0) * sum;
  }

  // c(ρ) = √(dp/dρ) = c0 (ρ/ρ0)^{(γ−1)/2}.
  KOKKOS_INLINE_FUNCTION Real sound_speed(Real rho) const {
    const Real s = rho * inv_rho0;
    Real s_pow = Real(1);
    for (int k = 1; k < gamma; ++k) s_pow *= s;
    return c0 * kmath::sqrt(s_pow);
  }
};

// c0 = factor · U_max, factor ≥ 10 (the paper, §2.2): density variations ≈ (U_max/c0)² ≤ 1%.
inline double speed_of_sound_for_velocity(double u_max, double factor = 10.0) {
  if (!(std::isfinite(u_max) && u_max > 0))
    throw std::invalid_argument("sph: maximum expected velocity U_max must be > 0, got " + std::to_string(u_max));
  if (!(std::isfinite(factor) && factor >= 10))
    throw std::invalid_argument("sph: c0/U_max must be >= 10 for density variations below 1%, got " +
                                std::to_string(factor));
  return factor * u_max;
}

// Morris et al. (1997): c0² = max(U²/δ, ν U/(L δ), |F| L/δ), for velocity scale U,
// kinematic viscosity ν, length scale L, body force per unit mass |F| and relative density
// variation δ (0.01 by default).
inline double morris_speed_of_sound(double u_max, double nu, double length, double body_accel, double delta = 0.01) {
  if (!(std::isfinite(u_max) && u_max >= 0 && std::isfinite(nu) && nu >= 0 && std::isfinite(length) && length > 0 &&
        std::isfinite(body_accel) && body_accel >= 0))
    throw std::invalid_argument("sph: morris_speed_of_sound needs U, nu, |F| >= 0 and L > 0");
  if (!(delta > 0 && delta < 1))
    throw std::invalid_argument("sph: density variation delta must be in (0, 1), got " + std::to_string(delta));
  const double c2 = std::max({u_max * u_max, nu * u_max / length, body_accel * length}) / delta;
  if (!(c2 > 0)) throw std::invalid_argument("sph: morris_speed_of_sound: every scale is zero");
  return std::sqrt(c2);
}

}  // namespace mesoflow::sph
