// at_minus_a_collision.hpp — MPC-AT−a, the cell-level Andersen thermostat: v_i* = v_C + v_i^ran −
// (1/N_C) Σ_j v_j^ran (Appendix B, eq. B.2 without its angular-momentum term; Noguchi & Gompper,
// PRE 78, 016706 (2008)). Conserves each cell's mass and momentum, not its angular momentum;
// thermostats at k_BT through v^ran (Maxwell–Boltzmann, drawn by MpcCollision).
//
// A collision rule for MpcCollision: per-cell sums {N, Σ v, Σ v^ran}; per-cell value
// v_C − ⟨v^ran⟩_C.
#pragma once

#include "kernels/common/kokkos_compat.hpp"

namespace mesoflow::mpc {

template <int D, class Real>
struct AtMinusACollision {
  static_assert(D == 2 || D == 3, "MPC-AT-a: 2D or 3D");
  static constexpr int num_sums = 1 + 2 * D;
  static constexpr int num_cell_values = D;
  static constexpr bool uses_random_velocity = true;
  static constexpr bool uses_position = false;

  KOKKOS_INLINE_FUNCTION void add(double* s, const Real (&)[D], const Real (&v)[D], const Real (&vran)[D]) const {
    s[0] += 1.0;
    for (int d = 0; d < D; ++d) {
      s[1 + d] += double(v[d]);
      s[1 + D + d] += double(vran[d]);
    }
  }

  KOKKOS_INLINE_FUNCTION void cell_values(int, const double* s, Real* c) const {
    const double inv_n = 1.0 / s[0];
    for (int d = 0; d < D; ++d) c[d] = Real((s[1 + d] - s[1 + D + d]) * inv_n);
  }

  KOKKOS_INLINE_FUNCTION void apply(const Real* c, const Real (&)[D], const Real (&vran)[D], Real (&v)[D]) const {
    for (int d = 0; d < D; ++d) v[d] = c[d] + vran[d];
  }
};

}  // namespace mesoflow::mpc
