#include "analysis/hopper/flow_rate_fits.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>

namespace mesoflow::hopper {

namespace {

constexpr double nan_value = std::numeric_limits<double>::quiet_NaN();

std::string str(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// Checks shared by both fits; every message starts with the function and names the parameter.
void check_series(const char* fn, const char* xname, const std::vector<double>& x, const char* yname,
                  const std::vector<double>& y, const char* ename, const std::vector<double>& e,
                  std::size_t min_points, std::size_t min_distinct_x) {
  const std::string f = std::string(fn) + ": ";
  if (x.size() != y.size())
    throw std::invalid_argument(f + xname + " and " + yname + " differ in size (" + std::to_string(x.size()) +
                                " vs " + std::to_string(y.size()) + ")");
  if (!e.empty() && e.size() != y.size())
    throw std::invalid_argument(f + ename + " must be empty (unweighted) or as long as " + yname + " (" +
                                std::to_string(e.size()) + " vs " + std::to_string(y.size()) + ")");
  if (x.size() < min_points)
    throw std::invalid_argument(f + "needs at least " + std::to_string(min_points) + " points in " + xname +
                                ", got " + std::to_string(x.size()));
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!std::isfinite(x[i]) || !(x[i] > 0))
      throw std::invalid_argument(f + xname + "[" + std::to_string(i) + "] must be finite and > 0, got " + str(x[i]));
    if (!e.empty() && (!std::isfinite(e[i]) || !(e[i] > 0)))
      throw std::invalid_argument(f + ename + "[" + std::to_string(i) + "] must be finite and > 0, got " + str(e[i]));
  }
  std::vector<double> sorted = x;
  std::sort(sorted.begin(), sorted.end());
  const auto distinct = std::size_t(std::unique(sorted.begin(), sorted.end()) - sorted.begin());
  if (distinct < min_distinct_x)
    throw std::invalid_argument(f + xname + " needs at least " + std::to_string(min_distinct_x) +
                                " distinct values, got " + std::to_string(distinct));
}

// Levenberg–Marquardt (Marquardt's diagonal scaling) on weighted residuals r_i = (y_i − f_i)/σ_i
// with J_ij = (∂f_i/∂p_j)/σ_i. model(p, r, J) fills both and returns false where p is outside the
// domain (the step is then rejected like one that raises χ²).
template <int P>
struct LmResult {
  Eigen::Matrix<double, P, 1> p;
  Eigen::Matrix<double, P, P> JtJ;
  double chi2 = 0;
  bool converged = false;
  int iterations = 0;
};

template <int P, class Model>
LmResult<P> levenberg_marquardt(Model model, Eigen::Matrix<double, P, 1> p, int n, double data_norm2,
                                int max_iterations = 1000) {
  using Vec = Eigen::Matrix<double, P, 1>;
  using Mat = Eigen::Matrix<double, P, P>;
  Eigen::VectorXd r(n), r_try(n);
  Eigen::Matrix<double, Eigen::Dynamic, P> J(n, P), J_try(n, P);
  LmResult<P> out;
  if (!model(p, r, J)) throw std::logic_error("levenberg_marquardt: starting point outside the domain");
  double chi2 = r.squaredNorm(), mu = 1e-3;
  int it = 0;
  bool converged = false;
  for (; it < max_iterations; ++it) {
    const Mat A = J.transpose() * J;
    const Vec g = J.transpose() * r;
    Mat M = A;
    for (int j = 0; j < P; ++j) M(j, j) += mu * std::max(A(j, j), 1e-300);
    const Vec step = M.ldlt().solve(g);
    const Vec p_try = p + step;
    const bool ok = step.allFinite() && model(p_try, r_try, J_try);
    const double chi2_try = ok ? r_try.squaredNorm() : std::numeric_limits<double>::infinity();
    if (ok && chi2_try <= chi2) {
      bool small = true;
      for (int j = 0; j < P; ++j) small = small && std::abs(step(j)) <= 1e-10 * (std::abs(p_try(j)) + 1e-10);
      p = p_try;
      r.swap(r_try);
      J.swap(J_try);
      chi2 = chi2_try;
      mu = std::max(mu * 0.1, 1e-12);
      if (small) {
        converged = true;
        ++it;
        break;
      }
    } else {
      mu *= 10;
      if (mu > 1e16) {
        // No step lowers χ²: at a minimum to round-off if the residuals are at round-off, or if the
        // Gauss–Newton step would explain a negligible part of them (Bates–Watts orthogonality).
        const Vec gn = A.ldlt().solve(g);
        const double explained = std::sqrt(std::max(0.0, g.dot(gn)));
        converged = chi2 <= 1e-24 * data_norm2 || explained <= 1e-6 * std::sqrt(chi2);
        ++it;
        break;
      }
    }
  }
  out.p = p;
  out.JtJ = J.transpose() * J;
  out.chi2 = chi2;
  out.converged = converged;
  out.iterations = it;
  return out;
}

}  // namespace

BeverlooFit fit_beverloo(const std::vector<double>& x, const std::vector<double>& Q,
                         const std::vector<double>& Q_error) {
  check_series("fit_beverloo", "w_over_sigma", x, "Q", Q, "Q_error", Q_error, 4, 3);
  for (std::size_t i = 0; i < Q.size(); ++i)
    if (!std::isfinite(Q[i]) || !(Q[i] > 0))
      throw std::invalid_argument("fit_beverloo: Q[" + std::to_string(i) +
                                  "] must be finite and > 0 (leave clogged widths out), got " + str(Q[i]));
  const int n = int(x.size());
  const bool weighted = !Q_error.empty();
  std::vector<double> inv_sigma(n, 1.0);
  double data_norm2 = 0;
  for (int i = 0; i < n; ++i) {
    if (weighted) inv_sigma[i] = 1.0 / Q_error[i];
    data_norm2 += (Q[i] * inv_sigma[i]) * (Q[i] * inv_sigma[i]);
  }
  const double x_min = *std::min_element(x.begin(), x.end());
  const double span = *std::max_element(x.begin(), x.end()) - x_min;

  // Starting values: scan k = x_min − δ, regress ln Q on ln(x − k) with the weights (Q/σ)² that
  // make log-space residuals match linear ones to first order, keep the lowest linear-space χ².
  double best_chi2 = std::numeric_limits<double>::infinity();
  Eigen::Vector3d p0(1, x_min - 1, 1);
  for (int s = 0; s <= 140; ++s) {
    const double k = x_min - span * std::pow(10.0, -4.0 + 0.05 * s);
    if (!(k < x_min)) continue;
    double sw = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (int i = 0; i < n; ++i) {
      const double w = (Q[i] * inv_sigma[i]) * (Q[i] * inv_sigma[i]), lx = std::log(x[i] - k), ly = std::log(Q[i]);
      sw += w, sx += w * lx, sy += w * ly, sxx += w * lx * lx, sxy += w * lx * ly;
    }
    const double det = sw * sxx - sx * sx;
    if (!(det > 0)) continue;
    const double beta = (sw * sxy - sx * sy) / det, C = std::exp((sy - beta * sx) / sw);
    double chi2 = 0;
    for (int i = 0; i < n; ++i) {
      const double r = (Q[i] - C * std::pow(x[i] - k, beta)) * inv_sigma[i];
      chi2 += r * r;
    }
    if (std::isfinite(chi2) && chi2 < best_chi2) best_chi2 = chi2, p0 = Eigen::Vector3d(C, k, beta);
  }

  auto model = [&](const Eigen::Vector3d& p, Eigen::VectorXd& r, Eigen::Matrix<double, Eigen::Dynamic, 3>& J) {
    const double C = p(0), k = p(1), beta = p(2);
    if (!(k < x_min)) return false;
    for (int i = 0; i < n; ++i) {
      const double u = x[i] - k, lu = std::log(u), ub = std::exp(beta * lu), f = C * ub;
      r(i) = (Q[i] - f) * inv_sigma[i];
      J(i, 0) = ub * inv_sigma[i];
      J(i, 1) = -beta * f / u * inv_sigma[i];
      J(i, 2) = f * lu * inv_sigma[i];
    }
    return r.allFinite() && J.allFinite();
  };
  const auto lm = levenberg_marquardt<3>(model, p0, n, data_norm2);

  BeverlooFit fit;
  fit.C = lm.p(0), fit.k = lm.p(1), fit.beta = lm.p(2);
  fit.chi2 = lm.chi2;
  fit.dof = n - 3;
  fit.chi2_per_dof = lm.chi2 / fit.dof;
  fit.weighted = weighted;
  fit.iterations = lm.iterations;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Constant(nan_value), inverse;
  bool invertible = false;
  lm.JtJ.computeInverseWithCheck(inverse, invertible);
  if (invertible) cov = inverse * (weighted ? 1.0 : fit.chi2_per_dof);
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) fit.covariance[a][b] = cov(a, b);
  fit.C_error = std::sqrt(cov(0, 0)), fit.k_error = std::sqrt(cov(1, 1)), fit.beta_error = std::sqrt(cov(2, 2));
  fit.converged = lm.converged && std::isfinite(fit.beta_error);
  return fit;
}

double beta_sigmoid(double lambda, int d, double lambda_c, double stretch) {
  return d - 1 - 0.5 * std::tanh(stretch * std::log10(lambda / lambda_c));
}

SigmoidFit fit_beta_sigmoid(const std::vector<double>& lambda, const std::vector<double>& beta,
                            const std::vector<double>& beta_error, int dimension) {
  if (dimension != 2 && dimension != 3)
    throw std::invalid_argument("fit_beta_sigmoid: dimension must be 2 or 3, got " + std::to_string(dimension));
  check_series("fit_beta_sigmoid", "lambda", lambda, "beta", beta, "beta_error", beta_error, 3, 2);
  for (std::size_t i = 0; i < beta.size(); ++i)
    if (!std::isfinite(beta[i]))
      throw std::invalid_argument("fit_beta_sigmoid: beta[" + std::to_string(i) + "] must be finite, got " + str(beta[i]));
  const int n = int(lambda.size());
  const bool weighted = !beta_error.empty();
  std::vector<double> ell(n), inv_sigma(n, 1.0);
  double data_norm2 = 0;
  for (int i = 0; i < n; ++i) {
    ell[i] = std::log10(lambda[i]);
    if (weighted) inv_sigma[i] = 1.0 / beta_error[i];
    data_norm2 += (beta[i] * inv_sigma[i]) * (beta[i] * inv_sigma[i]);
  }
  const double mid = dimension - 1;
  auto chi2_at = [&](double a, double s) {
    double c = 0;
    for (int i = 0; i < n; ++i) {
      const double r = (beta[i] - (mid - 0.5 * std::tanh(s * (ell[i] - a)))) * inv_sigma[i];
      c += r * r;
    }
    return c;
  };
  const double lo = *std::min_element(ell.begin(), ell.end()) - 1, hi = *std::max_element(ell.begin(), ell.end()) + 1;
  Eigen::Vector2d p0(0.5 * (lo + hi), 1.0);
  double best = std::numeric_limits<double>::infinity();
  const int na = std::max(2, int(std::ceil((hi - lo) / 0.1)));
  for (int ia = 0; ia <= na; ++ia)
    for (int is = 0; is <= 30; ++is) {
      const double a = lo + (hi - lo) * ia / na, s = std::pow(10.0, -1.7 + 0.1 * is);
      const double c = chi2_at(a, s);
      if (c < best) best = c, p0 = Eigen::Vector2d(a, s);
    }
  auto model = [&](const Eigen::Vector2d& p, Eigen::VectorXd& r, Eigen::Matrix<double, Eigen::Dynamic, 2>& J) {
    const double a = p(0), s = p(1);
    for (int i = 0; i < n; ++i) {
      const double z = s * (ell[i] - a), t = std::tanh(z), sech2 = 1 - t * t;
      r(i) = (beta[i] - (mid - 0.5 * t)) * inv_sigma[i];
      J(i, 0) = 0.5 * s * sech2 * inv_sigma[i];
      J(i, 1) = -0.5 * (ell[i] - a) * sech2 * inv_sigma[i];
    }
    return r.allFinite() && J.allFinite();
  };
  const auto lm = levenberg_marquardt<2>(model, p0, n, data_norm2);

  SigmoidFit fit;
  fit.dimension = dimension;
  fit.log10_lambda_c = lm.p(0);
  fit.lambda_c = std::pow(10.0, lm.p(0));
  fit.stretch = lm.p(1);
  fit.chi2 = lm.chi2;
  fit.dof = n - 2;
  fit.chi2_per_dof = fit.dof > 0 ? lm.chi2 / fit.dof : nan_value;
  fit.weighted = weighted;
  fit.iterations = lm.iterations;
  Eigen::Matrix2d cov = Eigen::Matrix2d::Constant(nan_value), inverse;
  bool invertible = false;
  lm.JtJ.computeInverseWithCheck(inverse, invertible);
  if (invertible) cov = inverse * (weighted ? 1.0 : fit.chi2_per_dof);
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b) fit.covariance[a][b] = cov(a, b);
  fit.log10_lambda_c_error = std::sqrt(cov(0, 0));
  fit.lambda_c_error = fit.lambda_c * std::log(10.0) * fit.log10_lambda_c_error;
  fit.stretch_error = std::sqrt(cov(1, 1));
  fit.converged = lm.converged && std::isfinite(fit.stretch_error);
  return fit;
}

double corrected_flow_rate(double Q, double number_density, double mean_particle_area) {
  if (!std::isfinite(Q) || Q < 0)
    throw std::invalid_argument("corrected_flow_rate: Q must be finite and >= 0, got " + str(Q));
  if (!std::isfinite(number_density) || !(number_density > 0))
    throw std::invalid_argument("corrected_flow_rate: number_density must be finite and > 0, got " + str(number_density));
  if (!std::isfinite(mean_particle_area) || !(mean_particle_area > 0))
    throw std::invalid_argument("corrected_flow_rate: mean_particle_area must be finite and > 0, got " +
                                str(mean_particle_area));
  return Q / (number_density * mean_particle_area);
}

}  // namespace mesoflow::hopper
