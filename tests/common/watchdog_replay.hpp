// watchdog_replay.hpp — test helpers for scenes' NaN-watchdog views (scenes/common/nan_watchdog.hpp):
// whether a restore of the kept state makes the steps after it retrace the run, and the first step
// of a plain run whose state is non-finite (the step the watchdog's replay must find).
#pragma once

#include "scenes/common/nan_watchdog.hpp"

#include <Kokkos_Core.hpp>

#include <cstring>
#include <vector>

namespace mesoflow::testing {

// Host copy of a rank-2 View, row by row.
template <class View>
std::vector<double> host_values(const View& a) {
  const auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), a);
  std::vector<double> out;
  for (std::size_t i = 0; i < h.extent(0); ++i)
    for (std::size_t d = 0; d < h.extent(1); ++d) out.push_back(double(h(i, d)));
  return out;
}

// Host copies of rank-2 Views, one after the other.
template <class... Views>
std::vector<double> host_values_of(const Views&... views) {
  std::vector<double> out;
  for (const auto& part : {host_values(views)...}) out.insert(out.end(), part.begin(), part.end());
  return out;
}

// Keeps the watched state (as a passed check does), runs `steps` steps and copies `views` (x, v…);
// restores the state as the watchdog does before its replay and runs the same steps again. Returns
// the number of entries whose bits differ between the two runs (0: the replay retraces the run), or
// -1 if the step counter was not restored.
template <class... Views>
long long replay_mismatches(watchdog::Watched& w, long long steps, const Views&... views) {
  for (auto& f : w.state) f.save();
  if (w.save_host) w.save_host();
  const long long start = w.steps();
  for (long long s = 0; s < steps; ++s) w.step();
  const std::vector<double> first = host_values_of(views...);
  for (auto& f : w.state) f.restore();
  w.set_steps(start);
  if (w.restore_host) w.restore_host();
  if (w.after_restore) w.after_restore();
  if (w.steps() != start) return -1;
  for (long long s = 0; s < steps; ++s) w.step();
  const std::vector<double> second = host_values_of(views...);
  long long differ = 0;
  for (std::size_t k = 0; k < first.size(); ++k)
    differ += std::memcmp(&first[k], &second[k], sizeof(double)) != 0;
  return differ;
}

// The first step after which any of `fields` holds a non-finite value, stepping `step` at most
// `max_steps` times from `steps()` (-1 if none).
template <class Step, class Steps>
long long first_non_finite_step(Step&& step, Steps&& steps, const std::vector<watchdog::Field>& fields,
                                long long max_steps) {
  const long long end = steps() + max_steps;
  while (steps() < end) {
    step();
    for (const auto& f : fields)
      if (f.first_bad() >= 0) return steps();
  }
  return -1;
}

}  // namespace mesoflow::testing
