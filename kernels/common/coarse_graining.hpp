// coarse_graining.hpp — Gaussian coarse-grained fields on a line of points (hopper-flows paper §4,
// after Goldhirsch and Weinhart et al.):
//   n(r)   = Σ_i φ(r − r_i),            number density,
//   j_g(r) = Σ_i v_g,i φ(r − r_i),      the paper's v_g(r) (a number-weighted velocity sum),
//   φ(r)   = (√(2π) w)^{−D} exp(−|r|²/2w²),  w the coarse-graining width (the paper: σ_avg),
// v_g,i the velocity of particle i along gravity (−axis D−1). The mean speed of the particles at r is
// j_g(r)/n(r); the paper's v_g(r) is j_g itself (units of speed × number density).
//
// Points lie on the axis of gravity through the lateral origin (the hopper's centre line): r_k has
// lateral coordinates 0 and height h0 + k·dh, k = 0 … P−1. One parallel reduction over particles,
// each adding to the P points within `cutoff_widths` w of it (φ there < e^{−cutoff²/2}: 5w → 4·10⁻⁶
// of the peak); deterministic at a fixed thread count.
#pragma once

#include "kokkos_compat.hpp"
#include "particles.hpp"
#include "reductions.hpp"

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace mesoflow {

template <int P>
struct AxisProfile {
  std::array<double, P> number_density{};  // n(r_k)
  std::array<double, P> velocity_sum{};    // j_g(r_k) = Σ v_g,i φ
};

constexpr double coarse_graining_cutoff = 5.0;  // in widths w

template <int P, int D, class Real, class ExecSpace>
AxisProfile<P> gaussian_axis_profile(const Particles<D, Real, ExecSpace>& p, double h0, double dh, double width) {
  if (!(width > 0) || !std::isfinite(width))
    throw std::invalid_argument("gaussian_axis_profile: width must be finite and > 0, got " + std::to_string(width));
  if (!(dh > 0) || !std::isfinite(dh) || !std::isfinite(h0))
    throw std::invalid_argument("gaussian_axis_profile: dh must be finite and > 0, h0 finite");
  constexpr double two_pi = 6.283185307179586;
  const double norm = std::pow(std::sqrt(two_pi) * width, -D);
  const double inv_two_w2 = 1 / (2 * width * width), reach = coarse_graining_cutoff * width;
  const auto x = p.x;
  const auto v = p.v;
  const auto sums = parallel_sum<2 * P, ExecSpace>(
      "mesoflow::coarse_graining::axis_profile", int(p.size()), KOKKOS_LAMBDA(int i, double(&acc)[2 * P]) {
        double lateral2 = 0;
        for (int d = 0; d < D - 1; ++d) lateral2 += double(x(i, d)) * double(x(i, d));
        if (lateral2 >= reach * reach) return;
        const double h = double(x(i, D - 1)), vg = -double(v(i, D - 1));
        const int first = -int(kmath::floor((h0 + reach - h) / dh)), last = int(kmath::floor((h + reach - h0) / dh));
        for (int k = first < 0 ? 0 : first; k <= last && k < P; ++k) {
          const double dz = h0 + k * dh - h;
          const double phi = norm * kmath::exp(-(lateral2 + dz * dz) * inv_two_w2);
          acc[k] += phi;
          acc[P + k] += vg * phi;
        }
      });
  AxisProfile<P> out;
  for (int k = 0; k < P; ++k) {
    out.number_density[k] = sums[k];
    out.velocity_sum[k] = sums[P + k];
  }
  return out;
}

}  // namespace mesoflow
