// Flow-rate fits (hopper-flows paper): the Beverloo law, eq. 1, recovered from exact and noisy
// synthetic data, its standard errors checked by coverage over many noisy data sets; the sigmoid
// β(λ), eq. 14; the corrected flow rate of Appendix B; bad input refused naming the parameter.
#include "analysis/hopper/flow_rate_fits.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <iostream>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace mesoflow::hopper {
namespace {

struct Beverloo {
  double C, k, beta;
  double operator()(double x) const { return C * std::pow(x - k, beta); }
};

// n widths evenly spaced from x0 to x1.
std::vector<double> widths(int n, double x0, double x1) {
  std::vector<double> x(n);
  for (int i = 0; i < n; ++i) x[i] = x0 + (x1 - x0) * i / (n - 1);
  return x;
}

// Q_i = Q(x_i) (1 + rel ε_i), ε standard normal; errors (if wanted) are the true rel Q(x_i).
struct Data {
  std::vector<double> x, Q, Q_error;
};
Data synthetic(const Beverloo& law, const std::vector<double>& x, double rel, std::mt19937_64* gen) {
  std::normal_distribution<double> eps(0.0, 1.0);
  Data d{x, {}, {}};
  for (double xi : x) {
    const double q = law(xi);
    d.Q.push_back(gen ? q * (1 + rel * eps(*gen)) : q);
    d.Q_error.push_back(rel * q);
  }
  return d;
}

void expect_relative(double got, double want, double tol, const char* what) {
  EXPECT_NEAR(got / want, 1.0, tol) << what << ": got " << got << ", want " << want;
}

// The paper's 2D hard-particle limits (Appendix B, Fig. 10): λ → 0 (friction only) C ≈ 0.14,
// k ≈ 1.6, β = 3/2; λ → ∞ (drag only) C ≈ 0.42, k ≈ 3.4, β = 1/2. Widths as in Fig. 2/10.
const Beverloo friction_2d{0.14, 1.6, 1.5}, drag_2d{0.42, 3.4, 0.5};

TEST(BeverlooFit, ExactDataRecoversTheParameters) {
  struct Case {
    Beverloo law;
    double x0, x1;
  };
  const Case cases[] = {{friction_2d, 2.5, 12}, {drag_2d, 4, 12}, {{0.3, 2.0, 2.5}, 3, 10},  // 3D, β = d − 1/2
                        {{0.5, -0.4, 1.0}, 1, 8}};  // soft particles: k may be ≤ 0
  for (const auto& c : cases)
    for (bool weighted : {false, true}) {
      const Data d = synthetic(c.law, widths(10, c.x0, c.x1), 0.03, nullptr);
      const auto fit = fit_beverloo(d.x, d.Q, weighted ? d.Q_error : std::vector<double>{});
      EXPECT_TRUE(fit.converged);
      EXPECT_EQ(fit.weighted, weighted);
      EXPECT_EQ(fit.dof, 7);
      expect_relative(fit.C, c.law.C, 1e-8, "C");
      EXPECT_NEAR(fit.k, c.law.k, 1e-8);
      expect_relative(fit.beta, c.law.beta, 1e-8, "beta");
      std::cout << "[ measured ] exact data, beta " << c.law.beta << (weighted ? " weighted" : " unweighted")
                << ": |dC/C| " << std::abs(fit.C / c.law.C - 1) << ", |dk| " << std::abs(fit.k - c.law.k)
                << ", |dbeta/beta| " << std::abs(fit.beta / c.law.beta - 1) << ", " << fit.iterations
                << " iterations\n";
    }
}

TEST(BeverlooFit, NoisyDataWithinTheirErrors) {
  // 3% Gaussian noise, 15 widths, one fixed seed: the estimates must lie within 3 standard errors
  // of the truth and within the stated absolute tolerances (several standard errors wide).
  std::mt19937_64 gen(4);
  for (const auto& law : {friction_2d, drag_2d}) {
    const Data d = synthetic(law, widths(15, law.k + 1, 12), 0.03, &gen);
    for (bool weighted : {true, false}) {
      const auto fit = fit_beverloo(d.x, d.Q, weighted ? d.Q_error : std::vector<double>{});
      ASSERT_TRUE(fit.converged);
      EXPECT_LT(std::abs(fit.beta - law.beta), 3 * fit.beta_error);
      EXPECT_LT(std::abs(fit.k - law.k), 3 * fit.k_error);
      EXPECT_LT(std::abs(fit.C - law.C), 3 * fit.C_error);
      EXPECT_NEAR(fit.beta, law.beta, 0.15);
      EXPECT_NEAR(fit.k, law.k, 0.5);
      std::cout << "[ measured ] 3% noise, beta " << law.beta << (weighted ? " weighted" : " unweighted")
                << ": C " << fit.C << " +- " << fit.C_error << ", k " << fit.k << " +- " << fit.k_error
                << ", beta " << fit.beta << " +- " << fit.beta_error << ", chi2/dof " << fit.chi2_per_dof
                << ", " << fit.iterations << " iterations\n";
    }
  }
}

TEST(BeverlooFit, StandardErrorsAreHonest) {
  // 1000 data sets per case (12 widths): |θ̂ − θ| < 1.96 SE in 95% of them if the linearised errors
  // are right. Weighted: 3% relative noise, errors known, normal → 0.95 expected, and mean χ²/dof
  // = 1. Unweighted: homoscedastic noise (σ = 1% of the mean Q, the model the reduced-χ² scaling
  // assumes), 9 dof, Student t → P(|t₉| < 1.96) = 0.918 expected. Band [0.90, 0.98]: ±3 binomial
  // standard errors (0.7-0.9% each) around 0.95 and 0.918 lie inside it.
  const auto start = std::chrono::steady_clock::now();
  std::mt19937_64 gen(5);
  std::normal_distribution<double> eps(0.0, 1.0);
  const int sets = 1000;
  int fits = 0;
  // mode 0: weighted, relative noise; 1: unweighted, absolute noise; 2: unweighted fit of relative
  // noise (misspecified: reported, not asserted).
  for (const auto& law : {friction_2d, drag_2d})
    for (int mode : {0, 1, 2}) {
      int covered_beta = 0, covered_k = 0, covered_C = 0, failed = 0;
      double chi2_sum = 0;
      const auto x = widths(12, law.k + 1, 12);
      double mean_Q = 0;
      for (double xi : x) mean_Q += law(xi) / x.size();
      for (int s = 0; s < sets; ++s) {
        Data d = synthetic(law, x, 0.03, mode == 1 ? nullptr : &gen);
        if (mode == 1)
          for (auto& q : d.Q) q += 0.01 * mean_Q * eps(gen);
        const auto fit = fit_beverloo(d.x, d.Q, mode == 0 ? d.Q_error : std::vector<double>{});
        ++fits;
        failed += !fit.converged;
        covered_beta += std::abs(fit.beta - law.beta) < 1.96 * fit.beta_error;
        covered_k += std::abs(fit.k - law.k) < 1.96 * fit.k_error;
        covered_C += std::abs(fit.C - law.C) < 1.96 * fit.C_error;
        chi2_sum += fit.chi2_per_dof;
      }
      const double cb = double(covered_beta) / sets, ck = double(covered_k) / sets, cC = double(covered_C) / sets;
      const char* name[] = {"weighted, 3% relative noise", "unweighted, absolute noise",
                            "unweighted fit of 3% relative noise (misspecified, not asserted)"};
      std::cout << "[ measured ] coverage of 1.96 SE over " << sets << " sets, beta " << law.beta << " " << name[mode]
                << ": beta " << cb << ", k " << ck << ", C " << cC << "; mean chi2/dof " << chi2_sum / sets
                << "; not converged " << failed << "\n";
      EXPECT_EQ(failed, 0);
      if (mode == 2) continue;
      for (double c : {cb, ck, cC}) {
        EXPECT_GT(c, 0.90);
        EXPECT_LT(c, 0.98);
      }
      if (mode == 0) {
        EXPECT_NEAR(chi2_sum / sets, 1.0, 0.05);  // E[χ²/dof] = 1, standard error √(2/9)/√1000 = 0.015
      }
    }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << "[ measured ] " << fits << " fits in " << seconds << " s\n";
}

TEST(BeverlooFit, TellsThePapersTwoLimitsApart) {
  // The 2D limits β = 3/2 (k ≈ 1.6) and β = 1/2 (k ≈ 3.4) from 3% noisy data: each fit excludes
  // the other limit's exponent by more than 5 standard errors.
  std::mt19937_64 gen(6);
  const Data f = synthetic(friction_2d, widths(12, 2.5, 12), 0.03, &gen);
  const Data g = synthetic(drag_2d, widths(12, 4.0, 12), 0.03, &gen);
  const auto ff = fit_beverloo(f.x, f.Q, f.Q_error), fg = fit_beverloo(g.x, g.Q, g.Q_error);
  ASSERT_TRUE(ff.converged && fg.converged);
  std::cout << "[ measured ] friction limit: beta " << ff.beta << " +- " << ff.beta_error << ", k " << ff.k << " +- "
            << ff.k_error << "; drag limit: beta " << fg.beta << " +- " << fg.beta_error << ", k " << fg.k << " +- "
            << fg.k_error << "\n";
  EXPECT_NEAR(ff.beta, 1.5, 3 * ff.beta_error);
  EXPECT_NEAR(fg.beta, 0.5, 3 * fg.beta_error);
  EXPECT_GT(std::abs(ff.beta - 0.5), 5 * ff.beta_error);
  EXPECT_GT(std::abs(fg.beta - 1.5), 5 * fg.beta_error);
  EXPECT_NEAR(ff.k, 1.6, 3 * ff.k_error);
  EXPECT_NEAR(fg.k, 3.4, 3 * fg.k_error);
}

// Runs f, expects std::invalid_argument whose message contains `name`.
template <class F>
void expect_refused(F f, const std::string& name) {
  try {
    f();
    ADD_FAILURE() << "accepted; expected an error naming " << name;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what() << " (expected to name " << name << ")";
  }
}

TEST(BeverlooFit, RefusesBadInputNamingTheParameter) {
  const std::vector<double> x{3, 4, 5, 6, 7}, Q{0.3, 0.6, 0.9, 1.3, 1.7}, e{0.01, 0.01, 0.01, 0.01, 0.01};
  const double nan = std::nan(""), inf = INFINITY;
  expect_refused([&] { fit_beverloo({3, 4, 5, 6}, Q, {}); }, "w_over_sigma and Q differ in size");
  expect_refused([&] { fit_beverloo(x, Q, {0.1, 0.1}); }, "Q_error");
  expect_refused([&] { fit_beverloo({3, 4, 5}, {1, 2, 3}, {}); }, "at least 4 points");
  expect_refused([&] { fit_beverloo({3, 4, nan, 6, 7}, Q, {}); }, "w_over_sigma[2]");
  expect_refused([&] { fit_beverloo({3, 4, 5, -6, 7}, Q, {}); }, "w_over_sigma[3]");
  expect_refused([&] { fit_beverloo(x, {0.3, 0.6, 0.0, 1.3, 1.7}, {}); }, "Q[2]");
  expect_refused([&] { fit_beverloo(x, {0.3, -0.6, 0.9, 1.3, 1.7}, {}); }, "Q[1]");
  expect_refused([&] { fit_beverloo(x, {0.3, 0.6, 0.9, inf, 1.7}, {}); }, "Q[3]");
  expect_refused([&] { fit_beverloo(x, Q, {0.01, 0.01, 0.0, 0.01, 0.01}); }, "Q_error[2]");
  expect_refused([&] { fit_beverloo(x, Q, {0.01, nan, 0.01, 0.01, 0.01}); }, "Q_error[1]");
  expect_refused([&] { fit_beverloo({3, 3, 4, 4, 4}, Q, {}); }, "distinct");
  EXPECT_NO_THROW(fit_beverloo(x, Q, e));
}

TEST(BetaSigmoid, HasThePapersPlateausAndMidpoint) {
  for (int d : {2, 3}) {
    EXPECT_NEAR(beta_sigmoid(1e-40, d, 0.05, 0.6), d - 0.5, 1e-12);  // λ → 0: Beverloo, friction only
    EXPECT_NEAR(beta_sigmoid(1e40, d, 0.05, 0.6), d - 1.5, 1e-12);   // λ → ∞: drag only
    EXPECT_DOUBLE_EQ(beta_sigmoid(0.05, d, 0.05, 0.6), d - 1.0);    // β_c = d − 1 at λ_c
  }
  // 2D: equals the printed ½(d − tanh[log10(λ/λ_c)^{1/b}]).
  EXPECT_NEAR(beta_sigmoid(0.3, 2, 0.05, 0.6), 0.5 * (2 - std::tanh(0.6 * std::log10(0.3 / 0.05))), 1e-15);
}

std::vector<double> lambdas() {  // 10⁻⁴ … 10² as in Fig. 4, two points per decade
  std::vector<double> l;
  for (int i = 0; i <= 12; ++i) l.push_back(std::pow(10.0, -4 + 0.5 * i));
  return l;
}

TEST(BetaSigmoid, FitRecoversItsParameters) {
  struct Case {
    int d;
    double lambda_c, stretch;
  };
  for (const Case c : {Case{2, 0.05, 0.6}, Case{3, 0.07, 0.4}, Case{2, 0.01, 0.9}}) {
    const auto l = lambdas();
    std::vector<double> b, e;
    for (double li : l) b.push_back(beta_sigmoid(li, c.d, c.lambda_c, c.stretch)), e.push_back(0.05);
    for (bool weighted : {false, true}) {
      const auto fit = fit_beta_sigmoid(l, b, weighted ? e : std::vector<double>{}, c.d);
      EXPECT_TRUE(fit.converged);
      expect_relative(fit.lambda_c, c.lambda_c, 1e-8, "lambda_c");
      expect_relative(fit.stretch, c.stretch, 1e-8, "stretch");
      std::cout << "[ measured ] sigmoid exact, d " << c.d << ": |dlambda_c/lambda_c| "
                << std::abs(fit.lambda_c / c.lambda_c - 1) << ", |dstretch/stretch| "
                << std::abs(fit.stretch / c.stretch - 1) << ", " << fit.iterations << " iterations\n";
    }
  }
  // Noisy (σ_β = 0.05, 13 points): coverage of 1.96 SE over 1000 sets, weighted.
  std::mt19937_64 gen(7);
  std::normal_distribution<double> eps(0.0, 0.05);
  const auto l = lambdas();
  const std::vector<double> e(l.size(), 0.05);
  int cov_lc = 0, cov_s = 0, failed = 0;
  const int sets = 1000;
  for (int s = 0; s < sets; ++s) {
    std::vector<double> b;
    for (double li : l) b.push_back(beta_sigmoid(li, 2, 0.05, 0.6) + eps(gen));
    const auto fit = fit_beta_sigmoid(l, b, e, 2);
    failed += !fit.converged;
    cov_lc += std::abs(fit.log10_lambda_c - std::log10(0.05)) < 1.96 * fit.log10_lambda_c_error;
    cov_s += std::abs(fit.stretch - 0.6) < 1.96 * fit.stretch_error;
    if (s == 0)
      std::cout << "[ measured ] sigmoid, sigma_beta 0.05, one set: lambda_c " << fit.lambda_c << " +- "
                << fit.lambda_c_error << ", 1/b " << fit.stretch << " +- " << fit.stretch_error << ", chi2/dof "
                << fit.chi2_per_dof << "\n";
  }
  std::cout << "[ measured ] sigmoid coverage of 1.96 SE over " << sets << " sets: log10 lambda_c "
            << double(cov_lc) / sets << ", 1/b " << double(cov_s) / sets << "; not converged " << failed << "\n";
  EXPECT_EQ(failed, 0);
  for (int c : {cov_lc, cov_s}) {
    EXPECT_GT(double(c) / sets, 0.90);
    EXPECT_LT(double(c) / sets, 0.98);
  }
}

TEST(BetaSigmoid, RefusesBadInputNamingTheParameter) {
  const std::vector<double> l{0.001, 0.01, 0.1, 1}, b{1.4, 1.2, 0.8, 0.6};
  expect_refused([&] { fit_beta_sigmoid(l, b, {}, 4); }, "dimension");
  expect_refused([&] { fit_beta_sigmoid({0.0, 0.01, 0.1, 1}, b, {}, 2); }, "lambda[0]");
  expect_refused([&] { fit_beta_sigmoid(l, {1.4, std::nan(""), 0.8, 0.6}, {}, 2); }, "beta[1]");
  expect_refused([&] { fit_beta_sigmoid(l, {1.4, 1.2}, {}, 2); }, "lambda and beta differ in size");
  expect_refused([&] { fit_beta_sigmoid(l, b, {0.1, 0.1, -0.1, 0.1}, 2); }, "beta_error[2]");
  expect_refused([&] { fit_beta_sigmoid({0.1, 1}, {1.0, 0.8}, {}, 2); }, "at least 3 points");
}

TEST(CorrectedFlowRate, AppendixB) {
  // Q' = Q a_eff/a_avg, a_eff = 1/ρ_n: unchanged without overlaps (ρ_n a_avg = 1); overlapping
  // particles pack denser than their area allows (ρ_n a_avg > 1) and Q' < Q.
  EXPECT_DOUBLE_EQ(corrected_flow_rate(0.8, 2.0, 0.5), 0.8);
  EXPECT_DOUBLE_EQ(corrected_flow_rate(0.8, 2.5, 0.5), 0.64);
  expect_refused([] { corrected_flow_rate(0.8, 0.0, 0.5); }, "number_density");
  expect_refused([] { corrected_flow_rate(0.8, 1.0, -0.5); }, "mean_particle_area");
  expect_refused([] { corrected_flow_rate(std::nan(""), 1.0, 0.5); }, "Q");
}

}  // namespace
}  // namespace mesoflow::hopper
