// flow_measurement.hpp — the flow rate Q of a hopper scene (hopper-flows paper §4): area (2D) or
// volume (3D) leaving through the orifice per unit time, in Q0 = σ_avg^d/t0, after a steady state.
//
// The run is cut into windows of `window` t0; each gives a window rate q_n (crossed measure / window).
// Steady state: the first window n ≥ 2M (M = steady_windows) where the means of the last M rates and
// of the M before them differ by at most twice the standard error of that difference (the running Q
// has stopped drifting beyond its noise) and the last mean is > 0. Q is then the mean of the next
// `measure_windows` rates and its error the caller's estimate (`mean_and_error`: the driver, tests
// and perf/ pass the block-averaging one of analysis/common/block_average.hpp, a floor above this).
// Clogging: no particle has crossed for `clog_time` t0 (checked at each window's end) → Q = 0,
// clogged. Neither by `max_time` → steady = false, Q and its error from the windows of the run's
// second half.
#pragma once

#include "scenes/common/nan_watchdog.hpp"

#include <cmath>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace mesoflow::hopper {

struct FlowSettings {
  double window = 2.0;       // t0 per rate window
  int steady_windows = 4;    // M
  int measure_windows = 12;  // windows averaged once steady
  double clog_time = 20.0;   // t0 without a crossing → clogged
  double max_time = 2000.0;  // t0
  long long check_interval = 100;  // steps between NaN-watchdog checks (scenes/common/nan_watchdog.hpp)

  void validate() const {
    auto require = [](bool ok, const std::string& name, const std::string& range, double value) {
      if (!ok)
        throw std::invalid_argument("flow measurement: " + name + " must be " + range + ", got " +
                                    std::to_string(value));
    };
    require(std::isfinite(window) && window > 0, "window", "finite and > 0", window);
    require(steady_windows >= 2, "steady windows", ">= 2", steady_windows);
    require(measure_windows >= 4, "measure windows", ">= 4", measure_windows);
    require(std::isfinite(clog_time) && clog_time >= window, "clog time", ">= window", clog_time);
    require(std::isfinite(max_time) && max_time > window, "max time", "> window", max_time);
    require(check_interval >= 1 && check_interval <= 1000000, "watchdog interval", "in [1, 10^6] steps",
            double(check_interval));
  }
};

struct FlowResult {
  double Q = 0, Q_error = 0;
  bool clogged = false, steady = false;
  double steady_time = 0;  // t0 at which the steady state was detected
  double end_time = 0;
  std::vector<double> window_rates;
};

// Steps `scene` until steady and measured, clogged, or max_time; after each window calls
// on_window(scene, rate, measuring), measuring true for the windows that make Q (those after the
// steady state was detected; without a steady state, none). Q and Q_error come from
// mean_and_error(rates, Q, Q_error), rates a const std::vector<double>& of the windows that make Q
// (e.g. analysis::block_average).
template <class Scene, class MeanAndError>
FlowResult measure_flow_rate(Scene& scene, const FlowSettings& s, MeanAndError&& mean_and_error,
                             const std::function<void(const Scene&, double, bool)>& on_window = {}) {
  s.validate();
  const long long steps_per_window = std::max(1LL, std::llround(s.window / scene.dt()));
  const double window = steps_per_window * scene.dt();
  const int M = s.steady_windows;
  FlowResult r;
  double crossed = scene.crossed_measure();
  int measure_from = -1;
  auto watch = watchdog::watch_if_possible(scene, s.check_interval);
  while (scene.time() < s.max_time) {
    for (long long k = 0; k < steps_per_window; ++k) {
      scene.step();
      if (watch) watch->after_step();
    }
    const double q = (scene.crossed_measure() - crossed) / window;
    crossed = scene.crossed_measure();
    r.window_rates.push_back(q);
    if (watch) watch->check();  // no window is measured from a non-finite state
    if (on_window) on_window(scene, q, measure_from >= 0);
    if (scene.time() - scene.last_crossing_time() >= s.clog_time) {
      r.clogged = true;
      r.end_time = scene.time();
      return r;
    }
    const int n = int(r.window_rates.size());
    if (measure_from < 0 && n >= 2 * M) {
      double ma = 0, mb = 0, va = 0, vb = 0;
      for (int j = 0; j < M; ++j) {
        ma += r.window_rates[std::size_t(n - 2 * M + j)] / M;
        mb += r.window_rates[std::size_t(n - M + j)] / M;
      }
      for (int j = 0; j < M; ++j) {
        va += std::pow(r.window_rates[std::size_t(n - 2 * M + j)] - ma, 2) / (M - 1);
        vb += std::pow(r.window_rates[std::size_t(n - M + j)] - mb, 2) / (M - 1);
      }
      if (mb > 0 && std::abs(mb - ma) <= 2 * std::sqrt(va / M + vb / M)) {
        measure_from = n;
        r.steady = true;
        r.steady_time = scene.time();
      }
    }
    if (measure_from >= 0 && n - measure_from >= s.measure_windows) {
      mean_and_error(std::vector<double>(r.window_rates.begin() + measure_from, r.window_rates.end()), r.Q, r.Q_error);
      r.end_time = scene.time();
      return r;
    }
  }
  const std::size_t half = r.window_rates.size() / 2;
  mean_and_error(std::vector<double>(r.window_rates.begin() + long(half), r.window_rates.end()), r.Q, r.Q_error);
  r.end_time = scene.time();
  return r;
}

}  // namespace mesoflow::hopper
