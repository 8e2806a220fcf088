// phonon_spectra.hpp — phonon analysis of a 1D microfluidic crystal (microfluidic-crystal-phonons
// paper, §4–5): droplet elongations, the power spectra of eqs. (1)–(2), the correlation strength of
// longitudinal and transverse modes, eqs. (5)–(7), and their output with the theory curves of
// dispersion_theory.hpp (HDF5 + CSV; scripts/plot_crystal.py draws Figs. 3c,d and 4a from it).
// Host-side analysis (Eigen's FFT, kissfft backend), no Kokkos.
//
// Input: droplet centres x_j(t), y_j(t), j = 0..N−1 ordered along the train, t = 0..T−1 frames Δt
// apart, stored row-major as [t N + j]; x unwrapped, the channel periodic in x with length L = N a.
//
// SIGN CONVENTION. Eqs. (1)–(2) as printed, exp[−i(jka + tωΔt)], put a forward-travelling wave
// cos(k₀ja − ω₀t) at (k₀, −ω₀), while the dispersion relations (3), (4), (8) come from plane waves
// e^{i(kna − ωt)} (Appendix C) and give ω > 0 for forward travel. Here the time transform has the
// opposite sign,
//     x̃(k, ω) = Σ_t Σ_j δx_j(t) exp[−i(jka − tωΔt)],
// so that e^{i(k₀ja − ω₀t)} peaks at (k₀, ω₀) and the theory curves apply as printed: a real
// forward wave (ω₀/k₀ > 0) has its two peaks at (k₀, ω₀) and (−k₀, −ω₀), in the first and third
// quadrants; a backward wave in the second and fourth.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "analysis/crystal/dispersion_theory.hpp"

namespace mesoflow::crystal {

// §4: δx_j(t) = x_{j+1}(t) − x_j(t) and δy_j(t) = y_{j+1}(t) − y_center, j = 0..N−1, with the
// periodic image x_N = x_0 + N a, y_N = y_0. δy uses index j + 1 as printed; against y_j − y_center
// this multiplies every mode by e^{ika}, a phase that no power spectrum or |correlation| sees.
struct Elongations {
  std::size_t droplets = 0;  // N
  std::size_t frames = 0;    // T
  std::vector<double> dx;    // δx_j(t) at [t N + j]
  std::vector<double> dy;    // δy_j(t) at [t N + j]
};

// x, y of size N T (N ≥ 2, T ≥ 2), finite; a > 0. Throws std::invalid_argument naming the parameter.
Elongations elongations(const std::vector<double>& x, const std::vector<double>& y, std::size_t droplets,
                        std::size_t frames, double a, double y_center);

enum class TimeWindow {
  rectangular,  // w_t = 1
  hann,         // periodic Hann w_t = sin²(πt/T) = ½[1 − cos(2πt/T)]: a tone between two bins leaks
                // into its neighbours only (−31 dB side lobes), where the rectangular window spreads
                // a strong transverse peak across the whole ω axis of a log-scale map
};

// Defaults: Hann window, time mean removed per droplet j (the mean of δx_j is ≈ a, the static
// lattice; of δy_j the static zigzag: left in, they put N T ⟨δ⟩ in the k = 0, ω = 0 bin and, with a
// window, its leakage). The mean is removed first, then the window applied:
//     f_j(t) → w_t [f_j(t) − (1/T) Σ_s f_j(s)].
struct SpectrumOptions {
  TimeWindow window = TimeWindow::hann;
  bool subtract_mean = true;
};

std::vector<double> window_weights(TimeWindow window, std::size_t frames);

// The shifted grids: k_p = 2π m/(N a), m = p − ⌊N/2⌋, p = 0..N−1, in [−π/a, π/a); ω_q = 2π l/(T Δt),
// l = q − ⌊T/2⌋, in [−π/Δt, π/Δt). Both ascending.
std::vector<double> wavenumbers(std::size_t droplets, double a);
std::vector<double> frequencies(std::size_t frames, double dt);

// P(k_p, ω_q) = |Σ_t Σ_j f_j(t) exp[−i(j k_p a − t ω_q Δt)]|² at [p T + q], with f prepared as in
// SpectrumOptions. Unnormalised, as eqs. (1)–(2); Parseval: Σ_{p,q} P = N T Σ_{j,t} |f_j(t)|² (f after
// mean removal and window). field: N T values at [t N + j].
std::vector<double> power_spectrum(const std::vector<double>& field, std::size_t droplets, std::size_t frames,
                                   const SpectrumOptions& options = {});

struct PowerSpectra {
  std::size_t droplets = 0, frames = 0;
  double a = 0, dt = 0;
  SpectrumOptions options;
  std::vector<double> k;             // N values, wavenumbers()
  std::vector<double> omega;         // T values, frequencies()
  std::vector<double> transverse;    // |ỹ(k, ω)|², eq. (2), at [p T + q]
  std::vector<double> longitudinal;  // |x̃(k, ω)|², eq. (1), at [p T + q]
};

// a, dt > 0 and finite.
PowerSpectra power_spectra(const Elongations& e, double a, double dt, const SpectrumOptions& options = {});

// Correlation strength of longitudinal and transverse modes, eqs. (5)–(7), with the modes
//     x̃∥(m, t) = Σ_j δx_j(t) e^{−2πi jm/N},   ỹ⊥(m, t) = Σ_j δy_j(t) e^{−2πi jm/N}
// (j = 0..N−1: the same sums as j = 1..N of eqs. (6)–(7), the summand being N-periodic in j), after
// the time mean of each δ_j is removed (always: a static lattice or zigzag is no mode amplitude).
// Three definitions, each at [p∥ N + p⊥] over the shifted mode numbers m = p − ⌊N/2⌋:
//  (a) complex_literal: |⟨x̃(m∥) ỹ(m⊥)⟩_t| / √(⟨|x̃(m∥)|²⟩⟨|ỹ(m⊥)|²⟩), eq. (5) as printed (its
//      modulus). Phase-sensitive: 1 at m∥ = −m⊥ for a linear coupling δx_j ∝ δy_j (the acoustic
//      expectation k∥ = −k⊥ of §4), but ≈ 0 (noise, ~ T^{−1/2}) for the quadratic coupling
//      δx ∝ δy² the paper proposes: x̃(2m⊥) ỹ(m⊥) ∝ e^{−3iω⊥t} averages out.
//  (b) amplitude: ⟨|x̃(m∥)| |ỹ(m⊥)|⟩_t / √(⟨|x̃|²⟩⟨|ỹ|²⟩) ∈ [0, 1]. 1 for any two modes of steady
//      amplitude, π/4 for two independent Gaussian modes, √π/2 for one of each: a weak contrast.
//  (c) amplitude_fluctuation: Pearson correlation of |x̃(m∥)| − ⟨|x̃(m∥)|⟩ and |ỹ(m⊥)| − ⟨|ỹ(m⊥)|⟩,
//      ∈ [−1, 1]; ≈ 0 for independent modes. Under δx ∝ δy² the amplitude of x̃(2m⊥) follows that
//      of ỹ(m⊥) squared, so whatever modulates the transverse amplitude (noise on δy, a slow
//      envelope) shows here. This is the definition that shows Fig. 4a's ridge at k∥ = 2k⊥ with
//      contrast: on a quadratically coupled test signal 0.59 there against ≤ 0.09 at any other k∥,
//      where (b) gives 0.995 against 0.89 and (a) 0.002 (tests/crystal/test_phonon_spectra.cpp,
//      ModeCorrelation.QuadraticCouplingShowsTheRidgeInAmplitudeFluctuations).
// (b) and (c) use |x̃|, even in m for real δ: both are symmetric under m∥ → −m∥ and m⊥ → −m⊥, so
// the ridge shows on k∥ = ±2k⊥ alike. A mode whose ⟨|x̃|²⟩_t is ≤ 10⁻²⁰ of the field's largest
// carries round-off only (e.g. x̃∥(0, t) = Σ_j (δx_j − ⟨δx_j⟩_t) = N a − N a = 0, since Σ_j δx_j(t) =
// N a in every frame) and gets C = 0 in every definition; in (c) so does a mode whose amplitude
// variance is that small (a steady amplitude).
struct ModeCorrelation {
  std::size_t droplets = 0, frames = 0;
  double a = 0;
  std::vector<int> mode;                      // m, N values
  std::vector<double> k;                      // 2π m/(N a)
  std::vector<double> complex_literal;        // (a), [p∥ N + p⊥]
  std::vector<double> amplitude;              // (b)
  std::vector<double> amplitude_fluctuation;  // (c)
};

ModeCorrelation mode_correlation(const Elongations& e, double a);

// HDF5 output (an existing file is replaced). Root attributes: a, W, R, u_d, u_oil, K, B, beta, dt
// (double), N, T (int64), y_center = W/2, convention (string). Groups:
//   /spectra:     k [N], omega [T], transverse [N, T], longitudinal [N, T]; attributes window
//                 ("hann" or "rectangular"), subtract_mean (bool)
//   /theory:      k [theory_points] from −π/a to π/a; omega_transverse (eq. 3),
//                 omega_longitudinal (eq. 4), omega_coupled (eq. 8), omega_longitudinal_continuum
//                 (eq. 11), omega_transverse_continuum (eq. 12), omega_longitudinal_nn (eq. 13),
//                 omega_transverse_nn (eq. 14), each with an attribute `equation`; attribute
//                 phase_velocity
//   /correlation: mode [N], k [N], complex_literal, amplitude, amplitude_fluctuation [N, N]
//                 (rows k∥, columns k⊥); attribute ridge = "amplitude_fluctuation"
// spectra and correlation must come from the same elongations with a = p.a; theory_points ≥ 2.
void write_phonon_analysis(const std::string& h5_path, const CrystalParameters& p, const PowerSpectra& spectra,
                           const ModeCorrelation& correlation, std::size_t theory_points = 401);

// The theory curves as CSV, one row per k from −π/a to π/a (points ≥ 2), columns
// k, omega_eq3, omega_eq4, omega_eq8, omega_eq11, omega_eq12, omega_eq13, omega_eq14, 17 significant
// digits (every value reads back exactly).
void write_theory_csv(const std::string& csv_path, const DispersionTheory& theory, std::size_t points = 201);

}  // namespace mesoflow::crystal
