// smoothing_kernels.hpp — the SPH smoothing kernels W(r, h) of the interpolation eq. (3) and their
// radial derivatives dW/dr, which make the gradients ∇_i W_ij = (dW/dr) r_ij/r of eqs. (4)–(5).
//
// Three kernels, each normalised to ∫ W dV = 1 in 2D and 3D (tests/sph/test_sph_kernels.cpp checks
// it by quadrature). h is *each kernel's own* smoothing length, as its authors define it; the
// support radius (where W reaches zero, the neighbor-list cutoff) differs:
//
//   Lucy quartic (Lucy 1977; the paper's kernel, §2.2)    support = h      (the paper's h)
//     W = σ_D/h^D (1 + 3q)(1 − q)³,               q = r/h ≤ 1,
//     σ_2 = 5/π,  σ_3 = 105/(16π)                  (LAMMPS' SPH package, which DMP runs on, the same)
//   cubic B-spline (Monaghan & Lattanzio 1985; Monaghan 1992)   support = 2h
//     W = σ_D/h^D [1 − 3q²/2 + 3q³/4]  (q < 1),   σ_D/h^D (2 − q)³/4  (1 ≤ q < 2),
//     σ_2 = 10/(7π),  σ_3 = 1/π
//   Wendland C2 (Wendland 1995, in the support-2h form of Dehnen & Aly 2012)   support = 2h
//     W = σ_D/h^D (1 − q/2)⁴ (2q + 1),            q ≤ 2,
//     σ_2 = 7/(4π),  σ_3 = 21/(16π)
//
// So a Lucy kernel and a spline of the same support have h_Lucy = 2 h_spline. The time-step limits
// (sph_time_step.hpp) are stated for Monaghan's h and take half the support radius, whatever the
// kernel.
//
// Each kernel gives value(r) = W, derivative(r) = dW/dr and derivative_over_r(r) = (1/r) dW/dr. The
// last is what the pair loops use (∇_i W_ij = derivative_over_r · r_ij): it is evaluated in closed
// form, finite at r = 0 for all three kernels, so no regularisation of 1/r is needed. All three
// return 0 at and beyond the support. Constants are computed in double and stored in Real.
#pragma once

#include "kernels/common/kokkos_compat.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace mesoflow::sph {

namespace kernel_detail {

constexpr double pi = 3.14159265358979323846;

inline void check_h(double h, const char* name) {
  if (!(std::isfinite(h) && h > 0))
    throw std::invalid_argument(std::string("sph: ") + name + " smoothing length h must be > 0, got " +
                                std::to_string(h));
}

inline double h_power(double h, int D) { return D == 2 ? h * h : h * h * h; }

}  // namespace kernel_detail

// Lucy's quartic kernel; support radius = h (the paper's convention).
template <int D, class Real>
struct LucyKernel {
  static_assert(D == 2 || D == 3, "sph: kernels are normalised in 2D and 3D");
  static constexpr double support_per_h = 1.0;
  static constexpr const char* name = "lucy";

  Real h, inv_h, support, support2;
  Real norm;            // σ_D / h^D
  Real gradient_norm;   // −12 σ_D / h^{D+2}: (1/r) dW/dr = gradient_norm (1 − q)²

  explicit LucyKernel(Real h_) {
    kernel_detail::check_h(double(h_), name);
    const double hd = double(h_);
    const double norm_d =
        (D == 2 ? 5.0 / kernel_detail::pi : 105.0 / (16.0 * kernel_detail::pi)) / kernel_detail::h_power(hd, D);
    h = h_;
    inv_h = Real(1.0 / hd);
    support = h_;
    support2 = Real(hd * hd);
    norm = Real(norm_d);
    gradient_norm = Real(-12.0 * norm_d / (hd * hd));
  }

  KOKKOS_INLINE_FUNCTION Real value(Real r) const {
    const Real q = r * inv_h;
    if (q >= Real(1)) return Real(0);
    const Real s = Real(1) - q;
    return norm * (Real(1) + Real(3) * q) * s * s * s;
  }
  // dW/dr = −12 σ q (1 − q)² / h^{D+1}.
  KOKKOS_INLINE_FUNCTION Real derivative(Real r) const {
    const Real q = r * inv_h;
    if (q >= Real(1)) return Real(0);
    const Real s = Real(1) - q;
    return -Real(12) * norm * inv_h * q * s * s;
  }
  KOKKOS_INLINE_FUNCTION Real derivative_over_r(Real r) const {
    const Real q = r * inv_h;
    if (q >= Real(1)) return Real(0);
    const Real s = Real(1) - q;
    return gradient_norm * s * s;
  }
};

// Monaghan's cubic B-spline; support radius = 2h.
template <int D, class Real>
struct CubicSplineKernel {
  static_assert(D == 2 || D == 3, "sph: kernels are normalised in 2D and 3D");
  static constexpr double support_per_h = 2.0;
  static constexpr const char* name = "cubic spline";

  Real h, inv_h, support, support2;
  Real norm;  // σ_D / h^D

  explicit CubicSplineKernel(Real h_) {
    kernel_detail::check_h(double(h_), name);
    const double hd = double(h_);
    h = h_;
    inv_h = Real(1.0 / hd);
    support = Real(2.0 * hd);
    support2 = Real(4.0 * hd * hd);
    norm = Real((D == 2 ? 10.0 / (7.0 * kernel_detail::pi) : 1.0 / kernel_detail::pi) / kernel_detail::h_power(hd, D));
  }

  KOKKOS_INLINE_FUNCTION Real value(Real r) const {
    const Real q = r * inv_h;
    if (q >= Real(2)) return Real(0);
    if (q < Real(1)) return norm * (Real(1) - Real(1.5) * q * q + Real(0.75) * q * q * q);
    const Real s = Real(2) - q;
    return norm * Real(0.25) * s * s * s;
  }
  KOKKOS_INLINE_FUNCTION Real derivative(Real r) const {
    const Real q = r * inv_h;
    if (q >= Real(2)) return Real(0);
    if (q < Real(1)) return norm * inv_h * q * (Real(2.25) * q - Real(3));
    const Real s = Real(2) - q;
    return -norm * inv_h * Real(0.75) * s * s;
  }
  KOKKOS_INLINE_FUNCTION Real derivative_over_r(Real r) const {
    const Real q = r * inv_h;
    if (q >= Real(2)) return Real(0);
    if (q < Real(1)) return norm * inv_h * inv_h * (Real(2.25) * q - Real(3));
    const Real s = Real(2) - q;
    return -norm * inv_h * inv_h * Real(0.75) * s * s / q;
  }
};

// Wendland's C2 kernel; support radius = 2h.
template <int D, class Real>
struct WendlandC2Kernel {
  static_assert(D == 2 || D == 3, "sph: kernels are normalised in 2D and 3D");
  static constexpr double support_per_h = 2.0;
  static constexpr const char* name = "Wendland C2";

  Real h, inv_h, support, support2;
  Real norm;  // σ_D / h^D

  explicit WendlandC2Kernel(Real h_) {
    kernel_detail::check_h(double(h_), name);
    const double hd = double(h_);
    h = h_;
    inv_h = Real(1.0 / hd);
    support = Real(2.0 * hd);
    support2 = Real(4.0 * hd * hd);
    norm = Real((D == 2 ? 7.0 / (4.0 * kernel_detail::pi) : 21.0 / (16.0 * kernel_detail::pi)) /
                kernel_detail::h_power(hd, D));
  }

  KOKKOS_INLINE_FUNCTION Real value(Real r) const {
    const Real q = r * inv_h;
    if (q >= Real(2)) return Real(0);
    const Real s = Real(1) - Real(0.5) * q;
    const Real s2 = s * s;
    return norm * s2 * s2 * (Real(2) * q + Real(1));
  }
  // dW/dr = −5 σ q (1 − q/2)³ / h^{D+1}.
  KOKKOS_INLINE_FUNCTION Real derivative(Real r) const {
    const Real q = r * inv_h;
    if (q >= Real(2)) return Real(0);
    const Real s = Real(1) - Real(0.5) * q;
    return -Real(5) * norm * inv_h * q * s * s * s;
  }
  KOKKOS_INLINE_FUNCTION Real derivative_over_r(Real r) const {
    const Real q = r * inv_h;
    if (q >= Real(2)) return Real(0);
    const Real s = Real(1) - Real(0.5) * q;
    return -Real(5) * norm * inv_h * inv_h * s * s * s;
  }
};

}  // namespace mesoflow::sph
