// continuity_density.hpp — the SPH continuity equation, eq. (4) (Monaghan, Annu. Rev. Astron.
// Astrophys. 30, 543 (1992)):
//
//   dρ_i/dt = Σ_j m_j u_ij · ∇_i W_ij,     u_ij = ū_i − ū_j,   ∇_i W_ij = (1/r dW/dr)(x_i − x_j),
//
// with the extrapolated velocities ū of eq. (13) (sph_integrator.hpp), as the paper prescribes for
// the density update.
//
// Sign: the paper prints eq. (4) with a leading minus, ρ̇_i = −Σ_j m_j u_ij ∂W_ij/∂x_i. Read with
// ∂W_ij/∂x_i = ∇_i W_ij that would thin a fluid under compression: two particles approaching each
// other (u_ij · (x_i − x_j) < 0, dW/dr < 0) must gain density, and only the plus sign does that, as
// eq. (1), Dρ/Dt = −ρ ∇·u, requires. We use the plus sign (Monaghan 1992; LAMMPS' `sph/taitwater`
// pair styles that the paper's DMP model runs on: drho[i] += m_j (v_ij · r_ij) (1/r dW/dr)).
// tests/sph/test_sph_kernels.cpp checks dρ/dt = −ρ0 ∇·u for a linear velocity field.
//
// The sum runs in the fused SPH pair loop (sph_pair_interactions.hpp) next to eq. (5), which needs
// the same pairs at the same time.
#pragma once

#include "kernels/common/vec.hpp"

namespace mesoflow::sph {

template <int D, class Real>
struct ContinuityDensity {
  // m_j u_ij · ∇_i W_ij for one pair: dW_over_r = (1/r) dW/dr at r = |dr|, dr = x_i − x_j.
  KOKKOS_INLINE_FUNCTION static Real rate(Real m_j, Real dW_over_r, const Vec<D, Real>& dr, const Vec<D, Real>& u_ij) {
    return m_j * dW_over_r * dot(u_ij, dr);
  }
};

}  // namespace mesoflow::sph
