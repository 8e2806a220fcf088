// stability_estimate.hpp — the explicit time-step limit of a model as a sum of named terms, the form
// of kernels/dp/stability.hpp shared by the models that have no limit of their own yet
// (kernels/mpc/stability.hpp, kernels/mdpd/stability.hpp, kernels/common/lennard_jones_stability.hpp).
//
// Three kinds of term act on a particle:
//   a stiffness (a spring, a contact): the harmonic mode ω of its Hessian. Several stiff terms act
//     on the same particles, so their squared frequencies are summed (an upper bound of the largest
//     eigenvalue of a sum of positive semi-definite Hessians);
//   a rate (a friction, a drag integrated explicitly with the predicted velocity v + ½Δt a, as
//     velocity_verlet.hpp does): the rates of several frictions add;
//   a bound: a largest Δt that a scheme's geometry needs (a particle must not cross an obstacle
//     within one step), taken as it is.
// Velocity Verlet with the predicted velocity is stable for a damped mode x'' = −ω²x − νx' while
//   ν Δt + (ω Δt)²/2 < 2
// (the amplification matrix of one step has the eigenvalues 0 and the roots of
// z² − (2 − νΔt − ω²Δt²) z + 1 − νΔt = 0, one of which reaches −1 there; ν = 0 gives Verlet's
// ωΔt < 2, ω = 0 explicit Euler's νΔt < 2). The edge Δt_edge solves it with equality, and
// max_dt() = min(safety × Δt_edge, bounds). With safety = ½ a conservative term alone gets
// ω Δt ≤ 1, the margin kernels/dp/stability.hpp keeps. Host code only (std::string names),
// computed once per run.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace mesoflow {

class StabilityEstimate {
 public:
  // A stiffness term of frequency omega (1/time); omega = 0 adds a term that does not bind.
  void add_mode(const std::string& name, double omega) { modes_.push_back({name, omega}); }
  // An explicit friction of rate nu (1/time).
  void add_rate(const std::string& name, double nu) { rates_.push_back({name, nu}); }
  // A largest Δt of its own.
  void add_bound(const std::string& name, double dt) { bounds_.push_back({name, dt}); }

  double omega() const {
    double sum = 0;
    for (const auto& t : modes_) sum += t.value * t.value;
    return std::sqrt(sum);
  }
  double rate() const {
    double sum = 0;
    for (const auto& t : rates_) sum += t.value;
    return sum;
  }
  // The stability edge of the summed mode and rate: ν Δt + (ω Δt)²/2 = 2 (infinite when no term acts).
  double edge() const {
    const double w = omega(), nu = rate();
    if (w > 0) return (std::sqrt(nu * nu + 4 * w * w) - nu) / (w * w);
    return nu > 0 ? 2 / nu : HUGE_VAL;
  }
  // The fraction of the edge a run may use (default ½).
  void set_safety(double fraction) { safety_ = fraction; }
  double safety() const { return safety_; }
  // Largest Δt: safety × edge, or a bound if smaller.
  double max_dt() const { return std::min(safety_ * edge(), by_bounds()); }
  // The term that sets max_dt(), with its value, for error messages: the bound that binds, else the
  // largest term of the kind (stiffness or rate) that uses more of the budget at the edge:
  // "dissipation D (rate 113.1/τ of a total 113.1/τ)", "disc WCA contacts (ω = 2.909/τ of a total 2.909/τ)".
  std::string limiting_term(const std::string& time_unit) const {
    const double w = omega(), nu = rate(), dt = edge();
    if (by_bounds() < safety_ * dt) {
      const auto least = std::min_element(bounds_.begin(), bounds_.end(),
                                          [](const Term& a, const Term& b) { return a.value < b.value; });
      return least->name + " (Δt ≤ " + number(least->value) + time_unit + ")";
    }
    const bool by_rate = nu * dt > 0.5 * w * w * dt * dt;
    const auto& terms = by_rate ? rates_ : modes_;
    if (terms.empty()) return "no term (unbounded)";
    const auto top = std::max_element(terms.begin(), terms.end(),
                                      [](const Term& a, const Term& b) { return a.value < b.value; });
    if (by_rate)
      return top->name + " (rate " + number(top->value) + "/" + time_unit + " of a total " + number(nu) + "/" +
             time_unit + ")";
    return top->name + " (ω = " + number(top->value) + "/" + time_unit + " of a total " + number(w) + "/" +
           time_unit + ")";
  }

 private:
  double by_bounds() const {
    double least = HUGE_VAL;
    for (const auto& t : bounds_) least = std::min(least, t.value);
    return least;
  }
  struct Term {
    std::string name;
    double value;
  };
  static std::string number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4g", v);
    return buf;
  }
  std::vector<Term> modes_, rates_, bounds_;
  double safety_ = 0.5;
};

}  // namespace mesoflow
