// kernel_launch.hpp: the checked launches compute what Kokkos' own do, and the device handles that
// kernels capture stay small (issue 26, item 2). A closure above the bound does not compile at all:
// tests/portability/oversized_closure.cpp, built by the ctest KernelLaunch.OversizedClosureDoesNotCompile.
#include "kernels/common/body_obstacle_list.hpp"
#include "kernels/common/kernel_launch.hpp"
#include "kernels/common/neighbor_list.hpp"
#include "test_types.hpp"

#include <cstdio>

namespace mesoflow {
namespace {

template <class T>
class KernelLaunchTest : public ::testing::Test {};
TYPED_TEST_SUITE(KernelLaunchTest, testing::BackendsAndPrecisions);

// What the surface-force loop of a droplet in an obstacle array captures (BodySurfaces: walls plus
// the droplet's obstacle candidates) and what the pair loops capture: before the handles, 424 and
// 112 bytes, and the whole closures 560–632 (kernel_launch.hpp); the bounds here leave the terms and
// evaluators room under max_kernel_closure_bytes.
static_assert(sizeof(ObstacleArrayQuery<double>) <= 160, "the obstacle array's device handle grew");
static_assert(sizeof(BodyObstacleQuery<double>) <= 200, "the body obstacle list's device handle grew");
static_assert(sizeof(BodySurfaces<double>) <= 224, "BodySurfaces grew");
static_assert(sizeof(NeighborData<Kokkos::DefaultExecutionSpace>) <= 48, "NeighborData grew");
static_assert(sizeof(PeriodicImages<3, double>) <= 56, "PeriodicImages grew");
static_assert(kernel_closure_fits<BodySurfaces<double>>());

template <class Exec, class Real>
void fill_and_sum(const Kokkos::View<Real*, Exec>& v, double& sum, const Kokkos::View<Real*, Exec>& prefix) {
  const int n = int(v.extent(0));
  launch::parallel_for("test::fill", Kokkos::RangePolicy<Exec>(0, n), KOKKOS_LAMBDA(int i) { v(i) = Real(i % 7); });
  launch::parallel_reduce(
      "test::sum", Kokkos::RangePolicy<Exec>(0, n), KOKKOS_LAMBDA(int i, double& s) { s += double(v(i)); }, sum);
  launch::parallel_scan(
      "test::scan", Kokkos::RangePolicy<Exec>(0, n), KOKKOS_LAMBDA(int i, Real& partial, bool final) {
        partial += v(i);
        if (final) prefix(i) = partial;
      });
}

template <class Exec, class Real>
Real checked_max(const Kokkos::View<Real*, Exec>& v) {
  Real m = 0;
  launch::parallel_reduce(
      "test::max", Kokkos::RangePolicy<Exec>(0, int(v.extent(0))),
      KOKKOS_LAMBDA(int i, Real& acc) { acc = v(i) > acc ? v(i) : acc; }, Kokkos::Max<Real>(m));
  return m;
}

TYPED_TEST(KernelLaunchTest, CheckedLaunchesComputeWhatKokkosComputes) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  const int n = 1000;
  Kokkos::View<Real*, Exec> v("v", n), prefix("prefix", n);
  double sum = 0;
  fill_and_sum(v, sum, prefix);
  double expect = 0;
  for (int i = 0; i < n; ++i) expect += i % 7;
  EXPECT_EQ(sum, expect);
  const auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), prefix);
  EXPECT_EQ(double(h(n - 1)), expect);
  EXPECT_EQ(double(h(6)), 21.0);
  EXPECT_EQ(double(checked_max(v)), 6.0);
}

// The handles' sizes on this build (docs/portability.md quotes them).
TEST(KernelLaunch, HandleSizes) {
  using Exec = Kokkos::DefaultExecutionSpace;
  std::printf("[ closures ] bytes in double on %s: ObstacleArray %zu, ObstacleArrayQuery %zu, BodyObstacleList %zu, "
              "BodyObstacleQuery %zu, BodySurfaces %zu, Surfaces %zu, NeighborData %zu, Box<3> %zu, "
              "PeriodicImages<3> %zu; bound %zu\n",
              Exec::name(), sizeof(ObstacleArray<double, Exec>), sizeof(ObstacleArrayQuery<double, Exec>),
              sizeof(BodyObstacleList<double, Exec>), sizeof(BodyObstacleQuery<double, Exec>),
              sizeof(BodySurfaces<double, Exec>), sizeof(Surfaces<double, Exec>), sizeof(NeighborData<Exec>),
              sizeof(Box<3, double>), sizeof(PeriodicImages<3, double>), max_kernel_closure_bytes);
  EXPECT_LT(sizeof(BodySurfaces<double, Exec>), sizeof(BodyObstacleList<double, Exec>));
}

}  // namespace
}  // namespace mesoflow
