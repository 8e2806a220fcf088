// Permeability theory (pillar-array permeability paper, Fig. 7b, eqs. 5 and 7): every κ(ε) formula
// against numbers printed in its source or in a secondary source (cited beside each), the exact
// square-array results of Sangani & Acrivos 1982 as the common yardstick, Brinkman's profile and
// eq. 7 with their limits, the (B, α) fit on synthetic profiles, and the Darcy line fit; the
// estimators of a flow run on a synthetic measurement whose region is denser than the array.
#include "analysis/pillars/permeability_estimates.hpp"
#include "analysis/pillars/permeability_theory.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

// Own namespace: this file shares a unity translation unit with others (tests/CMakeLists.txt).
namespace mesoflow::pillars::permeability_theory_test {
namespace {

constexpr double pi = 3.14159265358979323846;

template <class F>
void expect_invalid(F f, const std::string& word) {
  try {
    f();
    ADD_FAILURE() << "no exception; expected one mentioning " << word;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(word), std::string::npos) << e.what();
  }
}

// SA 1982 Table 1 as κ/d² at φ = 0.05 ... 0.75 (index 0 ... 8).
const std::vector<std::array<double, 2>> exact = sangani_acrivos_square_table();

// A synthetic 2D measurement: flux q = 0.02 everywhere (steady state), a region x ∈ [5, 15) of a
// 20 × 10 box whose fluid fraction is 0.6 while the array's porosity is 0.7, and whose 2 pillars
// carry the drag of a local permeability κ_r = 0.5 (F_m = μ q V_r/κ_r). The paper's U_s = ε⟨u⟩ takes
// the region's ⟨u⟩ = q/0.6 with the array's ε (7/6 of q); the flux from the momentum, Σu/(ρV), is q
// in the region and over the box, and eq. (3) with the region's own pillar density gives κ_r back.
TEST(PermeabilityEstimates, RegionFluxAndLocalDragRecoverTheRegionsPermeability) {
  FlowMeasurement m;
  m.dim = 2;
  m.Lx = 20;
  m.Ly = 10;
  m.diameter = 2;
  m.porosity = 0.7;
  m.centres = {{8.0, 3.0}, {12.0, 7.0}, {2.0, 5.0}};  // two axes in the region, one outside
  m.x_lo = 5;
  m.x_hi = 15;
  m.viscosity = 26.1;
  m.driving_force = 0.3;
  m.density = 6;
  m.driving_length = 5;
  const double q = 0.02, kappa_r = 0.5, v_r = 100, samples = 10;
  m.samples = 10;
  m.count = {0.6 * m.density * v_r * samples};
  m.velocity = {q * m.density * v_r * samples};
  m.pillar_force = {0};
  const double f_m = m.viscosity * q * v_r / kappa_r;
  m.tether = -f_m * samples;
  m.sample_u.assign(10, q / 0.6);
  m.sample_tether.assign(10, f_m);
  m.sum_u = 10 * q / 0.6;
  m.sum_u2 = 10 * (q / 0.6) * (q / 0.6);
  m.velocity_all = q * m.density * m.Lx * m.Ly * samples;
  m.count_all = 0.7 * m.density * m.Lx * m.Ly * samples;
  const auto e = estimate_permeability(m);
  EXPECT_EQ(e.measured_pillars, 2);
  EXPECT_NEAR(e.region_fluid_fraction, 0.6, 1e-12);
  EXPECT_NEAR(e.superficial_velocity, 0.7 * q / 0.6, 1e-14);  // the paper's ε⟨u⟩: 7/6 of the flux
  EXPECT_NEAR(e.superficial_velocity_region, q, 1e-14);
  EXPECT_NEAR(e.superficial_velocity_box, q, 1e-14);
  EXPECT_NEAR(e.kappa_drag_tether_region, kappa_r, 1e-12);
  EXPECT_NEAR(e.kappa_darcy_box, m.viscosity * q * m.Lx / (0.3 * 6 * 5), 1e-12);  // the paper's Δp = f_b ρ L_d
  // Eq. (3) as printed, with the array's φ and the region's drag per pillar: another number.
  const double phi = 0.3, per_pillar = f_m / 2;
  EXPECT_NEAR(e.kappa_drag_tether, pi * m.viscosity * (0.7 * q / 0.6) * 4 / (4 * phi * per_pillar), 1e-12);
}

// The chosen estimator's error (docs/mdpd.md): the block error of the whole box's flux over its mean.
// 20 samples in 10 blocks of 2 whose means are 1 + 0.01k (k = 0…9), each block split ±0.5 so that
// the within-block scatter must not count: mean 1.045, SE of the 10 block means
// sqrt(0.01² (10² − 1)/12 / 9) = 3.0277e-3.
TEST(PermeabilityEstimates, BoxFluxErrorIsTheBlockErrorOfThePerSampleFlux) {
  FlowMeasurement m;
  m.Lx = m.Ly = 10;
  m.viscosity = 26.1, m.driving_force = 0.3, m.density = 6, m.driving_length = 5;
  m.samples = 20;
  m.count = {100}, m.velocity = {1}, m.pillar_force = {0};
  m.sample_u.assign(20, 0.01);
  m.sample_tether.assign(20, 1.0);
  for (int k = 0; k < 10; ++k) {
    m.sample_u_box.push_back(1 + 0.01 * k + 0.5);
    m.sample_u_box.push_back(1 + 0.01 * k - 0.5);
  }
  m.count_all = 1000, m.velocity_all = 20 * 1.045;
  const auto e = estimate_permeability(m);
  EXPECT_NEAR(e.kappa_darcy_box_relative_error, std::sqrt(1e-4 * 99.0 / 12.0 / 9.0) / 1.045, 1e-12);
  m.sample_u_box.clear();  // a measurement without per-sample flux: no error, not a made-up one
  EXPECT_EQ(estimate_permeability(m).kappa_darcy_box_relative_error, 0.0);
}

// The Brinkman fit's jackknife error (issue 28, items 3-4): 100 samples in 10 blocks; block k's
// samples carry the exact eq. 5 profile with α_k = 0.9 (1 + 10⁻³ δ_k), B = 0.02, H = 7.5, 15 bins.
// For so small a spread the fit of the summed profile is linear in the α_k, and the delete-one-block
// jackknife must give the standard error of the 10 block values, √(Σ(α_k − ᾱ)²/(10 · 9)), to 2%
// (the fit's own tolerance on α, about 10⁻⁷ relative, is far below the 10⁻⁴ spread). Equal blocks
// give 0; a measurement without per-sample profiles gives no error, not a made-up one.
TEST(PermeabilityEstimates, BrinkmanJackknifeIsTheStandardErrorOfBlockFits) {
  FlowMeasurement m;
  m.dim = 3, m.H = 7.5, m.Lx = m.Ly = 20, m.Lz = 9, m.diameter = 5, m.porosity = 0.7;
  m.centres = {{5, 5}};
  m.x_lo = 0, m.x_hi = 20;
  m.viscosity = 17.5, m.driving_force = 0.6, m.density = 6, m.driving_length = 5;
  const int bins = 15, per_block = 10;
  const double B = 0.02, alpha0 = 0.9, H = 7.5;
  const std::array<double, 10> delta{0.3, -1.2, 0.8, 0.1, -0.5, 1.5, -0.9, 0.4, -0.2, 0.7};
  m.count.assign(bins, 0), m.velocity.assign(bins, 0), m.pillar_force.assign(bins, 0);
  double mean_alpha = 0;
  std::vector<double> alphas;
  for (int k = 0; k < 10; ++k) {
    const double a = alpha0 * (1 + 1e-3 * delta[k]);
    alphas.push_back(a);
    mean_alpha += a / 10;
    for (int s = 0; s < per_block; ++s) {
      for (int b = 0; b < bins; ++b) {
        const double z = (b + 0.5) * H / bins - 0.5 * H;
        const double u = brinkman_profile(z, B, a, H) / m.porosity;  // u_s = ε u
        m.sample_count_profile.push_back(1.0);
        m.sample_velocity_profile.push_back(u);
        m.count[b] += 1.0;
        m.velocity[b] += u;
      }
      m.sample_u.push_back(0.01), m.sample_tether.push_back(1.0), m.sample_u_box.push_back(1.0);
    }
  }
  m.samples = 10 * per_block;
  m.count_all = 1000, m.velocity_all = 100;
  double ss = 0;
  for (double a : alphas) ss += (a - mean_alpha) * (a - mean_alpha);
  const double expected = std::sqrt(ss / 90);
  const auto e = estimate_permeability(m);
  ASSERT_TRUE(e.fit.has_value());
  EXPECT_EQ(e.jackknife_blocks, 10);
  EXPECT_NEAR(e.fit->alpha, mean_alpha, 0.1 * expected);
  EXPECT_NEAR(e.alpha_jackknife_error / expected, 1.0, 0.02);
  EXPECT_GT(e.B_jackknife_error, 0.0);
  // Equal blocks: every delete-one fit is the same fit.
  FlowMeasurement same = m;
  for (int s = 0; s < 100; ++s)
    for (int b = 0; b < bins; ++b)
      same.sample_velocity_profile[s * bins + b] = same.sample_velocity_profile[b];
  for (int b = 0; b < bins; ++b) same.velocity[b] = 100 * same.sample_velocity_profile[b];
  EXPECT_EQ(estimate_permeability(same).alpha_jackknife_error, 0.0);
  m.sample_count_profile.clear(), m.sample_velocity_profile.clear();
  const auto none = estimate_permeability(m);
  EXPECT_EQ(none.jackknife_blocks, 0);
  EXPECT_EQ(none.alpha_jackknife_error, 0.0);
}

TEST(SquareArrayTheory, SanganiAcrivosTableIsTheirDragConverted) {
  ASSERT_EQ(exact.size(), 9u);
  // φ = 0.6, F/(μU) = 1763: κ/d² = π/(4 · 0.6 · 1763) = 7.4247e-4. Independent check: an integral-
  // equation solver (arXiv:1906.06884, quoted in its demo scripts) gets κ = 5.671e-4 L² for a cell
  // of side L at φ = 0.6, i.e. κ/d² = 5.671e-4 π/(4 · 0.6) = 7.4234e-4: agreement to 2e-4.
  EXPECT_NEAR(exact[6][0], 0.4, 1e-12);
  EXPECT_NEAR(exact[6][1] / (5.671e-4 * pi / 2.4), 1.0, 5e-4);
}

TEST(SquareArrayTheory, GebartMatchesItsPublishedDeviationFromTheExactResults) {
  // Gebart/exact − 1 in %, tabulated with the constants C1 = 16/(9π√2) and φ_max = π/4 in the
  // W9-C LBM benchmark of the tensorlbm project (SANGANI_EXACT_BIAS_SQ), at φ = 0.05 ... 0.75.
  const double bias_percent[] = {49.793, 37.951, 25.331, 18.062, 13.212, 9.532, 6.226, 2.978, 0.268};
  for (std::size_t k = 0; k < exact.size(); ++k) {
    const double ratio = kappa_gebart_square(exact[k][0]) / exact[k][1];
    EXPECT_NEAR(100 * (ratio - 1), bias_percent[k], 6e-4) << "phi " << 1 - exact[k][0];
  }
  // polytex (fiber-tow permeability library) docstring: gebart(vf=0.5, rf=1.7e-5) gives the
  // transverse κ = 3.73472833e-12 m² (square, 'Quad') and 4.72786599e-12 m² (hexagonal).
  const double d2 = 4 * 1.7e-5 * 1.7e-5;
  EXPECT_NEAR(kappa_gebart_square(0.5) * d2, 3.73472833e-12, 1e-20);
  EXPECT_NEAR(kappa_gebart_hexagonal(0.5) * d2, 4.72786599e-12, 1e-20);
}

TEST(SquareArrayTheory, GebartVanishesAtClosePackingLikeTheGapToThe5Over2) {
  const double eps_c = 1 - pi / 4;
  EXPECT_LT(kappa_gebart_square(eps_c + 1e-9), 1e-20);
  // κ ∝ (√(φ_max/φ) − 1)^{5/2} → (δ/2)^{5/2} with δ = 1 − φ/φ_max: halving δ divides κ by 2^{5/2}.
  const double k1 = kappa_gebart_square(eps_c + 1e-6 * pi / 4), k2 = kappa_gebart_square(eps_c + 0.5e-6 * pi / 4);
  EXPECT_NEAR(k1 / k2, std::pow(2.0, 2.5), 1e-5);
  const double eps_h = 1 - pi / (2 * std::sqrt(3.0));
  EXPECT_LT(kappa_gebart_hexagonal(eps_h + 1e-9), 1e-20);
  expect_invalid([&] { kappa_gebart_square(eps_c); }, "porosity");
  expect_invalid([] { kappa_gebart_hexagonal(1.0); }, "porosity");
}

TEST(SquareArrayTheory, SanganiAcrivosLimitsBracketTheirExactResults) {
  // Dilute series (SA 1982; quoted as 4π/(−½ln c − 0.738 + c − 0.887c² + 2.038c³) in e.g. the
  // porewise and warpSPH validation scripts): within 0.1 % of Table 1 at φ = 0.05 and 0.1, and no
  // longer valid at φ = 0.4 (it overshoots by 88 %).
  EXPECT_NEAR(kappa_sangani_acrivos_dilute(exact[0][0]) / exact[0][1], 1.0, 1e-3);
  EXPECT_NEAR(kappa_sangani_acrivos_dilute(exact[1][0]) / exact[1][1], 1.0, 1e-3);
  EXPECT_GT(kappa_sangani_acrivos_dilute(exact[4][0]) / exact[4][1], 1.5);
  // Dense (lubrication) limit: within 1 % of Table 1 at φ = 0.6, 0.7, 0.75 (13525 against 13520 at 0.7).
  for (std::size_t k = 6; k < 9; ++k)
    EXPECT_NEAR(kappa_sangani_acrivos_dense(exact[k][0]) / exact[k][1], 1.0, 0.01) << "phi " << 1 - exact[k][0];
  // It and Gebart share the leading order at close packing.
  const double eps = 1 - pi / 4 + 1e-7;
  EXPECT_NEAR(kappa_sangani_acrivos_dense(eps) / kappa_gebart_square(eps), 1.0, 1e-3);
}

TEST(SquareArrayTheory, DrummondTahirSeriesAndPadeForm) {
  // The square-array series equals SA's dilute series (same coefficients ×2).
  for (double eps : {0.3, 0.6, 0.95})
    EXPECT_DOUBLE_EQ(kappa_drummond_tahir_square(eps), kappa_sangani_acrivos_dilute(eps));
  // At φ = 0.1 by hand: κ/a² = (2.302585 − 1.476 + 0.2 − 0.01774 + 0.004076)/0.8 = 1.266151.
  EXPECT_NEAR(4 * kappa_drummond_tahir_square(0.9), 1.266151, 2e-6);
  // The Padé form agrees with the series at small φ and follows SA's Table 1 further: within 5 %
  // up to φ = 0.3 (+4.5 % there) where the series is already 14 % high.
  EXPECT_NEAR(kappa_drummond_tahir_square_pade(0.99) / kappa_drummond_tahir_square(0.99), 1.0, 1e-5);
  for (std::size_t k = 0; k < 4; ++k)
    EXPECT_NEAR(kappa_drummond_tahir_square_pade(exact[k][0]) / exact[k][1], 1.0, 0.05) << "phi " << 1 - exact[k][0];
  EXPECT_GT(kappa_drummond_tahir_square(exact[3][0]) / exact[3][1], 1.10);
}

TEST(HexagonalArrayTheory, DrummondTahirMatchesPublishedValues) {
  // polytex docstring: drummond_tahir(vf=0.3, 'Hex') κ_t/r² = 0.10851671; vf=0.7: 0.01110984.
  EXPECT_NEAR(kappa_drummond_tahir_hexagonal(0.7) * 4, 0.10851671, 1e-8);
  EXPECT_NEAR(kappa_drummond_tahir_hexagonal(0.3) * 4, 0.01110984, 1e-8);
  // Hexagonal packing is the looser one near close packing of the square lattice (Fig. 8 trend).
  EXPECT_GT(kappa_gebart_hexagonal(0.25), kappa_gebart_square(0.25));
}

TEST(SquareArrayTheory, TsayWeinbaumFitFollowsSanganiAcrivos) {
  // The recalled fit κ/a² = 0.0572 (Δ/a)^{2.377} against SA Table 1: within 9 % up to φ = 0.7
  // (largest: +8.3 % at 0.7), +18 % at φ = 0.75 where a power 2.377 of the gap cannot follow Δ^{5/2}.
  for (std::size_t k = 0; k < 8; ++k)
    EXPECT_NEAR(kappa_tsay_weinbaum_fit(exact[k][0]) / exact[k][1], 1.0, 0.09) << "phi " << 1 - exact[k][0];
  EXPECT_NEAR(kappa_tsay_weinbaum_fit(exact[8][0]) / exact[8][1], 1.18, 0.02);
}

TEST(Brinkman, WallPermeabilityAndProfile) {
  // Paper, section 3.1: H = 20 μm gives κ_w = H²/12 = 33 μm².
  EXPECT_NEAR(kappa_walls(20.0), 33.33, 0.01);
  const double H = 7.5, B = 2.0;
  for (double alpha : {0.4, 0.9, 1.4}) {  // the fitted α of Fig. 10
    EXPECT_EQ(brinkman_profile(H / 2, B, alpha, H), 0.0);
    EXPECT_NEAR(brinkman_profile(-H / 2, B, alpha, H), 0.0, 1e-15);
    for (double z : {-3.0, -1.0, 0.0, 0.5, 2.5})
      EXPECT_NEAR(brinkman_profile(z, B, alpha, H), B * (1 - std::cosh(alpha * z) / std::cosh(alpha * H / 2)), 1e-13);
  }
  // α → 0: B α²(H²/4 − z²)/2, the Poiseuille parabola; α → ∞: a plug B away from the walls.
  const double a = 1e-6;
  EXPECT_NEAR(brinkman_profile(1.0, B, a, H) / (B * a * a * (H * H / 4 - 1) / 2), 1.0, 1e-9);
  EXPECT_NEAR(brinkman_profile(0.0, B, 1e3, H), B, 1e-15);
  EXPECT_NEAR(brinkman_profile(H / 2 - 1e-3, B, 1e3, H), B * (1 - std::exp(-1.0)), 1e-12);
  expect_invalid([&] { brinkman_profile(H, B, 1, H); }, "z");
}

TEST(Brinkman, Eq7IsTheMeanOfEq5AndHasBothLimits) {
  const double kp = 0.37, H = 7.5;
  for (double alpha : {0.05, 0.4, 0.9, 1.4, 5.0}) {
    // (1/H)∫ u_s dz with B = κ_p (unit pressure gradient and viscosity), Simpson's rule.
    const int n = 2000;
    double sum = 0;
    for (int i = 0; i <= n; ++i) {
      const double z = -H / 2 + H * i / n, w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
      sum += w * brinkman_profile(z, kp, alpha, H);
    }
    EXPECT_NEAR(sum / (3.0 * n), kappa_eff_brinkman(kp, alpha, H), 1e-10) << "alpha " << alpha;
  }
  // αH ≫ 1: κ_p (1 − 1/(αH/2)); αH ≪ 1: κ_p (αH/2)²/3 = (H²/12) μ/μ_eff.
  EXPECT_NEAR(kappa_eff_brinkman(kp, 100 / H, H), kp * (1 - 1 / 50.0), 1e-15);
  for (double alpha : {1e-2 / H, 1e-4 / H, 1e-7 / H}) {
    const double x = alpha * H / 2;
    EXPECT_NEAR(kappa_eff_brinkman(kp, alpha, H) / (kappa_walls(H) / mu_eff_ratio(kp, alpha)), 1.0, x * x);
  }
  EXPECT_EQ(kappa_eff_brinkman(kp, 0.0, H), 0.0);
  // μ_eff/μ = 1/(κ_p α²) and back; the paper's μ_eff ≈ 2.1 μ of the regular lattices.
  EXPECT_NEAR(mu_eff_ratio(kp, alpha_from_mu_eff(kp, 2.1)), 2.1, 1e-14);
  expect_invalid([] { mu_eff_ratio(-1, 1); }, "kappa_p");
}

// z at the centres of 0.5σ bins across H = 7.5σ (section 2.5.2).
std::vector<double> bin_centres(double H) {
  std::vector<double> z;
  for (double zi = -H / 2 + 0.25; zi < H / 2; zi += 0.5) z.push_back(zi);
  return z;
}

TEST(BrinkmanFit, RecoversExactProfiles) {
  const double H = 7.5;
  const auto z = bin_centres(H);
  for (double alpha : {0.4, 0.9, 1.4, 8.0}) {
    std::vector<double> u;
    for (double zi : z) u.push_back(brinkman_profile(zi, 0.02, alpha, H));
    const auto fit = fit_brinkman(z, u, H);
    EXPECT_NEAR(fit.alpha / alpha, 1.0, 1e-7) << "alpha " << alpha;
    EXPECT_NEAR(fit.B / 0.02, 1.0, 1e-7);
    EXPECT_LT(fit.rms_residual, 1e-10);
    EXPECT_FALSE(fit.alpha_at_lower_bound || fit.alpha_at_upper_bound);
  }
}

TEST(BrinkmanFit, RecoversNoisyProfilesWithinTheirScatter) {
  // 1 % noise (of B) on 15 bins. Over these 400 noisy profiles at α = 0.9 (x = αH/2 = 3.4) the fitted
  // values scatter by 0.9 % in B and 2.1 % in α (largest deviations 2.6 % and 6.9 %, measured); each
  // must lie within 5 % and 15 %, and the means within 0.5 % and 1 % (no bias).
  const double H = 7.5, B = 1.0, alpha = 0.9;
  const auto z = bin_centres(H);
  std::mt19937_64 gen(42);
  std::normal_distribution<double> noise(0.0, 0.01);
  double sum_a = 0, sum_b = 0;
  const int trials = 400;
  for (int t = 0; t < trials; ++t) {
    std::vector<double> u;
    for (double zi : z) u.push_back(brinkman_profile(zi, B, alpha, H) + noise(gen));
    const auto fit = fit_brinkman(z, u, H);
    EXPECT_NEAR(fit.B, B, 0.05);
    EXPECT_NEAR(fit.alpha, alpha, 0.15 * alpha);
    EXPECT_NEAR(fit.rms_residual, 0.01, 0.006);
    sum_a += fit.alpha, sum_b += fit.B;
  }
  EXPECT_NEAR(sum_a / trials, alpha, 0.01 * alpha);  // no bias beyond 1 %
  EXPECT_NEAR(sum_b / trials, B, 0.005);
}

TEST(BrinkmanFit, PoiseuilleProfileStopsAtTheLowerBoundWithTheRightMidplaneVelocity) {
  const double H = 7.5;
  const auto z = bin_centres(H);
  std::vector<double> u;
  for (double zi : z) u.push_back(1.0 - 4 * zi * zi / (H * H));
  const auto fit = fit_brinkman(z, u, H);
  EXPECT_TRUE(fit.alpha_at_lower_bound);
  EXPECT_FALSE(fit.alpha_at_upper_bound);
  EXPECT_NEAR(fit.alpha * H / 2, 1e-3, 1e-9);
  EXPECT_NEAR(fit.B * fit.alpha * fit.alpha * H * H / 8, 1.0, 1e-6);  // u_s(0)
  EXPECT_LT(fit.rms_residual, 1e-6);
  // With 1 % noise the fit still returns a near-parabola: mid-plane velocity within 2 %.
  std::mt19937_64 gen(1);
  std::normal_distribution<double> noise(0.0, 0.01);
  for (double& ui : u) ui += noise(gen);
  const auto noisy = fit_brinkman(z, u, H);
  EXPECT_NEAR(brinkman_profile(0.0, noisy.B, noisy.alpha, H), 1.0, 0.02);
  EXPECT_LT(noisy.alpha * H / 2, 1.0);
}

TEST(BrinkmanFit, RefusesBadInput) {
  expect_invalid([] { fit_brinkman({0, 1}, {1, 1}, 4); }, "3 points");
  expect_invalid([] { fit_brinkman({0, 1, 3}, {1, 1, 1}, 4); }, "z[2]");
  expect_invalid([] { fit_brinkman({0, 1, 1.5}, {1, 1}, 4); }, "size");
  expect_invalid([] { fit_brinkman({0, 1, 1.5}, {0, 0, 0}, 4); }, "zero");
  expect_invalid([] { fit_brinkman({0, 1, 1.5}, {1, 1, 1}, 0); }, "H");
}

TEST(DarcyLine, ExactOnALineAndTheTextbookStandardErrors) {
  // Flux against pressure gradient through the origin, slope κ/μ: recovered to round-off.
  const std::vector<double> g = {0.1, 0.2, 0.3};
  std::vector<double> q;
  for (double gi : g) q.push_back(3.7e-3 * gi);
  const auto exact_fit = fit_line(g, q);
  EXPECT_NEAR(exact_fit.slope, 3.7e-3, 1e-15);
  EXPECT_NEAR(exact_fit.intercept, 0.0, 1e-16);
  EXPECT_NEAR(exact_fit.slope_error, 0.0, 1e-15);
  // By hand: x = 0..3, y = 0,1,1,3: slope 0.9, intercept −0.1, residuals 0.1, 0.2, −0.7, 0.4,
  // s² = 0.70/2, Sxx = 5: σ_slope = √0.07 = 0.2645751, σ_intercept = √(0.35 · 0.7) = 0.4949747.
  const auto fit = fit_line({0, 1, 2, 3}, {0, 1, 1, 3});
  EXPECT_NEAR(fit.slope, 0.9, 1e-14);
  EXPECT_NEAR(fit.intercept, -0.1, 1e-14);
  EXPECT_NEAR(fit.slope_error, 0.2645751311, 1e-9);
  EXPECT_NEAR(fit.intercept_error, 0.4949747468, 1e-9);
}

TEST(DarcyLine, SlopeErrorCoversTheTruthAtTheStudentTRate) {
  // 5 points (3 degrees of freedom): |slope − true| < t_{0.975,3} σ_slope = 3.182 σ_slope in 95 %
  // of noisy data sets; 4000 sets give 95 ± 0.7 % (2σ binomial tolerance 93.6–96.4 %).
  std::mt19937_64 gen(9);
  std::normal_distribution<double> noise(0.0, 0.05);
  const std::vector<double> x = {0.5, 1.0, 1.5, 2.0, 2.5};
  int covered = 0;
  const int sets = 4000;
  for (int s = 0; s < sets; ++s) {
    std::vector<double> y;
    for (double xi : x) y.push_back(0.2 + 1.3 * xi + noise(gen));
    const auto fit = fit_line(x, y);
    covered += std::abs(fit.slope - 1.3) < 3.182 * fit.slope_error;
  }
  EXPECT_NEAR(double(covered) / sets, 0.95, 0.014);
  expect_invalid([] { fit_line({1, 1, 1}, {1, 2, 3}); }, "distinct");
  expect_invalid([] { fit_line({1, 2}, {1, 2}); }, "3 points");
}

}  // namespace
}  // namespace mesoflow::pillars::permeability_theory_test
