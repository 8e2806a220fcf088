// nelder_mead.hpp — Nelder–Mead simplex minimisation over a box, host-only (no Kokkos): the
// calibration of the DP droplet (analysis/droplets/profile_calibration.hpp, capillary-droplets §4.1)
// and any fit without derivatives.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>
#include <vector>

namespace mesoflow::analysis {

// Nelder–Mead simplex minimisation (Lagarias et al., SIAM J. Optim. 9, 112 (1998): reflection 1,
// expansion 2, contraction ½, shrink ½) of f over a box. Points outside the box are projected onto
// it. Stops when every vertex lies within x_tolerance (max norm) of the best one, or after
// max_evaluations. Deterministic; no derivatives, so a noisy-but-deterministic Δ_v is fine.
struct SimplexSettings {
  int max_evaluations = 60;
  double x_tolerance = 0.01;
  double initial_step = 0.2;
};

struct SimplexResult {
  std::vector<double> x;
  double value = HUGE_VAL;
  int evaluations = 0;
  bool converged = false;
};

inline SimplexResult nelder_mead(const std::function<double(const std::vector<double>&)>& f, std::vector<double> x0,
                                 const std::vector<double>& lo, const std::vector<double>& hi,
                                 const SimplexSettings& settings) {
  const std::size_t n = x0.size();
  auto project = [&](std::vector<double> x) {
    for (std::size_t d = 0; d < n; ++d) x[d] = std::clamp(x[d], lo[d], hi[d]);
    return x;
  };
  SimplexResult result;
  auto evaluate = [&](const std::vector<double>& x) {
    ++result.evaluations;
    return f(x);
  };
  std::vector<std::vector<double>> p{project(x0)};
  for (std::size_t d = 0; d < n; ++d) {
    auto x = p[0];
    x[d] += (x[d] + settings.initial_step <= hi[d]) ? settings.initial_step : -settings.initial_step;
    p.push_back(project(x));
  }
  std::vector<double> fp;
  for (const auto& x : p) fp.push_back(evaluate(x));
  auto combine = [&](const std::vector<double>& a, const std::vector<double>& b, double t) {  // a + t (b − a)
    std::vector<double> x(n);
    for (std::size_t d = 0; d < n; ++d) x[d] = a[d] + t * (b[d] - a[d]);
    return project(x);
  };
  while (true) {
    std::vector<std::size_t> order(n + 1);
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return fp[a] < fp[b]; });
    decltype(p) ps;
    std::vector<double> fs;
    for (auto k : order) {
      ps.push_back(p[k]);
      fs.push_back(fp[k]);
    }
    p = ps;
    fp = fs;
    double spread = 0;
    for (std::size_t k = 1; k <= n; ++k)
      for (std::size_t d = 0; d < n; ++d) spread = std::max(spread, std::abs(p[k][d] - p[0][d]));
    if (spread < settings.x_tolerance) {
      result.converged = true;
      break;
    }
    if (result.evaluations >= settings.max_evaluations) break;
    std::vector<double> centroid(n, 0.0);
    for (std::size_t k = 0; k < n; ++k)
      for (std::size_t d = 0; d < n; ++d) centroid[d] += p[k][d] / double(n);
    const auto xr = combine(centroid, p[n], -1.0);
    const double fr = evaluate(xr);
    if (fr < fp[0]) {
      const auto xe = combine(centroid, p[n], -2.0);
      const double fe = evaluate(xe);
      if (fe < fr) {
        p[n] = xe;
        fp[n] = fe;
      } else {
        p[n] = xr;
        fp[n] = fr;
      }
    } else if (fr < fp[n - 1]) {
      p[n] = xr;
      fp[n] = fr;
    } else {
      const bool outside = fr < fp[n];
      const auto xc = combine(centroid, outside ? xr : p[n], 0.5);
      const double fc = evaluate(xc);
      if (fc < (outside ? fr : fp[n])) {
        p[n] = xc;
        fp[n] = fc;
      } else {
        for (std::size_t k = 1; k <= n; ++k) {
          p[k] = combine(p[0], p[k], 0.5);
          fp[k] = evaluate(p[k]);
        }
      }
    }
  }
  result.x = p[0];
  result.value = fp[0];
  return result;
}

}  // namespace mesoflow::analysis
