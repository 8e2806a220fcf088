// progress.cpp — ProgressLine, KernelTimers and ScopedTimer.
#include "drivers/common/progress.hpp"

#include <Kokkos_Core.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <sstream>

namespace mesoflow::cli {
namespace {

double seconds_of(std::chrono::steady_clock::duration duration) {
  return std::chrono::duration<double>(duration).count();
}

// numerator / denominator, or 0 for a run too short to have been timed.
double ratio(double numerator, double denominator) { return denominator > 0.0 ? numerator / denominator : 0.0; }

// "H:MM:SS", hours unbounded.
std::string clock_time(double seconds) {
  const long long total = std::llround(std::max(seconds, 0.0));
  char text[32];
  std::snprintf(text, sizeof text, "%lld:%02lld:%02lld", total / 3600, total / 60 % 60, total % 60);
  return text;
}

// The clock is read at least this many times per interval, and at most twice as often as that.
constexpr int checks_per_interval = 16;
constexpr std::int64_t max_check_stride = std::int64_t{1} << 20;

}  // namespace

ProgressLine::ProgressLine(std::int64_t total_steps, std::int64_t particle_count, bool enabled, std::ostream& out,
                           Clock::duration interval)
    : total_steps_(total_steps),
      particle_count_(particle_count),
      enabled_(enabled),
      out_(&out),
      interval_(interval),
      start_(Clock::now()),
      last_check_(start_),
      last_print_(start_) {}

void ProgressLine::update(std::int64_t steps_done) {
  if (!enabled_) return;
  steps_done_ = steps_done;
  if (++calls_since_check_ < check_stride_) return;
  calls_since_check_ = 0;
  const Clock::time_point now = Clock::now();
  adapt_stride(now - last_check_);
  last_check_ = now;
  if (now - last_print_ >= interval_) print_progress(steps_done, now);
}

void ProgressLine::adapt_stride(Clock::duration since_last_check) {
  const Clock::duration target = interval_ / checks_per_interval;
  if (since_last_check < target / 2 && check_stride_ < max_check_stride) {
    check_stride_ *= 2;
  } else if (since_last_check > target && check_stride_ > 1) {
    check_stride_ /= 2;
  }
}

void ProgressLine::print_progress(std::int64_t steps_done, Clock::time_point now) {
  const double seconds = seconds_of(now - last_print_);
  const std::int64_t steps = steps_done - last_print_steps_;
  if (steps <= 0 || seconds <= 0.0) return;
  const double steps_per_second = ratio(static_cast<double>(steps), seconds);
  const double percent =
      total_steps_ > 0 ? 100.0 * static_cast<double>(steps_done) / static_cast<double>(total_steps_) : 100.0;
  const double remaining = static_cast<double>(std::max<std::int64_t>(total_steps_ - steps_done, 0));
  char line[192];
  std::snprintf(line, sizeof line, "step %lld/%lld (%.1f%%)  %.1e steps/s  %.1e particle-updates/s  ETA %s\n",
                static_cast<long long>(steps_done), static_cast<long long>(total_steps_), percent, steps_per_second,
                steps_per_second * static_cast<double>(particle_count_),
                clock_time(remaining / steps_per_second).c_str());
  *out_ << line << std::flush;
  last_print_ = now;
  last_print_steps_ = steps_done;
}

void ProgressLine::finish() {
  if (!enabled_) return;
  const double seconds = seconds_of(Clock::now() - start_);
  const double steps_per_second = ratio(static_cast<double>(steps_done_), seconds);
  char line[192];
  std::snprintf(line, sizeof line, "done: %lld steps in %s (%.3g s)  mean %.1e steps/s  %.1e particle-updates/s\n",
                static_cast<long long>(steps_done_), clock_time(seconds).c_str(), seconds, steps_per_second,
                steps_per_second * static_cast<double>(particle_count_));
  *out_ << line << std::flush;
}

KernelTimers::KernelTimers() : start_(std::chrono::steady_clock::now()) {}

std::size_t KernelTimers::entry(std::string_view name) {
  const auto found =
      std::find_if(entries_.begin(), entries_.end(), [name](const Entry& entry) { return entry.name == name; });
  if (found != entries_.end()) return static_cast<std::size_t>(found - entries_.begin());
  entries_.push_back({std::string(name)});
  return entries_.size() - 1;
}

void KernelTimers::record(std::size_t entry, double seconds) {
  entries_[entry].seconds += seconds;
  entries_[entry].calls += 1;
}

void KernelTimers::print(std::ostream& out) const {
  const double run_seconds = seconds_of(std::chrono::steady_clock::now() - start_);
  std::size_t width = std::string_view("kernel").size();
  for (const Entry& entry : entries_) width = std::max(width, entry.name.size());
  const int name_width = static_cast<int>(width);

  std::ostringstream table;
  table << std::fixed << std::left << std::setw(name_width) << "kernel" << std::right << std::setw(12) << "seconds"
        << std::setw(10) << "% of run" << std::setw(12) << "calls" << '\n';
  const auto row = [&](const std::string& name, double seconds) -> std::ostringstream& {
    table << std::left << std::setw(name_width) << name << std::right << std::setprecision(3) << std::setw(12)
          << seconds << std::setprecision(1) << std::setw(10) << 100.0 * ratio(seconds, run_seconds);
    return table;
  };
  double timed_seconds = 0.0;
  for (const Entry& entry : entries_) {
    row(entry.name, entry.seconds) << std::setw(12) << entry.calls << '\n';
    timed_seconds += entry.seconds;
  }
  row("other", std::max(run_seconds - timed_seconds, 0.0)) << '\n';
  row("run", run_seconds) << '\n';
  out << table.str();
}

ScopedTimer::ScopedTimer(KernelTimers& timers, std::string_view name)
    : timers_(timers), entry_(timers.entry(name)) {
  Kokkos::fence();
  start_ = std::chrono::steady_clock::now();
}

ScopedTimer::~ScopedTimer() {
  Kokkos::fence();
  timers_.record(entry_, seconds_of(std::chrono::steady_clock::now() - start_));
}

}  // namespace mesoflow::cli
