// pair_repulsion.hpp — purely repulsive soft-sphere contact between soft particles of different
// sizes (hopper study, eq. 2), an evaluator for the generic pair loop (kernels/common/pair_force.hpp):
//   U_mn = (ε_sp/2)(1 − r_mn/σ_mn)² Θ(1 − r_mn/σ_mn),   σ_mn = (σ_m + σ_n)/2,
// with the diameter σ_m taken from the particle's type (bidisperse packings: two types). The force
// on m, −∂U/∂r_m = (ε_sp/(σ_mn r))(1 − r/σ_mn)(r_m − r_n), vanishes continuously at contact. The
// neighbor list's cutoff must be at least the largest σ_mn.
#pragma once

#include "kernels/common/kokkos_compat.hpp"

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace mesoflow::sp {

template <class Real>
struct SoftSphereRepulsion {
  static constexpr int max_types = 4;
  Real epsilon;                   // ε_sp
  Real contact[max_types][max_types];  // σ_mn by type pair
  int num_types;

  // `diameters`: σ of each particle type (at most max_types), each finite and > 0; ε_sp ≥ 0.
  SoftSphereRepulsion(Real epsilon_sp, const std::vector<double>& diameters) : epsilon(epsilon_sp) {
    if (!(epsilon_sp >= Real(0)) || !std::isfinite(double(epsilon_sp)))
      throw std::invalid_argument("soft_sphere_repulsion: epsilon_sp must be finite and >= 0, got " +
                                  std::to_string(double(epsilon_sp)));
    if (diameters.empty() || int(diameters.size()) > max_types)
      throw std::invalid_argument("soft_sphere_repulsion: between 1 and " + std::to_string(max_types) +
                                  " particle types, got " + std::to_string(diameters.size()));
    for (double s : diameters)
      if (!(s > 0) || !std::isfinite(s))
        throw std::invalid_argument("soft_sphere_repulsion: diameters must be finite and > 0, got " + std::to_string(s));
    num_types = int(diameters.size());
    for (int a = 0; a < max_types; ++a)
      for (int b = 0; b < max_types; ++b)
        contact[a][b] = a < num_types && b < num_types ? Real(0.5 * (diameters[a] + diameters[b])) : Real(0);
  }

  // Largest σ_mn: the neighbor-list cutoff this evaluator needs.
  Real cutoff() const {
    Real c = 0;
    for (int a = 0; a < num_types; ++a)
      for (int b = 0; b < num_types; ++b) c = contact[a][b] > c ? contact[a][b] : c;
    return c;
  }

  KOKKOS_INLINE_FUNCTION bool evaluate(Real r2, int ti, int tj, Real& force_over_r, Real& energy) const {
    const Real s = contact[ti][tj];
    if (!(r2 < s * s) || r2 == Real(0)) return false;
    const Real r = kmath::sqrt(r2);
    const Real overlap = Real(1) - r / s;
    force_over_r = epsilon * overlap / (s * r);
    energy = Real(0.5) * epsilon * overlap * overlap;
    return true;
  }
};

}  // namespace mesoflow::sp
