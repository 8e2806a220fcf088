// Box: minimum image and wrapping on periodic axes, nothing on bounded ones.
#include "kernels/common/box.hpp"
#include "test_types.hpp"

#include <cmath>
#include <random>

namespace mesoflow {
namespace {

template <class T>
class BoxTest : public ::testing::Test {};

// Kernels live in free functions, not test bodies: CUDA forbids extended lambdas in the private
// TestBody() that gtest generates.
template <class Exec, class Real, class View>
void apply_minimum_image(const Box<3, Real>& box, const View& dr) {
  Kokkos::parallel_for(
      Kokkos::RangePolicy<Exec>(0, dr.extent(0)), KOKKOS_LAMBDA(int i) {
        Vec<3, Real> r = Vec<3, Real>::load(dr, i);
        box.minimum_image(r);
        r.store(dr, i);
      });
}
TYPED_TEST_SUITE(BoxTest, testing::BackendsAndPrecisions);

TYPED_TEST(BoxTest, MinimumImageIsTheShortestImageOnPeriodicAxesOnly) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  const Real lo[3] = {-2, 0, 1}, len[3] = {4, 5, 6};
  const bool per[3] = {true, true, false};
  const Box<3, Real> box(lo, len, per);
  const int n = 2000;
  Kokkos::View<Real* [3], Exec> dr("dr", n);
  auto h = Kokkos::create_mirror_view(dr);
  std::mt19937 gen(1);
  std::uniform_real_distribution<double> u(-20.0, 20.0);
  for (int i = 0; i < n; ++i)
    for (int d = 0; d < 3; ++d) h(i, d) = Real(u(gen));
  h(0, 0) = Real(2);  // exactly half a box: maps to −L/2
  h(1, 1) = Real(-2.5);
  Kokkos::deep_copy(dr, h);
  auto in = Kokkos::create_mirror(dr);  // a copy: a mirror view would alias dr on the host
  Kokkos::deep_copy(in, h);
  apply_minimum_image<Exec>(box, dr);
  Kokkos::deep_copy(h, dr);
  const double tol = 64 * testing::eps<Real>() * 20;
  for (int i = 0; i < n; ++i) {
    for (int d = 0; d < 2; ++d) {
      EXPECT_GE(h(i, d), -len[d] / 2 - tol);
      EXPECT_LT(h(i, d), len[d] / 2 + tol);
      const double shift = (double(in(i, d)) - double(h(i, d))) / len[d];
      EXPECT_NEAR(shift, std::round(shift), 1e-4) << "image differs by a whole box";
    }
    EXPECT_EQ(h(i, 2), in(i, 2)) << "bounded axis must be untouched";
  }
  EXPECT_NEAR(double(h(0, 0)), -2.0, tol);
  EXPECT_NEAR(double(h(1, 1)), -2.5, tol);
}

TYPED_TEST(BoxTest, WrapFoldsIntoTheHalfOpenBox) {
  using Real = typename TypeParam::real;
  const Real lo[2] = {-1, 3}, len[2] = {2, 7};
  const bool per[2] = {true, false};
  const Box<2, Real> box(lo, len, per);
  for (double x : {-1.0, 0.999, 1.0, -3.0, 7.5, -1e-9, 1.0 - 1e-9, -1.0 - 1e-9}) {
    Vec<2, Real> r;
    r[0] = Real(x);
    r[1] = Real(100);
    box.wrap(r);
    EXPECT_GE(r[0], Real(-1)) << x;
    EXPECT_LT(r[0], Real(1)) << x;
    EXPECT_EQ(r[1], Real(100));
  }
  EXPECT_THROW((Box<2, Real>(lo, {Real(2), Real(0)}, per)), std::invalid_argument);
  EXPECT_DOUBLE_EQ(double(Box<3, Real>::cube(Real(2), true).volume()), 8.0);
}

}  // namespace
}  // namespace mesoflow
