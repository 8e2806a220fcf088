// srd_collision.hpp — stochastic rotation dynamics, v_i* = v_C + R(α)(v_i − v_C) (Malevanets &
// Kapral 1999; Gompper et al., Adv. Polym. Sci. 221 (2009) eq. 9). Conserves each cell's mass,
// momentum and kinetic energy; no thermostat.
//
// A collision rule for MpcCollision (see mpc_collision.hpp for the interface): per-cell sums are
// {N, Σ v}; per-cell values are {v_C, rotation}, the rotation being ±sin α (2D, the sign drawn per
// cell) or a unit axis n uniform on the sphere (3D), both from cell_stream(seed, step, cell).
#pragma once

#include "kernels/common/kokkos_compat.hpp"
#include "kernels/common/random.hpp"

#include <cmath>
#include <cstdint>

namespace mesoflow::mpc {

template <int D, class Real>
struct SrdCollision {
  static_assert(D == 2 || D == 3, "SRD: 2D or 3D");
  static constexpr int num_sums = 1 + D;
  static constexpr int num_cell_values = D == 2 ? D + 1 : 2 * D;
  static constexpr bool uses_random_velocity = false;
  static constexpr bool uses_position = false;

  Real cos_angle, sin_angle;
  std::uint64_t seed, step;

  SrdCollision(Real angle, std::uint64_t seed_, std::uint64_t step_)
      : cos_angle(Real(std::cos(double(angle)))), sin_angle(Real(std::sin(double(angle)))), seed(seed_), step(step_) {}

  KOKKOS_INLINE_FUNCTION void add(double* s, const Real (&)[D], const Real (&v)[D], const Real (&)[D]) const {
    s[0] += 1.0;
    for (int d = 0; d < D; ++d) s[1 + d] += double(v[d]);
  }

  KOKKOS_INLINE_FUNCTION void cell_values(int cell, const double* s, Real* c) const {
    const double inv_n = 1.0 / s[0];
    for (int d = 0; d < D; ++d) c[d] = Real(s[1 + d] * inv_n);
    RandomStream rs = cell_stream(seed, step, static_cast<std::uint32_t>(cell));
    if constexpr (D == 2) {
      c[2] = (rs.next_u32() & 1u) ? sin_angle : -sin_angle;
    } else {
      // Uniform on the sphere without trigonometric functions (Marsaglia, Ann. Math. Stat. 43, 645
      // (1972)): (u, w) uniform in the unit disc, s = u² + w², n = (2u√(1−s), 2w√(1−s), 1 − 2s).
      Real u, w, s2;
      do {
        u = rs.uniform_symmetric<Real>();
        w = rs.uniform_symmetric<Real>();
        s2 = u * u + w * w;
      } while (s2 >= Real(1));
      const Real root = Real(2) * kmath::sqrt(Real(1) - s2);
      c[3] = u * root;
      c[4] = w * root;
      c[5] = Real(1) - Real(2) * s2;
    }
  }

  // 2D: rotation by ±α. 3D: Rodrigues' formula, R d = cos α d + (1 − cos α)(n·d) n + sin α n × d.
  KOKKOS_INLINE_FUNCTION void apply(const Real* c, const Real (&)[D], const Real (&)[D], Real (&v)[D]) const {
    Real dv[D];
    for (int d = 0; d < D; ++d) dv[d] = v[d] - c[d];
    if constexpr (D == 2) {
      const Real s = c[2];
      v[0] = c[0] + (cos_angle * dv[0] - s * dv[1]);
      v[1] = c[1] + (s * dv[0] + cos_angle * dv[1]);
    } else {
      const Real nx = c[3], ny = c[4], nz = c[5];
      const Real along = (Real(1) - cos_angle) * (nx * dv[0] + ny * dv[1] + nz * dv[2]);
      const Real cx = ny * dv[2] - nz * dv[1];
      const Real cy = nz * dv[0] - nx * dv[2];
      const Real cz = nx * dv[1] - ny * dv[0];
      v[0] = c[0] + (cos_angle * dv[0] + along * nx + sin_angle * cx);
      v[1] = c[1] + (cos_angle * dv[1] + along * ny + sin_angle * cy);
      v[2] = c[2] + (cos_angle * dv[2] + along * nz + sin_angle * cz);
    }
  }
};

}  // namespace mesoflow::mpc
