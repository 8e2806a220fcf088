// Several obstacle arrays in one ObstacleArray (one per replica of an ensemble): nearest(a, x) and
// the per-body candidate lists see array a only, and equal a brute-force nearest over that array.
#include "kernels/common/body_obstacle_list.hpp"
#include "test_types.hpp"

#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace mesoflow {
namespace {

template <class T>
class ObstacleArraysPerReplicaTest : public ::testing::Test {};
TYPED_TEST_SUITE(ObstacleArraysPerReplicaTest, testing::BackendsAndPrecisions);

constexpr double kL = 12.0, kSigmaOb = 0.3, kGap = 0.4;
constexpr int kArrays = 3;

template <class Real>
Box<2, Real> square() {
  const Real lo[2] = {0, 0}, len[2] = {Real(kL), Real(kL)};
  const bool periodic[2] = {true, true};
  return Box<2, Real>(lo, len, periodic);
}

// Distance from x to the nearest obstacle surface of `centres`, by brute force over the minimum image.
double brute_force(const std::vector<Vec<2, double>>& centres, double x, double y) {
  double best = std::numeric_limits<double>::max();
  for (const auto& c : centres) {
    double dx = x - c[0], dy = y - c[1];
    dx -= kL * std::floor(dx / kL + 0.5);
    dy -= kL * std::floor(dy / kL + 0.5);
    best = std::min(best, std::sqrt(dx * dx + dy * dy) - 0.5 * kSigmaOb);
  }
  return best;
}

std::vector<std::vector<Vec<2, double>>> arrays() {
  std::vector<std::vector<Vec<2, double>>> a;
  for (int k = 0; k < kArrays; ++k) a.push_back(poisson_disk_obstacles(kL, kL, kSigmaOb, kGap, 100 + k));
  return a;
}

// Kernels of the tests below live in free functions: nvcc rejects a KOKKOS_LAMBDA in a TYPED_TEST
// body (GoogleTest's private TestBody()).

// d(i, a): distance from point i to the nearest obstacle of array a.
template <class Real, class Exec, class PointView>
Kokkos::View<double**, Exec> nearest_in_every_array(const ObstacleArray<Real, Exec>& all, const PointView& x) {
  const int n = int(x.extent(0));
  Kokkos::View<double**, Exec> d("d", n, kArrays);
  Kokkos::parallel_for(
      "mesoflow::test::nearest_in_every_array", Kokkos::RangePolicy<Exec>(0, n), KOKKOS_LAMBDA(int i) {
        for (int a = 0; a < kArrays; ++a)
          d(i, a) = all.nearest(a, Vec<2, Real>{{Real(x(i, 0)), Real(x(i, 1))}}).distance;
      });
  return d;
}

// d(i): distance from particle i to the nearest candidate obstacle of its body (per particles each).
template <class Real, class Exec, class PositionView>
Kokkos::View<double*, Exec> nearest_candidate(const BodyObstacleList<Real, Exec>& list, const PositionView& x,
                                              int per) {
  const int n = int(x.extent(0));
  Kokkos::View<double*, Exec> d("d", n);
  Kokkos::parallel_for(
      "mesoflow::test::nearest_candidate", Kokkos::RangePolicy<Exec>(0, n), KOKKOS_LAMBDA(int i) {
        d(i) = list.nearest(i / per, Vec<2, Real>::load(x, i)).distance;
      });
  return d;
}

TYPED_TEST(ObstacleArraysPerReplicaTest, NearestSeesOnlyItsOwnArray) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  const auto centres = arrays();
  const auto all = ObstacleArray<Real, Exec>::from_arrays(square<Real>(), centres, Real(kSigmaOb), Real(kSigmaOb + kGap));
  ASSERT_EQ(all.num_arrays(), kArrays);
  int total = 0;
  for (int a = 0; a < kArrays; ++a) {
    EXPECT_EQ(all.size(a), int(centres[a].size()));
    total += all.size(a);
  }
  EXPECT_EQ(all.size(), total);
  const int n = 500;
  Kokkos::View<double* [2], Kokkos::HostSpace> xh("x", n);
  std::mt19937_64 gen(5);
  std::uniform_real_distribution<double> u(-kL, 2 * kL);  // images of the box too
  for (int i = 0; i < n; ++i) xh(i, 0) = u(gen), xh(i, 1) = u(gen);
  const auto x = Kokkos::create_mirror_view_and_copy(typename Exec::memory_space(), xh);
  const auto d = nearest_in_every_array(all, x);
  const auto dh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), d);
  const double tol = 1e3 * testing::eps<Real>() * kL;  // positions of magnitude 2L rounded to Real
  double worst = 0;
  int differs_from_other_arrays = 0;
  for (int i = 0; i < n; ++i)
    for (int a = 0; a < kArrays; ++a) {
      worst = std::max(worst, std::abs(dh(i, a) - brute_force(centres[a], xh(i, 0), xh(i, 1))));
      differs_from_other_arrays += std::abs(dh(i, a) - brute_force(centres[(a + 1) % kArrays], xh(i, 0), xh(i, 1))) > tol;
    }
  EXPECT_LE(worst, tol);
  // The arrays differ, so a query that leaked into another array would show: most points must see
  // another distance there.
  EXPECT_GT(differs_from_other_arrays, n * kArrays / 2);
}

TYPED_TEST(ObstacleArraysPerReplicaTest, BodyCandidatesComeFromTheBodysArray) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  const auto centres = arrays();
  const auto all = ObstacleArray<Real, Exec>::from_arrays(square<Real>(), centres, Real(kSigmaOb), Real(kSigmaOb + kGap));
  // Six bodies (rings of 24 particles, radius 0.5), body b in array b % 3.
  const int bodies = 6, per = 24;
  Kokkos::View<int*, Exec> offset("offset", bodies + 1), body_array("body_array", bodies);
  auto oh = Kokkos::create_mirror_view(offset);
  auto ah = Kokkos::create_mirror_view(body_array);
  for (int b = 0; b <= bodies; ++b) oh(b) = b * per;
  for (int b = 0; b < bodies; ++b) ah(b) = b % kArrays;
  Kokkos::deep_copy(offset, oh);
  Kokkos::deep_copy(body_array, ah);
  Particles<2, Real, Exec> p(bodies * per);
  auto xh = Kokkos::create_mirror_view(p.x);
  std::vector<double> xd(2 * bodies * per);
  for (int b = 0; b < bodies; ++b)
    for (int k = 0; k < per; ++k) {
      const double t = 2 * 3.14159265358979 * k / per;
      xd[2 * (b * per + k)] = 1.7 * b + 0.5 * std::cos(t) + 1.0;
      xd[2 * (b * per + k) + 1] = 0.9 * b + 0.5 * std::sin(t) + 2.0;
      xh(b * per + k, 0) = Real(xd[2 * (b * per + k)]);
      xh(b * per + k, 1) = Real(xd[2 * (b * per + k) + 1]);
    }
  Kokkos::deep_copy(p.x, xh);
  BodyObstacleList<Real, Exec> list(all, offset, body_array, Real(0.5));
  list.update(p.x);
  const auto d = nearest_candidate(list, p.x, per);
  const auto dh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), d);
  double worst = 0;
  for (int i = 0; i < bodies * per; ++i)
    worst = std::max(worst, std::abs(dh(i) - brute_force(centres[(i / per) % kArrays], xd[2 * i], xd[2 * i + 1])));
  EXPECT_LE(worst, 1e3 * testing::eps<Real>() * kL);
}

TEST(ObstacleArraysPerReplica, SingleArrayApiIsArrayZero) {
  using Exec = Kokkos::DefaultExecutionSpace;
  const auto centres = arrays();
  const ObstacleArray<double, Exec> one(square<double>(), centres[0], kSigmaOb, kSigmaOb + kGap);
  EXPECT_EQ(one.num_arrays(), 1);
  EXPECT_EQ(one.size(0), one.size());
  const Kokkos::View<int*, Exec> one_body("offset", 2), three_arrays("body_array", 3);
  EXPECT_THROW((BodyObstacleList<double, Exec>(one, one_body, three_arrays, 0.5)), std::invalid_argument);
}

}  // namespace
}  // namespace mesoflow
