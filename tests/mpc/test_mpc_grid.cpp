// MPC collision grid and streaming: locate() against a brute-force floor in long double (periodic
// wrap, the extra layer of walled axes, points on cell faces), the grid shift's range and
// reproducibility, the size checks, and eq. (B.1) with periodic wrapping.
#include "kernels/mpc/collision_grid.hpp"
#include "kernels/mpc/split_body_force.hpp"
#include "kernels/mpc/streaming.hpp"
#include "test_types.hpp"

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

namespace mesoflow {
namespace {

using mpc::CollisionGrid;
using mpc::make_collision_grid;

template <class T>
class MpcGridTest : public ::testing::Test {};
TYPED_TEST_SUITE(MpcGridTest, testing::BackendsAndPrecisions);

// The exact cell coordinate on axis d of x: floor((x − lo + shift)/a) in long double, wrapped on a
// periodic axis, clamped on a walled one; offset = x − the cell's lower face (outside [0, a) only
// where clamped).
template <int D, class Real>
int exact_axis_cell(const CollisionGrid<D, Real>& g, Real x, int d, long double& offset) {
  const long double u = (long double)x - (long double)g.lo[d] + (long double)g.shift[d];
  long long k = (long long)std::floor(u / (long double)g.a);
  offset = u - (long double)k * (long double)g.a;
  if (g.periodic[d]) {
    k = ((k % g.n[d]) + g.n[d]) % g.n[d];
  } else {
    k = k < 0 ? 0 : (k >= g.n[d] ? g.n[d] - 1 : k);
    offset = u - (long double)k * (long double)g.a;
  }
  return int(k);
}

TYPED_TEST(MpcGridTest, CellCountsPerAxis) {
  using Real = typename TypeParam::real;
  const auto g = make_collision_grid<3, Real>(Real(0.5), {Real(-1), Real(0), Real(2)}, {Real(4), Real(3.2), Real(3)},
                                              {1, 0, 0});
  EXPECT_EQ(g.n[0], 8);   // periodic: length / a
  EXPECT_EQ(g.n[1], 8);   // walled: ceil(6.4) + 1
  EXPECT_EQ(g.n[2], 7);   // walled: ceil(6) + 1
  EXPECT_EQ(g.num_cells(), 8 * 8 * 7);
}

TYPED_TEST(MpcGridTest, PeriodicLengthNotAMultipleOfTheCellSizeThrows) {
  using Real = typename TypeParam::real;
  try {
    make_collision_grid<2, Real>(Real(1), {Real(0), Real(0)}, {Real(10), Real(7.5)}, {1, 1});
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("periodic axis 1"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("7.5"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW((make_collision_grid<2, Real>(Real(1), {Real(0), Real(0)}, {Real(10), Real(7.5)}, {1, 0})));
  EXPECT_THROW((make_collision_grid<2, Real>(Real(0), {Real(0), Real(0)}, {Real(1), Real(1)}, {1, 1})),
               std::invalid_argument);
}

// Random points (inside the domain and up to one cell outside it) for random shifts: the cell
// equals the exact floor except within a few ulps of a face, where either neighbour is allowed;
// the local offset is in [0, a) and x = corner + local up to a period.
TYPED_TEST(MpcGridTest, LocateAgreesWithBruteForceFloor) {
  using Real = typename TypeParam::real;
  auto g = make_collision_grid<3, Real>(Real(0.7), {Real(-1.3), Real(2.1), Real(0.4)},
                                        {Real(7), Real(6.35), Real(4.9)}, {1, 0, 1});
  ASSERT_EQ(g.n[0], 10);
  ASSERT_EQ(g.n[1], 11);
  ASSERT_EQ(g.n[2], 7);
  std::mt19937_64 gen(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double face_tolerance = 8 * testing::eps<Real>() * 16.0;  // a few ulps of coordinates ≤ 16
  int near_face = 0;
  for (int step = 0; step < 20; ++step) {
    g.draw_shift(3, step);
    for (int trial = 0; trial < 500; ++trial) {
      Real x[3], local[3];
      for (int d = 0; d < 3; ++d) {
        const double lo = g.lo[d], len = g.length[d];
        x[d] = Real(g.periodic[d] ? lo + len * u(gen) : lo - 0.7 + (len + 1.4) * u(gen));
      }
      const int cell = g.locate(x, local);
      Real corner[3];
      g.lower_corner(cell, corner);
      int c = cell;
      for (int d = 0; d < 3; ++d) {
        const int k = c % g.n[d];
        c /= g.n[d];
        long double offset;
        const int exact = exact_axis_cell(g, x[d], d, offset);
        const bool on_face = std::fabs(double(offset)) < face_tolerance ||
                             std::fabs(double(offset - (long double)g.a)) < face_tolerance;
        near_face += on_face;
        const bool outside_walls = offset < 0 || offset >= (long double)g.a;
        if (on_face) {
          const int distance = std::abs(k - exact);
          EXPECT_TRUE(distance <= 1 || (g.periodic[d] && distance == g.n[d] - 1)) << "axis " << d;
        } else {
          EXPECT_EQ(k, exact) << "axis " << d << " x " << x[d] << " shift " << g.shift[d];
        }
        if (!outside_walls) {
          EXPECT_GE(local[d], Real(0)) << "axis " << d;
          EXPECT_LT(local[d], g.a) << "axis " << d;
        }
        // x − (corner + local) is 0, or a period on a periodic axis.
        double image = double(x[d]) - (double(corner[d]) + double(local[d]));
        if (g.periodic[d]) image -= double(g.length[d]) * std::round(image / double(g.length[d]));
        EXPECT_NEAR(image, 0.0, 4 * testing::eps<Real>() * 16.0) << "axis " << d;
      }
    }
  }
  EXPECT_LT(near_face, 100);
}

// Dyadic grid, shift and points, so every face position is exact: a point on a face belongs to the
// cell above it (local 0); the periodic face lo + L − shift wraps to cell 0; a walled axis puts lo
// in cell 0 at offset shift and lo + L in the extra layer.
TYPED_TEST(MpcGridTest, PointsExactlyOnCellFaces) {
  using Real = typename TypeParam::real;
  auto g = make_collision_grid<2, Real>(Real(0.5), {Real(1), Real(-2)}, {Real(4), Real(3)}, {1, 0});
  ASSERT_EQ(g.n[0], 8);
  ASSERT_EQ(g.n[1], 7);
  g.shift[0] = Real(0.125);
  g.shift[1] = Real(0.375);
  Real local[2];
  for (int k = 0; k < 8; ++k) {
    const Real x[2] = {Real(1 - 0.125 + 0.5 * k), Real(-2 - 0.375 + 0.5 * 3)};
    const int cell = g.locate(x, local);
    EXPECT_EQ(cell, k + 8 * 3) << "face k = " << k;
    EXPECT_EQ(local[0], Real(0));
    EXPECT_EQ(local[1], Real(0));
  }
  const Real wrap[2] = {Real(1 + 4 - 0.125), Real(-2)};
  EXPECT_EQ(g.locate(wrap, local), 0);
  EXPECT_EQ(local[0], Real(0));
  EXPECT_EQ(local[1], Real(0.375));
  const Real top[2] = {Real(1), Real(1)};  // lo + L on the walled axis: −2 + 3
  EXPECT_EQ(g.locate(top, local), 8 * 6);
  EXPECT_EQ(local[0], Real(0.125));
  EXPECT_EQ(local[1], Real(0.375));
  Real corner[2];
  g.lower_corner(8 * 6 + 7, corner);
  EXPECT_EQ(corner[0], Real(1 - 0.125 + 3.5));
  EXPECT_EQ(corner[1], Real(-2 - 0.375 + 3));
}

// Shift components in [0, a), reproducible for (seed, step), different between steps and seeds,
// and uniform: 4000 draws per axis in 8 bins, each within 5σ of 500.
TYPED_TEST(MpcGridTest, ShiftIsUniformInZeroToAAndReproducible) {
  using Real = typename TypeParam::real;
  auto g = make_collision_grid<3, Real>(Real(0.8), {Real(0), Real(0), Real(0)}, {Real(8), Real(8), Real(8)}, {1, 1, 0});
  auto h = g;
  int bins[3][8] = {};
  for (int step = 0; step < 4000; ++step) {
    g.draw_shift(17, step);
    h.draw_shift(17, step);
    for (int d = 0; d < 3; ++d) {
      ASSERT_GE(g.shift[d], Real(0));
      ASSERT_LT(g.shift[d], g.a);
      ASSERT_EQ(g.shift[d], h.shift[d]);
      ++bins[d][int(g.shift[d] / g.a * 8)];
    }
  }
  for (int d = 0; d < 3; ++d)
    for (int b = 0; b < 8; ++b) EXPECT_NEAR(bins[d][b], 500, 5 * std::sqrt(500 * 7.0 / 8)) << d << " " << b;
  g.draw_shift(17, 1);
  h.draw_shift(17, 2);
  auto k = g;
  k.draw_shift(18, 1);
  for (int d = 0; d < 3; ++d) {
    EXPECT_NE(g.shift[d], h.shift[d]);
    EXPECT_NE(g.shift[d], k.shift[d]);
  }
}

// Eq. (B.1) against the same arithmetic on the host, with a body acceleration; wrapped on the
// periodic axis (into [lo, lo + L)), not on the walled one.
TYPED_TEST(MpcGridTest, StreamingAppliesB1AndWrapsPeriodicAxesOnly) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  const auto g = make_collision_grid<2, Real>(Real(1), {Real(-5), Real(0)}, {Real(10), Real(6)}, {1, 0});
  const int n = 2000;
  Kokkos::View<Real* [2], Kokkos::LayoutLeft, Exec> x("x", n), v("v", n);
  auto xh = Kokkos::create_mirror(x);  // copies, not aliases on host spaces: kept as the input
  auto vh = Kokkos::create_mirror(v);
  std::mt19937 gen(2);
  std::uniform_real_distribution<double> ux(-5.0, 5.0), uy(0.0, 6.0), uv(-30.0, 30.0);
  for (int i = 0; i < n; ++i) {
    xh(i, 0) = Real(ux(gen));
    xh(i, 1) = Real(uy(gen));
    vh(i, 0) = Real(uv(gen));
    vh(i, 1) = Real(uv(gen));
  }
  Kokkos::deep_copy(x, xh);
  Kokkos::deep_copy(v, vh);
  const Real h = Real(0.1);
  const Kokkos::Array<Real, 2> gravity = {Real(0.5), Real(-2)};
  mpc::stream(x, v, h, gravity, g);
  auto xs = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), x);
  auto vs = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), v);
  int wrapped = 0, left_walled_box = 0;
  for (int i = 0; i < n; ++i) {
    for (int d = 0; d < 2; ++d) {
      const Real vn = vh(i, d) + gravity[d] * h;
      // v + g h and x + h v: bitwise on host backends; a device compiler contracts each into one FMA
      // (testing::agrees_with_host, 2 and 4 operations at the scales of v and of x's wrap, 10).
      ASSERT_TRUE((testing::agrees_with_host<Exec, Real>(vs(i, d), vn, 2, 31.0))) << "particle " << i;
      Real xn = xh(i, d) + h * vn;
      if (d == 0) {
        if (xn >= Real(5)) {
          xn -= Real(10);
          ++wrapped;
        } else if (xn < Real(-5)) {
          xn += Real(10);
          ++wrapped;
        }
        EXPECT_GE(xs(i, d), Real(-5));
        EXPECT_LT(xs(i, d), Real(5));
      } else {
        left_walled_box += xn < Real(0) || xn > Real(6);
      }
      // A position within round-off of the periodic edge may be wrapped on one side and not the other:
      // compare the separation's minimum image along the periodic axis.
      double dx = double(xs(i, d)) - double(xn);
      if (d == 0) dx -= 10.0 * std::round(dx / 10.0);
      ASSERT_TRUE((testing::agrees_with_host<Exec, Real>(double(xn) + dx, xn, 4, 10.0)))
          << "particle " << i << " axis " << d;
    }
  }
  EXPECT_GT(wrapped, 50);
  EXPECT_GT(left_walled_box, 50);
}

// The periodic-Poiseuille drive: v_x += g h in the lower half of the gradient axis (periodic images
// folded back), −g h in the upper half, v_y untouched; with equal halves the total momentum is
// unchanged. A gradient axis equal to the flow axis is refused.
TYPED_TEST(MpcGridTest, SplitBodyForceKicksEachHalfOppositelyAndConservesMomentum) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  const auto g = make_collision_grid<2, Real>(Real(1), {Real(0), Real(-4)}, {Real(10), Real(8)}, {1, 1});
  // y: lower half [-4, 0), upper half [0, 4), and images one box length away.
  const double ys[] = {-3.5, -0.25, 0.25, 3.5, 4.5, 11.75, -11.5, -4.25};
  const double expected_sign[] = {1, 1, -1, -1, 1, -1, 1, -1};
  const int n = 8;
  Kokkos::View<Real* [2], Kokkos::LayoutLeft, Exec> x("x", n), v("v", n);
  auto xh = Kokkos::create_mirror_view(x);
  auto vh = Kokkos::create_mirror_view(v);
  for (int i = 0; i < n; ++i) {
    xh(i, 0) = Real(0.5 * i);
    xh(i, 1) = Real(ys[i]);
    vh(i, 0) = Real(0.1 * i);
    vh(i, 1) = Real(-0.2 * i);
  }
  Kokkos::deep_copy(x, xh);
  Kokkos::deep_copy(v, vh);
  const Real gravity = Real(0.3), h = Real(0.5);
  mpc::kick_split_body_force(x, v, gravity, h, g, 1);
  Kokkos::deep_copy(vh, v);
  double px = 0;
  for (int i = 0; i < n; ++i) {
    EXPECT_NEAR(double(vh(i, 0)), 0.1 * i + expected_sign[i] * 0.15, 8 * testing::eps<Real>()) << "particle " << i;
    EXPECT_EQ(double(vh(i, 1)), double(Real(-0.2 * i)));
    px += double(vh(i, 0)) - 0.1 * i;
  }
  EXPECT_NEAR(px, 0.0, 16 * testing::eps<Real>());
  EXPECT_THROW(mpc::kick_split_body_force(x, v, gravity, h, g, 0), std::invalid_argument);
}

}  // namespace
}  // namespace mesoflow
