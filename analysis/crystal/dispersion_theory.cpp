#include "analysis/crystal/dispersion_theory.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>

namespace mesoflow::crystal {

namespace {

constexpr double pi = 3.14159265358979323846;

std::string str(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// c⊥(x) = [1 + cosh x]² csch³ x = 2e^{−x}(1 + q)/(1 − q)³, q = e^{−x} (eq. 3).
double c_perp(double x) {
  const double q = std::exp(-x), one_minus_q = -std::expm1(-x);
  return 2 * q * (1 + q) / (one_minus_q * one_minus_q * one_minus_q);
}

// c∥(x) = coth x csch² x = 4e^{−2x}(1 + q²)/(1 − q²)³, q = e^{−x} (eq. 4).
double c_par(double x) {
  const double q2 = std::exp(-2 * x), one_minus_q2 = -std::expm1(-2 * x);
  return 4 * q2 * (1 + q2) / (one_minus_q2 * one_minus_q2 * one_minus_q2);
}

// c(jπβ) for j = 1..J with the stopping rule of the header: ratio = e^{−mπβ}.
template <class C>
std::vector<double> coefficients(C c, double beta, double ratio) {
  const double eps = 0.5 * std::numeric_limits<double>::epsilon();
  const double inv_gap2 = 1 / ((1 - ratio) * (1 - ratio));
  std::vector<double> out{c(pi * beta)};
  for (;;) {
    const double next = c(pi * beta * double(out.size() + 1));
    if (next * double(out.size() + 1) * inv_gap2 <= eps * out.front()) break;
    out.push_back(next);
  }
  return out;
}

double first_moment(const std::vector<double>& c) {
  double s = 0;
  for (std::size_t j = c.size(); j-- > 0;) s += double(j + 1) * c[j];  // smallest terms first
  return s;
}

double sine_sum(const std::vector<double>& c, double ka) {
  double s = 0;
  for (std::size_t j = c.size(); j-- > 0;) s += std::sin(double(j + 1) * ka) * c[j];
  return s;
}

}  // namespace

void check_parameters(const CrystalParameters& p) {
  const auto positive = [](const char* name, double v) {
    if (!std::isfinite(v) || !(v > 0))
      throw std::invalid_argument(std::string("crystal parameters: ") + name + " must be finite and > 0, got " +
                                  str(v));
  };
  positive("a", p.a);
  positive("W", p.W);
  positive("R", p.R);
  positive("u_oil", p.u_oil);
  if (!(p.R < 0.5 * p.W))
    throw std::invalid_argument("crystal parameters: R must be < W/2 (tan(pi R/W) finite), got R = " + str(p.R) +
                                ", W = " + str(p.W));
  if (!std::isfinite(p.u_d)) throw std::invalid_argument("crystal parameters: u_d must be finite, got " + str(p.u_d));
}

double velocity_ratio(const CrystalParameters& p) {
  check_parameters(p);
  return p.u_d / p.u_oil;
}

double spacing_ratio(const CrystalParameters& p) {
  check_parameters(p);
  return p.a / p.W;
}

double dispersion_prefactor(const CrystalParameters& p) {
  const double c0 = velocity_ratio(p) * (p.u_oil - p.u_d);
  return c0 * (pi * pi * p.R / (p.W * p.W)) * std::tan(pi * p.R / p.W);
}

DispersionTheory::DispersionTheory(double B, double beta, double a) : B_(B), beta_(beta), a_(a) {
  if (!std::isfinite(B)) throw std::invalid_argument("DispersionTheory: B must be finite, got " + str(B));
  if (!std::isfinite(beta) || !(beta >= 1e-3))
    throw std::invalid_argument("DispersionTheory: beta = a/W must be finite and >= 1e-3, got " + str(beta));
  if (!std::isfinite(a) || !(a > 0))
    throw std::invalid_argument("DispersionTheory: a must be finite and > 0, got " + str(a));
  c_perp_ = coefficients(c_perp, beta, std::exp(-pi * beta));
  c_par_ = coefficients(c_par, beta, std::exp(-2 * pi * beta));
  moment_perp_ = first_moment(c_perp_);
  moment_par_ = first_moment(c_par_);
}

DispersionTheory::DispersionTheory(const CrystalParameters& p)
    : DispersionTheory(dispersion_prefactor(p), spacing_ratio(p), p.a) {}

double DispersionTheory::transverse(double k) const { return 2 * B_ * sine_sum(c_perp_, k * a_); }

double DispersionTheory::longitudinal(double k) const { return -4 * B_ * sine_sum(c_par_, k * a_); }

double DispersionTheory::longitudinal_coupled(double k) const { return 2 * transverse(0.5 * k); }

double DispersionTheory::longitudinal_continuum(double k) const { return -4 * k * a_ * B_ * moment_par_; }

double DispersionTheory::transverse_continuum(double k) const { return 2 * k * a_ * B_ * moment_perp_; }

double DispersionTheory::longitudinal_nearest_neighbour(double k) const { return -4 * k * a_ * B_ * c_par_.front(); }

double DispersionTheory::transverse_nearest_neighbour(double k) const { return 2 * k * a_ * B_ * c_perp_.front(); }

double DispersionTheory::phase_velocity() const { return 2 * a_ * B_ * moment_perp_; }

}  // namespace mesoflow::crystal
