// MPC between no-slip walls: the bounce-back of a wall crossing by hand (2D, 3D), no particle ever
// outside the channel, the geometry and statistics of both kinds of virtual wall particles (the
// mirror images, and Appendix B's Maxwell–Boltzmann particles), the momentum bookkeeping of the
// walls, and plane Poiseuille flow (2D and 3D) with the viscosity of eq. (B.3): no slip with the
// mirror images, a small residual slip with Appendix B's particles, more without either.
#include "kernels/common/reductions.hpp"
#include "scenes/crystal/channel_flow.hpp"
#include "kernels/mpc/collision_grid.hpp"
#include "kernels/mpc/maxwell_boltzmann.hpp"
#include "kernels/mpc/mpc_collision.hpp"
#include "kernels/mpc/streaming.hpp"
#include "kernels/mpc/virtual_particles.hpp"
#include "kernels/mpc/wall_bounce_back.hpp"
#include "kernels/mpc/wall_mirror_particles.hpp"
#include "test_types.hpp"

#include <Eigen/Dense>

#include <array>
#include <chrono>
#include <cmath>
#include <iostream>
#include <vector>

namespace mesoflow {
namespace {

using mpc::ChannelFlow;
using mpc::ChannelFlowParameters;
using mpc::ChannelWalls;
using mpc::CollisionRule;
using mpc::WallVirtualRule;

template <class T>
class MpcWallsTest : public ::testing::Test {};
TYPED_TEST_SUITE(MpcWallsTest, testing::BackendsAndPrecisions);

// An independent host copy (create_mirror_view_and_copy would alias a host view).
template <class View>
auto host_copy(const View& v) {
  auto h = Kokkos::create_mirror(Kokkos::HostSpace(), v);
  Kokkos::deep_copy(h, v);
  return h;
}

template <int D, class Real, class Exec>
Kokkos::View<Real* [D], Kokkos::LayoutLeft, Exec> make_view(const std::vector<std::array<double, D>>& rows) {
  Kokkos::View<Real* [D], Kokkos::LayoutLeft, Exec> v("test::rows", rows.size());
  auto h = Kokkos::create_mirror_view(v);
  for (std::size_t i = 0; i < rows.size(); ++i)
    for (int d = 0; d < D; ++d) h(i, d) = Real(rows[i][d]);
  Kokkos::deep_copy(v, h);
  return v;
}

// Channel [0, 10) × [0, 5], periodic in x. Particle 0 crosses the bottom wall, particle 1 the top
// wall and the periodic face x = 10, particle 2 stays inside. Streamed by mpc::stream for h = 0.1,
// then bounced: returned along the path, x' = x − 2 t_r v, y' = 2 y_wall − y, v' = −v.
TYPED_TEST(MpcWallsTest, CrossingParticleReturnsAlongItsPathWithReversedVelocity) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  const auto grid = mpc::make_collision_grid<2, Real>(Real(1), {Real(0), Real(0)}, {Real(10), Real(5)}, {1, 0});
  auto x = make_view<2, Real, Exec>({{3.0, 0.2}, {9.95, 4.9}, {5.0, 2.5}});
  auto v = make_view<2, Real, Exec>({{1.0, -4.0}, {2.0, 3.0}, {0.5, 0.5}});
  const Real h = Real(0.1);
  mpc::stream(x, v, h, Kokkos::Array<Real, 2>{Real(0), Real(0)}, grid);
  ChannelWalls<2, Real, Exec> walls(grid, Real(2));  // m = 2
  walls.bounce_back(x, v, h);
  auto xh = host_copy(x);
  auto vh = host_copy(v);
  const double tol = 20 * testing::eps<Real>() * 10;
  // Particle 0: streamed to (3.1, −0.2), t_r = 0.05: x' = 3.1 − 0.1 = 3.0, y' = 0.2.
  EXPECT_NEAR(xh(0, 0), 3.0, tol);
  EXPECT_NEAR(xh(0, 1), 0.2, tol);
  EXPECT_EQ(vh(0, 0), Real(-1));
  EXPECT_EQ(vh(0, 1), Real(4));
  // Particle 1: streamed to (10.15 → 0.15, 5.2), t_r = 0.2/3: x' = 0.15 − 4/15 + 10 = 9.8833…,
  // y' = 4.8.
  EXPECT_NEAR(xh(1, 0), 10.15 - 4.0 / 15.0, tol);
  EXPECT_NEAR(xh(1, 1), 4.8, tol);
  EXPECT_EQ(vh(1, 0), Real(-2));
  EXPECT_EQ(vh(1, 1), Real(-3));
  // Particle 2: free streaming only.
  EXPECT_NEAR(xh(2, 0), 5.05, tol);
  EXPECT_NEAR(xh(2, 1), 2.55, tol);
  EXPECT_EQ(vh(2, 0), Real(0.5));
  // Momentum taken up: −m(v' − v) = 2 m v: bottom (2·2·1, 2·2·(−4)), top (2·2·2, 2·2·3).
  const auto p = walls.momentum();
  EXPECT_NEAR(p[0][0], 4.0, 1e-12);
  EXPECT_NEAR(p[0][1], -16.0, 1e-12);
  EXPECT_NEAR(p[1][0], 8.0, 1e-12);
  EXPECT_NEAR(p[1][1], 12.0, 1e-12);
}

TYPED_TEST(MpcWallsTest, CrossingIn3DReflectsOnlyTheWalledAxis) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  const auto grid = mpc::make_collision_grid<3, Real>(Real(1), {Real(0), Real(-2), Real(0)},
                                                      {Real(4), Real(4), Real(3)}, {1, 0, 1});
  // Old position (1, 1.9, 0.05), v = (1, 2, −1), h = 0.1: streamed to (1.1, 2.1, −0.05 → 2.95);
  // t_r = 0.05: x' = 1.0, y' = 1.9, z' = 2.95 + 0.1 = 3.05 → 0.05.
  auto x = make_view<3, Real, Exec>({{1.0, 1.9, 0.05}});
  auto v = make_view<3, Real, Exec>({{1.0, 2.0, -1.0}});
  mpc::stream(x, v, Real(0.1), Kokkos::Array<Real, 3>{Real(0), Real(0), Real(0)}, grid);
  ChannelWalls<3, Real, Exec> walls(grid, Real(1));
  walls.bounce_back(x, v, Real(0.1));
  auto xh = host_copy(x);
  auto vh = host_copy(v);
  const double tol = 200 * testing::eps<Real>();
  EXPECT_NEAR(xh(0, 0), 1.0, tol);
  EXPECT_NEAR(xh(0, 1), 1.9, tol);
  EXPECT_NEAR(xh(0, 2), 0.05, tol);
  EXPECT_EQ(vh(0, 0), Real(-1));
  EXPECT_EQ(vh(0, 1), Real(-2));
  EXPECT_EQ(vh(0, 2), Real(1));
  EXPECT_THROW((ChannelWalls<3, Real, Exec>(mpc::make_collision_grid<3, Real>(
                   Real(1), {Real(0), Real(0), Real(0)}, {Real(4), Real(4), Real(3)}, {1, 1, 1}), Real(1))),
               std::invalid_argument);
}

// A fluid with a large time step (h = 0.5, many wall crossings per step) and a strong body force:
// after every step all particles are in the channel, y ∈ [0, W], x ∈ [0, L).
TYPED_TEST(MpcWallsTest, NoParticleEverLeavesTheChannel) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  ChannelFlowParameters<Real> p;
  p.length = 12;
  p.width = Real(6.5);
  p.density = 5;
  p.h = Real(0.5);
  p.body_acceleration = Real(0.2);
  p.seed = 5;
  ChannelFlow<Real, Exec> flow(p);
  int outside = 0;
  for (int s = 0; s < 100; ++s) {
    flow.step();
    auto x = host_copy(flow.positions());
    for (std::size_t i = 0; i < x.extent(0); ++i) {
      const bool inside = x(i, 0) >= Real(0) && x(i, 0) < p.length && x(i, 1) >= Real(0) && x(i, 1) <= p.width;
      outside += inside ? 0 : 1;
    }
  }
  // Both walls were hit (each took up momentum towards itself).
  const auto wall = flow.wall_momentum();
  EXPECT_EQ(outside, 0);
  EXPECT_LT(wall[0][1], -1.0);
  EXPECT_GT(wall[1][1], 1.0);
}

// Virtual particles for one shift: every one lies in the covered slab of its wall ([lo − s, lo) or
// [lo + L, lo + L + w_t)), every cell of a cut row has the same count, ⌊n w/a + u⌋ or the next
// integer below/above it; over many steps the mean count per cell is n w/a and the velocities are
// Maxwell–Boltzmann (mean 0, variance k_BT/m).
TYPED_TEST(MpcWallsTest, VirtualWallParticlesFillTheCoveredPartOfTheCutCells) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  using view = Kokkos::View<Real* [2], Kokkos::LayoutLeft, Exec>;
  const double n = 12, kT = 2, m = 0.5, L = 7.4;  // L not a multiple of a: the top cut differs
  const auto grid0 = mpc::make_collision_grid<2, Real>(Real(1), {Real(0), Real(-1)}, {Real(16), Real(L)}, {1, 0});
  mpc::WallVirtualParticles<2, Real, Exec> wall_virtual(grid0, Real(n), Real(kT), Real(m), 9);
  ASSERT_EQ(wall_virtual.capacity(), 2u * 16u * 12u);
  EXPECT_EQ((mpc::WallVirtualParticles<2, Real, Exec>::capacity(grid0, Real(n))), wall_virtual.capacity());
  view xv("xv", wall_virtual.capacity() + 3), vv("vv", wall_virtual.capacity() + 3);
  double count_error_bottom = 0, count_error_top = 0, v_sum = 0, v2_sum = 0, samples = 0;
  const int steps = 400;
  int misplaced = 0, unequal = 0;
  for (int s = 0; s < steps; ++s) {
    auto grid = grid0;
    grid.draw_shift(9, std::uint64_t(s));
    const std::size_t count = wall_virtual.generate(grid, xv, vv, 3, std::uint64_t(s));
    const double shift = double(grid.shift[1]);
    const double k_top = std::floor((L + shift) / 1.0);
    const double w_top = (k_top + 1) - shift - L < 1.0 ? (k_top + 1) - shift - L : 0.0;
    count_error_bottom += double(wall_virtual.per_cell(0)) - n * shift;
    count_error_top += double(wall_virtual.per_cell(1)) - n * w_top;
    EXPECT_LE(std::abs(double(wall_virtual.per_cell(0)) - n * shift), 1.0);
    EXPECT_EQ(count, 16 * (wall_virtual.per_cell(0) + wall_virtual.per_cell(1)));
    auto xh = host_copy(xv);
    auto vh = host_copy(vv);
    std::vector<int> per_cell(std::size_t(grid.num_cells()), 0);
    for (std::size_t q = 3; q < 3 + count; ++q) {
      const double y = xh(q, 1);
      const bool bottom = q - 3 < 16 * wall_virtual.per_cell(0);
      const bool in_slab = bottom ? (y >= -1.0 - shift - 1e-6 && y < -1.0 + 1e-6)
                                  : (y >= -1.0 + L - 1e-6 && y < -1.0 + L + w_top + 1e-6);
      misplaced += in_slab && xh(q, 0) >= Real(0) && xh(q, 0) < Real(16) ? 0 : 1;
      Real r[2];
      const Real xq[2] = {xh(q, 0), xh(q, 1)};
      per_cell[std::size_t(grid.locate(xq, r))] += 1;
      for (int d = 0; d < 2; ++d) {
        v_sum += vh(q, d);
        v2_sum += double(vh(q, d)) * vh(q, d);
        samples += 1;
      }
    }
    for (int c : per_cell)
      if (c != 0 && c != int(wall_virtual.per_cell(0)) && c != int(wall_virtual.per_cell(1))) ++unequal;
  }
  EXPECT_EQ(misplaced, 0);
  EXPECT_EQ(unequal, 0);
  // Mean count per cell: the rounding error u − frac has mean 0 and standard deviation ≤ 0.5 per
  // step; 400 steps: standard error ≤ 0.025, bound 0.1.
  EXPECT_NEAR(count_error_bottom / steps, 0.0, 0.1);
  EXPECT_NEAR(count_error_top / steps, 0.0, 0.1);
  // Velocities: ~2·10^4 components; standard errors of the mean 0.014, of the variance 0.015 k_BT/m
  // (relative √(2/N)); bounds at ~5σ.
  ASSERT_GT(samples, 5000);
  EXPECT_NEAR(v_sum / samples, 0.0, 5 * std::sqrt(kT / m / samples));
  EXPECT_NEAR(v2_sum / samples / (kT / m), 1.0, 5 * std::sqrt(2.0 / samples));
}

// Mirror images for many shifts: exactly the solvent particles of the two source slabs
// ([lo, lo + s) and (lo + L − w_t, lo + L]), in index order, each reflected across its wall
// (y' = 2 y_wall − y, same x) with reversed velocity, and each in its source's column of the cut
// row. The walls then take up exactly the images' momentum change.
TYPED_TEST(MpcWallsTest, WallMirrorParticlesAreTheImagesOfTheFluidNextToTheWalls) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  using view = Kokkos::View<Real* [2], Kokkos::LayoutLeft, Exec>;
  const double n = 12, L = 7.4;  // L not a multiple of a: the top cut differs from the bottom one
  const auto grid0 = mpc::make_collision_grid<2, Real>(Real(1), {Real(0), Real(-1)}, {Real(16), Real(L)}, {1, 0});
  const int N = int(n * 16 * L);
  view x("x", N), v("v", N);
  const Real lo[2] = {Real(0), Real(-1)}, hi[2] = {Real(16), Real(L - 1)};
  fill_uniform_counter(x, lo, hi, 5, 0);
  mpc::fill_maxwell_boltzmann<2, Real, Exec>(v, Real(1), Real(1), 5, 1);
  mpc::WallMirrorParticles<2, Real, Exec> mirror(grid0, Real(n), Real(0.5));
  EXPECT_EQ((mpc::WallMirrorParticles<2, Real, Exec>::capacity(grid0, Real(n))), mirror.capacity());
  ASSERT_GE(mirror.capacity(), std::size_t(2 * n * 16));
  view xv("xv", mirror.capacity() + 3), vv("vv", mirror.capacity() + 3);
  const auto xh = host_copy(x);
  const auto vh = host_copy(v);
  const double tol_y = 8 * testing::eps<Real>() * L;
  int wrong_rows = 0, wrong_cells = 0, steps_with_both = 0;
  double counted = 0, expected = 0;
  const int steps = 200;
  for (int s = 0; s < steps; ++s) {
    auto grid = grid0;
    grid.draw_shift(9, std::uint64_t(s));
    // The cut depths as generate() computes them, from the grid's own (Real) values.
    const double shift = double(grid.shift[1]), length = double(grid.length[1]), y0 = double(grid.lo[1]);
    const double k_top = std::floor(length + shift);
    const double w_top = (k_top + 1) - shift - length < 1.0 ? (k_top + 1) - shift - length : 0.0;
    const std::size_t count = mirror.generate(grid, x, v, std::size_t(N), xv, vv, 3);
    const auto xvh = host_copy(xv);
    const auto vvh = host_copy(vv);
    std::size_t q = 3;
    int bottom = 0, top = 0;
    for (int i = 0; i < N; ++i) {
      const Real y = xh(i, 1);
      const bool near_bottom = y < Real(y0 + shift);
      const bool near_top = w_top > 0 && y > Real(y0 + length - w_top);
      if (!near_bottom && !near_top) continue;
      (near_bottom ? bottom : top) += 1;
      const double y_image = near_bottom ? 2 * y0 - double(y) : 2 * (y0 + length) - double(y);
      if (q >= 3 + count) {
        ++wrong_rows;
        continue;
      }
      if (xvh(q, 0) != xh(i, 0) || std::abs(double(xvh(q, 1)) - y_image) > tol_y || vvh(q, 0) != -vh(i, 0) ||
          vvh(q, 1) != -vh(i, 1))
        ++wrong_rows;
      Real r[2];
      const Real source[2] = {xh(i, 0), xh(i, 1)}, image[2] = {xvh(q, 0), xvh(q, 1)};
      const int cs = grid.locate(source, r), ci = grid.locate(image, r);
      if (ci % grid.n[0] != cs % grid.n[0] || ci / grid.n[0] != (near_bottom ? 0 : int(k_top))) ++wrong_cells;
      ++q;
    }
    EXPECT_EQ(count, q - 3);
    EXPECT_EQ(mirror.count(), count);
    counted += double(count);
    expected += double(N) / length * (shift + w_top);
    steps_with_both += bottom > 0 && top > 0 ? 1 : 0;
  }
  EXPECT_EQ(wrong_rows, 0);
  EXPECT_EQ(wrong_cells, 0);
  EXPECT_GT(steps_with_both, steps / 2);
  // The mean count is the solvent density times the cut depths (a fixed uniform fill: ±2%).
  EXPECT_NEAR(counted / expected, 1.0, 0.02);

  // Momentum: add (1, −2) to every image's velocity, as a collision would change it; the bottom
  // wall takes up m (1, −2) per bottom image, the top wall per top image.
  mpc::ChannelWalls<2, Real, Exec> walls(grid0, Real(0.5));
  auto grid = grid0;
  grid.draw_shift(9, 7);
  const std::size_t count = mirror.generate(grid, x, v, std::size_t(N), xv, vv, 3);
  auto vvh = host_copy(vv);
  const auto xvh = host_copy(xv);
  double bottom = 0;
  for (std::size_t q = 3; q < 3 + count; ++q) {
    vvh(q, 0) += Real(1);
    vvh(q, 1) -= Real(2);
    bottom += xvh(q, 1) < Real(-1) ? 1 : 0;
  }
  Kokkos::deep_copy(vv, vvh);
  mirror.transfer(xv, vv, 3, walls);
  const auto pw = walls.momentum();
  const double top = double(count) - bottom;
  ASSERT_GT(bottom, 0);
  ASSERT_GT(top, 0);
  const double tol = 100 * testing::eps<Real>() * double(count);
  EXPECT_NEAR(pw[0][0], 0.5 * bottom, tol);
  EXPECT_NEAR(pw[0][1], -1.0 * bottom, tol);
  EXPECT_NEAR(pw[1][0], 0.5 * top, tol);
  EXPECT_NEAR(pw[1][1], -1.0 * top, tol);
}

// A solvent far denser near a wall than n (every particle within the cut depth) overflows the
// mirror images' capacity: an error naming the count, never a truncated fill. A channel narrower
// than two cells (overlapping source slabs) and a bad density or mass are refused.
TYPED_TEST(MpcWallsTest, WallMirrorParticlesRefuseMoreImagesThanTheirCapacity) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  using view = Kokkos::View<Real* [2], Kokkos::LayoutLeft, Exec>;
  auto grid = mpc::make_collision_grid<2, Real>(Real(1), {Real(0), Real(0)}, {Real(4), Real(6)}, {1, 0});
  mpc::WallMirrorParticles<2, Real, Exec> mirror(grid, Real(5), Real(1));
  const int N = int(mirror.capacity()) + 1;
  view x("x", N), v("v", N), xv("xv", mirror.capacity()), vv("vv", mirror.capacity());
  const Real lo[2] = {Real(0), Real(0)}, hi[2] = {Real(4), Real(0.01)};
  fill_uniform_counter(x, lo, hi, 3, 0);
  grid.shift[1] = Real(0.5);
  EXPECT_THROW(mirror.generate(grid, x, v, std::size_t(N), xv, vv, 0), std::length_error);
  const auto narrow = mpc::make_collision_grid<2, Real>(Real(1), {Real(0), Real(0)}, {Real(4), Real(1.5)}, {1, 0});
  EXPECT_THROW((mpc::WallMirrorParticles<2, Real, Exec>(narrow, Real(5), Real(1))), std::invalid_argument);
  // A density or mass that is not finite and positive is refused before any size is computed from it.
  EXPECT_THROW((mpc::WallMirrorParticles<2, Real, Exec>(grid, Real(NAN), Real(1))), std::invalid_argument);
  EXPECT_THROW((mpc::WallMirrorParticles<2, Real, Exec>(grid, Real(-3), Real(1))), std::invalid_argument);
  EXPECT_THROW((mpc::WallMirrorParticles<2, Real, Exec>(grid, Real(5), Real(0))), std::invalid_argument);
}

// Momentum bookkeeping with walls (bounce-back and either kind of virtual particles): the
// solvent's momentum plus what the walls took up equals N m g t (the body force's impulse), to
// round-off.
template <class Real, class Exec>
void check_wall_momentum_balance(WallVirtualRule rule) {
  SCOPED_TRACE(mpc::to_string(rule));
  ChannelFlowParameters<Real> p;
  p.wall_virtual = rule;
  p.length = 10;
  p.width = 6;
  p.density = 8;
  p.h = Real(0.1);
  p.body_acceleration = Real(0.05);
  p.seed = 17;
  ChannelFlow<Real, Exec> flow(p);
  const auto p0 = flow.solvent_momentum();
  const int steps = 200;
  for (int s = 0; s < steps; ++s) flow.step();
  const auto ps = flow.solvent_momentum();
  const auto pw = flow.wall_momentum();
  const double N = double(flow.num_solvent());
  const double drive = N * double(p.mass) * double(p.body_acceleration) * steps * double(p.h);
  const double balance_x = ps[0] - p0[0] + pw[0][0] + pw[1][0] - drive;
  const double balance_y = ps[1] - p0[1] + pw[0][1] + pw[1][1];
  // Round-off: the wall sums reach ~drive and take ~4 additions per step (relative ε each), the
  // solvent sum ~N velocities rounded to Real per step (measured 4e-12 in double, 2e-4 in float).
  const double tol = 20 * testing::eps<Real>() * drive * std::sqrt(double(steps));
  std::cout << "[ momentum ] drive " << drive << ", walls x " << pw[0][0] + pw[1][0] << ", imbalance (" << balance_x
            << ", " << balance_y << "), tolerance " << tol << "\n";
  EXPECT_GT(std::abs(pw[0][0] + pw[1][0]), 0.5 * drive);
  EXPECT_NEAR(balance_x, 0.0, tol);
  EXPECT_NEAR(balance_y, 0.0, tol);
}

TYPED_TEST(MpcWallsTest, WallsTakeUpExactlyTheMomentumTheSolventLoses) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  check_wall_momentum_balance<Real, Exec>(WallVirtualRule::mirror);
  check_wall_momentum_balance<Real, Exec>(WallVirtualRule::maxwell);
}

// Time- and x-averaged u_x(y) of a walled channel; fit u = A y (W − y) + B (B: slip velocity).
struct ProfileFit {
  double A, B, rms_residual, u_max;
};

ProfileFit fit_profile(const std::vector<double>& y, const std::vector<double>& u, double W) {
  Eigen::MatrixXd M(y.size(), 2);
  Eigen::VectorXd b(y.size());
  for (std::size_t k = 0; k < y.size(); ++k) {
    M(k, 0) = y[k] * (W - y[k]);
    M(k, 1) = 1.0;
    b(k) = u[k];
  }
  const Eigen::Vector2d c = M.colPivHouseholderQr().solve(b);
  const double rms = std::sqrt((M * c - b).squaredNorm() / double(y.size()));
  return {c(0), c(1), rms, c(0) * W * W / 4 + c(1)};
}

// Profile accumulator: bins of width W / bins across the channel.
struct Profile {
  std::vector<double> sum, count;
  double W;
  Profile(int bins, double W_) : sum(std::size_t(bins), 0.0), count(std::size_t(bins), 0.0), W(W_) {}
  template <class XView, class VView>
  void add(const XView& x, const VView& v) {
    auto xh = host_copy(x);
    auto vh = host_copy(v);
    const int bins = int(sum.size());
    for (std::size_t i = 0; i < xh.extent(0); ++i) {
      int b = int(std::floor(double(xh(i, 1)) / W * bins));
      b = b < 0 ? 0 : (b >= bins ? bins - 1 : b);
      sum[std::size_t(b)] += vh(i, 0);
      count[std::size_t(b)] += 1;
    }
  }
  ProfileFit fit() const {
    std::vector<double> y, u;
    for (std::size_t b = 0; b < sum.size(); ++b) {
      y.push_back((double(b) + 0.5) * W / double(sum.size()));
      u.push_back(sum[b] / count[b]);
    }
    return fit_profile(y, u, W);
  }
};

// Eq. (B.3).
double viscosity_b3(double n, double kT, double h, double m, double a, int d) {
  return n * kT * h / std::pow(a, d) * (n / (n - (d + 2) / 4.0) - 0.5) +
         m * (n - 7.0 / 5.0) / (24 * std::pow(a, d - 2) * h);
}

// Plane Poiseuille flow (AT+a, m = a = k_BT = 1): n = 10, h = 0.1, W = 10, g = 0.03 along x, so
// u_max ≈ 0.9 (a body-force-driven plane flow is uniform along x: no pressure or density
// gradient, compressibility does not enter). η(B.3) = 4.19 (2D), ν ≈ 0.42: the slowest mode
// relaxes in W²/(π² ν) ≈ 24 τ = 240 steps; 1500 steps of warm-up from rest (6 relaxation times),
// then profiles every 5 steps in 20 bins.
constexpr double kN = 10, kH = 0.1, kW = 10, kG = 0.03;
constexpr int kWarmup = 1500, kEvery = 5, kBins = 20;

struct PoiseuilleResult {
  ProfileFit fit;
  double eta_fit, seconds;
};

PoiseuilleResult poiseuille_result(const Profile& profile, std::chrono::steady_clock::time_point t0) {
  const ProfileFit fit = profile.fit();
  return {fit, kN * kG / (2 * fit.A), std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()};
}

// The 2D channel of the paper's scene, ChannelFlow (bounce-back + virtual wall particles of the
// given rule), L = 20.
PoiseuilleResult poiseuille_channel_flow(WallVirtualRule rule, int sampled) {
  const auto t0 = std::chrono::steady_clock::now();
  ChannelFlowParameters<double> p;
  p.length = 20;
  p.width = kW;
  p.density = kN;
  p.h = kH;
  p.body_acceleration = kG;
  p.rule = CollisionRule::at_plus_a;
  p.wall_virtual = rule;
  p.seed = 2024;
  ChannelFlow<double, Kokkos::DefaultExecutionSpace> flow(p);
  for (int s = 0; s < kWarmup; ++s) flow.step();
  Profile profile(kBins, kW);
  for (int s = 0; s < sampled; ++s) {
    flow.step();
    if (s % kEvery == 0) profile.add(flow.positions(), flow.velocities());
  }
  return poiseuille_result(profile, t0);
}

// What fills the wall part of the cut wall cells in poiseuille_components.
enum class WallFill { none, maxwell, mirror };

// The same step assembled from the components, in D = 2 or 3 (periodic x of length `length` and,
// in 3D, z of length `depth`).
template <int D>
PoiseuilleResult poiseuille_components(WallFill fill, double length, double depth, int sampled) {
  using Exec = Kokkos::DefaultExecutionSpace;
  using view = Kokkos::View<double* [D], Kokkos::LayoutLeft, Exec>;
  const auto t0 = std::chrono::steady_clock::now();
  Kokkos::Array<double, D> lo, len, g;
  Kokkos::Array<int, D> periodic;
  double lo_[D], hi_[D], volume = 1;
  for (int d = 0; d < D; ++d) {
    lo[d] = 0;
    len[d] = d == 0 ? length : (d == 1 ? kW : depth);
    periodic[d] = d != 1;
    g[d] = d == 0 ? kG : 0;
    lo_[d] = 0;
    hi_[d] = len[d];
    volume *= len[d];
  }
  const auto grid = mpc::make_collision_grid<D, double>(1.0, lo, len, periodic);
  const int n = int(kN * volume);
  view x("x", n), v("v", n);
  fill_uniform_counter(x, lo_, hi_, 2024, 0);
  mpc::fill_maxwell_boltzmann<D, double, Exec>(v, 1.0, 1.0, 2024, 1);
  mpc::CollisionParameters<double> cp;
  cp.rule = CollisionRule::at_plus_a;
  cp.seed = 2024;
  ChannelWalls<D, double, Exec> walls(grid, 1.0);
  mpc::WallVirtualParticles<D, double, Exec> wall_virtual(grid, kN, 1.0, 1.0, 2024);
  mpc::WallMirrorParticles<D, double, Exec> wall_mirror(grid, kN, 1.0);
  const std::size_t capacity =
      fill == WallFill::none ? 0 : (fill == WallFill::maxwell ? wall_virtual.capacity() : wall_mirror.capacity());
  view xv("xv", capacity), vv("vv", capacity);
  mpc::MpcCollision<D, double, Exec> collision(grid, cp, std::size_t(n), capacity);
  Profile profile(kBins, kW);
  for (int s = 0; s < kWarmup + sampled; ++s) {
    mpc::stream(x, v, kH, g, collision.grid());
    walls.bounce_back(x, v, kH);
    collision.shift_grid(std::uint64_t(s));
    if (fill == WallFill::maxwell) {
      const std::size_t nv = wall_virtual.generate(collision.grid(), xv, vv, 0, std::uint64_t(s));
      collision.collide(x, v, xv, vv, nv, std::uint64_t(s));
      wall_virtual.transfer(vv, 0, walls);
    } else if (fill == WallFill::mirror) {
      const std::size_t nv = wall_mirror.generate(collision.grid(), x, v, std::size_t(n), xv, vv, 0);
      collision.collide(x, v, xv, vv, nv, std::uint64_t(s));
      wall_mirror.transfer(xv, vv, 0, walls);
    } else {
      collision.collide(x, v, std::uint64_t(s));
    }
    if (s >= kWarmup && (s - kWarmup) % kEvery == 0) profile.add(x, v);
  }
  return poiseuille_result(profile, t0);
}

void report(const char* name, const PoiseuilleResult& r, double eta) {
  std::cout << "[ poiseuille " << name << " ] eta fit " << r.eta_fit << " vs B.3 " << eta << " (rel. "
            << r.eta_fit / eta - 1 << "), slip B/u_max " << r.fit.B / r.fit.u_max << ", slip length "
            << r.fit.B / (r.fit.A * kW) << " a, u_max " << r.fit.u_max << ", rms residual " << r.fit.rms_residual
            << ", " << r.seconds << " s\n";
}

// Bounce-back + mirror images (ChannelFlow's default): η from the fitted curvature within 4% of
// eq. (B.3) and no slip, |B| below 1.5% of u_max. Measured here: η +2.1%, B = −0.03% of u_max;
// over four more seeds (16000 sampled steps each) η +1.7 … +2.5% and B = +0.03 … +0.42%.
TEST(MpcPoiseuilleTest, ProfileIsParabolicWithTheViscosityOfB3AndNoSlip) {
  const double eta = viscosity_b3(kN, 1, kH, 1, 1, 2);
  const PoiseuilleResult r = poiseuille_channel_flow(WallVirtualRule::mirror, 16000);
  report("2D, mirror wall particles", r, eta);
  EXPECT_NEAR(r.eta_fit / eta, 1.0, 0.04);
  EXPECT_LT(std::abs(r.fit.B / r.fit.u_max), 0.015);
  EXPECT_LT(r.fit.rms_residual, 0.02 * r.fit.u_max);  // parabolic: residuals at the noise level
}

// Bounce-back + Appendix B's virtual particles (Maxwell–Boltzmann at the wall velocity): η within
// 5% of eq. (B.3), and a residual slip of 2–6% of u_max. Measured here: η +2.5%, B = 3.7% of u_max
// (a slip length b = B/u'(0) ≈ 0.1 a); over four more seeds η +2.3 … +3.0%, B = 3.9 … 4.1%.
// Particles at rest stand for a fluid at rest inside the wall, not for the continued shear of the
// no-slip extension (wall_mirror_particles.hpp; Bolintineanu et al., PRE 86, 066703 (2012)). The
// lower bound keeps the mirror images' gain measurable.
TEST(MpcPoiseuilleTest, AppendixBVirtualParticlesLeaveASmallSlip) {
  const double eta = viscosity_b3(kN, 1, kH, 1, 1, 2);
  const PoiseuilleResult r = poiseuille_channel_flow(WallVirtualRule::maxwell, 16000);
  report("2D, Maxwell-Boltzmann wall particles", r, eta);
  EXPECT_NEAR(r.eta_fit / eta, 1.0, 0.05);
  EXPECT_GT(r.fit.B / r.fit.u_max, 0.02);
  EXPECT_LT(r.fit.B / r.fit.u_max, 0.06);
  EXPECT_LT(r.fit.rms_residual, 0.02 * r.fit.u_max);
}

// The same channel without virtual wall particles (bounce-back alone on the shifted grid): the
// partly filled wall cells let the fluid slip (Lamura et al. 2001), B/u_max ≈ 13% (slip length
// ≈ 0.36 a) — so the no-slip checks above do test the virtual particles.
TEST(MpcPoiseuilleTest, WithoutVirtualWallParticlesTheFluidSlips) {
  const double eta = viscosity_b3(kN, 1, kH, 1, 1, 2);
  const PoiseuilleResult r = poiseuille_components<2>(WallFill::none, 20, 0, 3000);
  report("2D, bounce-back only", r, eta);
  EXPECT_GT(r.fit.B / r.fit.u_max, 0.09);
}

// 3D (x periodic 10, y walled W = 10, z periodic 4), mirror images and Appendix B's particles: a
// parabolic profile with both; no slip with the images (|B| < 1.5% of u_max; measured −0.09%,
// against 3.7% with Appendix B's particles). η against eq. (B.3) evaluated with d = 3 (the paper
// states B.3 for d = 2 only): −3.5% with the images, −4.3% with Appendix B's particles (−3.8%
// with 30000 sampled steps: a model offset, not noise), hence 7% bounds here against 4–5% in 2D.
TEST(MpcPoiseuilleTest, ThreeDimensionalChannelHasNoSlipAndTheViscosityOfB3) {
  const double eta = viscosity_b3(kN, 1, kH, 1, 1, 3);
  const PoiseuilleResult mirror = poiseuille_components<3>(WallFill::mirror, 10, 4, 6000);
  report("3D, mirror wall particles", mirror, eta);
  EXPECT_NEAR(mirror.eta_fit / eta, 1.0, 0.07);
  EXPECT_LT(std::abs(mirror.fit.B / mirror.fit.u_max), 0.015);
  EXPECT_LT(mirror.fit.rms_residual, 0.02 * mirror.fit.u_max);
  const PoiseuilleResult maxwell = poiseuille_components<3>(WallFill::maxwell, 10, 4, 6000);
  report("3D, Maxwell-Boltzmann wall particles", maxwell, eta);
  EXPECT_NEAR(maxwell.eta_fit / eta, 1.0, 0.07);
  EXPECT_LT(std::abs(maxwell.fit.B / maxwell.fit.u_max), 0.06);
  EXPECT_LT(maxwell.fit.rms_residual, 0.02 * maxwell.fit.u_max);
}

}  // namespace
}  // namespace mesoflow
