// lennard_jones_stability.hpp — the explicit time-step limit of Lennard-Jones contacts
// (lennard_jones.hpp: the full potential of the LJ fluid and its WCA truncation) under velocity
// Verlet, with an optional Langevin thermostat (langevin.hpp); the form of stability_estimate.hpp
// (ω Δt ≤ 1, ν Δt ≤ 2).
//
// Contacts: U(r) = 4ε[(σ/r)¹² − (σ/r)⁶] (+ ε for WCA) has the radial stiffness
// U''(r) = 4ε[156 σ¹²/r¹⁴ − 42 σ⁶/r⁸], steep on the repulsive branch, so the estimate needs the
// closest approach. A pair meets at relative kinetic energies of order k_BT; take the approach
// where the energy reaches lj_contact_energy_in_kT = 4.6 k_BT (a colliding pair's radial energy
// exceeds it with probability e^-4.6 = 1%). In the LJ liquid at LAMMPS' bench/in.lj state
// (ρσ³ = 0.8442, k_BT = 1.44ε) that is r = 0.90σ, U = 6.6ε, about where the liquid's g(r) starts.
// There U'' = 2.34·10³ ε/σ² and a pair (reduced mass m/2) vibrates at ω² = 2U''/m, ω = 68.4/τ:
// Δt ≤ 0.0146τ, three times the customary 0.005τ.
// Thermostat: the Langevin friction −γ m v is explicit, ν = γ.
// tests/stability/test_stability_limits.cpp runs an NVE fluid at 0.9 × the limit (bounded energy
// drift) and at 2.7 × (0.04τ), where the energy runs away.
#pragma once

#include "kernels/common/stability_estimate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace mesoflow {

constexpr double lj_contact_energy_in_kT = 4.6;

struct LennardJonesContact {
  double distance;   // closest approach r
  double stiffness;  // U''(r)
};

// The closest approach of a pair at temperature kT (U(r) = 4.6 k_BT, U shifted up by `shift`: 0 for
// the full LJ potential, ε for WCA) and the stiffness there.
inline LennardJonesContact lennard_jones_contact(double epsilon, double sigma, double kT, double shift = 0) {
  const auto energy = [&](double r) {
    const double s6 = std::pow(sigma / r, 6);
    return 4 * epsilon * (s6 * s6 - s6) + shift;
  };
  double lo = 0.3 * sigma, hi = std::pow(2.0, 1.0 / 6.0) * sigma;  // U decreases on (0, 2^{1/6}σ)
  const double target = lj_contact_energy_in_kT * kT;
  for (int k = 0; k < 200; ++k) {
    const double mid = 0.5 * (lo + hi);
    (energy(mid) > target ? lo : hi) = mid;
  }
  const double r = 0.5 * (lo + hi), s6 = std::pow(sigma / r, 6);
  return {r, 4 * epsilon * (156 * s6 * s6 - 42 * s6) / (r * r)};
}

// A name for the contact term: "Lennard-Jones contacts ε/σ² at r = 0.900σ".
inline std::string lennard_jones_term(const char* what, const LennardJonesContact& c, double sigma) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%s contacts ε/σ² at r = %.3fσ", what, c.distance / sigma);
  return buf;
}

inline StabilityEstimate lennard_jones_stability(double epsilon, double sigma, double mass, double kT, double gamma) {
  const auto c = lennard_jones_contact(epsilon, sigma, kT);
  StabilityEstimate e;
  e.add_mode(lennard_jones_term("Lennard-Jones", c, sigma), std::sqrt(2 * c.stiffness / mass));
  e.add_rate("Langevin friction γ", gamma);
  return e;
}

}  // namespace mesoflow
