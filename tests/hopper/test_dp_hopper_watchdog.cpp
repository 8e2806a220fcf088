// The NaN watchdog on the DP hopper (DpHopperScene::watched(), scenes/hopper/dp_hopper_scene.hpp):
// a restore of the kept state (with the neighbor list's reference positions and wall candidates)
// makes the steps after it retrace the run bit for bit, and a hopper forced to 4× its stability
// limit is stopped at the step a plain run first turns non-finite, naming a vertex of a polygon and
// a force term, and left in its last good state.
#include "scenes/hopper/dp_hopper_scene.hpp"
#include "common/watchdog_replay.hpp"

#include <gtest/gtest.h>

#include <iostream>
#include <string>

// Own namespace: this file shares a unity translation unit with others (tests/CMakeLists.txt).
namespace mesoflow::hopper::dp_hopper_watchdog_test {
namespace {

using Exec = Kokkos::DefaultExecutionSpace;
using Scene = DpHopperScene<double, Exec>;

DpHopperParameters small_hopper() {
  DpHopperParameters par;
  par.particles = 60;
  par.friction = 1;
  par.seed = 3;
  return par;
}

TEST(DpHopperWatchdog, ARestoreRetracesTheRunBitForBit) {
  Scene scene(small_hopper());
  scene.relax();
  for (int s = 0; s < 50; ++s) scene.step();
  auto w = scene.watched();
  const int builds = scene.neighbor_builds();
  EXPECT_EQ(testing::replay_mismatches(w, 400, scene.particles().x), 0);
  EXPECT_EQ(scene.steps(), 450);
  EXPECT_GT(scene.neighbor_builds(), builds + 2) << "the replay should cross neighbor-list rebuilds";
}

TEST(DpHopperWatchdog, StopsAHopperForcedAboveItsStabilityLimitAtTheStepAPlainRunBlowsUp) {
  auto par = small_hopper();
  par.dt = 4 * par.stability().max_dt();
  par.force_dt = true;
  Scene plain(par);
  plain.relax();
  auto plain_view = plain.watched();
  const long long expected = testing::first_non_finite_step([&] { plain.step(); }, [&] { return plain.steps(); },
                                                            plain_view.state, 20000);
  ASSERT_GT(expected, 50) << "the forced hopper should survive a few checks";

  Scene scene(par);
  scene.relax();
  watchdog::NanWatchdog dog(scene.watched(), 50);
  try {
    for (int s = 0; s < 20000; ++s) {
      scene.step();
      dog.after_step();
    }
    FAIL() << "a DP hopper at 4x the stability limit stayed finite";
  } catch (const watchdog::NonFiniteState& e) {
    std::cout << e.what() << '\n';
    const auto& d = e.diagnosis();
    EXPECT_EQ(d.first_bad_step, expected) << e.what();
    EXPECT_EQ(d.detected_step % 50, 0);
    EXPECT_FALSE(d.term.empty()) << e.what();
    EXPECT_NE(std::string(e.what()).find(" of polygon "), std::string::npos) << e.what();
    EXPECT_EQ(scene.steps(), d.last_good_step);
    EXPECT_EQ(first_non_finite(scene.particles().x), -1);
    EXPECT_EQ(first_non_finite(scene.particles().v), -1);
  }
}

}  // namespace
}  // namespace mesoflow::hopper::dp_hopper_watchdog_test
