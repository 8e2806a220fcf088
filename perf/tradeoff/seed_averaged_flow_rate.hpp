// seed_averaged_flow_rate.hpp — the flow rate Q of one hopper configuration, averaged over seeds,
// with the cost of the flow (FIRE excluded): the measurement loop the SP and DP hopper trade-off
// programs (tradeoff_hopper.cpp, tradeoff_dp_hopper.cpp) share.
#pragma once

#include "analysis/common/block_average.hpp"
#include "scenes/hopper/flow_measurement.hpp"
#include "perf/tradeoff/cost_clock.hpp"

#include <cmath>
#include <cstdint>
#include <iostream>
#include <string>

namespace mesoflow::tradeoff {

struct FlowRateRuns {
  double Q = 0, Q_error = 0;  // mean over seeds, its error
  double flow_time = 0;       // t0 of flow, all seeds
  Cost cost;                  // of the flow, all seeds
  int clogged = 0, unsteady = 0;
};

// For each seed first_seed … first_seed + seeds − 1: make_scene(seed) builds the scene, relax()
// places it, measure_flow_rate runs the flow (Q and its error of one seed: the block average of
// analysis/common/block_average.hpp, as the hopper driver measures them). Unless quiet, one line
// per seed on standard error, starting with `label`.
template <class MakeScene>
FlowRateRuns seed_averaged_flow_rate(int seeds, std::uint64_t first_seed, const hopper::FlowSettings& flow,
                                     MakeScene&& make_scene, const std::string& label, bool quiet) {
  FlowRateRuns c;
  double var = 0;
  for (int s = 0; s < seeds; ++s) {
    const std::uint64_t seed = first_seed + std::uint64_t(s);
    auto scene = make_scene(seed);
    scene.relax();
    const double t0 = scene.time();
    const CostClock clock;
    const auto r = hopper::measure_flow_rate(scene, flow, analysis::block_average);
    const auto cost = clock.elapsed();
    c.cost.wall += cost.wall;
    c.cost.cpu += cost.cpu;
    c.flow_time += scene.time() - t0;
    c.Q += r.Q / seeds;
    var += (std::isfinite(r.Q_error) ? r.Q_error * r.Q_error : 0.0) / (double(seeds) * seeds);
    c.clogged += r.clogged;
    c.unsteady += !r.steady && !r.clogged;
    if (!quiet)
      std::cerr << label << " seed " << seed << ": Q = " << r.Q << " ± " << r.Q_error
                << (r.clogged ? " (clogged)" : r.steady ? "" : " (not steady)") << ", " << scene.time() - t0
                << " t0 of flow in " << cost.wall << " s wall, " << cost.cpu << " s CPU\n";
  }
  c.Q_error = std::sqrt(var);
  return c;
}

}  // namespace mesoflow::tradeoff
