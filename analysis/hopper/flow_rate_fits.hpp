// flow_rate_fits.hpp — fits of hopper flow rates (hopper-flows paper): the Beverloo law Q(w) =
// C (w/σ_avg − k)^β (eq. 1), the sigmoid β(λ) of eq. 14 in λ = ζ/μ, and the corrected flow rate
// Q' = Q a_eff/a_avg of Appendix B. Host-side analysis (Eigen), no Kokkos.
#pragma once

#include <array>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <optional>
#include <string>
#include <vector>

namespace mesoflow::hopper {

// Weighted nonlinear least squares for (C, k, β) in Q = C (x − k)^β, x = w/σ_avg, with k < min(x).
// With errors σ_i: χ² = Σ ((Q_i − model_i)/σ_i)², covariance (JᵀWJ)⁻¹ (W = diag 1/σ_i²), i.e. the
// errors are taken as known. Without errors (Q_error empty): σ_i = 1 and the covariance is scaled
// by the reduced χ² (errors estimated from the scatter). Standard errors are the square roots of
// the diagonal; they are linearised (Gaussian) errors, so for few points and unweighted fits a
// Student t quantile with `dof` degrees of freedom is the honest multiplier for an interval.
struct BeverlooFit {
  double C = 0, k = 0, beta = 0;
  double C_error = 0, k_error = 0, beta_error = 0;
  std::array<std::array<double, 3>, 3> covariance{};  // order (C, k, β)
  double chi2 = 0;          // χ² at the minimum (unweighted: the sum of squared residuals)
  int dof = 0;              // n − 3
  double chi2_per_dof = 0;  // χ²/dof: ≈ 1 when weighted errors are right
  bool weighted = false;
  bool converged = false;
  int iterations = 0;       // Levenberg–Marquardt iterations (accepted or not)
};

// x = w/σ_avg, Q > 0 (a width that clogged has no flow rate: leave it out), Q_error > 0 or empty.
// At least 4 points and 3 distinct widths. Starting values: a scan of k = min(x) − δ over δ from
// 10⁻⁴ to 10³ times the width span (log-spaced), each a weighted linear regression of ln Q on
// ln(x − k); the best is refined by Levenberg–Marquardt, rejecting steps that would reach
// k ≥ min(x). Throws std::invalid_argument naming the offending parameter.
BeverlooFit fit_beverloo(const std::vector<double>& w_over_sigma, const std::vector<double>& Q,
                         const std::vector<double>& Q_error = {});

// Eq. 14: β(λ) between the plateaus d − 1/2 (λ → 0, friction only) and d − 3/2 (λ → ∞, drag only),
// midpoint β_c = d − 1 at λ = λ_c, stretching exponent 1/b:
//     β = d − 1 − ½ tanh[(1/b) log10(λ/λ_c)].
// The paper prints β = ½(d − tanh[log10(λ − λ_c)^{1/b}]); read literally it gives the plateaus
// (d ± 1)/2 (right in 2D only: 3D would be 2 and 1, not the paper's 5/2 and 3/2) and puts the
// midpoint at λ = λ_c + 1, not at λ_c as the text says. The form above is the one that satisfies
// everything the text states (plateaus, midpoint d − 1 at λ_c, 0 < 1/b < 1 a stretching of
// log10 λ) and equals the printed one in 2D with λ − λ_c read as λ/λ_c. The plateaus are fixed;
// the parameters are log10 λ_c and 1/b, fitted in log10 λ.
struct SigmoidFit {
  int dimension = 2;
  double lambda_c = 0, lambda_c_error = 0;              // error by the delta method: λ_c ln10 σ(log10 λ_c)
  double log10_lambda_c = 0, log10_lambda_c_error = 0;  // the fitted parameter
  double stretch = 0, stretch_error = 0;                // 1/b
  double covariance[2][2] = {{0, 0}, {0, 0}};           // order (log10 λ_c, 1/b)
  double chi2 = 0;
  int dof = 0;  // n − 2
  double chi2_per_dof = 0;
  bool weighted = false;
  bool converged = false;
  int iterations = 0;
};

// The model above, for plotting and tests.
double beta_sigmoid(double lambda, int dimension, double lambda_c, double stretch);

// lambda > 0 and finite (the limits λ = 0 and ∞ are the fixed plateaus, not data), beta finite,
// beta_error > 0 or empty (unweighted: covariance scaled by the reduced χ², as for fit_beverloo).
// At least 3 points and 2 distinct λ. dimension 2 or 3. Starting values: a grid over log10 λ_c
// (the data's range ± 1 decade) and 1/b (0.02 to 20, log-spaced), refined by Levenberg–Marquardt.
SigmoidFit fit_beta_sigmoid(const std::vector<double>& lambda, const std::vector<double>& beta,
                            const std::vector<double>& beta_error, int dimension);

// Appendix B: Q' = Q a_eff/a_avg with a_eff = 1/ρ_n (ρ_n the number density in the 2w × w region
// above the orifice) and a_avg = (a_s + a_l)/2 the mean undeformed particle area (volume in 3D).
double corrected_flow_rate(double Q, double number_density, double mean_particle_area);

}  // namespace mesoflow::hopper

namespace mesoflow::hopper {

// The Beverloo fit of a w sweep's flowing widths (fit_beverloo), when at least 4 widths flow.
inline std::optional<BeverlooFit> beverloo_fit(const std::vector<double>& x, const std::vector<double>& Q,
                                               const std::vector<double>& Q_error) {
  std::optional<BeverlooFit> fit;
  if (x.size() >= 4) fit = fit_beverloo(x, Q, Q_error);
  return fit;
}

// Output tables of the fits (the `hopper` driver).
// <stem>_fit.csv: the Beverloo fit over `points` widths.
inline void write_beverloo_csv(const std::string& path, const BeverlooFit& fit, std::size_t points) {
  std::ofstream fcsv(path);
  fcsv << std::setprecision(10) << "C,C_error,k,k_error,beta,beta_error,chi2_per_dof,points\n"
       << fit.C << ',' << fit.C_error << ',' << fit.k << ',' << fit.k_error << ',' << fit.beta << ',' << fit.beta_error
       << ',' << fit.chi2_per_dof << ',' << points << '\n';
}

// <stem>_vary.csv: the Beverloo parameters against each value of an outer sweep `name` and
// λ = ζ/μ; appends to (x, beta, beta_error) the fits with 0 < λ < ∞ (for the sigmoid β(λ), eq. 14).
inline void write_vary_csv(const std::string& path, const std::string& name, const std::vector<double>& values,
                           const std::vector<double>& lambdas, const std::vector<std::optional<BeverlooFit>>& fits,
                           std::vector<double>& x, std::vector<double>& beta, std::vector<double>& beta_error) {
  std::ofstream csv(path);
  csv << std::setprecision(10) << name << ",lambda,C,C_error,k,k_error,beta,beta_error,chi2_per_dof\n";
  for (std::size_t j = 0; j < values.size(); ++j) {
    csv << values[j] << ',' << lambdas[j];
    if (const auto& f = fits[j]) {
      csv << ',' << f->C << ',' << f->C_error << ',' << f->k << ',' << f->k_error << ',' << f->beta << ','
          << f->beta_error << ',' << f->chi2_per_dof << '\n';
      if (lambdas[j] > 0 && std::isfinite(lambdas[j])) {
        x.push_back(lambdas[j]);
        beta.push_back(f->beta);
        beta_error.push_back(f->beta_error);
      }
    } else {
      csv << ",,,,,,,\n";
    }
  }
}

// The sigmoid β(λ) of eq. 14 over the `points` sweeps of an outer sweep with 0 < λ < ∞.
struct VarySigmoid {
  SigmoidFit fit;
  std::size_t points = 0;
};

// The outputs of an outer sweep `name` over `values` (λ = ζ/μ and the Beverloo fit of each):
// <stem>_vary.csv at `path` (write_vary_csv), and, when drag or friction varies (`dissipation`) and
// at least 3 fits have 0 < λ < ∞, the sigmoid β(λ) of eq. 14 in `dimension` dimensions.
inline std::optional<VarySigmoid> vary_outputs(const std::string& path, const std::string& name,
                                               const std::vector<double>& values, const std::vector<double>& lambdas,
                                               const std::vector<std::optional<BeverlooFit>>& fits, bool dissipation,
                                               int dimension) {
  std::vector<double> x, beta, beta_error;  // the fits with 0 < λ < ∞
  write_vary_csv(path, name, values, lambdas, fits, x, beta, beta_error);
  if (!(dissipation && x.size() >= 3)) return std::nullopt;
  return VarySigmoid{fit_beta_sigmoid(x, beta, beta_error, dimension), x.size()};
}

}  // namespace mesoflow::hopper
