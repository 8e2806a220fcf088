// block_average.hpp — the block-averaging error of the mean of a correlated series, host-only (no
// Kokkos): the flow rate of the hoppers from its window rates (hopper-flows §4; the drivers and tests
// pass it to scenes/hopper/flow_measurement.hpp), and any time series whose neighbouring samples are
// correlated.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace mesoflow::analysis {

// Mean and block-averaged standard error of `q`: the standard error of the mean of blocks of 1, 2,
// 4, … consecutive values (at least 4 blocks), the largest of them (correlations between
// neighbouring values raise it until it plateaus). Fewer than 4 values: the error is NaN.
inline void block_average(const std::vector<double>& q, double& mean, double& error) {
  const int n = int(q.size());
  mean = 0;
  for (double v : q) mean += v;
  mean /= n;
  error = n >= 4 ? 0.0 : NAN;  // fewer than 4 windows: no error estimate
  for (int b = 1; n / b >= 4; b *= 2) {
    const int blocks = n / b;
    double s2 = 0;
    for (int k = 0; k < blocks; ++k) {
      double m = 0;
      for (int j = 0; j < b; ++j) m += q[std::size_t(k * b + j)];
      m /= b;
      double all = 0;
      for (int j = 0; j < blocks * b; ++j) all += q[std::size_t(j)];
      all /= blocks * b;
      s2 += (m - all) * (m - all);
    }
    error = std::max(error, std::sqrt(s2 / (blocks - 1) / blocks));
  }
}

}  // namespace mesoflow::analysis
