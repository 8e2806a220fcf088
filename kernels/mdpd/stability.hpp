// stability.hpp — the explicit time-step limit of an MDPD fluid with tethered solid particles,
// term by term (paper §2.5.1, eqs. 8–10), in the form of kernels/common/stability_estimate.hpp:
// a summed stiffness mode ω and a friction rate ν, stable while ν Δt + (ω Δt)²/2 < 2.
//
// Stiffness. The pair force of eq. (9a) along r̂ is F(r) = A w_A(r) + B(ρ̄_i + ρ̄_j) w_B(r), so a
// pair at distance r has the radial stiffness k(r) = −dF/dr = A/r_A + 2Bρ̄/r_B + B w_B |∂(ρ̄_i+ρ̄_j)/∂r|,
// the last term from the many-body density (density_weight.hpp, normalized: ∂ρ̄/∂r = −2c(1−r/r_B)/r_B
// with c = 6/(π r_B²) in 2D, 15/(2π r_B³) in 3D, so the term is 4Bc(1−r/r_B)²/r_B). The Hessian's
// diagonal for one particle in a fluid of density ρ is ρ ∫ k(r) cos²θ dⁿr, and by Gershgorin the
// largest eigenvalue is at most twice the diagonal, so ω² = 2 ρ ∫ k cos² dⁿr / m, with
//   2D: ρ∫ = π [A ρ r_A/2 + Bρ² r_B] + 2Bρ/r_B,    3D: ρ∫ = 4π/9 [A ρ r_A² + 2Bρ² r_B²] + 4Bρ/(3 r_B)
// (A < 0, the attraction, softens the mode and is kept with its sign). The paper's fluids
// (ρ = 6, A = −40, r_B = 0.75): 2D B = 30 gives ω = 72.8/τ, 3D B = 25 gives ω = 51.9/τ. The Lucy
// density kernel is estimated with the same formula (its weight is normalised to one too).
// Tethers (§2.5.1): a solid particle also feels −k_S(x − s), ω² = k_S/m (12.5/τ² at the paper's k_S).
// Core WCA (§2.5.1, mdpd_pair_force.hpp): a fluid particle that reaches a solid core meets a WCA
// wall, ε = k_BT, σ = r_A; its stiffness at the thermal closest approach (U = 4.6 k_BT, r = 0.927σ,
// kernels/common/lennard_jones_stability.hpp) gives a pair mode ω = 54.5/τ.
// Friction. The dissipative force of eq. (9b) sees the predicted velocity v + ½Δt a
// (mdpd_system.hpp); its rate per particle is ν = D ρ ∫ w_D cos² dⁿr with w_D = (1 − r/r_A)²:
//   2D: ν = π D ρ r_A²/12 = 113.1/τ,   3D: ν = 2π D ρ r_A³/45 = 60.3/τ   (D = R²/(2k_BT) = 72)
// as docs/mdpd.md computes. In 2D the friction uses most of the budget: the edge is Δt = 0.01345τ
// (ν Δt = 1.52), against 0.0275τ for the stiffness alone.
// Safety. Measured in the paper's 2D fluid (tests/stability/test_stability_limits.cpp and the
// pillars driver's viscosity mode, 384–512 particles): it blows up from a random start at
// 0.01305τ = 0.97 × the edge and runs 19% hot at 0.0125τ (0.93 ×), 4.1% hot at 0.0115τ (0.855 ×),
// 1.4% at 0.0105τ. The estimate keeps 0.85 of the edge, where the temperature is within 5%:
// 2D Δt ≤ 0.01143τ without solids, 0.01039τ with tethers and cores (the pillars flow mode); 3D
// 0.0189τ and 0.0153τ. The paper's Δt = 0.01τ is inside all four.
#pragma once

#include "kernels/common/lennard_jones_stability.hpp"
#include "kernels/common/stability_estimate.hpp"

#include <algorithm>
#include <cmath>

namespace mesoflow::mdpd {

constexpr double mdpd_safety = 0.85;  // fraction of the stability edge (see the file comment)

struct MdpdStiffnessInputs {
  int dimension = 3;
  double density = 6;        // ρ, particles per σ^D
  double A = -40, B = 25;    // eq. (9a)
  double r_A = 1, r_B = 0.75;
  double dissipation = 72;   // D of eq. (10)
  double mass = 1;
  double tether_stiffness = 0;  // k_S (0: no tethered particles)
  double kT = 1;
  double core_wca_epsilon = 0;  // ε of the fluid–core WCA (0: no solid cores), σ = r_A
};

inline StabilityEstimate mdpd_stability(const MdpdStiffnessInputs& s) {
  constexpr double pi = 3.14159265358979323846;
  const double rho = s.density;
  double diagonal = 0, nu = 0;
  if (s.dimension == 2) {
    diagonal = pi * (s.A * rho * s.r_A / 2 + s.B * rho * rho * s.r_B) + 2 * s.B * rho / s.r_B;
    nu = pi * s.dissipation * rho * s.r_A * s.r_A / 12;
  } else {
    diagonal = 4 * pi / 9 * (s.A * rho * s.r_A * s.r_A + 2 * s.B * rho * rho * s.r_B * s.r_B) + 4 * s.B * rho / (3 * s.r_B);
    nu = 2 * pi * s.dissipation * rho * s.r_A * s.r_A * s.r_A / 45;
  }
  StabilityEstimate e;
  e.set_safety(mdpd_safety);
  e.add_mode("conservative repulsion B with attraction A", std::sqrt(std::max(0.0, 2 * diagonal / s.mass)));
  e.add_mode("tether springs k_S", std::sqrt(s.tether_stiffness / s.mass));
  if (s.core_wca_epsilon > 0) {
    const auto c = lennard_jones_contact(s.core_wca_epsilon, s.r_A, s.kT, s.core_wca_epsilon);
    e.add_mode(lennard_jones_term("fluid-core WCA", c, s.r_A), std::sqrt(2 * c.stiffness / s.mass));
  }
  e.add_rate("dissipation D", nu / s.mass);
  return e;
}

}  // namespace mesoflow::mdpd
