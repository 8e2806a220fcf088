// Langevin thermostat: the random force has the fluctuation–dissipation variance, is reproducible on
// every backend, and velocity Verlet with it holds free particles at k_BT.
#include "kernels/common/langevin.hpp"
#include "kernels/common/reductions.hpp"
#include "kernels/common/velocity_verlet.hpp"
#include "test_types.hpp"

#include <cmath>

namespace mesoflow {
namespace {

template <class T>
class LangevinTest : public ::testing::Test {};
TYPED_TEST_SUITE(LangevinTest, testing::BackendsAndPrecisions);

// At rest (v = 0) the thermostat force is the noise alone: mean 0, variance 2γ m k_BT / Δt.
TYPED_TEST(LangevinTest, RandomForceHasTheFluctuationDissipationVariance) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  const int n = 50000;
  Particles<2, Real, Exec> p(n);
  Kokkos::deep_copy(p.mass, Real(2));
  const LangevinThermostat<Real> thermostat(Real(0.5), Real(1.5), 42);
  const Real dt = Real(0.01);
  thermostat.accumulate(p, p.v, dt, 7);
  auto f = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.f);
  double sum = 0, sum2 = 0;
  for (int i = 0; i < n; ++i)
    for (int d = 0; d < 2; ++d) {
      sum += f(i, d);
      sum2 += double(f(i, d)) * f(i, d);
    }
  const double samples = 2.0 * n, expected = 2 * 0.5 * 2 * 1.5 / 0.01;  // 300
  // Standard errors: mean √(300/10⁵) ≈ 0.055, variance 300·√(2/10⁵) ≈ 1.3; bounds at 5σ.
  EXPECT_NEAR(sum / samples, 0.0, 0.28);
  EXPECT_NEAR(sum2 / samples, expected, 7.0);
}

// The same noise on every backend: bitwise on host backends; on a device within
// testing::agrees_with_host's bound, since the Gaussian transform (log, sqrt, cos/sin: device math
// within 2 ulp of the host's) and the scaling by √(2γk_BT m/Δt) = 14.1 are contracted there:
// 30 operations at the scale of the force itself plus that amplitude.
TYPED_TEST(LangevinTest, NoiseIsReproducibleOnEveryBackendAndChangesWithTheStep) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  const int n = 1000;
  Particles<3, Real, Exec> a(n);
  Particles<3, Real, Kokkos::DefaultHostExecutionSpace> b(n), c(n);
  const LangevinThermostat<Real> thermostat(Real(1), Real(1), 3);
  thermostat.accumulate(a, a.v, Real(0.01), 5);
  thermostat.accumulate(b, b.v, Real(0.01), 5);
  thermostat.accumulate(c, c.v, Real(0.01), 6);
  auto fa = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), a.f);
  auto fb = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), b.f);
  auto fc = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), c.f);
  int differ = 0;
  for (int i = 0; i < n; ++i)
    for (int d = 0; d < 3; ++d) {
      ASSERT_TRUE((testing::agrees_with_host<Exec, Real>(fa(i, d), fb(i, d), 30, std::abs(double(fb(i, d))) + 14.1)))
          << i << " " << d;
      differ += fa(i, d) != fc(i, d);
    }
  EXPECT_EQ(differ, 3 * n);
}

// Free particles thermalise at k_BT: the mean kinetic temperature over the second half of a run
// (20 relaxation times) is within 2% (statistical error ~0.2%, discretisation ~γΔt/2 = 0.25%).
TYPED_TEST(LangevinTest, HoldsFreeParticlesAtTheSetTemperature) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  const int n = 2000, steps = 4000;
  const double kT = 1.5, gamma = 1.0, dt = 0.005;
  Particles<2, Real, Exec> p(n);
  VelocityVerlet<2, Real, Exec> vv{Real(dt)};
  const LangevinThermostat<Real> thermostat(Real(gamma), Real(kT), 11);
  double temperature = 0;
  int samples = 0;
  for (int s = 0; s < steps; ++s) {
    vv.first_half(p);
    p.zero_forces();
    thermostat.accumulate(p, vv.velocity_for_forces(p), Real(dt), s);
    vv.second_half(p);
    if (s >= steps / 2 && s % 10 == 0) {
      temperature += kinetic_energy(p) / n;  // 2D: k_BT = KE / N
      ++samples;
    }
  }
  temperature /= samples;
  EXPECT_NEAR(temperature / kT, 1.0, 0.02);
  EXPECT_THROW(LangevinThermostat<Real>(Real(-1), Real(1), 0), std::invalid_argument);
  EXPECT_FALSE(LangevinThermostat<Real>(Real(0), Real(1), 0).active());
}

}  // namespace
}  // namespace mesoflow
