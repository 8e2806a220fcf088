// MPC in a periodic box: the AT thermostats relax a far-from-equilibrium state (all speeds equal, at
// twice the set temperature) to the Maxwell–Boltzmann distribution at k_BT; SRD conserves the total
// energy and momentum over many steps; the initial Maxwell–Boltzmann velocities.
#include "kernels/common/random.hpp"
#include "kernels/mpc/maxwell_boltzmann.hpp"
#include "kernels/mpc/mpc_collision.hpp"
#include "test_types.hpp"

#include <array>
#include <cmath>
#include <iostream>
#include <vector>

namespace mesoflow {
namespace {

using mpc::CollisionParameters;
using mpc::CollisionRule;
using mpc::MpcCollision;

template <class T>
class MpcEquilibriumTest : public ::testing::Test {};
using Precisions = ::testing::Types<testing::Config<Kokkos::DefaultExecutionSpace, double>,
                                    testing::Config<Kokkos::DefaultExecutionSpace, float>>;
TYPED_TEST_SUITE(MpcEquilibriumTest, Precisions);

// Chi-square of velocity components (in units of σ = √(k_BT/m)) against the standard normal: 24
// bins of width σ/4 on [−3σ, 3σ) and the two tails, 26 bins, 25 degrees of freedom (nothing
// fitted). The smallest expected count is 0.00135 × samples.
struct ChiSquare {
  std::array<double, 26> counts{};
  double samples = 0;
  void add(double z) {
    int bin = z < -3.0 ? 0 : (z >= 3.0 ? 25 : 1 + int(std::floor((z + 3.0) * 4.0)));
    bin = bin > 24 && z < 3.0 ? 24 : bin;
    counts[bin] += 1;
    samples += 1;
  }
  double value() const {
    auto cdf = [](double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); };
    double chi2 = 0;
    for (int b = 0; b < 26; ++b) {
      const double lower = b == 0 ? -INFINITY : -3.0 + 0.25 * (b - 1);
      const double upper = b == 25 ? INFINITY : -3.0 + 0.25 * b;
      const double expected = samples * (cdf(upper) - cdf(lower));
      chi2 += (counts[b] - expected) * (counts[b] - expected) / expected;
    }
    return chi2;
  }
};
// χ² of 25 degrees of freedom exceeds 52.62 with probability 0.001.
constexpr double kChiSquareCritical = 52.62;

template <class View>
void add_samples(ChiSquare& chi, const View& v, int snapshot, double sigma) {
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), v);
  // Every tenth particle, a different tenth in each snapshot: particles from different cells, so
  // the samples are nearly independent (particles of one cell share its centre-of-mass velocity).
  for (std::size_t i = std::size_t(snapshot % 10); i < h.extent(0); i += 10)
    for (std::size_t d = 0; d < h.extent(1); ++d) chi.add(double(h(i, d)) / sigma);
}

// Σ m v² / (D (N − 1)): the kinetic temperature with the total momentum (zero) fixed.
template <int D, class View>
double temperature(const View& v, double mass) {
  const int n = int(v.extent(0));
  const auto s = parallel_sum<1, typename View::execution_space>(
      "mesoflow::test::temperature", n, KOKKOS_LAMBDA(const int i, double(&acc)[1]) {
        for (int d = 0; d < D; ++d) acc[0] += double(v(i, d)) * double(v(i, d));
      });
  return mass * s[0] / (D * (n - 1.0));
}

// Kernels of the tests below live in free functions: nvcc rejects a KOKKOS_LAMBDA in a TYPED_TEST
// body (GoogleTest's private TestBody()).

// 2D velocities of magnitude `speed` in random directions.
template <class View>
void set_equal_speeds(const View& v, typename View::value_type speed) {
  using Real = typename View::value_type;
  Kokkos::parallel_for(
      "mesoflow::test::equal_speeds", Kokkos::RangePolicy<typename View::execution_space>(0, v.extent(0)),
      KOKKOS_LAMBDA(const int i) {
        RandomStream rs(5, 0, stream_tag::initial_condition, static_cast<std::uint32_t>(i), 1);
        const Real angle = Real(6.283185307179586) * rs.uniform<Real>();
        v(i, 0) = speed * kmath::cos(angle);
        v(i, 1) = speed * kmath::sin(angle);
      });
}

// v_x += u for every particle.
template <class View>
void add_drift(const View& v, typename View::value_type u) {
  Kokkos::parallel_for(
      "mesoflow::test::drift", Kokkos::RangePolicy<typename View::execution_space>(0, v.extent(0)),
      KOKKOS_LAMBDA(const int i) { v(i, 0) += u; });
}

// Σ v_d (d < D) and Σ ½|v|², unit mass.
template <int D, class View>
std::array<double, D + 1> momentum_and_energy(const View& v) {
  return parallel_sum<D + 1, typename View::execution_space>(
      "mesoflow::test::totals", int(v.extent(0)), KOKKOS_LAMBDA(const int i, double(&acc)[D + 1]) {
        for (int d = 0; d < D; ++d) {
          acc[d] += double(v(i, d));
          acc[D] += 0.5 * double(v(i, d)) * double(v(i, d));
        }
      });
}

TYPED_TEST(MpcEquilibriumTest, AtRulesRelaxToMaxwellBoltzmannAtTheSetTemperature) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  constexpr int D = 2;
  const int cells = 50, per_cell = 10, n = cells * cells * per_cell;
  const double kT = 1.5, mass = 2.0, sigma = std::sqrt(kT / mass);
  const auto grid = mpc::make_collision_grid<D, Real>(Real(1), {Real(0), Real(0)}, {Real(cells), Real(cells)}, {1, 1});
  for (const auto rule : {CollisionRule::at_plus_a, CollisionRule::at_minus_a}) {
    CollisionParameters<Real> p;
    p.rule = rule;
    p.kT = Real(kT);
    p.mass = Real(mass);
    p.seed = 2024;
    MpcCollision<D, Real, Exec> collision(grid, p, n);
    Kokkos::View<Real* [D], Kokkos::LayoutLeft, Exec> x("x", n), v("v", n);
    const Real lo[D] = {Real(0), Real(0)}, hi[D] = {Real(cells), Real(cells)};
    fill_uniform_counter(x, lo, hi, 5);
    // All speeds equal to 2σ√2 (kinetic temperature 2 k_BT), random directions.
    const Real speed = Real(2 * sigma * std::sqrt(2.0));
    set_equal_speeds(v, speed);
    ChiSquare initial;
    add_samples(initial, v, 0, sigma);
    const Kokkos::Array<Real, D> no_force = {Real(0), Real(0)};
    ChiSquare chi;
    double t_sum = 0;
    int t_samples = 0;
    const int steps = 600, equilibration = 200;
    for (int s = 1; s <= steps; ++s) {
      collision.stream_and_collide(x, v, Real(0.1), no_force, s);
      if (s > equilibration) {
        t_sum += temperature<D>(v, mass);
        ++t_samples;
      }
      if (s >= equilibration && s % 100 == 0) add_samples(chi, v, s / 100, sigma);
    }
    const double t_mean = t_sum / t_samples;
    std::cout << "[ measured ] " << mpc::to_string(rule) << ": chi2 initial " << initial.value() << ", after "
              << chi.value() << " (" << chi.samples << " samples, 25 dof, critical " << kChiSquareCritical
              << "), T/kT = " << t_mean / kT << "\n";
    EXPECT_GT(initial.value(), 100 * kChiSquareCritical);  // the test can tell
    EXPECT_LT(chi.value(), kChiSquareCritical) << mpc::to_string(rule);
    EXPECT_NEAR(t_mean / kT, 1.0, 0.01) << mpc::to_string(rule);
  }
}

// SRD has no thermostat: total kinetic energy and momentum are conserved over 100 steps in a
// periodic box without body force, to round-off (16 ε per step, relative).
TYPED_TEST(MpcEquilibriumTest, SrdConservesTotalEnergyAndMomentumOverManySteps) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  constexpr int D = 3;
  const int n = 20 * 20 * 10 * 5;
  const auto grid = mpc::make_collision_grid<D, Real>(Real(1), {Real(0), Real(0), Real(0)},
                                                      {Real(20), Real(20), Real(10)}, {1, 1, 1});
  CollisionParameters<Real> p;
  p.rule = CollisionRule::srd;
  MpcCollision<D, Real, Exec> collision(grid, p, n);
  Kokkos::View<Real* [D], Kokkos::LayoutLeft, Exec> x("x", n), v("v", n);
  const Real lo[D] = {Real(0), Real(0), Real(0)}, hi[D] = {Real(20), Real(20), Real(10)};
  fill_uniform_counter(x, lo, hi, 8);
  mpc::fill_maxwell_boltzmann(v, Real(1), Real(1), 8);
  add_drift(v, Real(0.5));
  auto totals = [&] { return momentum_and_energy<D>(v); };
  const auto before = totals();
  const int steps = 100;
  for (int s = 0; s < steps; ++s) collision.stream_and_collide(x, v, Real(0.1), {Real(0), Real(0), Real(0)}, s);
  const auto after = totals();
  const double tol = 16 * testing::eps<Real>() * steps;
  std::cout << "[ measured ] SRD 100 steps: relative energy change " << (after[D] - before[D]) / before[D]
            << ", momentum change " << after[0] - before[0] << " " << after[1] - before[1] << " "
            << after[2] - before[2] << " (tolerance " << tol << " relative)\n";
  EXPECT_NEAR(after[D] / before[D], 1.0, tol);
  for (int d = 0; d < D; ++d) EXPECT_NEAR(after[d], before[d], tol * std::sqrt(2 * before[D] * n));
  EXPECT_NEAR(after[0] / n, 0.5, 1e-3);  // the drift is still there
}

// fill_maxwell_boltzmann: zero total momentum, temperature k_BT within 5σ (σ = √(2/(3N)) k_BT), and
// the same velocities on Serial and OpenMP up to the mean's round-off (on a device, up to FMA
// contraction).
TYPED_TEST(MpcEquilibriumTest, InitialMaxwellBoltzmannVelocities) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  const int n = 30000;
  const double kT = 1.5, mass = 2.0;
  Kokkos::View<Real* [3], Kokkos::LayoutLeft, Exec> v("v", n);
  Kokkos::View<Real* [3], Kokkos::LayoutLeft, Kokkos::Serial> w("w", n);
  mpc::fill_maxwell_boltzmann(v, Real(kT), Real(mass), 77);
  mpc::fill_maxwell_boltzmann(w, Real(kT), Real(mass), 77);
  auto vh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), v);
  double p[3] = {0, 0, 0}, v2 = 0, worst = 0;
  for (int i = 0; i < n; ++i)
    for (int d = 0; d < 3; ++d) {
      p[d] += vh(i, d);
      v2 += double(vh(i, d)) * vh(i, d);
      worst = std::max(worst, std::fabs(double(vh(i, d)) - w(i, d)));
    }
  for (int d = 0; d < 3; ++d) EXPECT_NEAR(p[d] / n, 0.0, 4 * testing::eps<Real>() * 6);
  EXPECT_NEAR(mass * v2 / (3.0 * (n - 1)), kT, 5 * std::sqrt(2.0 / (3 * n)) * kT);
  // Against Serial: the mean's round-off on host backends; on a device also the Gaussian transform
  // and the scaling, contracted (testing::contraction_bound: 30 operations at |v| ≤ 6).
  EXPECT_LE(worst, testing::has_host_arithmetic<Exec>() ? 8 * testing::eps<Real>() * 6
                                                         : testing::contraction_bound<Real>(30, 6.0));
  EXPECT_THROW(mpc::fill_maxwell_boltzmann(v, Real(-1), Real(1), 1), std::invalid_argument);
}

}  // namespace
}  // namespace mesoflow
