// cost_clock.hpp — the cost side of the speed–accuracy trade-off reports (perf/tradeoff/): wall
// seconds and process CPU seconds of one run. CPU time is kept beside wall time because the runs
// may share a machine: on a contended core wall time grows while CPU time does not.
#pragma once

#include <chrono>
#include <ctime>

namespace mesoflow::tradeoff {

struct Cost {
  double wall = 0;  // s
  double cpu = 0;   // s, user + system of the whole process (all threads)
};

class CostClock {
 public:
  CostClock() : wall0_(std::chrono::steady_clock::now()), cpu0_(cpu_now()) {}
  Cost elapsed() const {
    return {std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0_).count(), cpu_now() - cpu0_};
  }

 private:
  static double cpu_now() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
  }
  std::chrono::steady_clock::time_point wall0_;
  double cpu0_;
};

}  // namespace mesoflow::tradeoff
