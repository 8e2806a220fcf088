#include "analysis/droplets/clogging_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace mesoflow::droplets {

namespace {

// Inverse of the standard normal CDF by bisection on erfc: plenty fast for a one-off, and exact
// to double round-off.
double normal_quantile(double p) {
  double lo = -40, hi = 40;
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    (0.5 * std::erfc(-mid / std::sqrt(2.0)) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// Root of f on [a, b] where f changes sign (bisection in log space: λ spans decades).
template <class F>
double log_bisect(F f, double a, double b) {
  for (int it = 0; it < 200; ++it) {
    const double mid = std::sqrt(a * b);
    (f(mid) * f(a) > 0 ? a : b) = mid;
  }
  return std::sqrt(a * b);
}

}  // namespace

double chi_square_1_quantile(double p) {
  if (!(p > 0 && p < 1)) throw std::invalid_argument("chi_square_1_quantile: p must be in (0, 1), got " + std::to_string(p));
  const double z = normal_quantile(0.5 * (1 + p));
  return z * z;
}

DecayLengthEstimate decay_length(const std::vector<ReplicaOutcome>& outcomes, double level) {
  if (outcomes.empty()) throw std::invalid_argument("decay_length: no replicas");
  if (!(level > 0 && level < 1))
    throw std::invalid_argument("decay_length: confidence level must be in (0, 1), got " + std::to_string(level));
  DecayLengthEstimate e{0, 0, 0, 0, 0, 0};
  for (const auto& o : outcomes) {
    if (!(o.distance >= 0) || !std::isfinite(o.distance))
      throw std::invalid_argument("decay_length: distances must be finite and >= 0, got " + std::to_string(o.distance));
    e.total_distance += o.distance;
    (o.clogged ? e.clogged : e.censored) += 1;
  }
  const double T = e.total_distance, k = e.clogged, half_chi2 = 0.5 * chi_square_1_quantile(level);
  const double inf = std::numeric_limits<double>::infinity();
  if (T <= 0) throw std::invalid_argument("decay_length: every replica clogged at distance 0");
  if (e.clogged == 0) {
    // ℓ(λ) = −T/λ rises to 0 as λ → ∞: the interval is [T/(χ²/2), ∞).
    e.lambda = inf;
    e.lower = T / half_chi2;
    e.upper = inf;
    return e;
  }
  e.lambda = T / k;
  const double l_max = -k * std::log(e.lambda) - k;
  auto deficit = [&](double lambda) { return (l_max - (-k * std::log(lambda) - T / lambda)) - half_chi2; };
  e.lower = log_bisect(deficit, e.lambda * 1e-12, e.lambda);
  e.upper = log_bisect(deficit, e.lambda, e.lambda * 1e12);
  return e;
}

std::vector<SurvivalPoint> survival_curve(const std::vector<ReplicaOutcome>& outcomes) {
  std::vector<ReplicaOutcome> sorted = outcomes;
  // At equal distances clogs come before censorings (a censored replica was still at risk there).
  std::sort(sorted.begin(), sorted.end(), [](const ReplicaOutcome& a, const ReplicaOutcome& b) {
    return a.distance < b.distance || (a.distance == b.distance && a.clogged && !b.clogged);
  });
  std::vector<SurvivalPoint> curve{{0.0, 1.0}};
  double p = 1.0;
  std::size_t at_risk = sorted.size(), i = 0;
  while (i < sorted.size()) {
    const double r = sorted[i].distance;
    std::size_t clogs = 0, leaving = 0;
    for (; i < sorted.size() && sorted[i].distance == r; ++i, ++leaving) clogs += sorted[i].clogged;
    if (clogs > 0) {
      p *= 1.0 - double(clogs) / double(at_risk);
      curve.push_back({r, p});
    }
    at_risk -= leaving;
  }
  return curve;
}

}  // namespace mesoflow::droplets
