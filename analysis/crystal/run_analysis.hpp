// run_analysis.hpp — what a crystal run measured, from its frames (host only, no Kokkos): the
// means of u_d and u_oil over the measured frames (K = u_d/u_oil), and the phonon analysis of those
// frames (phonon_spectra.hpp) with the theory of dispersion_theory.hpp at this run's spacing and
// velocities (mpc-microfluidic-crystal-phonons §4–5, Appendix B).
#pragma once

#include "analysis/crystal/dispersion_theory.hpp"
#include "analysis/crystal/phonon_spectra.hpp"

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace mesoflow::crystal {

// The measured frames (step >= warmup, the frame at the warmup step included): the first one, how
// many, and the means of u_d and u_oil over them.
struct MeasuredFrames {
  std::size_t first = 0, count = 0;
  double u_d = 0, u_oil = 0;
};

inline MeasuredFrames measured_frames(const std::vector<std::int64_t>& steps, const std::vector<double>& u_d,
                                     const std::vector<double>& u_oil, std::int64_t warmup_steps) {
  MeasuredFrames m;
  while (m.first < steps.size() && steps[m.first] < warmup_steps) ++m.first;
  m.count = steps.size() - m.first;
  if (m.count < 2) throw std::runtime_error("crystal: fewer than two measured frames; raise --time or lower --frame-interval");
  for (std::size_t t = m.first; t < steps.size(); ++t) {
    m.u_d += u_d[t] / double(m.count);
    m.u_oil += u_oil[t] / double(m.count);
  }
  return m;
}

// K = u_d/u_oil and the dimensionless numbers of a run (Appendix B) from its measured frames, with
// the solvent's η (eq. B.3), mass density ρ = n m/Δx², the disc radius R, the plate friction γ and
// k_BT: Re = ρ u_oil R/η, Pe = u_oil R γ/k_BT (D = k_BT/γ: the plate friction dominates the discs'
// diffusion).
struct RunNumbers {
  double K = 0, reynolds = 0, peclet = 0;
};

inline RunNumbers run_numbers(const MeasuredFrames& m, double eta, double rho, double R, double friction, double kT) {
  return {m.u_d / m.u_oil, rho * m.u_oil * R / eta, m.u_oil * R * friction / kT};
}

// The theory's numbers at this run: u_oil used, spacing a = L/N, B, β and the phase velocity.
struct PhononSummary {
  double theory_uoil = 0, spacing = 0, B = 0, beta = 0, phase_velocity = 0;
};

// The phonon analysis of the measured frames (from frame `m.first` on; x, y: the disc centres of
// every frame, frame-major, `discs` per frame) in a channel of length L and width W with discs of
// radius R, frames dt_frame apart: the elongations, the power spectra and the mode correlation in
// `h5_path`, the theory curves in `csv_path`.
inline PhononSummary phonon_analysis(const std::vector<double>& x_all, const std::vector<double>& y_all,
                                     const MeasuredFrames& m, std::size_t discs, double L, double W, double R,
                                     double calibrated_ratio, double dt_frame, const std::string& h5_path,
                                     const std::string& csv_path) {
  PhononSummary p;
  p.spacing = L / double(discs);
  std::vector<double> x(x_all.begin() + std::ptrdiff_t(m.first * discs), x_all.end());
  std::vector<double> y(y_all.begin() + std::ptrdiff_t(m.first * discs), y_all.end());
  // Appendix B: the theory takes K from an independent single-disc run when one is given, with
  // this run's droplet velocity: u_oil = u_d/K.
  p.theory_uoil = calibrated_ratio > 0 ? m.u_d / calibrated_ratio : m.u_oil;
  const CrystalParameters cp{p.spacing, W, R, m.u_d, p.theory_uoil};
  const auto el = elongations(x, y, discs, m.count, p.spacing, 0.5 * W);
  const auto spectra = power_spectra(el, p.spacing, dt_frame);
  const auto corr = mode_correlation(el, p.spacing);
  write_phonon_analysis(h5_path, cp, spectra, corr);
  const DispersionTheory theory(cp);
  write_theory_csv(csv_path, theory);
  p.B = theory.B();
  p.beta = theory.beta();
  p.phase_velocity = theory.phase_velocity();
  return p;
}

}  // namespace mesoflow::crystal
