// progress.hpp — progress reporting for long runs, after LAMMPS: a periodic progress line (steps/s,
// particle-updates/s, time remaining), a closing summary, and a per-kernel wall-time table.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <iostream>
#include <string>
#include <string_view>
#include <vector>

namespace mesoflow::cli {

// Prints, at most once per interval, a full line such as
//   step 12000/100000 (12.0%)  4.1e+03 steps/s  8.2e+06 particle-updates/s  ETA 0:00:21
// Rates are measured since the previous line. Lines end in '\n' (no carriage returns), so CI logs
// stay readable. A disabled ProgressLine (--quiet) prints nothing at all.
class ProgressLine {
 public:
  using Clock = std::chrono::steady_clock;

  ProgressLine(std::int64_t total_steps, std::int64_t particle_count, bool enabled, std::ostream& out = std::cerr,
               Clock::duration interval = std::chrono::seconds(1));

  // Call after every step with the number of steps done. Cheap: the clock is read only every
  // check_stride calls, a stride that adapts so that the clock is read a few dozen times per interval.
  void update(std::int64_t steps_done);
  // Prints the summary: steps done, wall time since construction, mean rates.
  void finish();

 private:
  void adapt_stride(Clock::duration since_last_check);
  void print_progress(std::int64_t steps_done, Clock::time_point now);

  std::int64_t total_steps_;
  std::int64_t particle_count_;
  bool enabled_;
  std::ostream* out_;
  Clock::duration interval_;
  Clock::time_point start_;
  Clock::time_point last_check_;
  Clock::time_point last_print_;
  std::int64_t last_print_steps_ = 0;
  std::int64_t steps_done_ = 0;
  std::int64_t calls_since_check_ = 0;
  std::int64_t check_stride_ = 1;
};

// Wall time per kernel, printed at the end of a run as a table (name, seconds, % of run, calls).
// The run's clock starts when the KernelTimers is constructed: construct it just before the loop.
class KernelTimers {
 public:
  KernelTimers();

  void print(std::ostream& out) const;

 private:
  friend class ScopedTimer;
  struct Entry {
    std::string name;
    double seconds = 0.0;
    std::int64_t calls = 0;
  };

  std::size_t entry(std::string_view name);
  void record(std::size_t entry, double seconds);

  std::vector<Entry> entries_;  // in order of first use
  std::chrono::steady_clock::time_point start_;
};

// Times one scope into a KernelTimers entry: `ScopedTimer timer(timers, "neighbor");`.
// Kernel launches are asynchronous on GPUs, so it calls Kokkos::fence() on entry (earlier kernels
// are not charged to this one) and on exit (this one's kernels are).
class ScopedTimer {
 public:
  ScopedTimer(KernelTimers& timers, std::string_view name);
  ~ScopedTimer();
  ScopedTimer(const ScopedTimer&) = delete;
  ScopedTimer& operator=(const ScopedTimer&) = delete;

 private:
  KernelTimers& timers_;
  std::size_t entry_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace mesoflow::cli
