// The NaN watchdog on the capsule scene (CapsuleScene::watched(), scenes/capsule/capsule_scene.hpp).
// A restore puts back every permuted array, the bond maps, the slots, and the SPH system's counters
// and neighbor list (SphSystem::resume): the replay crosses memory sorts with the bonds and slots
// following them and repeats the run bit for bit. The particle slots that name particles by
// build-order index follow the sorts. (A forced run stopped by the watchdog is the driver tests
// Capsule.Watchdog*: the scene blows up fastest in the driver's shear and constriction set-ups.)
#include "scenes/capsule/capsule_scene.hpp"
#include "common/watchdog_replay.hpp"
#include "test_types.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>

namespace mesoflow {
namespace {

using capsule::CapsuleScene;
using capsule::CapsuleSceneParameters;
using Exec = Kokkos::DefaultExecutionSpace;

CapsuleSceneParameters small_scene() {
  CapsuleSceneParameters par;
  par.sites = {16, 16, 16};
  par.radius = 4;
  par.thickness = 1;
  par.level = 2;
  par.k_b = 1;
  par.u_max = 0.2;
  par.stretch = {1.2, 1 / std::sqrt(1.2), 1 / std::sqrt(1.2)};
  par.capsule_velocity = {0.1, 0, 0};
  return par;
}

// Membrane positions in mesh order (through the slots), on the host.
std::vector<double> membrane_positions(const CapsuleScene<double, Exec>& scene) {
  const auto x = testing::host_values(scene.system().particles.x);
  const auto slot = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), scene.membrane_slot());
  std::vector<double> out;
  for (std::size_t k = 0; k < slot.extent(0); ++k)
    for (int d = 0; d < 3; ++d) out.push_back(x[std::size_t(3 * slot(k) + d)]);
  return out;
}

// On a device backend with full lists, the deterministic-sum mode (testing::reproducible_by_default).
TEST(CapsuleWatchdog, AReplayAcrossMemorySortsRepeatsTheRunBitForBit) {
  auto par = small_scene();
  par.sph.sort_every = 2;
  if (!testing::reproducible_by_default<Exec>()) par.sph.list_kind = NeighborListKind::full;
  CapsuleScene<double, Exec> scene(par);
  scene.run(20);
  auto w = scene.watched();
  for (auto& f : w.state) f.save();
  w.save_host();
  const int sorts = scene.system().num_sorts();
  scene.run(150);
  const auto first = membrane_positions(scene);
  const int sorts_in_run = scene.system().num_sorts() - sorts;
  for (auto& f : w.state) f.restore();
  w.set_steps(20);
  w.restore_host();
  w.after_restore();
  EXPECT_EQ(scene.steps(), 20);
  const auto restored = membrane_positions(scene);
  scene.run(150);
  const auto second = membrane_positions(scene);
  double worst = 0, moved = 0;
  for (std::size_t k = 0; k < first.size(); ++k) {
    worst = std::max(worst, std::abs(first[k] - second[k]));
    moved = std::max(moved, std::abs(first[k] - restored[k]));
  }
  std::printf("[ capsule ] replay of 150 steps over %d sorts: membrane moved up to %.3g, replay differs by %.3g\n",
              sorts_in_run, moved, worst);
  EXPECT_GE(sorts_in_run, 2) << "the run should cross memory sorts";
  EXPECT_GT(moved, 1e-3);
  EXPECT_EQ(worst, 0.0);
}

TEST(CapsuleWatchdog, ParticleSlotsFollowMemorySorts) {
  auto par = small_scene();
  par.sph.sort_every = 1;
  CapsuleScene<double, Exec> scene(par);
  scene.run(40);
  ASSERT_GT(scene.system().num_sorts(), 0);
  // The slots stay a permutation consistent with the membrane slots.
  const auto all = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), scene.particle_slot());
  const auto membrane = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), scene.membrane_slot());
  std::vector<int> seen(all.extent(0), 0);
  for (std::size_t k = 0; k < all.extent(0); ++k) ++seen[std::size_t(all(k))];
  for (int c : seen) EXPECT_EQ(c, 1);
  for (std::size_t v = 0; v < membrane.extent(0); ++v)
    EXPECT_EQ(membrane(v), all(std::size_t(scene.membrane_offset()) + v));
}

}  // namespace
}  // namespace mesoflow
