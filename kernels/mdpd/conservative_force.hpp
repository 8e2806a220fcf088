// conservative_force.hpp — the MDPD conservative pair force, eq. (9a), and its potential.
//
//   F^C_ij = [A w_A(r) + B (ρ̄_i + ρ̄_j) w_B(r)] r̂_ij,   w_A = 1 − r/r_A,  w_B = 1 − r/r_B.
//
// With the normalized density weight (density_weight.hpp) this is −∇ of
//   U = Σ_{i<j} ½ A r_A w_A(r_ij)²  +  Σ_i ψ(ρ̄_i),   ψ(ρ) = B r_B ρ² / (4c),
// c the weight's prefactor: ∂ψ(ρ̄_i)/∂r_j = ψ'(ρ̄_i) w_ρ'(r) r̂ and w_ρ' = −2c w_B/r_B give exactly
// B(ρ̄_i + ρ̄_j) w_B once both ends of the pair are summed (Warren 2003, eq. 5).
#pragma once

#include "density_weight.hpp"
#include "mdpd_parameters.hpp"

namespace mesoflow::mdpd {

template <int D, class Real>
struct ConservativeForce {
  Real A, B, inv_rA, rB2, inv_rB;

  explicit ConservativeForce(const MdpdParameters& p)
      : A(Real(p.A)), B(Real(p.B)), inv_rA(Real(1 / p.r_A)), rB2(Real(p.r_B * p.r_B)), inv_rB(Real(1 / p.r_B)) {}

  // |F^C| along r̂_ij for a pair at distance r < r_A (r² = r2).
  KOKKOS_INLINE_FUNCTION Real magnitude(Real r, Real r2, Real rho_i, Real rho_j) const {
    Real f = A * (Real(1) - r * inv_rA);
    if (r2 < rB2) f += B * (rho_i + rho_j) * (Real(1) - r * inv_rB);
    return f;
  }
};

// The potential energy whose gradient is eq. (9a) (normalized density weight only): the pair part
// for one pair and the many-body part for one particle.
struct ConservativePotential {
  double A, r_A, psi_prefactor;

  template <int D>
  static ConservativePotential make(const MdpdParameters& p) {
    const DensityWeight<D, double> w(DensityKernel::normalized, p.r_B);
    return {p.A, p.r_A, p.B * p.r_B / (4.0 * w.prefactor)};
  }
  double pair(double r) const {
    if (r >= r_A) return 0.0;
    const double w = 1.0 - r / r_A;
    return 0.5 * A * r_A * w * w;
  }
  double many_body(double rho) const { return psi_prefactor * rho * rho; }
};

}  // namespace mesoflow::mdpd
