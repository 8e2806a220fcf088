// Clogging statistics: the censored maximum-likelihood decay length, its confidence interval's
// coverage on synthetic ensembles, and the Kaplan–Meier survival curve.
#include "analysis/droplets/clogging_statistics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>
#include <stdexcept>
#include <vector>

namespace mesoflow::droplets {
namespace {

// An ensemble whose clogging distances are exponential with mean lambda; runs end (censoring) at
// distance `limit`.
std::vector<ReplicaOutcome> synthetic_ensemble(int n, double lambda, double limit, std::mt19937_64& gen) {
  std::exponential_distribution<double> clog(1.0 / lambda);
  std::vector<ReplicaOutcome> out;
  for (int i = 0; i < n; ++i) {
    const double r = clog(gen);
    out.push_back(r < limit ? ReplicaOutcome{r, true} : ReplicaOutcome{limit, false});
  }
  return out;
}

TEST(CloggingStatistics, ChiSquareQuantilesMatchTables) {
  EXPECT_NEAR(chi_square_1_quantile(0.95), 3.841459, 1e-6);
  EXPECT_NEAR(chi_square_1_quantile(0.99), 6.634897, 1e-6);
  EXPECT_NEAR(chi_square_1_quantile(0.6826894921), 1.0, 1e-8);  // ±1σ
}

TEST(CloggingStatistics, WithoutCensoringTheEstimateIsTheMeanDistance) {
  const std::vector<ReplicaOutcome> o{{1.0, true}, {2.0, true}, {4.5, true}, {0.5, true}};
  const auto e = decay_length(o);
  EXPECT_DOUBLE_EQ(e.lambda, 2.0);
  EXPECT_EQ(e.clogged, 4);
  EXPECT_EQ(e.censored, 0);
  EXPECT_LT(e.lower, 2.0);
  EXPECT_GT(e.upper, 2.0);
  // The bounds are where the log-likelihood has dropped by χ²₁(0.95)/2 from its maximum.
  const double k = 4, T = 8, l_max = -k * std::log(2.0) - k, half = 0.5 * chi_square_1_quantile(0.95);
  for (double b : {e.lower, e.upper}) EXPECT_NEAR(l_max - (-k * std::log(b) - T / b), half, 1e-9);
}

TEST(CloggingStatistics, CensoredReplicasLengthenTheEstimate) {
  // Two clogs at 1 and 3, two runs that ended at 5 without clogging: λ̂ = (1 + 3 + 5 + 5)/2 = 7.
  const auto e = decay_length({{1.0, true}, {5.0, false}, {3.0, true}, {5.0, false}});
  EXPECT_DOUBLE_EQ(e.lambda, 7.0);
  EXPECT_EQ(e.censored, 2);
}

TEST(CloggingStatistics, NoClogGivesOnlyALowerBound) {
  const auto e = decay_length({{10.0, false}, {10.0, false}, {10.0, false}});
  EXPECT_TRUE(std::isinf(e.lambda));
  EXPECT_TRUE(std::isinf(e.upper));
  EXPECT_NEAR(e.lower, 30.0 / (0.5 * 3.841459), 1e-4);
}

TEST(CloggingStatistics, EstimateIsConsistentOnALargeEnsemble) {
  std::mt19937_64 gen(1);
  const auto e = decay_length(synthetic_ensemble(100000, 2.0, 3.0, gen));
  // About 78 000 clogs: the relative standard error of λ̂ is ~1/√k ≈ 0.36%.
  EXPECT_NEAR(e.lambda / 2.0, 1.0, 0.015);
  EXPECT_LT(e.lower, 2.0);
  EXPECT_GT(e.upper, 2.0);
}

TEST(CloggingStatistics, ConfidenceIntervalCoversTheTrueLengthAtItsLevel) {
  // 2000 ensembles of 50 replicas, λ = 3, runs cut at 4 (about 26% censored): the 95% interval
  // must contain λ in 95% of them; 4 binomial standard errors (0.49% each) either side.
  std::mt19937_64 gen(2);
  int covered = 0;
  const int trials = 2000;
  for (int t = 0; t < trials; ++t) {
    const auto e = decay_length(synthetic_ensemble(50, 3.0, 4.0, gen));
    covered += e.lower <= 3.0 && 3.0 <= e.upper;
  }
  const double coverage = double(covered) / trials;
  std::cout << "[ measured ] 95% interval coverage over " << trials << " ensembles: " << coverage << "\n";
  EXPECT_GT(coverage, 0.93);
  EXPECT_LT(coverage, 0.97);
}

TEST(CloggingStatistics, KaplanMeierSurvival) {
  // Without censoring: the empirical fraction still moving.
  const auto plain = survival_curve({{1.0, true}, {2.0, true}, {3.0, true}, {4.0, true}});
  ASSERT_EQ(plain.size(), 5u);
  EXPECT_DOUBLE_EQ(plain[2].probability, 0.5);
  EXPECT_DOUBLE_EQ(plain[4].probability, 0.0);
  // With censoring (textbook case): 1 censored, 2 and 2 clog, 3 censored, 4 clogs →
  // steps (2, 1 − 2/4 = 0.5) and (4, 0.5 · (1 − 1/1) = 0).
  const auto km = survival_curve({{1.0, false}, {2.0, true}, {2.0, true}, {3.0, false}, {4.0, true}});
  ASSERT_EQ(km.size(), 3u);
  EXPECT_DOUBLE_EQ(km[0].probability, 1.0);
  EXPECT_DOUBLE_EQ(km[1].distance, 2.0);
  EXPECT_DOUBLE_EQ(km[1].probability, 0.5);
  EXPECT_DOUBLE_EQ(km[2].distance, 4.0);
  EXPECT_DOUBLE_EQ(km[2].probability, 0.0);
}

TEST(CloggingStatistics, RejectsBadInput) {
  EXPECT_THROW(decay_length({}), std::invalid_argument);
  EXPECT_THROW(decay_length({{-1.0, true}}), std::invalid_argument);
  EXPECT_THROW(decay_length({{NAN, true}}), std::invalid_argument);
  EXPECT_THROW(decay_length({{1.0, true}}, 1.5), std::invalid_argument);
  EXPECT_THROW(decay_length({{0.0, true}}), std::invalid_argument);
}

}  // namespace
}  // namespace mesoflow::droplets
