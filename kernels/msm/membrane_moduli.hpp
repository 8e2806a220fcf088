// membrane_moduli.hpp — the elastic moduli of the capsule's mass-spring membrane (capsule paper §4,
// eq. 7's network): the surface shear modulus G_s = E h_t/(2(1 + ν)) with Young's modulus
// E = 5 k_b/(√3 δ_ave) of the spring network and ν = 1/4, as §4 quotes them (capsule_mesh.hpp shows
// that the paper's bond counts give 0.84 E and ν = 1/3; the crossed network, DiagonalBonds::both,
// gives the quoted values exactly at h_t = δ_ave). The capillary number is Ca = μ U a/G_s.
// Host- and device-callable; δ_ave is the mean in-layer bond length, h_t the membrane thickness.
#pragma once

#include "kernels/common/kokkos_compat.hpp"

#include <cmath>

namespace mesoflow::msm {

constexpr double membrane_poisson_ratio = 0.25;  // ν of §4

// G_s from the bond stiffness k_b.
KOKKOS_INLINE_FUNCTION double surface_shear_modulus(double k_b, double bond_length, double thickness) {
  const double E = 5 * k_b / (kmath::sqrt(3.0) * bond_length);
  return E * thickness / (2 * (1 + membrane_poisson_ratio));
}

// The bond stiffness k_b that gives the surface shear modulus G_s (the inverse of the above).
KOKKOS_INLINE_FUNCTION double bond_stiffness_for_shear_modulus(double G_s, double bond_length, double thickness) {
  return G_s * 2 * (1 + membrane_poisson_ratio) * kmath::sqrt(3.0) * bond_length / (5 * thickness);
}

}  // namespace mesoflow::msm
