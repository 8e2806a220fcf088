// test_obstacle_array.cpp — random obstacle arrays (kernels/common/obstacle_array.hpp).
//
// The Poisson-disk generator: every pair of centres at least σ_ob + w_ob apart under the minimum image,
// maximal (no point of a dense random probe fits another centre), the same array for a seed and another
// for another seed, invalid parameters refused. The obstacle cell list: nearest() equals a brute-force
// search over every obstacle and its periodic images — at random points, inside obstacles, across the
// periodic boundary and far outside the box — for maximal and sparse arrays, boxes of 2 × 2 cells and
// a box not at the origin; no obstacles give no surface; Surfaces picks the nearer of walls and
// obstacles; and the number of obstacles a query examines does not grow from L = 20σ to L = 200σ at
// fixed density. Queries run in parallel_for kernels on each backend, checks on the host.
#include <gtest/gtest.h>

#include "kernels/common/obstacle_array.hpp"
#include "test_types.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using mesoflow::Box;
using mesoflow::ObstacleArray;
using mesoflow::Shape;
using mesoflow::SurfacePoint;
using mesoflow::Surfaces;
using mesoflow::Vec;
using mesoflow::testing::eps;
using V2 = Vec<2, double>;

constexpr double kSigmaOb = 0.3;  // the obstacle arrays of the paper's Fig. 1(b), σ = 1
constexpr double kWOb = 1.0;

// Minimum-image separation in the periodic rectangle lx × ly.
double image_distance(const V2& a, const V2& b, double lx, double ly) {
  double dx = a[0] - b[0], dy = a[1] - b[1];
  dx -= lx * std::floor(dx / lx + 0.5);
  dy -= ly * std::floor(dy / ly + 0.5);
  return std::sqrt(dx * dx + dy * dy);
}

struct Scene {
  double lx, ly, sigma_ob, w_ob;
  std::uint64_t seed;
};

// Boxes much larger than the spacing, a rectangle whose sides are not multiples of the grid, and a box
// only a little wider than σ_ob + w_ob (where a centre sees its neighbours through several images).
const Scene kScenes[] = {{30.0, 30.0, kSigmaOb, kWOb, 1},
                         {17.3, 11.1, 0.5, 0.2, 2},
                         {2.9, 3.7, 0.5, 0.8, 3},
                         {9.0, 6.0, 1.0, 0.0, 4}};

TEST(PoissonDiskObstacles, CentresAreAtLeastTheMinimumSeparationApartUnderMinimumImage) {
  for (const Scene& s : kScenes) {
    const std::vector<V2> c = mesoflow::poisson_disk_obstacles(s.lx, s.ly, s.sigma_ob, s.w_ob, s.seed);
    ASSERT_FALSE(c.empty());
    double closest = std::numeric_limits<double>::max();
    for (std::size_t i = 0; i < c.size(); ++i) {
      EXPECT_TRUE(c[i][0] >= 0 && c[i][0] < s.lx && c[i][1] >= 0 && c[i][1] < s.ly);
      for (std::size_t j = i + 1; j < c.size(); ++j) closest = std::min(closest, image_distance(c[i], c[j], s.lx, s.ly));
    }
    if (c.size() > 1) {
      EXPECT_GE(closest, s.sigma_ob + s.w_ob) << "box " << s.lx << " x " << s.ly;
    }
  }
}

TEST(PoissonDiskObstacles, IsMaximalNoFurtherCentreFits) {
  for (const Scene& s : kScenes) {
    const std::vector<V2> c = mesoflow::poisson_disk_obstacles(s.lx, s.ly, s.sigma_ob, s.w_ob, s.seed);
    std::mt19937_64 gen(99 + s.seed);
    std::uniform_real_distribution<double> ux(0, s.lx), uy(0, s.ly);
    int fits = 0;
    for (int probe = 0; probe < 10000; ++probe) {
      const V2 p{{ux(gen), uy(gen)}};
      double nearest = std::numeric_limits<double>::max();
      for (const V2& q : c) nearest = std::min(nearest, image_distance(p, q, s.lx, s.ly));
      fits += nearest >= s.sigma_ob + s.w_ob;
    }
    EXPECT_EQ(fits, 0) << "box " << s.lx << " x " << s.ly << " with " << c.size() << " obstacles";
  }
}

TEST(PoissonDiskObstacles, SameArrayForASeedAnotherForAnotherSeed) {
  const auto a = mesoflow::poisson_disk_obstacles(25.0, 20.0, kSigmaOb, kWOb, 7);
  const auto b = mesoflow::poisson_disk_obstacles(25.0, 20.0, kSigmaOb, kWOb, 7);
  const auto c = mesoflow::poisson_disk_obstacles(25.0, 20.0, kSigmaOb, kWOb, 8);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i][0], b[i][0]);
    EXPECT_EQ(a[i][1], b[i][1]);
  }
  bool differs = a.size() != c.size();
  for (std::size_t i = 0; !differs && i < a.size(); ++i) differs = a[i][0] != c[i][0] || a[i][1] != c[i][1];
  EXPECT_TRUE(differs);
}

// Sparser arrays at a set obstacle count (random sequential addition): exactly that many centres,
// the same minimum separation, reproducible, and a count that cannot fit refused.
TEST(RandomSequentialObstacles, PlacesTheCountAtTheMinimumSeparation) {
  const double L = 20.0, sigma_ob = 0.3, w_ob = 0.2;
  const std::size_t count = 200;  // area fraction 200 · π 0.15² / 400 ≈ 0.035
  const auto c = mesoflow::random_sequential_obstacles(L, L, sigma_ob, w_ob, count, 5);
  ASSERT_EQ(c.size(), count);
  double closest = std::numeric_limits<double>::max();
  for (std::size_t i = 0; i < c.size(); ++i) {
    EXPECT_TRUE(c[i][0] >= 0 && c[i][0] < L && c[i][1] >= 0 && c[i][1] < L);
    for (std::size_t j = i + 1; j < c.size(); ++j) closest = std::min(closest, image_distance(c[i], c[j], L, L));
  }
  EXPECT_GE(closest, sigma_ob + w_ob);
  const auto again = mesoflow::random_sequential_obstacles(L, L, sigma_ob, w_ob, count, 5);
  for (std::size_t i = 0; i < c.size(); ++i) EXPECT_EQ(c[i][0], again[i][0]);
  // Sparser than the maximal sample of the same gap.
  EXPECT_LT(c.size(), mesoflow::poisson_disk_obstacles(L, L, sigma_ob, w_ob, 5).size() / 4);
}

TEST(RandomSequentialObstacles, RefusesACountThatDoesNotFit) {
  // A maximal sample of this box holds ~0.7 centres per (σ_ob + w_ob)²: 4000 in 20 × 20 at 0.5 cannot fit.
  try {
    mesoflow::random_sequential_obstacles(20.0, 20.0, 0.3, 0.2, 4000, 1);
    FAIL() << "4000 obstacles accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("lower the obstacle fraction"), std::string::npos) << e.what();
  }
}

TEST(PoissonDiskObstacles, RefusesInvalidParameters) {
  EXPECT_THROW(mesoflow::poisson_disk_obstacles(0.0, 10.0, kSigmaOb, kWOb, 1), std::invalid_argument);
  EXPECT_THROW(mesoflow::poisson_disk_obstacles(10.0, NAN, kSigmaOb, kWOb, 1), std::invalid_argument);
  EXPECT_THROW(mesoflow::poisson_disk_obstacles(10.0, 10.0, 0.0, kWOb, 1), std::invalid_argument);
  EXPECT_THROW(mesoflow::poisson_disk_obstacles(10.0, 10.0, kSigmaOb, -0.1, 1), std::invalid_argument);
  EXPECT_THROW(mesoflow::poisson_disk_obstacles(1.0, 10.0, kSigmaOb, kWOb, 1), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------------
// Queries on the device.

template <class ExecSpace, class Real>
Kokkos::View<Vec<2, Real>*, typename ExecSpace::memory_space> to_device(const std::vector<Vec<2, Real>>& points) {
  Kokkos::View<Vec<2, Real>*, typename ExecSpace::memory_space> x("mesoflow::test_obstacle_array::x", points.size());
  const auto host = Kokkos::create_mirror_view(x);
  for (std::size_t i = 0; i < points.size(); ++i) host(i) = points[i];
  Kokkos::deep_copy(x, host);
  return x;
}

// nearest(x) of an ObstacleArray or Surfaces at every point.
template <class ExecSpace, class Query, class Real>
std::vector<SurfacePoint<2, Real>> nearest_on_device(const Query& query, const std::vector<Vec<2, Real>>& points) {
  const auto x = to_device<ExecSpace>(points);
  Kokkos::View<SurfacePoint<2, Real>*, typename ExecSpace::memory_space> result("mesoflow::test_obstacle_array::result",
                                                                                points.size());
  Kokkos::parallel_for(
      "mesoflow::test_obstacle_array::nearest", Kokkos::RangePolicy<ExecSpace>(0, points.size()),
      KOKKOS_LAMBDA(const int i) { result(i) = query.nearest(x(i)); });
  const auto host = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), result);
  return std::vector<SurfacePoint<2, Real>>(host.data(), host.data() + points.size());
}

// The number of obstacles nearest_examined() looks at for each point.
template <class ExecSpace, class Real>
std::vector<int> examined_on_device(const ObstacleArray<Real, ExecSpace>& obstacles,
                                    const std::vector<Vec<2, Real>>& points) {
  const auto x = to_device<ExecSpace>(points);
  Kokkos::View<int*, typename ExecSpace::memory_space> count("mesoflow::test_obstacle_array::examined", points.size());
  Kokkos::parallel_for(
      "mesoflow::test_obstacle_array::examined", Kokkos::RangePolicy<ExecSpace>(0, points.size()),
      KOKKOS_LAMBDA(const int i) { obstacles.nearest_examined(x(i), count(i)); });
  const auto host = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), count);
  return std::vector<int>(host.data(), host.data() + points.size());
}

template <class Real>
Box<2, Real> periodic_box(double lo_x, double lo_y, double lx, double ly) {
  const Real lo[2] = {Real(lo_x), Real(lo_y)}, length[2] = {Real(lx), Real(ly)};
  const bool periodic[2] = {true, true};
  return Box<2, Real>(lo, length, periodic);
}

// Brute force in double over every obstacle and its images up to two boxes away from the box
// [lo, lo + L) that x is folded into: the nearest surface distance, the normal there, and the gap to
// the next candidate (another obstacle or another image), below which the nearest point is ambiguous.
struct Reference {
  double distance, gap;
  V2 normal;
};

Reference brute_force(V2 x, const std::vector<V2>& centers, double radius, const V2& lo, double lx, double ly) {
  x[0] -= lx * std::floor((x[0] - lo[0]) / lx);
  x[1] -= ly * std::floor((x[1] - lo[1]) / ly);
  Reference r{std::numeric_limits<double>::max(), std::numeric_limits<double>::max(), x};
  double second = std::numeric_limits<double>::max();
  for (const V2& c : centers)
    for (int sx = -2; sx <= 2; ++sx)
      for (int sy = -2; sy <= 2; ++sy) {
        const V2 image{{c[0] + sx * lx, c[1] + sy * ly}};
        const V2 dr = x - image;
        const double rho = std::sqrt(mesoflow::norm2(dr));
        const double d = rho - radius;
        if (d < r.distance) {
          second = r.distance;
          r.distance = d;
          r.normal = (1 / rho) * dr;
        } else {
          second = std::min(second, d);
        }
      }
  r.gap = second - r.distance;
  return r;
}

struct ArrayCase {
  const char* name;
  double lo_x, lo_y, lx, ly, diameter, cell_width;
  std::vector<V2> centers;  // in [lo, lo + L)
};

std::vector<ArrayCase> array_cases() {
  std::vector<ArrayCase> cases;
  cases.push_back({"maximal", 0, 0, 23.7, 17.1, kSigmaOb, kSigmaOb + kWOb,
                   mesoflow::poisson_disk_obstacles(23.7, 17.1, kSigmaOb, kWOb, 11)});
  // Three obstacles in a 20 × 15 box with unit cells, the box not at the origin: queries far from every
  // obstacle search many rings, up to the whole (clipped) box.
  cases.push_back({"sparse", -10, -7.5, 20, 15, 0.6, 1.0, {V2{{-9.7, -7.2}}, V2{{3.3, 2.0}}, V2{{9.8, 7.3}}}});
  // 2 × 2 cells (even count) and 3 × 2 cells: every offset clipped at once.
  {
    auto c = mesoflow::poisson_disk_obstacles(3.1, 2.9, 0.5, 0.8, 12);
    cases.push_back({"two-by-two", 0, 0, 3.1, 2.9, 0.5, 1.3, c});
  }
  {
    auto c = mesoflow::poisson_disk_obstacles(4.0, 2.7, 0.5, 0.8, 13);
    cases.push_back({"three-by-two", 0, 0, 4.0, 2.7, 0.5, 1.3, c});
  }
  return cases;
}

// Random points in the box, points inside obstacles, points within 0.6 of the periodic boundary on
// either side of it, and images of random points several boxes away.
std::vector<V2> query_points(const ArrayCase& c, std::uint64_t seed) {
  std::mt19937_64 gen(seed);
  std::uniform_real_distribution<double> u01(0, 1);
  std::vector<V2> q;
  for (int i = 0; i < 1500; ++i) q.push_back(V2{{c.lo_x + c.lx * u01(gen), c.lo_y + c.ly * u01(gen)}});
  const double radius = 0.5 * c.diameter;
  for (std::size_t i = 0; i < std::min<std::size_t>(c.centers.size(), 200); ++i) {
    const double rho = radius * (0.1 + 0.85 * u01(gen)), phi = 6.283185307179586 * u01(gen);
    q.push_back(V2{{c.centers[i][0] + rho * std::cos(phi), c.centers[i][1] + rho * std::sin(phi)}});
  }
  for (int i = 0; i < 400; ++i) {
    const double edge = 1.2 * u01(gen) - 0.6;  // signed offset from a boundary
    const double along = u01(gen);
    const bool upper = u01(gen) < 0.5;
    if (i % 2 == 0)
      q.push_back(V2{{c.lo_x + (upper ? c.lx : 0) + edge, c.lo_y + along * c.ly}});
    else
      q.push_back(V2{{c.lo_x + along * c.lx, c.lo_y + (upper ? c.ly : 0) + edge}});
  }
  for (int i = 0; i < 200; ++i) {
    const int kx = int(u01(gen) * 7) - 3, ky = int(u01(gen) * 7) - 3;
    q.push_back(V2{{c.lo_x + c.lx * (u01(gen) + kx), c.lo_y + c.ly * (u01(gen) + ky)}});
  }
  return q;
}

template <class Config>
class ObstacleArrayTest : public ::testing::Test {};
TYPED_TEST_SUITE(ObstacleArrayTest, mesoflow::testing::BackendsAndPrecisions);

TYPED_TEST(ObstacleArrayTest, NearestEqualsBruteForceOverAllObstaclesAndImages) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  for (const ArrayCase& c : array_cases()) {
    SCOPED_TRACE(c.name);
    const ObstacleArray<Real, Exec> obstacles(periodic_box<Real>(c.lo_x, c.lo_y, c.lx, c.ly), c.centers,
                                              Real(c.diameter), Real(c.cell_width));
    ASSERT_EQ(obstacles.size(), int(c.centers.size()));
    // The reference sees the centres and the radius as the kernel does, rounded to Real.
    std::vector<V2> centers;
    for (const V2& p : c.centers) centers.push_back(V2{{double(Real(p[0])), double(Real(p[1]))}});
    const double radius = double(Real(0.5) * Real(c.diameter));
    const std::vector<V2> points = query_points(c, 5);
    std::vector<Vec<2, Real>> x;
    for (const V2& p : points) x.push_back(Vec<2, Real>{{Real(p[0]), Real(p[1])}});
    const auto got = nearest_on_device<Exec>(obstacles, x);

    // Round-off: coordinates up to a few box lengths, times a few eps.
    const double scale = 8 * std::max(c.lx, c.ly);
    const double tol = 16 * eps<Real>() * scale;
    int inside = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const V2 xi{{double(x[i][0]), double(x[i][1])}};
      const Reference ref = brute_force(xi, centers, radius, V2{{c.lo_x, c.lo_y}}, c.lx, c.ly);
      const SurfacePoint<2, Real>& s = got[i];
      inside += ref.distance < 0;
      ASSERT_NEAR(double(s.distance), ref.distance, tol) << "query " << i << " at (" << xi[0] << ", " << xi[1] << ")";
      if (ref.gap < 1e-3) continue;  // two candidates equally near: either answer is right
      const double rho = ref.distance + radius;
      for (int d = 0; d < 2; ++d) {
        EXPECT_NEAR(double(s.normal[d]), ref.normal[d], tol / rho) << "query " << i;
        EXPECT_NEAR(double(s.point[d]), xi[d] - ref.distance * ref.normal[d], 4 * tol) << "query " << i;
      }
    }
    if (c.centers.size() > 10) {
      EXPECT_GT(inside, 100);
    }
  }
}

TYPED_TEST(ObstacleArrayTest, NoObstaclesIsNoSurface) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  const std::vector<Vec<2, Real>> x = {Vec<2, Real>{{Real(0.5), Real(-3)}}, Vec<2, Real>{{Real(40), Real(2)}}};
  const ObstacleArray<Real, Exec> none(periodic_box<Real>(0, 0, 10, 10), {}, Real(kSigmaOb), Real(1.3));
  for (const auto& got : {nearest_on_device<Exec>(none, x), nearest_on_device<Exec>(ObstacleArray<Real, Exec>(), x),
                          nearest_on_device<Exec>(Surfaces<Real, Exec>(), x)})
    for (std::size_t i = 0; i < x.size(); ++i) {
      EXPECT_EQ(got[i].distance, std::numeric_limits<Real>::max());
      EXPECT_EQ(got[i].point[0], x[i][0]);
      EXPECT_EQ(got[i].point[1], x[i][1]);
    }
}

TYPED_TEST(ObstacleArrayTest, SurfacesTakeTheNearerOfWallsAndObstacles) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  using R2 = Vec<2, Real>;
  // A floor y = 0 (fluid above) and two obstacles of radius 0.5 at (2, 3) and (6, 1.2).
  const std::vector<Shape<2, Real>> walls = {Shape<2, Real>::half_space(R2{{Real(0), Real(0)}}, R2{{Real(0), Real(1)}})};
  const ObstacleArray<Real, Exec> obstacles(periodic_box<Real>(0, 0, 10, 10), {V2{{2, 3}}, V2{{6, 1.2}}}, Real(1),
                                            Real(1.5));
  const Surfaces<Real, Exec> both(walls, obstacles);
  const Surfaces<Real, Exec> walls_only(walls);
  const Surfaces<Real, Exec> obstacles_only(obstacles);
  EXPECT_EQ(both.num_walls(), 1);
  EXPECT_EQ(both.obstacles().size(), 2);
  const std::vector<R2> x = {R2{{Real(2), Real(2)}},    // obstacle 0.5 away, floor 2
                             R2{{Real(6), Real(0.4)}},  // floor 0.4, obstacle 0.3
                             R2{{Real(9), Real(0.2)}},  // floor 0.2, obstacles ≥ 1.2
                             R2{{Real(2), Real(3.2)}}}; // inside obstacle: −0.3
  const double expect_d[] = {0.5, 0.3, 0.2, -0.3};
  const double expect_ny[] = {-1, -1, 1, 1};
  const auto got = nearest_on_device<Exec>(both, x);
  const auto wall = nearest_on_device<Exec>(walls_only, x);
  const auto obstacle = nearest_on_device<Exec>(obstacles_only, x);
  const double tol = 64 * eps<Real>();
  for (std::size_t i = 0; i < x.size(); ++i) {
    EXPECT_NEAR(double(got[i].distance), expect_d[i], tol) << "point " << i;
    EXPECT_NEAR(double(got[i].normal[1]), expect_ny[i], tol) << "point " << i;
    EXPECT_EQ(got[i].distance, std::min(wall[i].distance, obstacle[i].distance));
  }
}

TEST(ObstacleArrayCost, ExaminedObstaclesDoNotGrowWithBoxSize) {
  using Exec = Kokkos::DefaultExecutionSpace;
  struct Cost {
    double mean;
    int max;
    int obstacles;
  };
  const auto cost = [](double L) {
    const auto centers = mesoflow::poisson_disk_obstacles(L, L, kSigmaOb, kWOb, 21);
    const ObstacleArray<double, Exec> obstacles(periodic_box<double>(0, 0, L, L), centers, kSigmaOb, kSigmaOb + kWOb);
    std::mt19937_64 gen(22);
    std::uniform_real_distribution<double> u(0, L);
    std::vector<V2> x(20000);
    for (V2& p : x) p = V2{{u(gen), u(gen)}};
    const std::vector<int> n = examined_on_device<Exec>(obstacles, x);
    double sum = 0;
    for (int k : n) sum += k;
    return Cost{sum / double(n.size()), *std::max_element(n.begin(), n.end()), obstacles.size()};
  };
  const Cost small = cost(20), large = cost(200);
  std::cout << "[ cost ] L = 20: " << small.obstacles << " obstacles, examined per query mean " << small.mean
            << " max " << small.max << "; L = 200: " << large.obstacles << " obstacles, mean " << large.mean << " max "
            << large.max << "\n";
  // A maximal sample leaves no point σ_ob + w_ob from every centre, so the search stops after the 3 × 3
  // cells around the query; a cell of width ≈ σ_ob + w_ob holds at most 4 centres that far apart.
  EXPECT_LE(small.max, 36);
  EXPECT_LE(large.max, 36);
  EXPECT_LT(large.mean, 1.1 * small.mean);
  EXPECT_GT(large.obstacles, 90 * small.obstacles);
}

}  // namespace
