// The soft-particle many-body terms of the hopper study (kernels/sp/): the bidisperse soft-sphere
// repulsion (eq. 2) is minus the gradient of its energy (central finite differences, 2D and 3D, full
// and half lists agree); kinetic friction (eq. 6) acts only between overlapping particles, pair by
// pair equal and opposite, conserves total momentum and dissipates exactly −(μ/2) Σ |v_m − v_n|²
// (tangential variant: the same with the part of v_m − v_n along r_mn removed);
// the drag of eq. 5 is −ζ M v; a zero coefficient leaves the forces untouched. The finite-difference
// checks run in double; everything else runs on Serial and OpenMP in float and double, against
// brute forces in double over the stored values, with tolerances in multiples of the precision's
// round-off ε (positions are known to ε·L, which the contact stiffness ε_sp/σ² turns into force).
#include "kernels/common/pair_force.hpp"
#include "kernels/sp/kinetic_friction.hpp"
#include "kernels/sp/mass_proportional_drag.hpp"
#include "kernels/sp/pair_repulsion.hpp"
#include "finite_difference.hpp"
#include "test_types.hpp"

#include <array>
#include <cmath>
#include <iostream>
#include <random>
#include <vector>

namespace mesoflow {
namespace {

using Exec = Kokkos::DefaultExecutionSpace;
constexpr double kSmall = 1.0, kLarge = 1.4;  // σ_l/σ_s = 1.4 (hopper §2.2)

template <class T>
class SoftParticleTermsTest : public ::testing::Test {};
TYPED_TEST_SUITE(SoftParticleTermsTest, testing::BackendsAndPrecisions);

// A dense bidisperse packing: n random particles (half of each type) in a periodic box of side L,
// random velocities; at this density most particles overlap several neighbours.
template <int D, class Real = double, class ExecSpace = Exec>
struct Packing {
  Particles<D, Real, ExecSpace> p;
  Box<D, Real> box;
  sp::SoftSphereRepulsion<Real> contacts{Real(2.5), {kSmall, kLarge}};
  NeighborList<D, Real, ExecSpace> list;

  Packing(int n, double L, unsigned seed, NeighborListKind kind = NeighborListKind::full)
      : p(n, "packing"), box(Box<D, Real>::cube(Real(L), true)), list(contacts.cutoff(), Real(0.2), kind) {
    std::mt19937 gen(seed);
    std::uniform_real_distribution<double> u(0, L), w(-1, 1), m(0.5, 2);
    auto x = Kokkos::create_mirror_view(p.x);
    auto v = Kokkos::create_mirror_view(p.v);
    auto type = Kokkos::create_mirror_view(p.type);
    auto mass = Kokkos::create_mirror_view(p.mass);
    for (int i = 0; i < n; ++i) {
      for (int d = 0; d < D; ++d) {
        x(i, d) = Real(u(gen));
        v(i, d) = Real(w(gen));
      }
      type(i) = i % 2;
      mass(i) = Real(m(gen));
    }
    Kokkos::deep_copy(p.x, x);
    Kokkos::deep_copy(p.v, v);
    Kokkos::deep_copy(p.type, type);
    Kokkos::deep_copy(p.mass, mass);
    list.build(p, box);
  }

  double repulsion() {
    p.zero_forces();
    PairForce<D, Real, ExecSpace> pair;
    return pair.accumulate(contacts, p, list, box);
  }

  std::vector<double> forces() const {
    auto f = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.f);
    std::vector<double> out;
    for (std::size_t i = 0; i < f.extent(0); ++i)
      for (int d = 0; d < D; ++d) out.push_back(double(f(i, d)));
    return out;
  }

  // Minimum-image x_i − x_j of the stored positions, in double.
  template <class HostX>
  std::array<double, D> separation(const HostX& x, int i, int j) const {
    std::array<double, D> dx;
    for (int d = 0; d < D; ++d) {
      const double l = double(box.length[d]);
      dx[d] = double(x(i, d)) - double(x(j, d));
      dx[d] -= l * std::round(dx[d] / l);
    }
    return dx;
  }
};

template <int D>
void expect_repulsion_is_minus_gradient() {
  Packing<D> s(64, D == 2 ? 6.0 : 3.6, 3);
  // h = 10⁻⁸: the force's derivative jumps at contact, and in these random packings some pair is
  // within 10⁻⁶σ of it (measured error 3.4·10⁻⁵ at h = 10⁻⁶, 3.4·10⁻⁶ at 10⁻⁷: O(h)).
  const auto c = testing::check_gradient(s.p, [&] { return s.repulsion(); }, 1e-8);
  std::cout << "[ fd ] soft-sphere repulsion " << D << "D: max error / max |F| = " << c.max_error << "\n";
  EXPECT_GT(c.max_force, 0.1) << "the packing should overlap";
  EXPECT_LE(c.max_error, 1e-6);
}

TEST(SoftSphereRepulsion, ForceIsMinusTheEnergyGradient2D) { expect_repulsion_is_minus_gradient<2>(); }
TEST(SoftSphereRepulsion, ForceIsMinusTheEnergyGradient3D) { expect_repulsion_is_minus_gradient<3>(); }

TEST(SoftSphereRepulsion, ContactDistanceIsTheMeanDiameter) {
  const sp::SoftSphereRepulsion<double> c(2.0, {kSmall, kLarge});
  double f, e;
  EXPECT_FALSE(c.evaluate(1.2 * 1.2 * (1 + 1e-12), 0, 1, f, e));  // σ_sl = 1.2: just apart
  ASSERT_TRUE(c.evaluate(1.1 * 1.1, 0, 1, f, e));                   // overlap 1 − 1.1/1.2
  EXPECT_NEAR(e, 0.5 * 2.0 * std::pow(1 - 1.1 / 1.2, 2), 1e-15);
  EXPECT_NEAR(f * 1.1, 2.0 / 1.2 * (1 - 1.1 / 1.2), 1e-15);
  EXPECT_DOUBLE_EQ(c.cutoff(), kLarge);
  EXPECT_THROW(sp::SoftSphereRepulsion<double>(-1.0, {1.0}), std::invalid_argument);
  EXPECT_THROW(sp::SoftSphereRepulsion<double>(1.0, {1.0, 0.0}), std::invalid_argument);
  EXPECT_THROW(sp::SoftSphereRepulsion<double>(1.0, {}), std::invalid_argument);
}

// Eq. 2 by brute force over all pairs, in double on the stored positions: U = Σ_{m<n} (ε/2)(1 − r/σ)²
// and F_m = Σ_n (ε/σ)(1 − r/σ) r̂_mn. The kernel's r is off by ~ε·L (it subtracts positions of
// magnitude L in its own precision), which the stiffness ε_sp/σ² turns into a force error ~ε·L·ε_sp.
template <int D, class Real, class ExecSpace>
void expect_repulsion_equals_brute_force() {
  const double L = D == 2 ? 8.0 : 4.2;
  Packing<D, Real, ExecSpace> s(120, L, 11);
  const double u = s.repulsion();
  const auto f = s.forces();
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.p.x);
  auto type = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.p.type);
  const int n = int(x.extent(0));
  const double eps_sp = double(s.contacts.epsilon);
  double brute_u = 0, worst = 0, scale = 0;
  for (int i = 0; i < n; ++i) {
    std::array<double, D> fi{};
    for (int j = 0; j < n; ++j) {
      if (j == i) continue;
      const auto dx = s.separation(x, i, j);
      double r2 = 0;
      for (int d = 0; d < D; ++d) r2 += dx[d] * dx[d];
      const double sij = double(s.contacts.contact[type(i)][type(j)]), r = std::sqrt(r2);
      if (r >= sij) continue;
      for (int d = 0; d < D; ++d) fi[d] += eps_sp / sij * (1 - r / sij) * dx[d] / r;
      if (i < j) brute_u += 0.5 * eps_sp * (1 - r / sij) * (1 - r / sij);
    }
    for (int d = 0; d < D; ++d) {
      worst = std::max(worst, std::abs(f[std::size_t(i) * D + d] - fi[d]));
      scale = std::max(scale, std::abs(fi[d]));
    }
  }
  const double round_off = testing::eps<Real>() * L * eps_sp;
  std::cout << "[ brute ] soft-sphere repulsion " << D << "D, " << (sizeof(Real) == 4 ? "float" : "double")
            << ": max |ΔF| = " << worst << " = " << worst / round_off << " ε L ε_sp (max |F| " << scale << "), |ΔU|/U = "
            << std::abs(u - brute_u) / brute_u << "\n";
  EXPECT_GT(scale, 0.5) << "the packing should overlap";
  // Measured: max |ΔF| 0.39 (2D), 0.46 (3D) ε L ε_sp in double, 0.54, 0.83 in float; |ΔU|/U ≤ 1.9e-15, 9.2e-9.
  EXPECT_LE(worst, 4 * round_off);
  EXPECT_NEAR(u, brute_u, 8 * testing::eps<Real>() * L * brute_u);
}

TYPED_TEST(SoftParticleTermsTest, RepulsionEqualsBruteForce) {
  expect_repulsion_equals_brute_force<2, typename TypeParam::real, typename TypeParam::exec>();
  expect_repulsion_equals_brute_force<3, typename TypeParam::real, typename TypeParam::exec>();
}

TYPED_TEST(SoftParticleTermsTest, HalfListGivesTheFullListForces) {
  using Real = typename TypeParam::real;
  using ExecSpace = typename TypeParam::exec;
  Packing<2, Real, ExecSpace> full(200, 11.0, 4), half(200, 11.0, 4, NeighborListKind::half);
  const double ef = full.repulsion(), eh = half.repulsion();
  EXPECT_NEAR(ef, eh, 64 * testing::eps<Real>() * std::abs(ef));
  const auto a = full.forces(), b = half.forces();
  double scale = 0;
  for (double fk : a) scale = std::max(scale, std::abs(fk));
  // The same pair terms, summed in another order.
  for (std::size_t k = 0; k < a.size(); ++k) EXPECT_NEAR(a[k], b[k], 16 * testing::eps<Real>() * scale);
}

// Against a brute force over all pairs: each particle's friction, the power
// Σ_m F_m·v_m = −μ Σ_{m<n} |Δv|² Θ(1 − r_mn/σ_mn) (Δv = v_m − v_n, or its part perpendicular to r_mn
// for the tangential variant), and Σ_m F_m = 0 to round-off. Velocities are O(1), so are the forces:
// their error is a few ε of the precision (the tangential projection divides by r², known to ~ε·L).
template <int D, class Real = double, class ExecSpace = Exec>
void expect_friction_conserves_momentum_and_dissipates(sp::FrictionComponent component = sp::FrictionComponent::full) {
  const bool tangential = component == sp::FrictionComponent::tangential;
  const double L = D == 2 ? 8.0 : 4.2;
  Packing<D, Real, ExecSpace> s(120, L, 7);
  const Real mu = Real(0.7);
  s.p.zero_forces();
  sp::accumulate_kinetic_friction(mu, s.contacts, s.p, s.p.v, s.list, s.box, component);
  auto f = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.p.f);
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.p.x);
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.p.v);
  auto type = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.p.type);
  const int n = int(x.extent(0));
  double expected_power = 0, power = 0, total[D] = {}, magnitude = 0;
  int contacts = 0;
  std::vector<double> brute(std::size_t(n) * D, 0.0);
  double worst = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      if (i == j) continue;
      const auto dx = s.separation(x, i, j);
      double r2 = 0;
      for (int d = 0; d < D; ++d) r2 += dx[d] * dx[d];
      const double sij = double(s.contacts.contact[type(i)][type(j)]);
      if (r2 >= sij * sij) continue;
      ++contacts;
      double dv[D], along = 0;
      for (int d = 0; d < D; ++d) dv[d] = double(v(i, d)) - double(v(j, d)), along += dv[d] * dx[d] / r2;
      if (tangential)
        for (int d = 0; d < D; ++d) dv[d] -= along * dx[d];
      for (int d = 0; d < D; ++d) brute[std::size_t(i) * D + d] -= double(mu) * dv[d];
      if (i < j)
        for (int d = 0; d < D; ++d) expected_power -= double(mu) * dv[d] * dv[d];
    }
  // The forces are O(1)-O(10): measured max |F − brute| 15 (2D), 23 ε (3D) in double, 9, 13 ε in float.
  const double tolerance = 64 * testing::eps<Real>();
  for (int i = 0; i < n; ++i)
    for (int d = 0; d < D; ++d) {
      EXPECT_NEAR(double(f(i, d)), brute[std::size_t(i) * D + d], tolerance) << "particle " << i;
      worst = std::max(worst, std::abs(double(f(i, d)) - brute[std::size_t(i) * D + d]));
      power += double(f(i, d)) * double(v(i, d));
      total[d] += double(f(i, d));
      magnitude += std::abs(double(f(i, d)));
    }
  std::cout << "[ friction ] " << D << "D " << sp::to_string(component) << ", " << (sizeof(Real) == 4 ? "float" : "double")
            << ": " << contacts / 2 << " contacts, max |F − brute| = " << worst / testing::eps<Real>() << " ε, |Σ F| = "
            << std::sqrt([&] { double t = 0; for (double c : total) t += c * c; return t; }()) << " (Σ|F| = " << magnitude
            << "), power " << power << " vs " << expected_power << "\n";
  EXPECT_GT(contacts, n);  // dense: several contacts per particle
  // Each pair's two terms are exact negatives; each particle sums its own in its own order.
  for (int d = 0; d < D; ++d) EXPECT_LE(std::abs(total[d]), 4 * testing::eps<Real>() * magnitude);
  EXPECT_LT(power, 0.0);
  EXPECT_NEAR(power, expected_power, 16 * tolerance * std::abs(expected_power));
}

TYPED_TEST(SoftParticleTermsTest, FrictionConservesMomentumAndDissipates2D) {
  expect_friction_conserves_momentum_and_dissipates<2, typename TypeParam::real, typename TypeParam::exec>();
}
TYPED_TEST(SoftParticleTermsTest, FrictionConservesMomentumAndDissipates3D) {
  expect_friction_conserves_momentum_and_dissipates<3, typename TypeParam::real, typename TypeParam::exec>();
}
TYPED_TEST(SoftParticleTermsTest, TangentialFrictionConservesMomentumAndDissipates2D) {
  expect_friction_conserves_momentum_and_dissipates<2, typename TypeParam::real, typename TypeParam::exec>(
      sp::FrictionComponent::tangential);
}
TYPED_TEST(SoftParticleTermsTest, TangentialFrictionConservesMomentumAndDissipates3D) {
  expect_friction_conserves_momentum_and_dissipates<3, typename TypeParam::real, typename TypeParam::exec>(
      sp::FrictionComponent::tangential);
}

// Two overlapping particles, tangential friction: a head-on relative velocity is not damped at all,
// a sliding one is damped as in eq. 6, and a mixed one loses exactly its component along r_12; the
// two forces are exact negatives (bitwise) and perpendicular to r_12.
TYPED_TEST(SoftParticleTermsTest, TangentialFrictionDampsOnlySliding) {
  using Real = typename TypeParam::real;
  using ExecSpace = typename TypeParam::exec;
  const sp::SoftSphereRepulsion<Real> c(Real(1), {kSmall, kLarge});
  const Box<2, Real> box = Box<2, Real>::cube(Real(10), true);
  struct Case { double vx0, vy0, vx1, vy1, fx0, fy0; };
  // x_1 − x_0 = 1.1 n, n = (0.6, 0.8) (1.1 < σ_sl = 1.2); t = (0.8, −0.6) the sliding direction.
  for (const Case k : {Case{0.3, 0.4, -0.3, -0.4, 0.0, 0.0},                 // Δv = (0.6, 0.8): head-on
                       Case{0.4, -0.3, -0.4, 0.3, -0.5 * 0.8, 0.5 * 0.6},    // Δv = (0.8, −0.6): sliding
                       Case{1.0, 0.2, 0.0, 0.0, -0.5 * 0.544, 0.5 * 0.408}}) {  // Δv = (1, 0.2) = 0.76 n + 0.68 t
    Particles<2, Real, ExecSpace> p(2, "pair");
    auto x = Kokkos::create_mirror_view(p.x);
    auto v = Kokkos::create_mirror_view(p.v);
    auto type = Kokkos::create_mirror_view(p.type);
    x(0, 0) = Real(1), x(0, 1) = Real(1), x(1, 0) = Real(1.0 + 0.6 * 1.1), x(1, 1) = Real(1.0 + 0.8 * 1.1);
    v(0, 0) = Real(k.vx0), v(0, 1) = Real(k.vy0), v(1, 0) = Real(k.vx1), v(1, 1) = Real(k.vy1);
    type(0) = 0, type(1) = 1;
    Kokkos::deep_copy(p.x, x);
    Kokkos::deep_copy(p.v, v);
    Kokkos::deep_copy(p.type, type);
    NeighborList<2, Real, ExecSpace> list(c.cutoff(), Real(0.3));
    list.build(p, box);
    p.zero_forces();
    sp::accumulate_kinetic_friction(Real(0.5), c, p, p.v, list, box, sp::FrictionComponent::tangential);
    auto f = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.f);
    EXPECT_EQ(f(0, 0), -f(1, 0));
    EXPECT_EQ(f(0, 1), -f(1, 1));
    // Positions and velocities are rounded to the precision where they are set: ~10 ε in all.
    const double tolerance = 16 * testing::eps<Real>();
    EXPECT_NEAR(double(f(0, 0)), k.fx0, tolerance);
    EXPECT_NEAR(double(f(0, 1)), k.fy0, tolerance);
    EXPECT_NEAR(double(f(0, 0)) * 0.6 + double(f(0, 1)) * 0.8, 0.0, tolerance);  // perpendicular to r_01
  }
  EXPECT_EQ(sp::parse_friction_component("tangential"), sp::FrictionComponent::tangential);
  EXPECT_EQ(sp::parse_friction_component("full"), sp::FrictionComponent::full);
  EXPECT_THROW(sp::parse_friction_component("normal"), std::invalid_argument);
}

// Two particles: the forces are exact negatives (bitwise), −μ(v_1 − v_2) while they overlap and zero
// once they are apart.
TYPED_TEST(SoftParticleTermsTest, FrictionPairForcesAreExactlyOppositeAndOnlyInContact) {
  using Real = typename TypeParam::real;
  using ExecSpace = typename TypeParam::exec;
  for (double gap : {-0.05, 0.05}) {
    Particles<2, Real, ExecSpace> p(2, "pair");
    auto x = Kokkos::create_mirror_view(p.x);
    auto v = Kokkos::create_mirror_view(p.v);
    auto type = Kokkos::create_mirror_view(p.type);
    x(0, 0) = Real(1), x(0, 1) = Real(1), x(1, 0) = Real(1.0 + 1.2 + gap), x(1, 1) = Real(1);  // σ_sl = 1.2
    v(0, 0) = Real(0.3), v(0, 1) = Real(-0.1), v(1, 0) = Real(-0.7), v(1, 1) = Real(0.45);
    type(0) = 0, type(1) = 1;
    Kokkos::deep_copy(p.x, x);
    Kokkos::deep_copy(p.v, v);
    Kokkos::deep_copy(p.type, type);
    const sp::SoftSphereRepulsion<Real> c(Real(1), {kSmall, kLarge});
    NeighborList<2, Real, ExecSpace> list(c.cutoff(), Real(0.3));
    const Box<2, Real> box = Box<2, Real>::cube(Real(10), true);
    list.build(p, box);
    p.zero_forces();
    sp::accumulate_kinetic_friction(Real(0.5), c, p, p.v, list, box);
    auto f = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.f);
    if (gap < 0) {
      EXPECT_EQ(f(0, 0), -f(1, 0));
      EXPECT_EQ(f(0, 1), -f(1, 1));
      // −μ Δv of the stored velocities, in the precision's arithmetic.
      EXPECT_EQ(f(0, 0), -Real(0.5) * (Real(0.3) - Real(-0.7)));
      EXPECT_EQ(f(0, 1), -Real(0.5) * (Real(-0.1) - Real(0.45)));
    } else {
      EXPECT_EQ(f(0, 0), Real(0));
      EXPECT_EQ(f(1, 1), Real(0));
    }
  }
}

TYPED_TEST(SoftParticleTermsTest, MassProportionalDragIsMinusZetaMassVelocityAndFreeAtZero) {
  using Real = typename TypeParam::real;
  using ExecSpace = typename TypeParam::exec;
  Packing<3, Real, ExecSpace> s(10, 5.0, 9);
  s.p.zero_forces();
  sp::accumulate_mass_proportional_drag(Real(0), s.p, s.p.v);
  for (double fi : s.forces()) EXPECT_EQ(fi, 0.0);
  const Real zeta = Real(0.3);
  sp::accumulate_mass_proportional_drag(zeta, s.p, s.p.v);
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.p.v);
  auto m = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.p.mass);
  const auto f = s.forces();
  // Two roundings of the precision: −ζ m, then its product with v.
  for (int i = 0; i < 10; ++i)
    for (int d = 0; d < 3; ++d) {
      const double expected = -double(zeta) * double(m(i)) * double(v(i, d));
      EXPECT_NEAR(f[std::size_t(i) * 3 + d], expected, 2 * testing::eps<Real>() * std::abs(expected));
    }
  EXPECT_THROW(sp::accumulate_mass_proportional_drag(Real(-1), s.p, s.p.v), std::invalid_argument);
  EXPECT_THROW(sp::accumulate_kinetic_friction(Real(NAN), s.contacts, s.p, s.p.v, s.list, s.box), std::invalid_argument);
}

}  // namespace
}  // namespace mesoflow
