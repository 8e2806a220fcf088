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
template <class Exec, class Real, class View>
void apply_near_images(const PeriodicImages<3, Real>& images, const View& dr) {
  Kokkos::parallel_for(
      Kokkos::RangePolicy<Exec>(0, dr.extent(0)), KOKKOS_LAMBDA(int i) {
        Vec<3, Real> r = Vec<3, Real>::load(dr, i);
        images.minimum_image_near(r);
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
  // Separations at exactly (k + ½)L map to −L/2 on every backend: on axis 1 (L = 5, 1/L inexact) an
  // FMA-contracted floor(dr/L + ½) lands one image off, which the convention must not show.
  h(0, 0) = Real(2);  // exactly half a box: maps to −L/2
  h(1, 1) = Real(-2.5);
  h(2, 1) = Real(2.5);
  h(3, 1) = Real(7.5);
  h(4, 1) = Real(-7.5);
  h(5, 0) = Real(-6);
  h(6, 1) = Real(12.5);
  Kokkos::deep_copy(dr, h);
  auto in = Kokkos::create_mirror(dr);  // a copy: a mirror view would alias dr on the host
  Kokkos::deep_copy(in, h);
  apply_minimum_image<Exec>(box, dr);
  Kokkos::deep_copy(h, dr);
  for (int i = 0; i < n; ++i) {
    for (int d = 0; d < 2; ++d) {
      EXPECT_GE(h(i, d), -len[d] / 2) << "i = " << i;  // the half-open [−L/2, L/2), exactly
      EXPECT_LT(h(i, d), len[d] / 2) << "i = " << i;
      const double shift = (double(in(i, d)) - double(h(i, d))) / len[d];
      EXPECT_NEAR(shift, std::round(shift), 1e-4) << "image differs by a whole box";
    }
    EXPECT_EQ(h(i, 2), in(i, 2)) << "bounded axis must be untouched";
  }
  EXPECT_EQ(double(h(0, 0)), -2.0);
  for (int i : {1, 2, 3, 4, 6}) EXPECT_EQ(double(h(i, 1)), -2.5) << "i = " << i;
  EXPECT_EQ(double(h(5, 0)), -2.0);
}

// The pair loops' form (PeriodicImages, one conditional shift for |dr| < 1.5 L) picks the image
// minimum_image() picks, and keeps [−L/2, L/2) exactly too.
TYPED_TEST(BoxTest, NearImagesOfThePairLoopsPickTheSameImage) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  const Real lo[3] = {0, 0, 0}, len[3] = {5, 3, 7};
  const bool per[3] = {true, true, false};
  const Box<3, Real> box(lo, len, per);
  const int n = 3000;
  Kokkos::View<Real* [3], Exec> dr("dr", n);
  auto h = Kokkos::create_mirror_view(dr);
  std::mt19937 gen(2);
  for (int i = 0; i < n; ++i)
    for (int d = 0; d < 3; ++d) h(i, d) = Real(std::uniform_real_distribution<double>(-1.49, 1.49)(gen) * len[d]);
  h(0, 0) = Real(2.5);
  h(1, 0) = Real(-2.5);
  h(2, 1) = Real(1.5);
  h(3, 1) = Real(-4.5);
  Kokkos::deep_copy(dr, h);
  auto in = Kokkos::create_mirror(dr);
  Kokkos::deep_copy(in, h);
  apply_near_images<Exec>(box.images(), dr);
  Kokkos::deep_copy(h, dr);
  for (int i = 0; i < n; ++i) {
    Vec<3, Real> r{{in(i, 0), in(i, 1), in(i, 2)}};
    box.minimum_image(r);
    for (int d = 0; d < 2; ++d) {
      EXPECT_GE(h(i, d), -len[d] / 2) << "i = " << i;
      EXPECT_LT(h(i, d), len[d] / 2) << "i = " << i;
      // the same image: equal up to the rounding of one shift
      EXPECT_NEAR(double(h(i, d)), double(r[d]), 4 * testing::eps<Real>() * len[d]) << "i = " << i;
    }
    EXPECT_EQ(h(i, 2), in(i, 2));
  }
  EXPECT_EQ(double(h(0, 0)), -2.5);
  EXPECT_EQ(double(h(1, 0)), -2.5);
  EXPECT_EQ(double(h(2, 1)), -1.5);
  EXPECT_EQ(double(h(3, 1)), -1.5);
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
