// periodic_poiseuille.hpp — host-side pieces shared by the MPC and MDPD trade-off programs:
// the fit of a periodic-Poiseuille profile (Backer et al., J. Chem. Phys. 122, 154503 (2005)), its
// statistical error from block fits (the cost clock is cost_clock.hpp).
//
// Profile: the body force ±ρg reverses at y = 0 and y = L/2, so in each half
// u(y) = s a q(y) + c with q = y′(L/2 − y′), s = ±1, a = ρ g / (2η); η = ρ g / (2a).
// Bins within `exclude` of the reversal planes are left out of the fit (the kink is rounded over
// the interaction range there).
#pragma once

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace mesoflow::tradeoff {

// Least-squares curvature a of u = s a q + c over the bins outside the excluded layers.
// count[b], momentum[b]: particle count and summed u_x of bin b (bins of equal width over [0, L)).
inline double fit_curvature(const std::vector<double>& count, const std::vector<double>& momentum, double length,
                            double exclude) {
  const int bins = int(count.size());
  const double half = 0.5 * length;
  double sqq = 0, sq = 0, s1 = 0, squ = 0, su = 0;
  for (int b = 0; b < bins; ++b) {
    const double y = (b + 0.5) * length / bins;
    const double yp = y < half ? y : y - half;
    if (yp < exclude || half - yp < exclude || count[b] <= 0) continue;
    const double q = (y < half ? 1.0 : -1.0) * yp * (half - yp);
    const double u = momentum[b] / count[b];
    sqq += q * q;
    sq += q;
    s1 += 1;
    squ += q * u;
    su += u;
  }
  const double det = sqq * s1 - sq * sq;
  if (s1 < 3 || !(det > 0)) throw std::invalid_argument("periodic Poiseuille fit: fewer than 3 bins outside the kinks");
  return (squ * s1 - sq * su) / det;
}

// Accumulates binned profiles into `blocks` consecutive blocks of samples; the viscosity comes
// from the fit of all samples, its standard error from the spread of the blocks' curvatures.
class BlockedProfile {
 public:
  BlockedProfile(int bins, int blocks, long long samples)
      : bins_(bins), blocks_(blocks), samples_(samples), count_(blocks, std::vector<double>(bins, 0)),
        momentum_(blocks, std::vector<double>(bins, 0)) {
    if (blocks < 2 || samples < blocks) throw std::invalid_argument("BlockedProfile: need >= 2 blocks of samples");
  }
  // sample: 0 … samples − 1; sums: count of bin b at [b], momentum at [offset + b].
  template <class Array>
  void add(long long sample, const Array& sums, int offset) {
    const int k = int(std::min<long long>(blocks_ - 1, sample * blocks_ / samples_));
    for (int b = 0; b < bins_; ++b) {
      count_[k][b] += sums[b];
      momentum_[k][b] += sums[offset + b];
    }
  }
  struct Fit {
    double curvature, curvature_stderr;
  };
  // ⟨u_x²⟩ of the mean profile over all samples (Σ_b count_b u_b² / Σ_b count_b): the streaming
  // share of the kinetic energy per particle, which the thermal temperature leaves out.
  double mean_square_stream_velocity() const {
    double total = 0, sum = 0;
    for (int b = 0; b < bins_; ++b) {
      double c = 0, m = 0;
      for (int k = 0; k < blocks_; ++k) {
        c += count_[k][b];
        m += momentum_[k][b];
      }
      if (c > 0) sum += m * m / c;
      total += c;
    }
    return sum / total;
  }
  Fit fit(double length, double exclude) const {
    std::vector<double> c(bins_, 0), m(bins_, 0);
    std::vector<double> a(blocks_);
    for (int k = 0; k < blocks_; ++k) {
      for (int b = 0; b < bins_; ++b) {
        c[b] += count_[k][b];
        m[b] += momentum_[k][b];
      }
      a[k] = fit_curvature(count_[k], momentum_[k], length, exclude);
    }
    double mean = 0, var = 0;
    for (double ak : a) mean += ak / blocks_;
    for (double ak : a) var += (ak - mean) * (ak - mean) / (blocks_ - 1);
    return {fit_curvature(c, m, length, exclude), std::sqrt(var / blocks_)};
  }

 private:
  int bins_, blocks_;
  long long samples_;
  std::vector<std::vector<double>> count_, momentum_;
};

}  // namespace mesoflow::tradeoff
