// A term whose coefficient is zero launches no kernel (issue 8, item 4): the scenes' steps are
// recorded through Kokkos' tool callbacks, which see every parallel_for/reduce/scan by label.
#include "scenes/droplets/droplet_scene.hpp"
#include "scenes/hopper/dp_hopper_scene.hpp"
#include "kernels/common/geometry.hpp"
#include "scenes/hopper/hopper_scene.hpp"

#include <gtest/gtest.h>

#include <Kokkos_Core.hpp>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

namespace {

using namespace mesoflow;
using Exec = Kokkos::DefaultExecutionSpace;

// Records the label of every kernel launched while it lives.
class KernelLaunches {
 public:
  KernelLaunches() {
    labels().clear();
    namespace tools = Kokkos::Tools::Experimental;
    tools::set_begin_parallel_for_callback(&record);
    tools::set_begin_parallel_reduce_callback(&record);
    tools::set_begin_parallel_scan_callback(&record);
  }
  ~KernelLaunches() {
    namespace tools = Kokkos::Tools::Experimental;
    tools::set_begin_parallel_for_callback(nullptr);
    tools::set_begin_parallel_reduce_callback(nullptr);
    tools::set_begin_parallel_scan_callback(nullptr);
  }
  KernelLaunches(const KernelLaunches&) = delete;
  KernelLaunches& operator=(const KernelLaunches&) = delete;

  // How many launches had `label` as their label.
  static long count(const std::string& label) {
    return long(std::count(labels().begin(), labels().end(), label));
  }
  static long total() { return long(labels().size()); }
  static std::vector<std::string> sorted() {
    auto l = labels();
    std::sort(l.begin(), l.end());
    return l;
  }

 private:
  static std::vector<std::string>& labels() {
    static std::vector<std::string> l;
    return l;
  }
  static void record(const char* name, const std::uint32_t, std::uint64_t* id) {
    labels().emplace_back(name);
    *id = 0;
  }
};

constexpr const char* friction_kernel = "mesoflow::sp::kinetic_friction";
constexpr const char* drag_kernel = "mesoflow::sp::mass_proportional_drag";

// Launch counts of the friction and drag kernels over `steps` steps of a 2D soft-particle hopper.
std::pair<long, long> sp_hopper_friction_and_drag_launches(double friction, double drag, int steps) {
  hopper::HopperParameters par;
  par.particles = 100;
  par.friction = friction;
  par.drag = drag;
  par.dt = 1e-4;
  hopper::HopperScene<2, double, Exec> scene(par);
  KernelLaunches rec;
  for (int s = 0; s < steps; ++s) scene.step();
  EXPECT_GT(KernelLaunches::total(), 2L * steps);  // the recorder sees the step's kernels
  return {KernelLaunches::count(friction_kernel), KernelLaunches::count(drag_kernel)};
}

TEST(ZeroCoefficientTerms, SoftParticleHopperLaunchesNoFrictionOrDragKernelAtZero) {
  const auto off = sp_hopper_friction_and_drag_launches(0, 0, 20);
  EXPECT_EQ(off.first, 0);
  EXPECT_EQ(off.second, 0);
  const auto on = sp_hopper_friction_and_drag_launches(1, 1, 20);
  EXPECT_EQ(on.first, 20);  // once per step when the coefficient is non-zero
  EXPECT_EQ(on.second, 20);
  const auto friction_only = sp_hopper_friction_and_drag_launches(1, 0, 20);
  EXPECT_EQ(friction_only.first, 20);
  EXPECT_EQ(friction_only.second, 0);
}

// Deformable polygons: μ = 0 launches no vertex friction (eq. 12). (K_b = 0 drops bending from the
// one fused shape loop at compile time, dp_hopper_scene.hpp, which no launch count can see.)
TEST(ZeroCoefficientTerms, DeformablePolygonHopperLaunchesNoFrictionKernelAtZero) {
  for (const double mu : {0.0, 0.5}) {
    hopper::DpHopperParameters par;
    par.particles = 20;
    par.vertices = 16;
    par.friction = mu;
    par.dt = 0;  // min(10⁻³, a fraction of the stability limit)
    hopper::DpHopperScene<double, Exec> scene(par);
    KernelLaunches rec;
    for (int s = 0; s < 10; ++s) scene.step();
    EXPECT_EQ(KernelLaunches::count(friction_kernel), mu > 0 ? 10 : 0) << "mu = " << mu;
  }
}

// The kernels of 50 orifice-scene steps (Fig. 2 droplet between two wedges), sorted by label.
std::vector<std::string> orifice_step_kernels(double bending, bool empty_obstacle_array, bool obstacles) {
  droplets::DropletParameters par;
  par.vertices = 64;
  par.bending_stiffness = bending;
  const auto wedges = orifice_wedges<double>(0.4, 0.0, 0.0);
  const std::vector<Shape<2, double>> walls{wedges[0], wedges[1]};
  Surfaces<double, Exec> surfaces(walls);
  if (empty_obstacle_array) surfaces = Surfaces<double, Exec>(walls, ObstacleArray<double, Exec>());
  if (obstacles) {
    const double lo[2] = {0, 0}, len[2] = {20, 20};
    const bool periodic[2] = {true, true};
    surfaces = Surfaces<double, Exec>(
        walls, ObstacleArray<double, Exec>(Box<2, double>(lo, len, periodic),
                                           poisson_disk_obstacles(20, 20, 0.3, 1.0, 3), 0.3, 1.3));
  }
  droplets::DropletScene<double, Exec> scene(par, surfaces, {Vec<2, double>{{0.0, 2.0}}});
  KernelLaunches rec;
  for (int s = 0; s < 50; ++s) scene.step();
  return KernelLaunches::sorted();
}

TEST(ZeroCoefficientTerms, OrificeSceneLaunchesTheSameKernelsWithZeroBendingAndAnEmptyObstacleArray) {
  const auto only_its_terms = orifice_step_kernels(0, false, false);
  ASSERT_GE(only_its_terms.size(), 50u * 4);
  EXPECT_EQ(orifice_step_kernels(0, true, false), only_its_terms);
  // Bending joins the one fused shape loop: the same kernels, none more.
  EXPECT_EQ(orifice_step_kernels(0.1, false, false), only_its_terms);
  // A real obstacle array adds its candidate-list kernels: the comparison can tell.
  const auto with_obstacles = orifice_step_kernels(0, false, true);
  EXPECT_GT(with_obstacles.size(), only_its_terms.size());
  EXPECT_NE(std::find(with_obstacles.begin(), with_obstacles.end(), "mesoflow::body_obstacle_list::reference"),
            with_obstacles.end());
}

}  // namespace
