// sweep_results.hpp — the per-run results of the capsule sweeps (host only, no Kokkos): one row of
// the constriction table (passage time, D_∞,Λ at x_c = 4, C_f and C_r at x_c = 3.5, 4, 4.5, the run's
// numerics) with its CSV form, read back to reuse finished runs, and the sweep's table of Pearson's
// r against Ca per η (eq. 17, Table 1); the shear series (D_xy and θ/π per sample), the steady mean
// and spread of a shear series over its last part, and a shear run's row, read back likewise.
#pragma once

#include "analysis/capsule/capsule_shape.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
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

// The passage of a run whose rear left the constriction at `exit_time` (NaN: never), its front
// having reached it at `entry_time`: the passage time, its inverse, and the status "passed".
inline void set_passage(RunResult& r, double entry_time, double exit_time) {
  if (!std::isnan(exit_time)) {
    r.passage_time = exit_time - entry_time;
    r.inverse_passage_time = 1 / r.passage_time;
    r.status = "passed";
  }
}

// D_∞,Λ at x_c = 4 and C_f, C_r at x_c = 3.5, 4, 4.5 of `r` from a run's series against x_c.
inline void set_values_at(RunResult& r, const std::vector<double>& xs, const std::vector<double>& dx,
                          const std::vector<double>& dy, const std::vector<double>& dz, const std::vector<double>& cf,
                          const std::vector<double>& cr) {
  r.Dx4 = value_at(xs, dx, 4.0);
  r.Dy4 = value_at(xs, dy, 4.0);
  r.Dz4 = value_at(xs, dz, 4.0);
  const double at[3] = {3.5, 4.0, 4.5};
  for (int k = 0; k < 3; ++k) {
    r.Cf[k] = value_at(xs, cf, at[k]);
    r.Cr[k] = value_at(xs, cr, at[k]);
  }
}

// The sweep table: sweep_header and one csv_row per run.
inline std::string sweep_table(const std::vector<RunResult>& results) {
  std::ostringstream table;
  table << sweep_header << "\n";
  for (const auto& r : results) table << csv_row(r) << "\n";
  return table.str();
}

// Pearson's r against Ca per η (eq. 17, Table 1): for each η of `etas`, the named columns (as in
// the run summary) with r over the runs at that η (NaN where it has none, pearson_r).
inline std::vector<std::pair<double, std::vector<std::pair<std::string, double>>>> pearson_table(
    const std::vector<RunResult>& results, const std::vector<double>& etas) {
  std::vector<std::pair<double, std::vector<std::pair<std::string, double>>>> table;
  for (double eta : etas) {
    const auto column = [&](auto get) {
      std::vector<double> x, c;
      for (const auto& r : results)
        if (r.eta == eta) {
          x.push_back(get(r));
          c.push_back(r.ca);
        }
      return pearson_r(x, c);
    };
    using R = RunResult;
    std::vector<std::pair<std::string, double>> row{
        {"inverse_passage_time", column([](const R& r) { return r.inverse_passage_time; })},
        {"Dx_at_4", column([](const R& r) { return r.Dx4; })},
        {"Dy_at_4", column([](const R& r) { return r.Dy4; })},
        {"Dz_at_4", column([](const R& r) { return r.Dz4; })}};
    const char* at[3] = {"3.5", "4", "4.5"};
    for (int k = 0; k < 3; ++k) {
      row.emplace_back(std::string("Cf_at_") + at[k], column([k](const R& r) { return r.Cf[k]; }));
      row.emplace_back(std::string("Cr_at_") + at[k], column([k](const R& r) { return r.Cr[k]; }));
    }
    table.emplace_back(eta, std::move(row));
  }
  return table;
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

// A shear run's series: per sample the shear time, D_xy, θ/π, max |ρ − ρ0|/ρ0 and dt·γ̇, as CSV at
// `path` (flushed per row: the run can be watched), and kept for the steady values.
class ShearSeries {
 public:
  explicit ShearSeries(const std::string& path) : csv_(path) {
    csv_ << "shear_time,taylor_deformation,inclination_over_pi,max_density_deviation,dt_gamma\n"
         << std::setprecision(8);
  }

  void add(double t, const std::vector<Eigen::Vector3d>& y, double dens, double dt_gamma) {
    constexpr double pi = 3.14159265358979323846;
    const auto s = shear_plane_shape(y);
    csv_ << t << "," << s.taylor << "," << s.inclination / pi << "," << dens << "," << dt_gamma << std::endl;
    t_s.push_back(t);
    D_s.push_back(s.taylor);
    th_s.push_back(s.inclination / pi);
  }

  // The steady D_xy and θ/π: over the samples from shear time t_from on (steady_value).
  std::pair<SteadyValue, SteadyValue> steady_values(double t_from) const {
    return {steady_value(t_s, D_s, t_from), steady_value(t_s, th_s, t_from)};
  }

  std::vector<double> t_s, D_s, th_s;  // shear time, D_xy, θ/π per sample

 private:
  std::ofstream csv_;
};

inline const char* shear_header =
    "ca,taylor_deformation,taylor_deformation_std,inclination_over_pi,inclination_over_pi_std,dt_gamma,"
    "shear_time,particles,max_density_deviation,wall_seconds,series_csv,signature";

// A shear run's row under shear_header: Ca, the steady D_xy and θ/π, dt·γ̇, the run length, the
// particles, max |ρ − ρ0|/ρ0, the wall time, the series file and the scene's signature.
inline std::string shear_row(double ca, const SteadyValue& D, const SteadyValue& T, double dt_gamma, double t_max,
                             int particles, double max_density_deviation, double wall, const std::string& series_csv,
                             const std::string& signature) {
  std::ostringstream row;
  row << std::setprecision(8) << ca << "," << D.mean << "," << D.std << "," << T.mean << "," << T.std << ","
      << dt_gamma << "," << t_max << "," << particles << "," << max_density_deviation << "," << wall << ","
      << series_csv << "," << signature;
  return row.str();
}

// The row of a shear result file at `path` written under shear_header for the scene `signature`;
// nothing if there is none.
inline std::optional<std::string> read_shear_result(const std::string& path, const std::string& signature) {
  std::ifstream done(path);
  std::string h, row;
  if (done && std::getline(done, h) && std::getline(done, row) && h == shear_header &&
      row.size() > signature.size() && row.compare(row.size() - signature.size(), signature.size(), signature) == 0)
    return row;
  return std::nullopt;
}

}  // namespace mesoflow::capsule
