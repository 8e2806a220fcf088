// pressure_viscous_force.hpp — the SPH momentum equation, eq. (5): the force on particle i
//
//   f_i = − Σ_j m_i m_j (p_i/ρ_i² + p_j/ρ_j²) ∇_i W_ij                        pressure gradient
//         + Σ_j m_i m_j (μ_i + μ_j)/(ρ_i ρ_j) (1/r_ij ∂W_ij/∂r_ij) u_ij        laminar viscosity
//         + m_i F                                                             body force
//
// with u_ij = ū_i − ū_j (the extrapolated velocities of eq. 13), p from eq. (6) and μ the dynamic
// viscosity of each particle.
//
// The viscous term is Morris, Fox & Zhu's (1997) laminar viscosity, which the paper names:
// (μ_i + μ_j)/(ρ_i ρ_j) · (r_ij·∇_i W_ij)/r_ij² · u_ij. The paper prints it as "u_ij ∂W_ij/∂x_i",
// a vector times a vector; the scalar meant is (r_ij·∇_i W_ij)/r_ij² = (1/r) dW/dr, as in Morris
// et al. and in LAMMPS' `sph/taitwater/morris` pair style used by the paper's DMP model. Morris'
// regularisation r_ij² + 0.01h² is not needed: the kernels give (1/r) dW/dr in closed form, finite
// at r = 0 (smoothing_kernels.hpp), and it would lower the viscosity by a few per cent at the
// nearest-neighbour distance of a Lucy kernel.
//
// F is the volumetric body force of eq. (2), a force per unit mass (acceleration); it acts on fluid
// particles only, outer and inner (walls do not move; membrane particles are carried by the fluid:
// the paper accelerates the fluid particles, §4; particle_types.hpp).
//
// Both pair terms are antisymmetric in (i, j) — a symmetric coefficient times r_ij or u_ij — so
// the pair forces conserve momentum; the evaluator returns f_ij/m_i and the loop multiplies by m_i
// once per particle.
#pragma once

#include "kernels/common/vec.hpp"
#include "particle_types.hpp"

namespace mesoflow::sph {

template <int D, class Real>
struct PressureViscousForce {
  // f_ij/m_i for one pair: dW_over_r = (1/r) dW/dr at r = |dr|, dr = x_i − x_j, u_ij = ū_i − ū_j,
  // p_rho2 = p/ρ², inv_rho = 1/ρ.
  KOKKOS_INLINE_FUNCTION static Vec<D, Real> pair(Real m_j, Real p_rho2_i, Real p_rho2_j, Real mu_i, Real mu_j,
                                                  Real inv_rho_i, Real inv_rho_j, Real dW_over_r,
                                                  const Vec<D, Real>& dr, const Vec<D, Real>& u_ij) {
    const Real pressure = -m_j * (p_rho2_i + p_rho2_j) * dW_over_r;
    const Real viscous = m_j * (mu_i + mu_j) * (inv_rho_i * inv_rho_j) * dW_over_r;
    Vec<D, Real> f;
    for (int d = 0; d < D; ++d) f[d] = pressure * dr[d] + viscous * u_ij[d];
    return f;
  }
};

// The body force F of eq. (5), per unit mass, on fluid particles (outer and inner).
template <int D, class Real>
struct BodyForce {
  Real g[D] = {};

  bool active() const {
    for (int d = 0; d < D; ++d)
      if (g[d] != Real(0)) return true;
    return false;
  }
  // F on a particle of this type (zero on walls and membrane particles).
  KOKKOS_INLINE_FUNCTION Real component(int type, int d) const {
    return (type == particle_type::fluid || type == particle_type::inner_fluid) ? g[d] : Real(0);
  }
};

}  // namespace mesoflow::sph
