// time_step_limit.hpp — the one rule every driver applies to --dt: a time step above the scene's
// estimated explicit stability limit is refused with a message naming the limiting term and the
// limit, unless the user passes --force-dt, in which case the run goes on after a warning on
// standard error that names the same term and limit (docs/command-line.md, docs/stability.md).
//
// The limits themselves live next to the kernels of each model (kernels/<model>/stability.hpp,
// kernels/sph/sph_time_step.hpp); this header only applies them. It is free of CLI11 so that the
// scenes, which the tests build directly, can include it.
#pragma once

#include <cmath>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>

namespace mesoflow::cli {

// The switch every driver registers with DriverApp::add_flag(force_dt_flag, var, force_dt_help).
inline constexpr const char* force_dt_flag = "--force-dt";
inline constexpr const char* force_dt_help =
    "run with a --dt above the estimated stability limit (a warning naming the limiting term instead of an error)";

// A scene's largest stable Δt and the term that sets it ("wall repulsion E_w (ω = 12/t0)").
struct TimeStepLimit {
  double max_dt = HUGE_VAL;
  std::string term;
};

// "<who>: time step dt must be <= LIMIT for these parameters (stability limit set by TERM), got DT".
inline std::string time_step_message(const std::string& who, double dt, const TimeStepLimit& limit) {
  std::ostringstream s;
  s.precision(6);
  s << who << ": time step dt must be <= " << limit.max_dt << " for these parameters (stability limit set by "
    << limit.term << "), got " << dt;
  return s.str();
}

// Nothing when dt <= limit.max_dt. Above it: throws std::invalid_argument (DriverApp::run turns it
// into exit code 2) naming the term and the limit, or, with `force`, writes that message as a
// warning line to `warn` and returns.
inline void check_time_step(const std::string& who, double dt, const TimeStepLimit& limit, bool force,
                            std::ostream& warn = std::cerr) {
  if (!(dt > limit.max_dt)) return;
  if (!force) throw std::invalid_argument(time_step_message(who, dt, limit) + "; " + force_dt_flag + " runs it anyway");
  warn << "warning: " << time_step_message(who, dt, limit) << "; running anyway (" << force_dt_flag << ")\n";
}

}  // namespace mesoflow::cli
