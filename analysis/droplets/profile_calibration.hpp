// profile_calibration.hpp — calibration of the DP model against a measured speed profile
// (capillary-droplets §4.1), host-only (no Kokkos): Γ and b0/b∞ that minimise the RMS relative
// speed deviation Δ_v of eq. 14 between a measured v_g(h) and simulated orifice passages. b∞ is
// fixed beforehand by the terminal speed V_t (eq. 15). The passages are the caller's: a callable
// simulate(Γ, b0/b∞) returning a profile (.h, .vg, .outcome), which the `calibrate` driver and its
// tests compose from scenes/droplets/orifice_run.hpp (calibration_scene, run_orifice).
//
// Units as in scenes/droplets/droplet_scene.hpp; speeds are compared as v_g/v_t, so the measured
// profile may come from any experiment once h is in droplet diameters and v_g in terminal speeds.
#pragma once

#include "analysis/common/nelder_mead.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <functional>
#include <numeric>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace mesoflow::droplets {

// The simplex of the calibration: analysis/common/nelder_mead.hpp.
using analysis::nelder_mead;
using analysis::SimplexResult;
using analysis::SimplexSettings;

// A measured profile: one entry per video frame, h/σ and v_g/v_t.
struct MeasuredProfile {
  std::vector<double> h, vg_over_vt;
};

// Reads a CSV with a header naming the columns `h` and `vg_over_vt` (other columns are ignored;
// the `orifice` driver's profile CSV qualifies). Throws std::invalid_argument naming the file, line
// and column on anything else: a missing column, a non-numeric or non-finite value, fewer than 3 rows.
inline MeasuredProfile read_measured_profile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::invalid_argument("--measured " + path + ": cannot read the file");
  auto split = [](const std::string& line) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) {
      cell.erase(0, cell.find_first_not_of(" \t\r"));
      cell.erase(cell.find_last_not_of(" \t\r") + 1);
      cells.push_back(cell);
    }
    return cells;
  };
  std::string line;
  if (!std::getline(in, line)) throw std::invalid_argument("--measured " + path + ": the file is empty");
  const auto header = split(line);
  const auto column = [&](const char* name) {
    const auto it = std::find(header.begin(), header.end(), name);
    if (it == header.end())
      throw std::invalid_argument("--measured " + path + ": the header has no column '" + name +
                                  "' (needs h and vg_over_vt)");
    return std::size_t(it - header.begin());
  };
  const std::size_t ch = column("h"), cv = column("vg_over_vt");
  MeasuredProfile m;
  for (int number = 2; std::getline(in, line); ++number) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const auto cells = split(line);
    auto value = [&](std::size_t c, const char* name) {
      const std::string where = "--measured " + path + ": line " + std::to_string(number) + ", column " + name;
      if (c >= cells.size()) throw std::invalid_argument(where + ": missing value");
      std::size_t used = 0;
      double v;
      try {
        v = std::stod(cells[c], &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used == 0 || used != cells[c].size()) throw std::invalid_argument(where + ": '" + cells[c] + "' is not a number");
      if (!std::isfinite(v)) throw std::invalid_argument(where + ": value " + cells[c] + " is not finite");
      return v;
    };
    m.h.push_back(value(ch, "h"));
    m.vg_over_vt.push_back(value(cv, "vg_over_vt"));
  }
  if (m.h.size() < 3)
    throw std::invalid_argument("--measured " + path + ": needs at least 3 frames, got " + std::to_string(m.h.size()));
  return m;
}

// Relative deviations divide by v_sim (eq. 14); a simulated droplet that has stopped, or never
// reaches a measured h, has v_sim = 0 there, so the divisor is floored at this fraction of v_t
// (a frame it misses counts like a speed error of 1/floor: Δ_v stays finite and large).
constexpr double speed_floor = 0.01;

// v_sim at a measured h by linear interpolation between consecutive simulated samples (§4.1):
// the first sample pair in time order that brackets h; 0 if the droplet never gets there.
inline double simulated_speed_at(const std::vector<double>& h, const std::vector<double>& vg_over_vt, double at) {
  for (std::size_t k = 0; k + 1 < h.size(); ++k) {
    const double a = h[k], b = h[k + 1];
    if ((a <= at && at <= b) || (b <= at && at <= a)) {
      const double s = b == a ? 0.0 : (at - a) / (b - a);
      return vg_over_vt[k] + s * (vg_over_vt[k + 1] - vg_over_vt[k]);
    }
  }
  return 0.0;
}

// Δ_v of eq. 14: √( Σ_i ((v_exp,i − v_sim,i)/v_sim,i)² / N_f ), v_sim,i interpolated at h_exp,i.
inline double speed_deviation(const MeasuredProfile& measured, const std::vector<double>& sim_h,
                              const std::vector<double>& sim_vg_over_vt) {
  double sum = 0;
  for (std::size_t i = 0; i < measured.h.size(); ++i) {
    const double v_sim = std::max(simulated_speed_at(sim_h, sim_vg_over_vt, measured.h[i]), speed_floor);
    const double rel = (measured.vg_over_vt[i] - v_sim) / v_sim;
    sum += rel * rel;
  }
  return std::sqrt(sum / double(measured.h.size()));
}

// Which parameters the calibration fits; the other stays at the simulation's own value.
enum class FitParameters { both, line_tension, near_wall_drag };

struct CalibrationBounds {
  double gamma_min = 0.01, gamma_max = 10;  // Γ, the paper's range (§2.2)
  double drag_min = 0.005, drag_max = 1;    // b0/b∞

  void validate() const {
    if (!(gamma_min > 0 && gamma_min < gamma_max))
      throw std::invalid_argument("--gamma-min, --gamma-max: need 0 < gamma-min < gamma-max, got " +
                                  std::to_string(gamma_min) + ", " + std::to_string(gamma_max));
    if (!(drag_min > 0 && drag_min < drag_max))
      throw std::invalid_argument("--drag-min, --drag-max: need 0 < drag-min < drag-max, got " +
                                  std::to_string(drag_min) + ", " + std::to_string(drag_max));
  }
};

// The first guesses of the fitted parameters (a parameter that is not fitted keeps the simulation's
// own value, which the caller passes here too, so that every evaluation reports both).
struct CalibrationGuess {
  double line_tension, near_wall_drag;
};

// One orifice passage of the calibration; Outcome is the simulated profile's `.outcome` type.
template <class Outcome>
struct CalibrationEvaluation {
  double line_tension, near_wall_drag, speed_deviation;
  Outcome outcome;
  double seconds;
};

template <class Profile>
struct CalibrationResult {
  using Evaluation = CalibrationEvaluation<std::decay_t<decltype(std::declval<const Profile&>().outcome)>>;
  double line_tension = 0, near_wall_drag = 0, speed_deviation = HUGE_VAL;
  bool converged = false;
  std::vector<Evaluation> history;
  Profile best_profile;
};

// The profile that simulate(line_tension, near_wall_drag) returns, both arguments std::optional<double>.
template <class Simulate>
using SimulatedProfile =
    std::decay_t<std::invoke_result_t<Simulate&, std::optional<double>, std::optional<double>>>;

// Minimises Δ_v over Γ and/or b0/b∞ in logarithmic coordinates (both are positive scales) inside
// `bounds`: a grid of grid_points per fitted parameter (none if < 2: `guess` is the first point),
// then Nelder–Mead; settings.max_evaluations counts both (a point visited again is not run again).
// Each point is one call simulate(Γ, b0/b∞): the trial value of a fitted parameter, std::nullopt
// for one that is not fitted (the simulation keeps its own, guess's); the profile's v_g is divided
// by terminal_speed (v_t) before eq. 14. `on_evaluation` sees each passage as it completes.
template <class Simulate>
CalibrationResult<SimulatedProfile<Simulate>> calibrate(
    const MeasuredProfile& measured, Simulate&& simulate, const CalibrationGuess& guess, double terminal_speed,
    FitParameters fit, const CalibrationBounds& bounds, const SimplexSettings& settings, int grid_points,
    const std::function<void(const typename CalibrationResult<SimulatedProfile<Simulate>>::Evaluation&)>&
        on_evaluation = {}) {
  using Result = CalibrationResult<SimulatedProfile<Simulate>>;
  bounds.validate();
  const bool fit_gamma = fit != FitParameters::near_wall_drag, fit_drag = fit != FitParameters::line_tension;
  if (fit_drag && !(guess.near_wall_drag > 0))
    throw std::invalid_argument("--near-wall-drag: the first guess of b0/b∞ must be > 0 to fit it");
  std::vector<double> x0, lo, hi;
  if (fit_gamma) {
    x0.push_back(std::log(guess.line_tension));
    lo.push_back(std::log(bounds.gamma_min));
    hi.push_back(std::log(bounds.gamma_max));
  }
  if (fit_drag) {
    x0.push_back(std::log(guess.near_wall_drag));
    lo.push_back(std::log(bounds.drag_min));
    hi.push_back(std::log(bounds.drag_max));
  }
  Result result;
  std::vector<std::pair<std::vector<double>, double>> seen;  // the simplex revisits points: run each once
  auto objective = [&](const std::vector<double>& x) {
    for (const auto& [at, value] : seen)
      if (at == x) return value;
    std::optional<double> gamma, drag;
    std::size_t k = 0;
    if (fit_gamma) gamma = std::exp(x[k++]);
    if (fit_drag) drag = std::exp(x[k]);
    const auto start = std::chrono::steady_clock::now();
    auto prof = simulate(gamma, drag);
    std::vector<double> v(prof.vg.size());
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = prof.vg[i] / terminal_speed;
    const double dv = speed_deviation(measured, prof.h, v);
    const typename Result::Evaluation e{
        gamma.value_or(guess.line_tension), drag.value_or(guess.near_wall_drag), dv, prof.outcome,
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()};
    result.history.push_back(e);
    if (on_evaluation) on_evaluation(e);
    if (dv < result.speed_deviation) {
      result.speed_deviation = dv;
      result.line_tension = e.line_tension;
      result.near_wall_drag = e.near_wall_drag;
      result.best_profile = std::move(prof);
    }
    seen.emplace_back(x, dv);
    return dv;
  };
  // Stage 1: a coarse grid over the box (Δ_v is rugged far from the optimum: a stiffer or softer
  // droplet stalls at another h, and eq. 14 divides by the small speeds there), so the simplex
  // starts in the right basin. Stage 2: Nelder–Mead from the best grid point, steps of half a cell.
  SimplexSettings refine = settings;
  if (grid_points > 1) {
    const std::size_t n = x0.size();
    std::vector<int> index(n, 0);
    double best = HUGE_VAL;
    for (bool more = true; more;) {
      std::vector<double> x(n);
      for (std::size_t d = 0; d < n; ++d) x[d] = lo[d] + (hi[d] - lo[d]) * index[d] / (grid_points - 1);
      const double v = objective(x);
      if (v < best) {
        best = v;
        x0 = x;
      }
      more = false;
      for (std::size_t d = 0; d < n && !more; ++d) {
        if (++index[d] < grid_points) more = true;
        else index[d] = 0;
      }
    }
    double cell = HUGE_VAL;
    for (std::size_t d = 0; d < n; ++d) cell = std::min(cell, (hi[d] - lo[d]) / (grid_points - 1));
    refine.initial_step = 0.5 * cell;
    refine.max_evaluations = std::max(1, settings.max_evaluations - int(result.history.size()));
  }
  const auto best = nelder_mead(objective, x0, lo, hi, refine);
  result.converged = best.converged;
  return result;
}

}  // namespace mesoflow::droplets
