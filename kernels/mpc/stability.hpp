// stability.hpp — the time-step limit of the MPC channel with rigid discs (Appendix B), term by term
// (the form of kernels/common/stability_estimate.hpp).
//
// The MPC solvent alone has no explicit stability limit: streaming is exact and every collision
// rule (at_plus_a_collision.hpp, srd_collision.hpp) conserves momentum and, for AT+a, thermalises,
// at any h. The limits come from the discs (rigid_discs.hpp, disc_wca.hpp):
//   WCA contacts (eq. B.4): the disc update X ← X + hU, U ← U + hF/M is symplectic Euler, stable for
//     a harmonic mode while ω h < 2; the estimate asks ω h ≤ 1. The stiffness V''(r) =
//     4ε(156 s¹² − 42 s⁶)/r², s = r0/r, is taken at the closest approach the forces allow: the
//     smaller of r_F, where the WCA force equals M|g| (the pressure gradient ρg of the driven solvent
//     on a disc of area πR² — the force that presses a disc against its neighbour or a wall), and
//     r_E, where V = 10 k_BT (a thermal collision reaches it with probability ~e⁻¹⁰). A disc between
//     two neighbours and a wall has ω² ≤ (4 + 1) V''/M (the highest mode of a chain, 4k/M, plus the
//     wall). The paper's scene (R = 5, n = 40, g = 0.1, ε = k_BT, r0 = Δx): M = 3142, r_F = 0.851 r0,
//     V'' = 5.3·10³ ε/r0², ω = 2.9/τ, so h ≤ 0.34τ against the paper's 0.005τ.
//   Plate friction −γU: integrated implicitly (backward Euler, rigid_discs.hpp), stable at any γh/M;
//     it sets no limit (γh/M = 0.03 in the paper).
//   Solvent coupling: bounce-back (disc_bounce_back.hpp) finds the solvent particles that streamed
//     into a disc; one that crosses the whole disc in a step is missed. Solvent speeds beyond 4√(k_BT/m)
//     are rare (e⁻⁸), so h·4√(k_BT/m) ≤ R bounds the step (h ≤ 1.25τ at R = 5). The virtual-particle
//     collisions conserve momentum and set no limit.
// tests/stability/test_stability_limits.cpp runs discs just below the limit (bounded) and the
// crystal driver refuses an h above it (CrystalCli.TimeStepAboveStabilityLimit).
#pragma once

#include "kernels/common/stability_estimate.hpp"

#include <cmath>

namespace mesoflow::mpc {

struct DiscStiffnessInputs {
  double cell_size = 1;          // Δx
  double density = 40;           // n, solvent particles per cell
  double mass = 1;               // m
  double kT = 1;
  double disc_radius = 5;        // R
  double body_acceleration = 0.1;  // g on the solvent
  double wca_epsilon = 1, wca_r0 = 1;  // eq. (B.4)
  bool discs = true;             // false: solvent only, no limit
};

namespace stability_detail {
// The WCA surface separation in (0, 2^{1/6} r0] where f (the energy or the force, both decreasing
// there) equals target, by bisection; 2^{1/6} r0 when f is already >= target at the cutoff.
template <class F>
double separation_where(F f, double target, double r0) {
  double lo = 1e-3 * r0, hi = std::pow(2.0, 1.0 / 6.0) * r0;
  if (f(hi) >= target) return hi;
  for (int k = 0; k < 200; ++k) {
    const double mid = 0.5 * (lo + hi);
    (f(mid) > target ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}
}  // namespace stability_detail

constexpr double thermal_approach_energy = 10;  // V(r_E) = 10 k_BT (see the file comment)
constexpr double solvent_speed_factor = 4;      // 4 √(k_BT/m)

inline double disc_mass(const DiscStiffnessInputs& s) {
  constexpr double pi = 3.14159265358979323846;
  return s.density * s.mass * pi * s.disc_radius * s.disc_radius / (s.cell_size * s.cell_size);
}

// The closest WCA surface separation the step limit assumes: the smaller of the separations where
// the force equals the driving force on a disc, M g, and where the energy reaches 10 k_BT. Discs
// placed closer than this (to each other or to a wall) start stiffer than the limit allows; the
// channel flow refuses such a start (check_disc_centres).
inline double disc_closest_approach(const DiscStiffnessInputs& s) {
  const double eps = s.wca_epsilon, r0 = s.wca_r0, M = disc_mass(s);
  const auto energy = [&](double r) {
    const double s6 = std::pow(r0 / r, 6);
    return 4 * eps * (s6 * s6 - s6) + eps;
  };
  const auto force = [&](double r) {
    const double s6 = std::pow(r0 / r, 6);
    return 24 * eps * (2 * s6 * s6 - s6) / r;
  };
  const double r_force = stability_detail::separation_where(force, M * std::abs(s.body_acceleration), r0);
  const double r_thermal = stability_detail::separation_where(energy, thermal_approach_energy * s.kT, r0);
  return std::min(r_force, r_thermal);
}

inline StabilityEstimate disc_stability(const DiscStiffnessInputs& s) {
  StabilityEstimate e;
  if (!s.discs) return e;
  const double eps = s.wca_epsilon, r0 = s.wca_r0, M = disc_mass(s);
  const double r = disc_closest_approach(s);
  const double s6 = std::pow(r0 / r, 6);
  const double stiffness = eps > 0 ? 4 * eps * (156 * s6 * s6 - 42 * s6) / (r * r) : 0.0;
  e.add_mode("disc WCA contacts ε, r0", std::sqrt(5 * stiffness / M));
  e.add_bound("solvent crossing a disc (h·4√(k_BT/m) ≤ R)",
              s.disc_radius / (solvent_speed_factor * std::sqrt(s.kT / s.mass)));
  return e;
}

}  // namespace mesoflow::mpc
