// dispersion_theory.hpp — dispersion relations of phonons in a 1D microfluidic crystal
// (microfluidic-crystal-phonons paper): the linearised far-field theory of Appendix C, eqs. (3)
// and (4) (= C.8 and C.7), the phenomenological coupling ω∥(k) = 2ω⊥(k/2) of eq. (8), and the
// continuum approximations eqs. (11)–(12) with their nearest-neighbour forms eqs. (13)–(14).
// Host-side analysis, no Kokkos.
//
// Sign convention: the relations come from plane waves e^{i(k n a − ω t)} inserted into the
// equations of motion (C.5)–(C.6), so ω > 0 for k > 0 is a wave travelling forward (+x, the flow
// direction, in the frame co-moving with the droplets). ω⊥ > 0 for 0 < k < π/a: transverse
// phonons travel forward; eq. (4) gives ω∥ < 0 there: linear longitudinal phonons travel backward.
#pragma once

#include <cstddef>
#include <vector>

namespace mesoflow::crystal {

// The experiment's (or simulation's) parameters, in one consistent unit system (the paper: μm and
// μm/s, so k in 1/μm and ω in rad/s).
struct CrystalParameters {
  double a = 0;      // crystal spacing (L = N a)
  double W = 0;      // channel width (walls at y = 0 and y = W)
  double R = 0;      // droplet radius, 0 < R < W/2
  double u_d = 0;    // droplet speed
  double u_oil = 0;  // oil speed, > 0
};

// Throws std::invalid_argument naming the parameter unless a, W, u_oil > 0, 0 < R < W/2 (so that
// tan(πR/W) is finite and positive) and u_d is finite.
void check_parameters(const CrystalParameters& p);

double velocity_ratio(const CrystalParameters& p);  // K = u_d/u_oil
double spacing_ratio(const CrystalParameters& p);   // β = a/W
// B = c₀ (π² R/W²) tan(πR/W) with c₀ = K (u_oil − u_d) (§4 after eq. (4), Appendix C).
double dispersion_prefactor(const CrystalParameters& p);

// The lattice sums
//   ω⊥(k) = 2B Σ_{j≥1} sin(jka) c⊥(jπβ),   c⊥(x) = [1 + cosh x]² csch³ x        (eq. 3)
//   ω∥(k) = −4B Σ_{j≥1} sin(jka) c∥(jπβ),  c∥(x) = coth x csch² x              (eq. 4)
// with the coefficients evaluated as c⊥(x) = 2e^{−x}(1 + q)/(1 − q)³ and c∥(x) = 4e^{−2x}(1 + q²)/
// (1 − q²)³, q = e^{−x} (the same functions, free of overflow). Both are e^{−m x} g(x) with g
// decreasing (m = 1 for c⊥, 2 for c∥), so c_i ≤ ρ^{i−J−1} c_{J+1} for i > J, ρ = e^{−mπβ}, and
//   Σ_{i>J} i c_i ≤ c_{J+1} (J + 1)/(1 − ρ)².
// Stopping rule: the coefficients c_1..c_J are kept for the smallest J where that bound is
// ≤ ε c_1, ε = 2⁻⁵³ (half the unit round-off). Since |sin(jka)| ≤ min(1, j|ka|) ≤ j, the
// truncation error of every sum here (eqs. 3, 4, 11, 12 and the k → 0 slope) is below ε c_1
// (times |ka| for eqs. 3–4): below the round-off of the leading term. J ≈ 37/(mπβ) + a few:
// 19 and 10 terms at β = 2/3.
class DispersionTheory {
 public:
  // B finite (any sign), 1e-3 ≤ β < ∞ (the cost grows like 1/β; β = a/W < 10⁻³ is no 1D crystal),
  // a > 0. Throws std::invalid_argument naming the parameter.
  DispersionTheory(double B, double beta, double a);
  // B, β and a from the physical parameters (checked by check_parameters).
  explicit DispersionTheory(const CrystalParameters& p);

  double B() const { return B_; }
  double beta() const { return beta_; }
  double a() const { return a_; }

  double transverse(double k) const;                      // ω⊥(k), eq. (3)
  double longitudinal(double k) const;                    // ω∥(k), eq. (4)
  double longitudinal_coupled(double k) const;            // ω∥(k) = 2ω⊥(k/2), eq. (8)
  double longitudinal_continuum(double k) const;          // −4kaB Σ j c∥(jπβ), eq. (11)
  double transverse_continuum(double k) const;            // 2kaB Σ j c⊥(jπβ), eq. (12)
  double longitudinal_nearest_neighbour(double k) const;  // −4kaB c∥(πβ), eq. (13)
  double transverse_nearest_neighbour(double k) const;    // 2kaB c⊥(πβ), eq. (14)

  // v_p = dω⊥/dk at k → 0 = 2aB Σ j c⊥(jπβ): the slope of eq. (12), which the small-ka expansion
  // of eq. (3) shares (§5). For the paper's experiment (R = 64 μm, a = 140 μm, W = 210 μm,
  // u_d = 250 μm/s, u_oil = 500 μm/s) it is 347.70 μm/s; the paper quotes 312 μm/s (see
  // tests/crystal/test_dispersion_theory.cpp).
  double phase_velocity() const;

  // The kept coefficients c⊥(jπβ) and c∥(jπβ), j = 1..J (index j − 1).
  const std::vector<double>& transverse_coefficients() const { return c_perp_; }
  const std::vector<double>& longitudinal_coefficients() const { return c_par_; }

 private:
  double B_, beta_, a_;
  std::vector<double> c_perp_, c_par_;
  double moment_perp_ = 0, moment_par_ = 0;  // Σ j c_j
};

}  // namespace mesoflow::crystal
