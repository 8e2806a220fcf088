// Gaussian coarse-graining on the hopper axis (kernels/common/coarse_graining.hpp): equals a brute
// force over all particles without the 5w cutoff (2D and 3D); on a fine lattice it gives the lattice's
// number density and, for a velocity linear in height, that velocity exactly (a symmetric kernel
// averages a linear field to its value at the centre). Serial and OpenMP, float and double particle
// data: the kernel sums in double either way, so the bounds hold for both (float positions and
// velocities are rounded where they are set; the references use the stored values).
#include "kernels/common/coarse_graining.hpp"
#include "test_types.hpp"

#include <cmath>
#include <random>

namespace mesoflow {
namespace {

template <class T>
class CoarseGrainingTest : public ::testing::Test {};
TYPED_TEST_SUITE(CoarseGrainingTest, testing::BackendsAndPrecisions);

constexpr int P = 40;

template <int D, class Real, class Exec>
void expect_brute_force_agreement() {
  const int n = 3000;
  const double w = 1.0, h0 = -2.0, dh = 0.5;
  Particles<D, Real, Exec> p(n);
  auto x = Kokkos::create_mirror_view(p.x);
  auto v = Kokkos::create_mirror_view(p.v);
  std::mt19937 gen(D);
  std::uniform_real_distribution<double> lateral(-6, 6), height(-4, 20), u(-1, 1);
  for (int i = 0; i < n; ++i) {
    for (int d = 0; d < D - 1; ++d) x(i, d) = Real(lateral(gen));
    x(i, D - 1) = Real(height(gen));
    for (int d = 0; d < D; ++d) v(i, d) = Real(u(gen));
  }
  Kokkos::deep_copy(p.x, x);
  Kokkos::deep_copy(p.v, v);
  const auto prof = gaussian_axis_profile<P>(p, h0, dh, w);
  double worst = 0, peak = 0;
  for (int k = 0; k < P; ++k) {
    double nk = 0, jk = 0;
    for (int i = 0; i < n; ++i) {
      double r2 = 0;
      for (int d = 0; d < D - 1; ++d) r2 += double(x(i, d)) * double(x(i, d));
      r2 += std::pow(h0 + k * dh - double(x(i, D - 1)), 2);
      const double phi = std::pow(std::sqrt(2 * M_PI) * w, -D) * std::exp(-r2 / (2 * w * w));
      nk += phi;
      jk += -double(v(i, D - 1)) * phi;
    }
    peak = std::max(peak, nk);
    worst = std::max({worst, std::abs(prof.number_density[k] - nk), std::abs(prof.velocity_sum[k] - jk)});
  }
  EXPECT_GT(peak, 0.5);  // number density ≈ 10 (2D), 0.9 (3D)
  EXPECT_LE(worst, 1e-5 * peak) << D << "D";
}

TYPED_TEST(CoarseGrainingTest, AxisProfileEqualsBruteForce) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  expect_brute_force_agreement<2, Real, Exec>();
  expect_brute_force_agreement<3, Real, Exec>();
}

TYPED_TEST(CoarseGrainingTest, LatticeGivesItsDensityAndALinearVelocityExactly) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  const double a = 0.2, w = 1.0;  // spacing ≪ width: lattice sums equal integrals to ~exp(−2π²w²/a²)
  const int nx = 101, ny = 201;   // x ∈ [−10, 10], y ∈ [−10, 30]
  Particles<2, Real, Exec> p(nx * ny);
  auto x = Kokkos::create_mirror_view(p.x);
  auto v = Kokkos::create_mirror_view(p.v);
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j) {
      const int k = i * ny + j;
      x(k, 0) = Real(-10 + a * i), x(k, 1) = Real(-10 + a * j);
      v(k, 0) = Real(0.3), v(k, 1) = Real(-(0.5 + 0.1 * double(x(k, 1))));  // falling at v_g = 0.5 + 0.1 h
    }
  Kokkos::deep_copy(p.x, x);
  Kokkos::deep_copy(p.v, v);
  const auto prof = gaussian_axis_profile<P>(p, 0.0, 0.5, w);
  // In float the lattice sites are rounded (by ≤ 1e-6 at |x| ≤ 30) and so are the velocities (by
  // ≤ 2e-7): both shift the mean speed by ~1e-7, within the bound.
  for (int k = 0; k < P; ++k) {
    const double h = 0.5 * k;
    EXPECT_NEAR(prof.number_density[k], 1 / (a * a), 1e-4 / (a * a)) << "h = " << h;
    EXPECT_NEAR(prof.velocity_sum[k] / prof.number_density[k], 0.5 + 0.1 * h, 1e-6) << "h = " << h;
  }
  EXPECT_THROW(gaussian_axis_profile<P>(p, 0.0, 0.5, 0.0), std::invalid_argument);
  EXPECT_THROW(gaussian_axis_profile<P>(p, 0.0, -0.5, 1.0), std::invalid_argument);
}

}  // namespace
}  // namespace mesoflow
