// permeability_estimates.hpp — the permeabilities of a pillar-array flow run from its accumulated
// samples (pillar paper, eqs. 1–3, 5, 7; host only, no Kokkos). The samples come from
// scenes/pillars/pillar_flow.hpp (per elevation bin: fluid count, Σ u_x, pillar x-force; the
// tethers' force, the fluid in the driving region, per-sample means for block errors).
//
//   Darcy (eqs. 1-2): U_s = ε⟨u_x⟩, κ = μ U_s L_x / Δp, with the paper's Δp = f_b ρ L_d; also Δp from
//     the force balance f_b N_d/(ε A_⊥), N_d the fluid particles actually in the driving region.
//   Drag (eq. 3): κ_p = π μ U_s d²/(4 φ F_d), F_d = F_m/(n_m h), F_m the x-force of the fluid on the
//     n_m pillars whose axes lie in the measurement region (from the pair forces and the tethers).
//   Walls (3D): u_s(z) per bin, fitted with Brinkman's eq. (5).
// Errors: the naive standard error of ⟨u_x⟩ (samples treated as independent) and the block error
// from 10 block means (of the region's ⟨u_x⟩, and of the whole box's flux for the chosen estimator) (samples within a block are correlated; blocks of ≥ 100τ in the documented
// runs are not).
#pragma once

#include "analysis/pillars/permeability_theory.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <string>
#include <optional>
#include <utility>
#include <vector>

namespace mesoflow::pillars {

// What a flow run measured and the scene it ran in.
struct FlowMeasurement {
  // Scene.
  int dim = 2;
  double Lx = 0, Ly = 0, Lz = 0, H = 0;  // H > 0: walls (3D)
  double diameter = 0, porosity = 1;
  std::vector<std::array<double, 2>> centres;
  double x_lo = 0, x_hi = 0;            // measurement region
  double viscosity = 0, driving_force = 0, density = 0, driving_length = 0;
  // Samples, summed over `samples` samples.
  std::vector<double> count, velocity, pillar_force;  // per elevation bin
  double tether = 0, driven = 0;                      // Σ tether x-force on the measured pillars, Σ N_d
  double sum_u = 0, sum_u2 = 0;                       // Σ⟨u_x⟩, Σ⟨u_x⟩² per sample
  std::vector<double> sample_u, sample_tether;        // per sample
  long long samples = 0;
  double count_all = 0, velocity_all = 0, tether_all = 0;  // whole box: fluid count, Σu_x, all pillars' tethers
  std::vector<double> sample_u_box;                        // per sample: the whole box's Σu_x (its flux)
  // Per sample and elevation bin (sample-major): fluid count and Σu_x; empty: no jackknife.
  std::vector<double> sample_count_profile, sample_velocity_profile;

  bool walls() const { return dim == 3 && H > 0; }
};

struct PermeabilityEstimates {
  double mean_u = 0, mean_u_naive_error = 0, mean_u_block_error = 0, tether_block_error = 0;
  double superficial_velocity = 0;                     // U_s
  double pressure_difference = 0, pressure_difference_force_balance = 0;
  double kappa_darcy = 0, kappa_darcy_force_balance = 0;
  double pillar_force_pair = 0, pillar_force_tether = 0;  // F_m per sample
  int measured_pillars = 0;                            // n_m
  double kappa_drag_pair = 0, kappa_drag_tether = 0;
  // One volume for both estimators (issue 28, item 1). The volume flux from the fluid's momentum,
  // U_s = Σu_x/(ρ V), exact in a steady state whatever the local porosity (the paper's ε⟨u⟩ takes
  // the array's mean ε with the region's ⟨u⟩); in the region and over the whole box; the region's
  // fluid fraction N_f/(ρ V_r). Darcy over the whole period with the paper's Δp and the box flux;
  // eq. (3) over the region with the region's own pillar density (n_m pillars in V_r: F per volume
  // F_m/V_r) and the region's flux: the region's permeability.
  double region_fluid_fraction = 0, superficial_velocity_region = 0, superficial_velocity_box = 0;
  double kappa_darcy_box = 0, kappa_drag_tether_region = 0;
  double kappa_darcy_relative_error = 0, kappa_drag_tether_relative_error = 0;
  double kappa_darcy_box_relative_error = 0;  // block error of the box flux over its mean (0: no per-sample flux)
  // Elevation profile (one bin without walls): bin centre z (about the mid-plane), ⟨u_x⟩, u_s,
  // pillar force density, and the Brinkman fit (3D with walls and pillars).
  std::vector<double> z, mean_ux, u_s, pillar_force_density, brinkman;
  std::optional<BrinkmanFit> fit;
  // Jackknife over 10 blocks of samples (delete one block, refit; σ² = (n−1)/n Σ(θ_k − θ̄)²) of
  // the fit's α and B; 0 blocks: no per-sample profiles, no error.
  int jackknife_blocks = 0;
  double alpha_jackknife_error = 0, B_jackknife_error = 0;
};

// Standard error of the mean from 10 block means (0 with fewer than 10 samples).
inline double block_error(const std::vector<double>& x) {
  const int blocks = 10;
  const std::size_t per = x.size() / blocks;
  if (per == 0) return 0.0;
  double m = 0, m2 = 0;
  for (int b = 0; b < blocks; ++b) {
    double s = 0;
    for (std::size_t k = 0; k < per; ++k) s += x[b * per + k];
    s /= double(per);
    m += s;
    m2 += s * s;
  }
  m /= blocks;
  return std::sqrt(std::max(0.0, m2 / blocks - m * m) / (blocks - 1));
}

// The Brinkman fit's jackknife error (PermeabilityEstimates::alpha_jackknife_error): the profile
// with one of 10 equal blocks of samples left out (samples beyond 10 blocks always kept) is refitted
// per block. Needs ≥ 10 samples of per-sample profiles matching the bins; otherwise leaves 0.
inline void brinkman_jackknife(const FlowMeasurement& m, PermeabilityEstimates& e) {
  const int blocks = 10;
  const std::size_t bins = m.count.size();
  if (bins == 0 || m.sample_count_profile.size() != m.sample_velocity_profile.size() ||
      m.sample_count_profile.size() % bins != 0)
    return;
  const std::size_t n = m.sample_count_profile.size() / bins, per = n / blocks;
  if (per == 0) return;
  std::vector<double> total_c(bins, 0.0), total_u(bins, 0.0);
  for (std::size_t s = 0; s < n; ++s)
    for (std::size_t b = 0; b < bins; ++b) {
      total_c[b] += m.sample_count_profile[s * bins + b];
      total_u[b] += m.sample_velocity_profile[s * bins + b];
    }
  std::vector<double> alpha(blocks), amplitude(blocks), u_s(bins);
  for (int k = 0; k < blocks; ++k) {
    std::vector<double> c = total_c, u = total_u;
    for (std::size_t s = k * per; s < (k + 1) * per; ++s)
      for (std::size_t b = 0; b < bins; ++b) {
        c[b] -= m.sample_count_profile[s * bins + b];
        u[b] -= m.sample_velocity_profile[s * bins + b];
      }
    for (std::size_t b = 0; b < bins; ++b) u_s[b] = c[b] > 0 ? m.porosity * u[b] / c[b] : 0.0;
    const BrinkmanFit f = fit_brinkman(e.z, u_s, m.H);
    alpha[k] = f.alpha;
    amplitude[k] = f.B;
  }
  const auto jackknife = [&](const std::vector<double>& x) {
    double mean = 0, ss = 0;
    for (double v : x) mean += v;
    mean /= blocks;
    for (double v : x) ss += (v - mean) * (v - mean);
    return std::sqrt(ss * (blocks - 1) / blocks);
  };
  e.jackknife_blocks = blocks;
  e.alpha_jackknife_error = jackknife(alpha);
  e.B_jackknife_error = jackknife(amplitude);
}

inline PermeabilityEstimates estimate_permeability(const FlowMeasurement& m) {
  constexpr double pi = 3.14159265358979323846;
  PermeabilityEstimates e;
  const int bins = int(m.count.size());
  const double samples = double(m.samples);
  double n_fluid = 0, u_sum = 0, f_sum = 0;
  for (int b = 0; b < bins; ++b) {
    n_fluid += m.count[b];
    u_sum += m.velocity[b];
    f_sum += m.pillar_force[b];
  }
  e.mean_u = u_sum / n_fluid;
  e.mean_u_block_error = block_error(m.sample_u);
  e.tether_block_error = block_error(m.sample_tether);
  e.mean_u_naive_error =
      std::sqrt(std::max(0.0, m.sum_u2 / m.samples - (m.sum_u / m.samples) * (m.sum_u / m.samples)) / samples);
  e.superficial_velocity = m.porosity * e.mean_u;
  const double U_s = e.superficial_velocity;
  const double height = m.dim == 3 ? (m.walls() ? m.H : m.Lz) : 1.0;
  e.pressure_difference = m.driving_force * m.density * m.driving_length;
  e.pressure_difference_force_balance = m.driving_force * (m.driven / samples) / (m.porosity * m.Ly * height);
  e.kappa_darcy = m.viscosity * U_s * m.Lx / e.pressure_difference;
  e.kappa_darcy_force_balance = m.viscosity * U_s * m.Lx / e.pressure_difference_force_balance;
  e.pillar_force_pair = f_sum / samples;
  e.pillar_force_tether = -m.tether / samples;
  const bool has_pillars = !m.centres.empty();
  for (const auto& c : m.centres) {
    double s = c[0] - m.x_lo;
    s -= m.Lx * std::floor(s / m.Lx);
    e.measured_pillars += s < m.x_hi - m.x_lo;
  }
  const double phi = 1 - m.porosity;
  const int n_m = e.measured_pillars;
  const auto kappa_eq3 = [&](double F_m) {
    return has_pillars && n_m > 0 && F_m != 0
               ? pi * m.viscosity * U_s * m.diameter * m.diameter / (4 * phi * F_m / (n_m * height))
               : 0.0;
  };
  e.kappa_drag_pair = kappa_eq3(e.pillar_force_pair);
  e.kappa_drag_tether = kappa_eq3(e.pillar_force_tether);
  {
    const double v_region = (m.x_hi - m.x_lo) * m.Ly * height, v_box = m.Lx * m.Ly * height;
    if (m.density > 0 && samples > 0) {
      e.region_fluid_fraction = n_fluid / (samples * m.density * v_region);
      e.superficial_velocity_region = u_sum / (samples * m.density * v_region);
      e.superficial_velocity_box = m.velocity_all / (samples * m.density * v_box);
    }
    e.kappa_darcy_box = m.viscosity * e.superficial_velocity_box * m.Lx / e.pressure_difference;
    e.kappa_drag_tether_region = has_pillars && n_m > 0 && e.pillar_force_tether != 0
                                     ? m.viscosity * e.superficial_velocity_region * v_region / e.pillar_force_tether
                                     : 0.0;
  }
  e.kappa_darcy_relative_error = e.mean_u_block_error / std::abs(e.mean_u);
  if (!m.sample_u_box.empty()) {
    double mean_flux = 0;
    for (double v : m.sample_u_box) mean_flux += v;
    mean_flux /= double(m.sample_u_box.size());
    e.kappa_darcy_box_relative_error = mean_flux != 0 ? block_error(m.sample_u_box) / std::abs(mean_flux) : 0.0;
  }
  e.kappa_drag_tether_relative_error = std::sqrt(std::pow(e.mean_u_block_error / e.mean_u, 2) +
                                                 std::pow(e.tether_block_error / e.pillar_force_tether, 2));

  e.z.resize(bins);
  e.mean_ux.resize(bins);
  e.u_s.resize(bins);
  e.pillar_force_density.resize(bins);
  const double bw = m.walls() ? m.H / bins : 1.0;
  for (int b = 0; b < bins; ++b) {
    e.z[b] = m.walls() ? (b + 0.5) * bw - 0.5 * m.H : 0.0;
    e.mean_ux[b] = m.count[b] > 0 ? m.velocity[b] / m.count[b] : 0.0;
    e.u_s[b] = m.count[b] > 0 ? m.porosity * m.velocity[b] / m.count[b] : 0.0;
    e.pillar_force_density[b] = m.pillar_force[b] / samples / ((m.x_hi - m.x_lo) * m.Ly * bw);
  }
  if (m.walls() && has_pillars && bins >= 3) e.fit = fit_brinkman(e.z, e.u_s, m.H);
  if (e.fit) brinkman_jackknife(m, e);
  e.brinkman.resize(bins);
  for (int b = 0; b < bins; ++b) e.brinkman[b] = e.fit ? brinkman_profile(e.z[b], e.fit->B, e.fit->alpha, m.H) : 0.0;
  return e;
}

// The square-array theories of κ/d² at porosity ε (Fig. 7(b)), named as in the run summary.
inline std::array<std::pair<const char*, double>, 4> square_array_theory(double eps) {
  return {{{"gebart_square", kappa_gebart_square(eps)},
           {"drummond_tahir_square", kappa_drummond_tahir_square(eps)},
           {"sangani_acrivos_dense", kappa_sangani_acrivos_dense(eps)},
           {"tsay_weinbaum_fit", kappa_tsay_weinbaum_fit(eps)}}};
}

// Brinkman's fit (eq. 5, α with its error δα) with the pillars' own permeability κ_p (from the
// matching 2D run), walls H apart: κ_p, μ_eff/μ = 1/(κ_p α²) and its error from δα alone
// (2 μ_eff δα/α; κ_p's own error is the 2D run's), eq. (7)'s κ_eff and B's theory value
// κ_p Δp/(μ L_x), named as in the run summary.
inline std::array<std::pair<const char*, double>, 5> brinkman_theory(double kappa_p, double alpha, double alpha_error,
                                                                     double H, double pressure_difference,
                                                                     double mu, double Lx) {
  const double mu_eff = mu_eff_ratio(kappa_p, alpha);
  return {{{"kappa_p", kappa_p},
           {"mu_eff_over_mu", mu_eff},
           {"mu_eff_over_mu_error_alpha", 2 * mu_eff * alpha_error / alpha},
           {"kappa_eff_eq7", kappa_eff_brinkman(kappa_p, alpha, H)},
           {"B_theory", kappa_p * pressure_difference / (mu * Lx)}}};
}

// The elevation profile of a flow run as CSV at `path`: per bin z, the fluid samples `count`, ⟨u_x⟩,
// u_s, the pillar force density and the Brinkman fit.
inline void write_flow_profile(const std::string& path, const PermeabilityEstimates& e,
                               const std::vector<double>& count) {
  std::ofstream csv(path);
  csv << "z,fluid_samples,mean_ux,u_s,pillar_force_density,brinkman_fit\n" << std::setprecision(10);
  for (std::size_t b = 0; b < count.size(); ++b)
    csv << e.z[b] << "," << count[b] << "," << e.mean_ux[b] << "," << e.u_s[b] << "," << e.pillar_force_density[b]
        << "," << e.brinkman[b] << "\n";
}

// The viscosity of periodic Poiseuille flow (Backer et al. 2005) from its velocity profile: the
// force ±g reverses at z = 0 and L/2, so u(z) = s(z) a q(z) + c with q = z'(L/2 − z'), s = ±1 by
// half; a and c by linear least squares over the bins more than r_A = 1 from the reversal planes
// (the finite interaction range rounds the cusp there), η = ρ g/(2a).
struct PoiseuilleViscosity {
  std::vector<double> z, u, fit;  // bin centres, ⟨u_x⟩, the fitted profile
  double a = 0, c = 0, a_error = 0, viscosity = 0, viscosity_error = 0, max_velocity = 0;
  double thermal_temperature = 0;  // the kinetic temperature less the streaming profile's share
};

// `count`, `velocity`: per bin over z ∈ [0, L), summed over the samples; `mean_temperature`: the
// mean kinetic temperature of the samples; `dim`: the dimension (for the streaming share).
inline PoiseuilleViscosity fit_poiseuille_viscosity(const std::vector<double>& count,
                                                    const std::vector<double>& velocity, double L, double rho,
                                                    double force, double mean_temperature, int dim) {
  PoiseuilleViscosity r;
  const int bins = int(count.size());
  const double half = 0.5 * L;
  double sqq = 0, sq = 0, s1 = 0, squ = 0, su = 0;
  std::vector<double> model_q(bins);
  r.z.resize(bins);
  r.u.resize(bins);
  int fitted = 0;
  for (int b = 0; b < bins; ++b) {
    r.z[b] = (b + 0.5) * L / bins;
    const double zp = r.z[b] < half ? r.z[b] : r.z[b] - half;
    const double sign = r.z[b] < half ? 1.0 : -1.0;
    model_q[b] = sign * zp * (half - zp);
    r.u[b] = velocity[b] / count[b];
    if (zp < 1.0 || half - zp < 1.0) continue;
    ++fitted;
    sqq += model_q[b] * model_q[b];
    sq += model_q[b];
    s1 += 1;
    squ += model_q[b] * r.u[b];
    su += r.u[b];
  }
  const double det = sqq * s1 - sq * sq;
  r.a = (squ * s1 - sq * su) / det;
  r.c = (sqq * su - sq * squ) / det;
  r.viscosity = rho * force / (2 * r.a);
  double rss = 0;
  for (int b = 0; b < bins; ++b) {
    const double zp = r.z[b] < half ? r.z[b] : r.z[b] - half;
    if (zp >= 1.0 && half - zp >= 1.0) rss += std::pow(r.u[b] - (r.a * model_q[b] + r.c), 2);
  }
  double stream2 = 0, total_count = 0;
  for (int b = 0; b < bins; ++b) {
    stream2 += count[b] * r.u[b] * r.u[b];
    total_count += count[b];
  }
  r.thermal_temperature = mean_temperature - stream2 / total_count / dim;
  // Standard error of a from the residuals (bins independent) → relative error of η.
  const double sigma2 = rss / std::max(1, fitted - 2);
  r.a_error = std::sqrt(sigma2 * s1 / det);
  r.viscosity_error = r.viscosity * r.a_error / r.a;
  r.max_velocity = r.a * half * half / 4;
  r.fit.resize(bins);
  for (int b = 0; b < bins; ++b) r.fit[b] = r.a * model_q[b] + r.c;
  return r;
}

// The velocity profile of the Poiseuille run and its fit as CSV at `path` (z, ⟨u_x⟩, fit per bin).
inline void write_viscosity_profile(const std::string& path, const PoiseuilleViscosity& fit) {
  std::ofstream csv(path);
  csv << "z,mean_ux,fit\n" << std::setprecision(10);
  for (std::size_t b = 0; b < fit.z.size(); ++b) csv << fit.z[b] << "," << fit.u[b] << "," << fit.fit[b] << "\n";
}

// The square-array theory curves of Fig. 7(b) (and the hexagonal ones) over ε = 0.40 … 0.99 as
// CSV at `curves`, and Sangani & Acrivos' exact square-array values at `table`.
inline void write_theory_tables(const std::string& curves, const std::string& table) {
  std::ofstream csv(curves);
  csv << "porosity,gebart_square,drummond_tahir_square,sangani_acrivos_dilute,sangani_acrivos_dense,"
         "tsay_weinbaum_fit,gebart_hexagonal,drummond_tahir_hexagonal\n"
      << std::setprecision(8);
  for (int k = 0; k <= 118; ++k) {
    const double eps = 0.4 + 0.005 * k;
    csv << eps << "," << kappa_gebart_square(eps) << "," << kappa_drummond_tahir_square(eps) << ","
        << kappa_sangani_acrivos_dilute(eps) << "," << kappa_sangani_acrivos_dense(eps) << ","
        << kappa_tsay_weinbaum_fit(eps) << "," << kappa_gebart_hexagonal(eps) << ","
        << kappa_drummond_tahir_hexagonal(eps) << "\n";
  }
  std::ofstream t(table);
  t << "porosity,kappa_over_d2\n" << std::setprecision(8);
  for (const auto& row : sangani_acrivos_square_table()) t << row[0] << "," << row[1] << "\n";
}

}  // namespace mesoflow::pillars
