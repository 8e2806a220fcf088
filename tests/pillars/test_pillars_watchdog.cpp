// The NaN watchdog on the pillars' MDPD system (pillars::watched, scenes/pillars/pillar_scene.hpp): a
// restore of the kept state (with the counters and the neighbor list's reference positions) makes the
// steps after it retrace the run bit for bit, across memory sorts, with tethered pillar particles and
// the driving force; a system forced to 2× its stability limit is stopped at the step a plain run
// first turns non-finite, naming a particle by its tag and a force term, and left in its last good state.
#include "scenes/pillars/pillar_scene.hpp"
#include "common/watchdog_replay.hpp"
#include "test_types.hpp"

#include <gtest/gtest.h>

#include <iostream>
#include <string>

namespace mesoflow::pillars {
namespace {

using Exec = Kokkos::DefaultExecutionSpace;
using System = mdpd::MdpdSystem<2, double, Exec>;
constexpr std::uint64_t seed = 11;

// A 10σ × 10σ periodic box of the paper's 2D fluid with one tethered pillar of diameter 4 and the
// driving force; `sort_every` rebuilds between memory sorts; the fluid is equilibrated for
// `equilibrate` steps before the pillar is carved (the driver's order).
struct PillarBox {
  SceneGeometry g;
  std::optional<System> sys;

  PillarBox(double dt, int sort_every, int equilibrate = 0) {
    g.dim = 2;
    g.Lx = g.Ly = 10;
    g.diameter = 4;
    g.centres = {{5.0, 5.0}};
    mdpd::MdpdParameters mp;
    mp.B = 30;
    mp.dt = dt;
    mdpd::MdpdOptions opt;
    opt.sort_every = sort_every;
    // Bit-for-bit replays: on a device backend with full lists, the deterministic-sum mode
    // (testing::reproducible_by_default).
    if (!testing::reproducible_by_default<Exec>()) opt.list_kind = NeighborListKind::full;
    const double lo[2] = {0, 0}, len[2] = {10, 10};
    const bool periodic[2] = {true, true};
    sys.emplace(mp, Box<2, double>(lo, len, periodic), seed, opt);
    fill_fluid(*sys, g, 6.0, seed);
    sys->begin();
    for (int s = 0; s < equilibrate; ++s) sys->step();
    carve_solids(*sys, g);
    sys->begin(sys->current_step());
    mdpd::DrivingRegion<double> region;
    region.force = 0.2;
    region.length = 3;
    sys->set_driving_region(region);
  }
};

TEST(PillarsWatchdog, ARestoreRetracesTheRunBitForBitAcrossMemorySorts) {
  PillarBox box(0.01, 2);
  auto& sys = *box.sys;
  for (int s = 0; s < 30; ++s) sys.step();
  auto w = watched(sys);
  const int sorts = sys.num_sorts();
  EXPECT_EQ(testing::replay_mismatches(w, 120, sys.particles.x, sys.particles.v), 0);
  EXPECT_GT(sys.num_sorts(), sorts + 2) << "the replay should cross memory sorts";
  ASSERT_TRUE(sys.has_solids());
  std::vector<std::string> names;
  for (const auto& t : w.terms) names.push_back(t.name);
  EXPECT_EQ(names, (std::vector<std::string>{
                       "MDPD conservative force A, B (eq. 9a)", "MDPD dissipative and random forces D, R (eqs. 9b-c)",
                       "WCA repulsion of solid cores", "tether springs k_S", "driving force f_b"}));
}

// Each term alone, summed, is the force of a step's evaluation (the run's kernels on the same state).
TEST(PillarsWatchdog, TheTermsAloneSumToTheSystemsForces) {
  PillarBox box(0.01, 20);
  auto& sys = *box.sys;
  for (int s = 0; s < 20; ++s) sys.step();
  auto w = watched(sys);
  // The forces of the last step were evaluated at the half-step velocities: re-evaluate at v.
  sys.compute_forces(false, sys.particles.v);
  const auto full = testing::host_values(sys.particles.f);
  std::vector<double> sum(full.size(), 0.0);
  for (const auto& t : w.terms) {
    t.evaluate();
    const auto part = testing::host_values(sys.particles.f);
    for (std::size_t k = 0; k < sum.size(); ++k) sum[k] += part[k];
  }
  double worst = 0, scale = 0;
  for (std::size_t k = 0; k < sum.size(); ++k) {
    worst = std::max(worst, std::abs(sum[k] - full[k]));
    scale = std::max(scale, std::abs(full[k]));
  }
  EXPECT_LT(worst, 1e-10 * scale);
}

TEST(PillarsWatchdog, StopsASystemForcedAboveItsStabilityLimitAtTheStepAPlainRunBlowsUp) {
  // The 2D limit is 0.0104 (dissipation D): the fluid survives 40 steps, the carved box a few more.
  const double dt = 0.017;
  PillarBox plain_box(dt, 2, 40);
  auto& plain = *plain_box.sys;
  auto plain_view = watched(plain);
  const long long expected = testing::first_non_finite_step(
      [&] { plain.step(); }, [&] { return (long long)plain.current_step(); }, plain_view.state, 20000);
  ASSERT_GT(expected, 0);

  PillarBox box(dt, 2, 40);
  auto& sys = *box.sys;
  watchdog::NanWatchdog dog(watched(sys), 5);
  try {
    for (int s = 0; s < 20000; ++s) {
      sys.step();
      dog.after_step();
    }
    FAIL() << "an MDPD system at 2x the stability limit stayed finite";
  } catch (const watchdog::NonFiniteState& e) {
    std::cout << e.what() << '\n';
    const auto& d = e.diagnosis();
    EXPECT_EQ(d.first_bad_step, expected) << e.what();
    EXPECT_GE(d.last_good_step, 40) << e.what();  // after the carving
    EXPECT_FALSE(d.term.empty()) << e.what();
    EXPECT_NE(std::string(e.what()).find("of particle "), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(", stored at "), std::string::npos) << e.what();
    EXPECT_EQ((long long)sys.current_step(), d.last_good_step);
    EXPECT_EQ(first_non_finite(sys.particles.x), -1);
    EXPECT_EQ(first_non_finite(sys.particles.v), -1);
  }
}

}  // namespace
}  // namespace mesoflow::pillars
