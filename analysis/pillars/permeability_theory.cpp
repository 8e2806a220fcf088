#include "analysis/pillars/permeability_theory.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>

namespace mesoflow::pillars {

namespace {

constexpr double pi = 3.14159265358979323846;
const double phi_max_square = pi / 4.0;
const double phi_max_hexagonal = pi / (2.0 * std::sqrt(3.0));

std::string str(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

// Solid fraction φ = 1 − ε, checked against the packing limit of the array.
double solid_fraction(const char* fn, double porosity, double phi_max) {
  if (!(porosity > 1.0 - phi_max && porosity < 1.0))
    throw std::invalid_argument(std::string(fn) + ": porosity must be in (" + str(1.0 - phi_max) +
                                ", 1) (touching pillars at the lower end), got " + str(porosity));
  return 1.0 - porosity;
}

void check_positive(const char* fn, const char* name, double v) {
  if (!(v > 0) || !std::isfinite(v))
    throw std::invalid_argument(std::string(fn) + ": " + name + " must be finite and > 0, got " + str(v));
}

double gebart(double phi, double C1, double phi_max) {
  return C1 * std::pow(std::sqrt(phi_max / phi) - 1.0, 2.5) / 4.0;  // κ/R² → κ/d²
}

// Sangani–Acrivos / Drummond–Tahir dilute square-array series, κ/d² (κ/a² / 4).
double dilute_square_series(double phi) {
  return (-std::log(phi) - 1.476 + 2 * phi - 1.774 * phi * phi + 4.076 * phi * phi * phi) / (32.0 * phi);
}

// 1 − cosh(αz)/cosh(αH/2) for |z| ≤ H/2, written as a product of sinh (no cancellation as α → 0)
// or, for large α, through exponentials (no overflow).
double brinkman_shape(double z, double alpha, double H) {
  const double half = 0.5 * H, az = alpha * std::abs(z);
  if (alpha * half <= 20)
    return 2 * std::sinh(0.5 * alpha * (half + z)) * std::sinh(0.5 * alpha * (half - z)) / std::cosh(alpha * half);
  return 1 - std::exp(az - alpha * half) * (1 + std::exp(-2 * az)) / (1 + std::exp(-alpha * H));
}

}  // namespace

double kappa_gebart_square(double porosity) {
  return gebart(solid_fraction("kappa_gebart_square", porosity, phi_max_square),
                16.0 / (9.0 * pi * std::sqrt(2.0)), phi_max_square);
}

double kappa_gebart_hexagonal(double porosity) {
  return gebart(solid_fraction("kappa_gebart_hexagonal", porosity, phi_max_hexagonal),
                16.0 / (9.0 * pi * std::sqrt(6.0)), phi_max_hexagonal);
}

double kappa_drummond_tahir_square(double porosity) {
  return dilute_square_series(solid_fraction("kappa_drummond_tahir_square", porosity, phi_max_square));
}

double kappa_drummond_tahir_square_pade(double porosity) {
  const double phi = solid_fraction("kappa_drummond_tahir_square_pade", porosity, phi_max_square);
  return (-std::log(phi) - 1.476 + (2 * phi - 0.796 * phi * phi) / (1 + 0.489 * phi - 1.605 * phi * phi)) /
         (32.0 * phi);
}

double kappa_drummond_tahir_hexagonal(double porosity) {
  const double phi = solid_fraction("kappa_drummond_tahir_hexagonal", porosity, phi_max_hexagonal);
  const double phi2 = phi * phi;
  return (-std::log(phi) - 1.497 + 2 * phi - 0.5 * phi2 - 0.739 * phi2 * phi2 +
          2.534 * phi2 * phi2 * phi / (1 + 1.2758 * phi)) /
         (32.0 * phi);
}

double kappa_sangani_acrivos_dilute(double porosity) {
  return dilute_square_series(solid_fraction("kappa_sangani_acrivos_dilute", porosity, phi_max_square));
}

double kappa_sangani_acrivos_dense(double porosity) {
  const double phi = solid_fraction("kappa_sangani_acrivos_dense", porosity, phi_max_square);
  const double gap = 1.0 - std::sqrt(4.0 * phi / pi);
  const double drag = 9.0 * pi / (2.0 * std::sqrt(2.0)) * std::pow(gap, -2.5);  // F/(μU)
  return pi / (4.0 * phi * drag);
}

std::vector<std::array<double, 2>> sangani_acrivos_square_table() {
  // SA 1982 Table 1 (φ, F/(μU)), as transcribed in Basilisk's test src/test/cylinders.c.
  static const double table[][2] = {{0.05, 15.56},  {0.10, 24.83},  {0.20, 51.53},
                                     {0.30, 102.90}, {0.40, 217.89}, {0.50, 532.55},
                                     {0.60, 1.763e3}, {0.70, 1.352e4}, {0.75, 1.263e5}};
  std::vector<std::array<double, 2>> out;
  for (const auto& row : table) out.push_back({1.0 - row[0], pi / (4.0 * row[0] * row[1])});
  return out;
}

double kappa_tsay_weinbaum_fit(double porosity) {
  const double phi = solid_fraction("kappa_tsay_weinbaum_fit", porosity, phi_max_square);
  const double gap_over_a = std::sqrt(pi / phi) - 2.0;
  return 0.0572 * std::pow(gap_over_a, 2.377) / 4.0;
}

double kappa_walls(double H) {
  check_positive("kappa_walls", "H", H);
  return H * H / 12.0;
}

double brinkman_profile(double z, double B, double alpha, double H) {
  check_positive("brinkman_profile", "H", H);
  if (!(alpha >= 0) || !std::isfinite(alpha))
    throw std::invalid_argument("brinkman_profile: alpha must be finite and >= 0, got " + str(alpha));
  if (!(std::abs(z) <= 0.5 * H * (1 + 1e-12)))
    throw std::invalid_argument("brinkman_profile: z must be in [-H/2, H/2] = [" + str(-0.5 * H) + ", " +
                                str(0.5 * H) + "], got " + str(z));
  return B * brinkman_shape(std::clamp(z, -0.5 * H, 0.5 * H), alpha, H);
}

double kappa_eff_brinkman(double kappa_p, double alpha, double H) {
  check_positive("kappa_eff_brinkman", "kappa_p", kappa_p);
  check_positive("kappa_eff_brinkman", "H", H);
  if (!(alpha >= 0) || !std::isfinite(alpha))
    throw std::invalid_argument("kappa_eff_brinkman: alpha must be finite and >= 0, got " + str(alpha));
  const double x = 0.5 * alpha * H;
  // 1 − tanh(x)/x = x²/3 − 2x⁴/15 + 17x⁶/315 − …: the series avoids the cancellation at small x.
  const double factor = x < 1e-3 ? x * x / 3.0 - 2.0 * x * x * x * x / 15.0 : 1.0 - std::tanh(x) / x;
  return kappa_p * factor;
}

double mu_eff_ratio(double kappa_p, double alpha) {
  check_positive("mu_eff_ratio", "kappa_p", kappa_p);
  check_positive("mu_eff_ratio", "alpha", alpha);
  return 1.0 / (kappa_p * alpha * alpha);
}

double alpha_from_mu_eff(double kappa_p, double mu_eff_ratio) {
  check_positive("alpha_from_mu_eff", "kappa_p", kappa_p);
  check_positive("alpha_from_mu_eff", "mu_eff_ratio", mu_eff_ratio);
  return 1.0 / std::sqrt(kappa_p * mu_eff_ratio);
}

BrinkmanFit fit_brinkman(const std::vector<double>& z, const std::vector<double>& u_s, double H) {
  const std::string f = "fit_brinkman: ";
  check_positive("fit_brinkman", "H", H);
  if (z.size() != u_s.size())
    throw std::invalid_argument(f + "z and u_s differ in size (" + std::to_string(z.size()) + " vs " +
                                std::to_string(u_s.size()) + ")");
  if (z.size() < 3) throw std::invalid_argument(f + "needs at least 3 points, got " + std::to_string(z.size()));
  bool all_zero = true;
  for (std::size_t i = 0; i < z.size(); ++i) {
    if (!(std::abs(z[i]) <= 0.5 * H * (1 + 1e-12)))
      throw std::invalid_argument(f + "z[" + std::to_string(i) + "] = " + str(z[i]) + " is outside [-H/2, H/2]");
    if (!std::isfinite(u_s[i]))
      throw std::invalid_argument(f + "u_s[" + std::to_string(i) + "] is not finite");
    all_zero = all_zero && u_s[i] == 0;
  }
  if (all_zero) throw std::invalid_argument(f + "u_s is zero everywhere: no profile to fit");

  const double x_lo = 1e-3, x_hi = 50.0;
  // Residual sum of squares at x = αH/2, with the best B for that α.
  auto evaluate = [&](double x, double* B_out) {
    const double alpha = 2 * x / H;
    double sgg = 0, sug = 0;
    for (std::size_t i = 0; i < z.size(); ++i) {
      const double g = brinkman_shape(std::clamp(z[i], -0.5 * H, 0.5 * H), alpha, H);
      sgg += g * g, sug += u_s[i] * g;
    }
    const double B = sgg > 0 ? sug / sgg : 0;
    double ssr = 0;
    for (std::size_t i = 0; i < z.size(); ++i) {
      const double r = u_s[i] - B * brinkman_shape(std::clamp(z[i], -0.5 * H, 0.5 * H), alpha, H);
      ssr += r * r;
    }
    if (B_out) *B_out = B;
    return ssr;
  };

  const int grid = 160;
  const double t_lo = std::log(x_lo), t_hi = std::log(x_hi), dt = (t_hi - t_lo) / grid;
  int best = 0;
  double best_ssr = std::numeric_limits<double>::infinity();
  for (int k = 0; k <= grid; ++k) {
    const double ssr = evaluate(std::exp(t_lo + k * dt), nullptr);
    if (ssr < best_ssr) best_ssr = ssr, best = k;
  }
  // Golden section in t = ln x over the grid neighbours of the best point.
  double a = t_lo + std::max(best - 1, 0) * dt, b = t_lo + std::min(best + 1, grid) * dt;
  const double r = 0.5 * (std::sqrt(5.0) - 1);
  double c = b - r * (b - a), d = a + r * (b - a);
  double fc = evaluate(std::exp(c), nullptr), fd = evaluate(std::exp(d), nullptr);
  for (int it = 0; it < 200 && b - a > 1e-12; ++it) {
    if (fc <= fd) {
      b = d, d = c, fd = fc;
      c = b - r * (b - a);
      fc = evaluate(std::exp(c), nullptr);
    } else {
      a = c, c = d, fc = fd;
      d = a + r * (b - a);
      fd = evaluate(std::exp(d), nullptr);
    }
  }
  double t = 0.5 * (a + b);
  // The ends of the range are candidates too (the golden section never evaluates them).
  for (double end : {t_lo, t_hi})
    if (std::abs(end - t) <= dt && evaluate(std::exp(end), nullptr) <= evaluate(std::exp(t), nullptr)) t = end;

  BrinkmanFit fit;
  const double x = std::exp(t);
  fit.rms_residual = std::sqrt(evaluate(x, &fit.B) / double(z.size()));
  fit.alpha = 2 * x / H;
  fit.alpha_at_lower_bound = t - t_lo < 1e-6;
  fit.alpha_at_upper_bound = t_hi - t < 1e-6;
  return fit;
}

DarcyFit fit_line(const std::vector<double>& x, const std::vector<double>& y) {
  const std::string f = "fit_line: ";
  if (x.size() != y.size())
    throw std::invalid_argument(f + "x and y differ in size (" + std::to_string(x.size()) + " vs " +
                                std::to_string(y.size()) + ")");
  const std::size_t n = x.size();
  if (n < 3) throw std::invalid_argument(f + "needs at least 3 points for an error estimate, got " + std::to_string(n));
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(x[i]) || !std::isfinite(y[i]))
      throw std::invalid_argument(f + "point " + std::to_string(i) + " is not finite");
    mx += x[i], my += y[i];
  }
  mx /= n, my /= n;
  double sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < n; ++i) sxx += (x[i] - mx) * (x[i] - mx), sxy += (x[i] - mx) * (y[i] - my);
  if (!(sxx > 0)) throw std::invalid_argument(f + "x needs at least two distinct values");
  DarcyFit fit;
  fit.slope = sxy / sxx;
  fit.intercept = my - fit.slope * mx;
  double ssr = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double r = y[i] - fit.intercept - fit.slope * x[i];
    ssr += r * r;
  }
  const double s2 = ssr / double(n - 2);
  fit.slope_error = std::sqrt(s2 / sxx);
  fit.intercept_error = std::sqrt(s2 * (1.0 / n + mx * mx / sxx));
  return fit;
}

}  // namespace mesoflow::pillars
