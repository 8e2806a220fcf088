// density_weight.hpp — the weight functions of the MDPD many-body density
//   ρ̄_i = s + Σ_{j≠i} w_ρ(r_ij),   s = w_ρ(0) with the self term, 0 without (the default).
//
// normalized (the paper, §2.5.1, after Warren, Phys. Rev. E 68, 066702 (2003)):
//   3D  w_ρ(r) = 15/(2π r_B³) (1 − r/r_B)²,   2D  w_ρ(r) = 6/(π r_B²) (1 − r/r_B)².
//   Both integrate to one over space. The force B(ρ̄_i + ρ̄_j) w_B r̂ of eq. (9a) is then exactly
//   −∇ of Σ_i ψ(ρ̄_i) with ψ(ρ) = B r_B ρ²/(4c), c the prefactor above (ψ = πB r_B⁴ρ²/30 in 3D,
//   conservative_force.hpp), which the gradient test checks (a constant self term keeps it so).
// lucy (LAMMPS' `pair_style mdpd/rhosum`, Li et al., J. Comput. Phys. 355, 534 (2018)):
//   3D  w_ρ(r) = 105/(16π h³) (1 + 3r/h)(1 − r/h)³,   2D  w_ρ(r) = 5/(π h²) (1 + 3r/h)(1 − r/h)³,
//   h = r_B (LAMMPS: the `pair_coeff … mdpd/rhosum h`). With this weight eq. (9a) is not the
//   gradient of a potential (LAMMPS' convention); it is there to cross-check against LAMMPS.
//
// The self term (DensitySelfTerm, the driver's --density-self-term) is an explicit choice, off by
// default for both weights. LAMMPS has none: src/DPD-MESO/pair_mdpd_rhosum.cpp,
// PairMDPDRhoSum::compute(), read in LAMMPS 29 Sep 2021 update 2 (Debian 12's source package
// lammps 20220106.git7586adbb6a+ds1-2) and in lammps/lammps on GitHub (commit 2279b28), sets
//     // initialize density with zero self-contribution,
//     rho[i] = 0;
// and then adds mass[jtype]*wf over its full neighbor list (j ≠ i) only; pair_mdpd.cpp reads
// rho[i] as it is and fix mvv/dpd never touches it. `on` adds w_ρ(0) (105/(16π h³) for lucy in
// 3D), the convention of some SPH-style MDPD codes; docs/mdpd.md compares both with LAMMPS.
#pragma once

#include "kernels/common/kokkos_compat.hpp"

#include <stdexcept>
#include <string>

namespace mesoflow::mdpd {

enum class DensityKernel { normalized, lucy };
// Whether ρ̄_i includes particle i's own weight w_ρ(0). `off` is LAMMPS' mdpd/rhosum.
enum class DensitySelfTerm { off, on };

inline DensityKernel parse_density_kernel(const std::string& s) {
  if (s == "normalized") return DensityKernel::normalized;
  if (s == "lucy") return DensityKernel::lucy;
  throw std::invalid_argument("mdpd: density kernel must be 'normalized' or 'lucy', got '" + s + "'");
}

inline DensitySelfTerm parse_density_self_term(const std::string& s) {
  if (s == "off") return DensitySelfTerm::off;
  if (s == "on") return DensitySelfTerm::on;
  throw std::invalid_argument("mdpd: density self term must be 'off' (LAMMPS' mdpd/rhosum) or 'on', got '" + s +
                              "'");
}

inline const char* to_string(DensitySelfTerm s) { return s == DensitySelfTerm::on ? "on" : "off"; }

template <int D, class Real>
struct DensityWeight {
  DensityKernel kernel;
  Real h, inv_h, h2, prefactor, self;

  DensityWeight(DensityKernel kernel_, Real r_B, DensitySelfTerm self_term = DensitySelfTerm::off)
      : kernel(kernel_), h(r_B), inv_h(Real(1) / r_B), h2(r_B * r_B) {
    constexpr double pi = 3.14159265358979323846;
    const double hd = D == 2 ? double(r_B) * r_B : double(r_B) * r_B * r_B;
    if (kernel == DensityKernel::normalized)
      prefactor = Real((D == 2 ? 6.0 / pi : 15.0 / (2.0 * pi)) / hd);
    else
      prefactor = Real((D == 2 ? 5.0 / pi : 105.0 / (16.0 * pi)) / hd);
    self = self_term == DensitySelfTerm::on ? prefactor : Real(0);  // w_ρ(0) = prefactor for both weights
  }

  // w_ρ(r) for r² < h² (callers test the range).
  KOKKOS_INLINE_FUNCTION Real operator()(Real r) const {
    const Real s = Real(1) - r * inv_h;
    if (kernel == DensityKernel::normalized) return prefactor * s * s;
    return prefactor * (Real(1) + Real(3) * r * inv_h) * s * s * s;
  }

  // dw_ρ/dr (for the gradient test and the potential).
  KOKKOS_INLINE_FUNCTION Real derivative(Real r) const {
    const Real s = Real(1) - r * inv_h;
    if (kernel == DensityKernel::normalized) return -Real(2) * prefactor * s * inv_h;
    return -Real(12) * prefactor * r * inv_h * inv_h * s * s;
  }
};

}  // namespace mesoflow::mdpd
