// Reductions against host sums, and their determinism.
#include "kernels/common/reductions.hpp"
#include "test_types.hpp"

#include <cmath>
#include <random>

namespace mesoflow {
namespace {

template <class T>
class ReductionsTest : public ::testing::Test {};
TYPED_TEST_SUITE(ReductionsTest, testing::BackendsAndPrecisions);

template <int D, class Real, class Exec>
Particles<D, Real, Exec> random_particles(int n, unsigned seed) {
  Particles<D, Real, Exec> p(n);
  auto x = Kokkos::create_mirror_view(p.x);
  auto v = Kokkos::create_mirror_view(p.v);
  auto m = Kokkos::create_mirror_view(p.mass);
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < n; ++i) {
    for (int d = 0; d < D; ++d) {
      x(i, d) = Real(5 * u(gen));
      v(i, d) = Real(u(gen));
    }
    m(i) = Real(1.5 + u(gen));
  }
  Kokkos::deep_copy(p.x, x);
  Kokkos::deep_copy(p.v, v);
  Kokkos::deep_copy(p.mass, m);
  return p;
}

TYPED_TEST(ReductionsTest, KineticEnergyMomentumAndCentreOfMassMatchHostSums) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  const int n = 10007;
  auto p = random_particles<3, Real, Exec>(n, 1);
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.x);
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.v);
  auto m = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.mass);
  long double ke = 0, mom[3] = {0, 0, 0}, mx[3] = {0, 0, 0}, mass = 0;
  for (int i = 0; i < n; ++i) {
    mass += m(i);
    for (int d = 0; d < 3; ++d) {
      ke += 0.5L * m(i) * v(i, d) * v(i, d);
      mom[d] += (long double)m(i) * v(i, d);
      mx[d] += (long double)m(i) * x(i, d);
    }
  }
  // Double accumulation of n terms: relative error ~ n·2e-16 at worst.
  EXPECT_NEAR(kinetic_energy(p), double(ke), 1e-11 * double(ke));
  const auto P = momentum(p);
  const auto com = center_of_mass(p);
  for (int d = 0; d < 3; ++d) {
    EXPECT_NEAR(P[d], double(mom[d]), 1e-11 * n);
    EXPECT_NEAR(com[d], double(mx[d] / mass), 1e-11 * n);
  }
}

TYPED_TEST(ReductionsTest, MaxDisplacementUsesTheMinimumImage) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  const auto box = Box<2, Real>::cube(Real(10), true);
  Particles<2, Real, Exec> p(3);
  auto ref = Kokkos::create_mirror(p.x);
  auto now = Kokkos::create_mirror(p.x);
  // Particle 0 crossed the periodic boundary (9.9 → 0.1: moved 0.2), particle 1 moved 0.5,
  // particle 2 stayed.
  ref(0, 0) = Real(9.9); ref(0, 1) = Real(1); now(0, 0) = Real(0.1); now(0, 1) = Real(1);
  ref(1, 0) = Real(3);   ref(1, 1) = Real(3); now(1, 0) = Real(3.3); now(1, 1) = Real(3.4);
  ref(2, 0) = Real(5);   ref(2, 1) = Real(5); now(2, 0) = Real(5);   now(2, 1) = Real(5);
  typename Particles<2, Real, Exec>::vector_view x_ref("ref", 3);
  Kokkos::deep_copy(x_ref, ref);
  Kokkos::deep_copy(p.x, now);
  EXPECT_NEAR(double(max_displacement<2, Real, Exec>(p.x, x_ref, box)), 0.5, 1e-5);
}

TYPED_TEST(ReductionsTest, RepeatedReductionsAreBitwiseIdentical) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  auto p = random_particles<2, Real, Exec>(100003, 2);
  const double ke = kinetic_energy(p);
  const auto P = momentum(p);
  for (int k = 0; k < 5; ++k) {
    EXPECT_EQ(kinetic_energy(p), ke);
    EXPECT_EQ(momentum(p), P);
  }
}

}  // namespace
}  // namespace mesoflow
