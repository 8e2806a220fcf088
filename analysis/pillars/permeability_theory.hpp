// permeability_theory.hpp — theory for the pillar-array permeability paper (Hulikal Chakrapani et
// al., Soft Matter 2023): permeabilities κ_p/d² of transverse Stokes flow through regular arrays of
// cylinders as functions of the porosity ε = 1 − φ (Fig. 7b, ESI Tables S13/S14), Brinkman's theory
// for pillars between two walls (eqs. 5 and 7), and the fits that turn simulation output into κ
// (Darcy line, Fig. 7a) and into the Brinkman parameters (B, α) (Figs. 10 and 11). Host-side.
//
// The ESI tables were not available; every formula below is from the source named beside it,
// checked in tests/pillars/test_permeability_theory.cpp against numbers printed in a source.
// Conventions: d = 2a the pillar diameter, φ = 1 − ε the solid area fraction, κ the Darcy
// permeability (superficial velocity U_s = −(κ/μ) dp/dx). All κ functions return κ/d² and throw
// std::invalid_argument for ε outside (1 − φ_max, 1), φ_max = π/4 (square) or π/(2√3) (hexagonal).
//
// Not implemented, because the formulas could not be found in any source reachable here:
//   Tamayol & Bahrami 2011 (Phys. Rev. E 83, 046314), the curve TB of Figs. 7b/8;
//   Tsay & Weinbaum 1991 (J. Fluid Mech. 226, 125) as printed: their merger of Sangani & Acrivos's
//   limits (SATW) is represented by SA's two limits plus kappa_tsay_weinbaum_fit (see there).
#pragma once

#include <array>
#include <vector>

namespace mesoflow::pillars {

// ---- Square arrays (flow along a lattice vector; a 45° rotation does not change κ) ----

// Gebart 1992 (J. Compos. Mater. 26, 1100), lubrication theory for the gaps:
//   κ/R² = C1 (√(φ_max/φ) − 1)^{5/2},  C1 = 16/(9π√2),  φ_max = π/4,  R = d/2.
double kappa_gebart_square(double porosity);

// Drummond & Tahir 1984 (Int. J. Multiphase Flow 10, 515), series for dilute square arrays:
//   κ/a² = [−ln φ − 1.476 + 2φ − 1.774 φ² + 4.076 φ³] / (8φ).
// Identical to the dilute series of Sangani & Acrivos 1982 (kappa_sangani_acrivos_dilute).
double kappa_drummond_tahir_square(double porosity);

// Drummond & Tahir 1984, Padé form of the same series (more accurate at moderate φ):
//   κ/a² = [−ln φ − 1.476 + (2φ − 0.796 φ²)/(1 + 0.489 φ − 1.605 φ²)] / (8φ).
double kappa_drummond_tahir_square_pade(double porosity);

// Sangani & Acrivos 1982 (Int. J. Multiphase Flow 8, 193), the two limits of their square-array
// drag F/(μU) per unit length (U superficial; κ/a² = π/(φ F/(μU)) from the force balance
// −dp/dx · cell area = F):
//   dilute:  F/(μU) = 4π / (−½ ln φ − 0.738 + φ − 0.887 φ² + 2.038 φ³);
//   dense:   F/(μU) = (9π/(2√2)) ε_g^{−5/2},  ε_g = 1 − √(4φ/π) the gap over the spacing.
// The dense form is the lubrication flow through the gaps to leading order; it coincides with
// Gebart's formula as φ → π/4.
double kappa_sangani_acrivos_dilute(double porosity);
double kappa_sangani_acrivos_dense(double porosity);

// The exact (multipole) results of Sangani & Acrivos 1982, Table 1, square arrays: {ε, κ/d²}
// at φ = 0.05, 0.1, 0.2, ..., 0.7, 0.75 (F/(μU) = 15.56 ... 1.263e5), κ/d² = π/(4 φ F/(μU)).
std::vector<std::array<double, 2>> sangani_acrivos_square_table();

// A power-law fit to Sangani & Acrivos's square-array results attributed to Tsay & Weinbaum 1991:
//   κ/a² = 0.0572 (Δ/a)^{2.377},  Δ = s − 2a the gap between pillar surfaces.
// UNVERIFIED: recalled from its citation in Weinbaum et al. 2003 (PNAS 100, 7988), not read in
// either paper here, and may not be the SATW curve of Fig. 7b. It agrees with SA's Table 1 to within
// 9 % for 0.05 ≤ φ ≤ 0.7 and 18 % at φ = 0.75 (tested), which is what it claims to be.
double kappa_tsay_weinbaum_fit(double porosity);

// ---- Hexagonal arrays (rows along the flow), ESI Table S14 ----

// Gebart 1992, hexagonal packing: C1 = 16/(9π√6), φ_max = π/(2√3).
double kappa_gebart_hexagonal(double porosity);

// Drummond & Tahir 1984, hexagonal (triangular) arrays:
//   κ/a² = [−ln φ − 1.497 + 2φ − φ²/2 − 0.739 φ⁴ + 2.534 φ⁵/(1 + 1.2758 φ)] / (8φ).
double kappa_drummond_tahir_hexagonal(double porosity);

// ---- Walls and Brinkman's theory (section 2.2) ----

// Plane Poiseuille flow between walls a distance H apart: κ_w = H²/12.
double kappa_walls(double H);

// Eq. 5 with the sign chosen so that B > 0 is flow along +x:
//   u_s(z) = B (1 − cosh(αz)/cosh(αH/2)),  z ∈ [−H/2, H/2] from the mid-plane,
// B = (κ_p/μ)|Δp|/L, α = √(μ/(μ_eff κ_p)). Evaluated without overflow or cancellation for any αH.
double brinkman_profile(double z, double B, double alpha, double H);

// Eq. 7: κ_eff = κ_p (1 − tanh(αH/2)/(αH/2)). Limits: κ_p (1 − 2/(αH)) for αH ≫ 1 (pillars
// dominate) and κ_p (αH/2)²/3 = (H²/12) μ/μ_eff for αH ≪ 1 (walls dominate).
double kappa_eff_brinkman(double kappa_p, double alpha, double H);

// μ_eff/μ = 1/(κ_p α²) (section 3.2.2) and its inverse α = 1/√(κ_p μ_eff/μ).
double mu_eff_ratio(double kappa_p, double alpha);
double alpha_from_mu_eff(double kappa_p, double mu_eff_ratio);

// Least squares of eq. 5 to a superficial-velocity profile u_s(z_i), z from the mid-plane. For fixed
// α the amplitude B is linear (closed form); the residual is minimised over x = αH/2 ∈ [1e-3, 50] by
// a scan on a log grid and golden-section refinement in ln x. A Poiseuille-like profile has its
// optimum at α → 0 (with B → ∞, B α² H²/8 → u_s(0)): the fit then stops at the lower bound and says
// so; B α²H²/8 still gives the mid-plane velocity. Needs ≥ 3 points, |z| ≤ H/2, u_s not all zero.
struct BrinkmanFit {
  double B = 0, alpha = 0;
  double rms_residual = 0;            // √(Σ (u_i − model_i)² / n)
  bool alpha_at_lower_bound = false;  // αH/2 = 1e-3: Poiseuille-like, α is an upper limit
  bool alpha_at_upper_bound = false;  // αH/2 = 50: plug flow, α is a lower limit
};
BrinkmanFit fit_brinkman(const std::vector<double>& z, const std::vector<double>& u_s, double H);

// Ordinary least squares y = intercept + slope x (flux against pressure gradient, Fig. 7a: the
// slope is κ/μ). Standard errors from the scatter: s² = Σ r²/(n − 2), σ_slope = √(s²/Sxx),
// σ_intercept = √(s² (1/n + x̄²/Sxx)). Needs ≥ 3 points and two distinct x.
struct DarcyFit {
  double slope = 0, intercept = 0;
  double slope_error = 0, intercept_error = 0;
};
DarcyFit fit_line(const std::vector<double>& x, const std::vector<double>& y);

}  // namespace mesoflow::pillars
