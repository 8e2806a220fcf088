// at_plus_a_collision.hpp — MPC-AT+a, eq. (B.2): v_i* = v_C + v_i^ran − ⟨v^ran⟩_C
// + m Π⁻¹ [Σ_j r_jC × (v_j − v_j^ran)] × r_iC, with Π the cell's moment of inertia tensor about
// its centre of mass r_C and r_iC = r_i − r_C (Noguchi & Gompper, PRE 78, 016706 (2008)).
// Conserves each cell's mass, momentum and angular momentum; thermostats at k_BT.
//
// A collision rule for MpcCollision. Positions are the offsets from the cell's lower corner
// (CollisionGrid::locate), so the sums stay accurate in large boxes. Per-cell sums:
//   {N, Σ v, Σ v^ran, Σ r, Σ|r|² (2D) or Σ r rᵀ (3D: xx yy zz xy xz yz), Σ r × (v − v^ran)};
// per-cell values {v_C − ⟨v^ran⟩_C, r_C, ω} with ω = m Π⁻¹ L the angular velocity, so that
// v_i* = (v_C − ⟨v^ran⟩_C) + v_i^ran + ω × (r_i − r_C). The mass cancels: Π/m and L are
// computed without it.
#pragma once

#include "kernels/common/kokkos_compat.hpp"

namespace mesoflow::mpc {

// Solves P x = b for a symmetric 3×3 P = (xx, yy, zz, xy, xz, yz) by its adjugate (Cramer's rule);
// returns det P (x is meaningful only where det P is not negligible). Device-safe.
KOKKOS_INLINE_FUNCTION double solve_symmetric_3x3(const double (&p)[6], const double (&b)[3], double (&x)[3]) {
  const double xx = p[0], yy = p[1], zz = p[2], xy = p[3], xz = p[4], yz = p[5];
  const double c00 = yy * zz - yz * yz;
  const double c01 = xz * yz - xy * zz;
  const double c02 = xy * yz - xz * yy;
  const double c11 = xx * zz - xz * xz;
  const double c12 = xy * xz - xx * yz;
  const double c22 = xx * yy - xy * xy;
  const double det = xx * c00 + xy * c01 + xz * c02;
  const double inv = det != 0.0 ? 1.0 / det : 0.0;
  x[0] = (c00 * b[0] + c01 * b[1] + c02 * b[2]) * inv;
  x[1] = (c01 * b[0] + c11 * b[1] + c12 * b[2]) * inv;
  x[2] = (c02 * b[0] + c12 * b[1] + c22 * b[2]) * inv;
  return det;
}

// ω with Π ω = L for the moment of inertia Π = tr(M) I − M of a point set with second moment M
// about its centre (M = Σ r_C r_Cᵀ, entries xx yy zz xy xz yz). `r2` is Σ|r|² about the point the
// sums were taken from (the cell corner), which sets the round-off of M: δM ≈ ε r2. Degenerate
// sets: all points at the centre (tr M ≤ 64 ε r2, which includes a single particle) give ω = 0;
// collinear points, where Π is singular up to that round-off (det Π ≤ 64 ε r2 (tr M)², the
// eigenvalues of Π being ≈ tr M, tr M and the smallest one), give the minimum-norm solution
// ω = 2L / tr Π = L / tr M, exact because then Π = tr M (I − n nᵀ) and L ⊥ n.
KOKKOS_INLINE_FUNCTION void angular_velocity_3d(const double (&m)[6], const double (&l)[3], double r2,
                                                double (&omega)[3]) {
  constexpr double tolerance = 64.0 * 2.220446049250313e-16;
  const double tr_m = m[0] + m[1] + m[2];
  if (!(tr_m > tolerance * r2) || !(tr_m > 0.0)) {
    for (int d = 0; d < 3; ++d) omega[d] = 0.0;
    return;
  }
  const double pi[6] = {tr_m - m[0], tr_m - m[1], tr_m - m[2], -m[3], -m[4], -m[5]};
  const double det = solve_symmetric_3x3(pi, l, omega);
  if (!(det > tolerance * r2 * tr_m * tr_m)) {
    for (int d = 0; d < 3; ++d) omega[d] = l[d] / tr_m;
  }
}

template <int D, class Real>
struct AtPlusACollision {
  static_assert(D == 2 || D == 3, "MPC-AT+a: 2D or 3D");
  static constexpr int num_moments = D == 2 ? 1 : 6;  // Σ|r|² or Σ r rᵀ
  static constexpr int num_torques = D == 2 ? 1 : 3;  // components of Σ r × w
  static constexpr int num_sums = 1 + 3 * D + num_moments + num_torques;
  static constexpr int num_cell_values = 2 * D + num_torques;
  static constexpr bool uses_random_velocity = true;
  static constexpr bool uses_position = true;

  // Offsets into the sums.
  static constexpr int sum_v = 1, sum_vran = 1 + D, sum_r = 1 + 2 * D, sum_rr = 1 + 3 * D,
                       sum_torque = 1 + 3 * D + num_moments;

  KOKKOS_INLINE_FUNCTION void add(double* s, const Real (&r)[D], const Real (&v)[D], const Real (&vran)[D]) const {
    double rd[D], w[D];
    for (int d = 0; d < D; ++d) {
      rd[d] = double(r[d]);
      w[d] = double(v[d]) - double(vran[d]);
    }
    s[0] += 1.0;
    for (int d = 0; d < D; ++d) {
      s[sum_v + d] += double(v[d]);
      s[sum_vran + d] += double(vran[d]);
      s[sum_r + d] += rd[d];
    }
    if constexpr (D == 2) {
      s[sum_rr] += rd[0] * rd[0] + rd[1] * rd[1];
      s[sum_torque] += rd[0] * w[1] - rd[1] * w[0];
    } else {
      s[sum_rr + 0] += rd[0] * rd[0];
      s[sum_rr + 1] += rd[1] * rd[1];
      s[sum_rr + 2] += rd[2] * rd[2];
      s[sum_rr + 3] += rd[0] * rd[1];
      s[sum_rr + 4] += rd[0] * rd[2];
      s[sum_rr + 5] += rd[1] * rd[2];
      s[sum_torque + 0] += rd[1] * w[2] - rd[2] * w[1];
      s[sum_torque + 1] += rd[2] * w[0] - rd[0] * w[2];
      s[sum_torque + 2] += rd[0] * w[1] - rd[1] * w[0];
    }
  }

  // Moments about the centre of mass: M_C = Σ r rᵀ − N r_C r_Cᵀ, L_C = Σ r × w − r_C × Σ w.
  KOKKOS_INLINE_FUNCTION void cell_values(int, const double* s, Real* c) const {
    const double count = s[0];
    const double inv_n = 1.0 / count;
    double rc[D], sw[D];
    for (int d = 0; d < D; ++d) {
      c[d] = Real((s[sum_v + d] - s[sum_vran + d]) * inv_n);
      rc[d] = s[sum_r + d] * inv_n;
      c[D + d] = Real(rc[d]);
      sw[d] = s[sum_v + d] - s[sum_vran + d];
    }
    if constexpr (D == 2) {
      const double inertia = s[sum_rr] - count * (rc[0] * rc[0] + rc[1] * rc[1]);
      const double torque = s[sum_torque] - (rc[0] * sw[1] - rc[1] * sw[0]);
      c[2 * D] = count > 1.0 && inertia > 64.0 * 2.220446049250313e-16 * s[sum_rr] ? Real(torque / inertia) : Real(0);
    } else {
      const double m[6] = {s[sum_rr + 0] - count * rc[0] * rc[0], s[sum_rr + 1] - count * rc[1] * rc[1],
                           s[sum_rr + 2] - count * rc[2] * rc[2], s[sum_rr + 3] - count * rc[0] * rc[1],
                           s[sum_rr + 4] - count * rc[0] * rc[2], s[sum_rr + 5] - count * rc[1] * rc[2]};
      const double l[3] = {s[sum_torque + 0] - (rc[1] * sw[2] - rc[2] * sw[1]),
                           s[sum_torque + 1] - (rc[2] * sw[0] - rc[0] * sw[2]),
                           s[sum_torque + 2] - (rc[0] * sw[1] - rc[1] * sw[0])};
      double omega[3] = {0.0, 0.0, 0.0};
      if (count > 1.0) angular_velocity_3d(m, l, s[sum_rr + 0] + s[sum_rr + 1] + s[sum_rr + 2], omega);
      for (int d = 0; d < 3; ++d) c[2 * D + d] = Real(omega[d]);
    }
  }

  KOKKOS_INLINE_FUNCTION void apply(const Real* c, const Real (&r)[D], const Real (&vran)[D], Real (&v)[D]) const {
    Real q[D];
    for (int d = 0; d < D; ++d) q[d] = r[d] - c[D + d];
    if constexpr (D == 2) {
      const Real w = c[2 * D];
      v[0] = c[0] + vran[0] - w * q[1];
      v[1] = c[1] + vran[1] + w * q[0];
    } else {
      const Real wx = c[2 * D], wy = c[2 * D + 1], wz = c[2 * D + 2];
      v[0] = c[0] + vran[0] + (wy * q[2] - wz * q[1]);
      v[1] = c[1] + vran[1] + (wz * q[0] - wx * q[2]);
      v[2] = c[2] + vran[2] + (wx * q[1] - wy * q[0]);
    }
  }
};

}  // namespace mesoflow::mpc
