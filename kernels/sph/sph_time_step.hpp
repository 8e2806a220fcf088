// sph_time_step.hpp — the stability limits of the explicit SPH time step (§2.5):
//
//   Δt_visc  = C_ν h²/ν_max,       C_ν = 0.125   (Morris, Fox & Zhu, J. Comput. Phys. 136, 214 (1997))
//   Δt_sound = C_c h/c_max,        C_c = 0.25    (the CFL condition; Morris et al. 1997, Monaghan 1992)
//   Δt_force = C_f √(h/|a|_max),   C_f = 0.25    (Monaghan 1992; Morris et al. 1997)
//   Δt_av    = C_av ν_min/c_max²,  C_av = 2     (this scheme's acoustic–viscous limit, below)
//   Δt = min of the four,
//
// ν the kinematic viscosity μ/ρ, c the largest sound speed (c0 of eq. 6 for small density
// variations), |a| = |f|/m the largest acceleration of a fluid particle.
//
// Which h: these coefficients belong to Monaghan's h, half the support of the cubic spline
// (smoothing_kernels.hpp), so time_step_length() is half the support radius for every kernel —
// for the paper's Lucy kernel, h_Lucy/2.
//
// The viscous limit is the one that bites in the paper's creeping flows, and the extrapolated
// velocity ū of eq. (13) halves its stability range (the viscous force at step n+1 is evaluated at
// an explicit-Euler prediction: for a decay rate λ the scheme is stable for λΔt < 1, against 2 for
// explicit Euler). Measured in plane Poiseuille flow (tests/sph/test_sph_flow.cpp, Lucy kernel of
// support 3Δx, viscous limit binding): stable up to C_ν ≈ 0.21 with the paper's walls and up to
// 0.15–0.18 with Morris walls (β ≤ 8, no_slip_walls.hpp), so 0.125 keeps a margin. The paper
// writes Δt = ζ h²/ν with ζ = 0.125 (citing Alexiadis 2015) and its Lucy h = the support: 0.5 in
// our units, four times our limit and beyond the measured stability; the test shows that run blow
// up. Pass other coefficients to reproduce another choice.
//
// The acoustic–viscous limit. In eqs. (11)–(16) the forces at n+1 use the pressure of the
// half-updated density ρ* (eq. 12) while the continuity eq. (4) sees the extrapolated velocity ū;
// for a sound wave of frequency ω = c k this coupling acts like an explicit-Euler step, whose
// amplification √(1 + ω²Δt²) exceeds 1 at every Δt: the wave grows at the rate ω²Δt/2 unless
// viscosity damps it faster, ν k² > c² k² Δt/2, i.e. Δt < 2ν/c². (LAMMPS' `fix sph`, the same
// scheme, shares it.) Measured (a periodic box of SPH fluid, Lucy support 2.5Δx, random velocities
// 0.05 c0/90, c0 = 90, ν = 2): unstable at the acoustic limit alone (Δt = 14 ν/c², |u| ×200 in 400
// steps), slowly growing at 6 ν/c², bounded at 4 ν/c² and 2 ν/c² over 2000 steps — C_av = 2.
// It binds where c is large next to ν — low Re with c0 raised for a pressure drop — and costs
// steps there; an inviscid fluid (ν_min = 0) gets no such limit and grows slowly at any Δt.
// tests/sph/test_sph_flow.cpp checks both sides of it.
//
// The limits need the largest acceleration, a reduction to the host: call them when choosing or
// revising Δt, not every step.
#pragma once

#include "../common/kernel_launch.hpp"
#include "kernels/common/particles.hpp"
#include "particle_types.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace mesoflow::sph {

struct SphTimeStepCoefficients {
  double viscous = 0.125;
  double acoustic = 0.25;
  double force = 0.25;
  double acoustic_viscous = 2.0;
};

struct SphTimeStepLimits {
  double viscous = std::numeric_limits<double>::infinity();
  double acoustic = std::numeric_limits<double>::infinity();
  double force = std::numeric_limits<double>::infinity();
  double acoustic_viscous = std::numeric_limits<double>::infinity();

  double dt() const { return std::min({viscous, acoustic, force, acoustic_viscous}); }
  // The limit that sets dt.
  const char* binding() const {
    const double m = dt();
    return m == viscous ? "viscous" : (m == acoustic ? "acoustic" : (m == force ? "force" : "acoustic-viscous"));
  }
};

// h of the limits: half the support radius of the kernel (see the file comment).
template <class Kernel>
double time_step_length(const Kernel& kernel) {
  return 0.5 * double(kernel.support);
}

// The limits for length h, largest kinematic viscosity nu_max, largest sound speed c_max, largest
// acceleration accel_max and smallest kinematic viscosity nu_min of the moving particles (default,
// negative: nu_max, a single fluid); a zero viscosity or acceleration leaves its limits infinite.
inline SphTimeStepLimits sph_time_step_limits(double h, double nu_max, double c_max, double accel_max,
                                              const SphTimeStepCoefficients& c = {}, double nu_min = -1) {
  if (!(std::isfinite(h) && h > 0)) throw std::invalid_argument("sph: time-step length h must be > 0, got " + std::to_string(h));
  if (!(std::isfinite(c_max) && c_max > 0))
    throw std::invalid_argument("sph: sound speed must be > 0, got " + std::to_string(c_max));
  if (!(std::isfinite(nu_max) && nu_max >= 0))
    throw std::invalid_argument("sph: kinematic viscosity must be >= 0, got " + std::to_string(nu_max));
  if (!(std::isfinite(accel_max) && accel_max >= 0))
    throw std::invalid_argument("sph: acceleration must be finite and >= 0, got " + std::to_string(accel_max));
  if (!(c.viscous > 0 && c.acoustic > 0 && c.force > 0 && c.acoustic_viscous > 0))
    throw std::invalid_argument("sph: time-step coefficients must be > 0");
  if (nu_min < 0) nu_min = nu_max;
  if (!(std::isfinite(nu_min) && nu_min <= nu_max))
    throw std::invalid_argument("sph: smallest kinematic viscosity must be in [0, nu_max], got " + std::to_string(nu_min));
  SphTimeStepLimits l;
  if (nu_max > 0) l.viscous = c.viscous * h * h / nu_max;
  l.acoustic = c.acoustic * h / c_max;
  if (accel_max > 0) l.force = c.force * std::sqrt(h / accel_max);
  if (nu_min > 0) l.acoustic_viscous = c.acoustic_viscous * nu_min / (c_max * c_max);
  return l;
}

// max |f_i|/m_i over the moving (fluid) particles.
template <int D, class Real, class ExecSpace>
double max_fluid_acceleration(const Particles<D, Real, ExecSpace>& p) {
  const auto f = p.f;
  const auto m = p.mass;
  const auto type = p.type;
  double a2 = 0;
  mesoflow::launch::parallel_reduce(
      "mesoflow::sph::max_acceleration", Kokkos::RangePolicy<ExecSpace>(0, p.size()),
      KOKKOS_LAMBDA(int i, double& acc) {
        if (is_fixed(type(i))) return;
        double s = 0;
        for (int d = 0; d < D; ++d) s += double(f(i, d)) * double(f(i, d));
        s /= double(m(i)) * double(m(i));
        if (s > acc) acc = s;
      },
      Kokkos::Max<double>(a2));
  return std::sqrt(a2);
}

}  // namespace mesoflow::sph
