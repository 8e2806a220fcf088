// mdpd_parameters.hpp — the parameters of a many-body DPD (MDPD) fluid, validated once on the host.
//
// Hulikal Chakrapani et al., Soft Matter 19, 436 (2023), §2.5.1, eqs. (8)–(10): every pair within
// r_A interacts through
//   F^C_ij = A w_A(r) r̂ + B (ρ̄_i + ρ̄_j) w_B(r) r̂                     (9a)
//   F^D_ij = −D w_D(r) (v_ij·r̂) r̂,     w_D = w_R²                    (9b)
//   F^R_ij = R w_R(r) θ_ij/√dt r̂,       w_R = w_A = 1 − r/r_A          (9c)
//   2 k_BT D = R²                                                      (10)
// with w_B = 1 − r/r_B and the many-body density ρ̄_i = Σ_{j≠i} w_ρ(r_ij) (density_weight.hpp; plus
// w_ρ(0) only with density_self_term = on, which LAMMPS' mdpd/rhosum does not add).
// Units: r_A = σ (length), m (mass), k_BT = ε (energy), τ = σ√(m/ε). The paper's fluid:
// ρ = 6σ^-3, A = −40ε/σ, B = 25εσ², r_B = 0.75σ, R = 12 ετ^½/σ (so D = 72 ετ/σ²), dt = 0.01τ;
// in 2D ρ = 6σ^-2 and B = 30εσ.
#pragma once

#include "density_weight.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace mesoflow::mdpd {

struct MdpdParameters {
  double A = -40.0;          // attraction strength (negative: attractive)
  double B = 25.0;           // density-dependent repulsion strength
  double r_A = 1.0;          // cut-off of w_A, w_D, w_R (the unit of length)
  double r_B = 0.75;         // cut-off of w_B and of the density weight
  double R = 12.0;           // random-force strength; D follows from eq. (10)
  double kT = 1.0;           // thermal energy
  double dt = 0.01;          // time step
  DensityKernel density_kernel = DensityKernel::normalized;
  DensitySelfTerm density_self_term = DensitySelfTerm::off;  // off: LAMMPS' mdpd/rhosum

  double dissipation() const { return R * R / (2.0 * kT); }  // D of eq. (10)

  // Throws std::invalid_argument naming the parameter and its allowed range.
  void validate() const {
    auto fail = [](const std::string& what) { throw std::invalid_argument("mdpd: " + what); };
    auto finite = [](double v) { return std::isfinite(v); };
    if (!finite(A)) fail("A must be finite, got " + std::to_string(A));
    if (!(finite(B) && B >= 0)) fail("B must be >= 0, got " + std::to_string(B));
    if (!(finite(r_A) && r_A > 0)) fail("r_A must be > 0, got " + std::to_string(r_A));
    if (!(finite(r_B) && r_B > 0 && r_B <= r_A))
      fail("r_B must be in (0, r_A = " + std::to_string(r_A) + "], got " + std::to_string(r_B));
    if (!(finite(R) && R >= 0)) fail("R must be >= 0, got " + std::to_string(R));
    if (!(finite(kT) && kT > 0)) fail("kT must be > 0, got " + std::to_string(kT));
    if (!(finite(dt) && dt > 0)) fail("dt must be > 0, got " + std::to_string(dt));
  }
};

}  // namespace mesoflow::mdpd
