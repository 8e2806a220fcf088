// sweep_results.hpp — the per-run results of the capsule sweeps (host only, no Kokkos): one row of
// the constriction table (passage time, D_∞,Λ at x_c = 4, C_f and C_r at x_c = 3.5, 4, 4.5, the run's
// numerics) with its CSV form, read back to reuse finished runs; the steady mean and spread of a
// shear series over its last part.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace mesoflow::capsule {

// One constriction run's results (a row of the sweep table).
struct RunResult {
  double ca = 0, eta = 0, eta_effective = 0;
  std::string status;  // passed, blocked (stalled), blocked (t-max)
  double passage_time = NAN, inverse_passage_time = 0;
  double Dx4 = NAN, Dy4 = NAN, Dz4 = NAN;
  double Cf[3] = {NAN, NAN, NAN}, Cr[3] = {NAN, NAN, NAN};  // at x_c = 3.5, 4, 4.5
  double max_density_deviation = 0;
  double dt = 0, c0 = 0, k_b = 0, steps = 0, wall_seconds = 0, particle_steps_per_second = 0;
  int particles = 0;
  std::string series_csv, sections_csv, signature;
};

inline const char* sweep_header =
    "ca,eta,eta_effective,status,passage_time,inverse_passage_time,Dx_at_4,Dy_at_4,Dz_at_4,Cf_at_3.5,Cf_at_4,"
    "Cf_at_4.5,Cr_at_3.5,Cr_at_4,Cr_at_4.5,max_density_deviation,dt,c0,k_b,steps,particles,wall_seconds,"
    "particle_steps_per_second,series_csv,sections_csv,signature";

inline std::string csv_row(const RunResult& r) {
  std::ostringstream s;
  s << std::setprecision(8) << r.ca << "," << r.eta << "," << r.eta_effective << "," << r.status << ","
    << r.passage_time << "," << r.inverse_passage_time << "," << r.Dx4 << "," << r.Dy4 << "," << r.Dz4;
  for (double c : r.Cf) s << "," << c;
  for (double c : r.Cr) s << "," << c;
  s << "," << r.max_density_deviation << "," << r.dt << "," << r.c0 << "," << r.k_b << "," << r.steps << ","
    << r.particles << "," << r.wall_seconds << "," << r.particle_steps_per_second << "," << r.series_csv << ","
    << r.sections_csv << "," << r.signature;
  return s.str();
}

// The row of a result file written by csv_row under sweep_header; nothing if it is not one.
inline std::optional<RunResult> read_result(const std::string& path) {
  std::ifstream f(path);
  std::string header, row;
  if (!f || !std::getline(f, header) || !std::getline(f, row) || header != sweep_header) return std::nullopt;
  std::vector<std::string> c;
  std::stringstream ss(row);
  std::string item;
  while (std::getline(ss, item, ',')) c.push_back(item);
  if (c.size() != 26) return std::nullopt;
  auto num = [&](int k) { return std::strtod(c[std::size_t(k)].c_str(), nullptr); };
  RunResult r;
  r.ca = num(0);
  r.eta = num(1);
  r.eta_effective = num(2);
  r.status = c[3];
  r.passage_time = num(4);
  r.inverse_passage_time = num(5);
  r.Dx4 = num(6);
  r.Dy4 = num(7);
  r.Dz4 = num(8);
  for (int k = 0; k < 3; ++k) {
    r.Cf[k] = num(9 + k);
    r.Cr[k] = num(12 + k);
  }
  r.max_density_deviation = num(15);
  r.dt = num(16);
  r.c0 = num(17);
  r.k_b = num(18);
  r.steps = num(19);
  r.particles = int(num(20));
  r.wall_seconds = num(21);
  r.particle_steps_per_second = num(22);
  r.series_csv = c[23];
  r.sections_csv = c[24];
  r.signature = c[25];
  return r;
}

// Mean and standard deviation of x over the samples with t ≥ t_from (NaN mean without any).
struct SteadyValue {
  double mean = NAN, std = NAN;
};
inline SteadyValue steady_value(const std::vector<double>& t, const std::vector<double>& x, double t_from) {
  double s = 0, s2 = 0;
  int n = 0;
  for (std::size_t k = 0; k < t.size(); ++k)
    if (t[k] >= t_from) {
      s += x[k];
      s2 += x[k] * x[k];
      ++n;
    }
  const double m = n ? s / n : NAN;
  return {m, std::sqrt(std::max(0.0, s2 / n - m * m))};
}

}  // namespace mesoflow::capsule
