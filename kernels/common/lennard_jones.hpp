// lennard_jones.hpp — truncated and shifted Lennard-Jones pair evaluator (one type pair),
//   U(r) = 4ε[(σ/r)^12 − (σ/r)^6] − U_shift  for r < r_c,
// U_shift = 4ε[(σ/r_c)^12 − (σ/r_c)^6] so U(r_c) = 0. With r_c = 2^{1/6}σ it is the purely repulsive
// WCA potential used for disc–disc and disc–wall contacts in the MPC study (eq. B.4) and for
// fluid–solid repulsion in the MDPD study.
#pragma once

#include "kokkos_compat.hpp"

#include <stdexcept>
#include <string>

namespace mesoflow {

template <class Real>
struct LennardJones {
  Real epsilon, sigma2, cutoff2, energy_shift;

  LennardJones(Real epsilon_, Real sigma, Real cutoff) {
    if (!(epsilon_ >= Real(0))) throw std::invalid_argument("lennard_jones: epsilon must be >= 0");
    if (!(sigma > Real(0))) throw std::invalid_argument("lennard_jones: sigma must be > 0");
    if (!(cutoff > Real(0))) throw std::invalid_argument("lennard_jones: cutoff must be > 0");
    epsilon = epsilon_;
    sigma2 = sigma * sigma;
    cutoff2 = cutoff * cutoff;
    const Real s6 = sigma2 * sigma2 * sigma2 / (cutoff2 * cutoff2 * cutoff2);
    energy_shift = Real(4) * epsilon * (s6 * s6 - s6);
  }

  // The WCA potential: cut at the minimum 2^{1/6}σ and shifted by ε.
  static LennardJones wca(Real epsilon_, Real sigma) {
    return LennardJones(epsilon_, sigma, sigma * Real(1.122462048309373));
  }

  KOKKOS_INLINE_FUNCTION bool evaluate(Real r2, int, int, Real& force_over_r, Real& energy) const {
    if (r2 >= cutoff2) return false;
    const Real inv_r2 = Real(1) / r2;
    const Real s6 = sigma2 * sigma2 * sigma2 * inv_r2 * inv_r2 * inv_r2;
    force_over_r = Real(24) * epsilon * inv_r2 * (Real(2) * s6 * s6 - s6);
    energy = Real(4) * epsilon * (s6 * s6 - s6) - energy_shift;
    return true;
  }
};

}  // namespace mesoflow
