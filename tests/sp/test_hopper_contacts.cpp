// The soft-particle many-body terms of the hopper study (kernels/sp/): the bidisperse soft-sphere
// repulsion (eq. 2) is minus the gradient of its energy (central finite differences, 2D and 3D, full
// and half lists agree); kinetic friction (eq. 6) acts only between overlapping particles, pair by
// pair equal and opposite, conserves total momentum and dissipates exactly −(μ/2) Σ |v_m − v_n|²
// (tangential variant: the same with the part of v_m − v_n along r_mn removed);
// the drag of eq. 5 is −ζ M v; a zero coefficient leaves the forces untouched.
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

// A dense bidisperse packing: n random particles (half of each type) in a periodic box of side L,
// random velocities; at this density most particles overlap several neighbours.
template <int D>
struct Packing {
  Particles<D, double, Exec> p;
  Box<D, double> box;
  sp::SoftSphereRepulsion<double> contacts{2.5, {kSmall, kLarge}};
  NeighborList<D, double, Exec> list;

  Packing(int n, double L, unsigned seed, NeighborListKind kind = NeighborListKind::full)
      : p(n, "packing"), box(Box<D, double>::cube(L, true)), list(contacts.cutoff(), 0.2, kind) {
    std::mt19937 gen(seed);
    std::uniform_real_distribution<double> u(0, L), w(-1, 1), m(0.5, 2);
    auto x = Kokkos::create_mirror_view(p.x);
    auto v = Kokkos::create_mirror_view(p.v);
    auto type = Kokkos::create_mirror_view(p.type);
    auto mass = Kokkos::create_mirror_view(p.mass);
    for (int i = 0; i < n; ++i) {
      for (int d = 0; d < D; ++d) {
        x(i, d) = u(gen);
        v(i, d) = w(gen);
      }
      type(i) = i % 2;
      mass(i) = m(gen);
    }
    Kokkos::deep_copy(p.x, x);
    Kokkos::deep_copy(p.v, v);
    Kokkos::deep_copy(p.type, type);
    Kokkos::deep_copy(p.mass, mass);
    list.build(p, box);
  }

  double repulsion() {
    p.zero_forces();
    PairForce<D, double, Exec> pair;
    return pair.accumulate(contacts, p, list, box);
  }

  std::vector<double> forces() const {
    auto f = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.f);
    std::vector<double> out;
    for (std::size_t i = 0; i < f.extent(0); ++i)
      for (int d = 0; d < D; ++d) out.push_back(f(i, d));
    return out;
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

TEST(SoftSphereRepulsion, HalfListGivesTheFullListForces) {
  Packing<2> full(200, 11.0, 4), half(200, 11.0, 4, NeighborListKind::half);
  const double ef = full.repulsion(), eh = half.repulsion();
  EXPECT_NEAR(ef, eh, 1e-12 * std::abs(ef));
  const auto a = full.forces(), b = half.forces();
  for (std::size_t k = 0; k < a.size(); ++k) EXPECT_NEAR(a[k], b[k], 1e-12);
}

// Against a brute force over all pairs: each particle's friction, the power
// Σ_m F_m·v_m = −μ Σ_{m<n} |Δv|² Θ(1 − r_mn/σ_mn) (Δv = v_m − v_n, or its part perpendicular to r_mn
// for the tangential variant), and Σ_m F_m = 0 to round-off.
template <int D>
void expect_friction_conserves_momentum_and_dissipates(sp::FrictionComponent component = sp::FrictionComponent::full) {
  const bool tangential = component == sp::FrictionComponent::tangential;
  Packing<D> s(120, D == 2 ? 8.0 : 4.2, 7);
  const double mu = 0.7;
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
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      if (i == j) continue;
      double r2 = 0, dx[D];
      for (int d = 0; d < D; ++d) {
        dx[d] = x(i, d) - x(j, d);
        dx[d] -= s.box.length[d] * std::round(dx[d] / s.box.length[d]);
        r2 += dx[d] * dx[d];
      }
      const double sij = s.contacts.contact[type(i)][type(j)];
      if (r2 >= sij * sij) continue;
      ++contacts;
      double dv[D], along = 0;
      for (int d = 0; d < D; ++d) dv[d] = v(i, d) - v(j, d), along += dv[d] * dx[d] / r2;
      if (tangential)
        for (int d = 0; d < D; ++d) dv[d] -= along * dx[d];
      for (int d = 0; d < D; ++d) brute[std::size_t(i) * D + d] -= mu * dv[d];
      if (i < j)
        for (int d = 0; d < D; ++d) expected_power -= mu * dv[d] * dv[d];
    }
  for (int i = 0; i < n; ++i)
    for (int d = 0; d < D; ++d) {
      EXPECT_NEAR(f(i, d), brute[std::size_t(i) * D + d], 1e-12) << "particle " << i;
      power += f(i, d) * v(i, d);
      total[d] += f(i, d);
      magnitude += std::abs(f(i, d));
    }
  std::cout << "[ friction ] " << D << "D " << sp::to_string(component) << ": " << contacts / 2 << " contacts, |Σ F| = "
            << std::sqrt([&] { double t = 0; for (double c : total) t += c * c; return t; }()) << " (Σ|F| = " << magnitude
            << "), power " << power << " vs " << expected_power << "\n";
  EXPECT_GT(contacts, n);  // dense: several contacts per particle
  for (int d = 0; d < D; ++d) EXPECT_LE(std::abs(total[d]), 1e-13 * magnitude);
  EXPECT_LT(power, 0.0);
  EXPECT_NEAR(power, expected_power, 1e-12 * std::abs(expected_power));
}

TEST(KineticFriction, ConservesMomentumAndDissipates2D) { expect_friction_conserves_momentum_and_dissipates<2>(); }
TEST(KineticFriction, ConservesMomentumAndDissipates3D) { expect_friction_conserves_momentum_and_dissipates<3>(); }
TEST(KineticFriction, TangentialConservesMomentumAndDissipates2D) {
  expect_friction_conserves_momentum_and_dissipates<2>(sp::FrictionComponent::tangential);
}
TEST(KineticFriction, TangentialConservesMomentumAndDissipates3D) {
  expect_friction_conserves_momentum_and_dissipates<3>(sp::FrictionComponent::tangential);
}

// Two overlapping particles, tangential friction: a head-on relative velocity is not damped at all,
// a sliding one is damped as in eq. 6, and a mixed one loses exactly its component along r_12; the
// two forces are exact negatives (bitwise) and perpendicular to r_12.
TEST(KineticFriction, TangentialDampsOnlySliding) {
  const sp::SoftSphereRepulsion<double> c(1.0, {kSmall, kLarge});
  const Box<2, double> box = Box<2, double>::cube(10.0, true);
  struct Case { double vx0, vy0, vx1, vy1, fx0, fy0; };
  // x_1 − x_0 = 1.1 n, n = (0.6, 0.8) (1.1 < σ_sl = 1.2); t = (0.8, −0.6) the sliding direction.
  for (const Case k : {Case{0.3, 0.4, -0.3, -0.4, 0.0, 0.0},                 // Δv = (0.6, 0.8): head-on
                       Case{0.4, -0.3, -0.4, 0.3, -0.5 * 0.8, 0.5 * 0.6},    // Δv = (0.8, −0.6): sliding
                       Case{1.0, 0.2, 0.0, 0.0, -0.5 * 0.544, 0.5 * 0.408}}) {  // Δv = (1, 0.2) = 0.76 n + 0.68 t
    Particles<2, double, Exec> p(2, "pair");
    auto x = Kokkos::create_mirror_view(p.x);
    auto v = Kokkos::create_mirror_view(p.v);
    auto type = Kokkos::create_mirror_view(p.type);
    x(0, 0) = 1.0, x(0, 1) = 1.0, x(1, 0) = 1.0 + 0.6 * 1.1, x(1, 1) = 1.0 + 0.8 * 1.1;
    v(0, 0) = k.vx0, v(0, 1) = k.vy0, v(1, 0) = k.vx1, v(1, 1) = k.vy1;
    type(0) = 0, type(1) = 1;
    Kokkos::deep_copy(p.x, x);
    Kokkos::deep_copy(p.v, v);
    Kokkos::deep_copy(p.type, type);
    NeighborList<2, double, Exec> list(c.cutoff(), 0.3);
    list.build(p, box);
    p.zero_forces();
    sp::accumulate_kinetic_friction(0.5, c, p, p.v, list, box, sp::FrictionComponent::tangential);
    auto f = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.f);
    EXPECT_EQ(f(0, 0), -f(1, 0));
    EXPECT_EQ(f(0, 1), -f(1, 1));
    EXPECT_NEAR(f(0, 0), k.fx0, 1e-14);
    EXPECT_NEAR(f(0, 1), k.fy0, 1e-14);
    EXPECT_NEAR(f(0, 0) * 0.6 + f(0, 1) * 0.8, 0.0, 1e-14);  // perpendicular to r_01
  }
  EXPECT_EQ(sp::parse_friction_component("tangential"), sp::FrictionComponent::tangential);
  EXPECT_EQ(sp::parse_friction_component("full"), sp::FrictionComponent::full);
  EXPECT_THROW(sp::parse_friction_component("normal"), std::invalid_argument);
}

// Two particles: the forces are exact negatives (bitwise), −μ(v_1 − v_2) while they overlap and zero
// once they are apart.
TEST(KineticFriction, PairForcesAreExactlyOppositeAndOnlyInContact) {
  for (double gap : {-0.05, 0.05}) {
    Particles<2, double, Exec> p(2, "pair");
    auto x = Kokkos::create_mirror_view(p.x);
    auto v = Kokkos::create_mirror_view(p.v);
    auto type = Kokkos::create_mirror_view(p.type);
    x(0, 0) = 1.0, x(0, 1) = 1.0, x(1, 0) = 1.0 + 1.2 + gap, x(1, 1) = 1.0;  // σ_sl = 1.2
    v(0, 0) = 0.3, v(0, 1) = -0.1, v(1, 0) = -0.7, v(1, 1) = 0.45;
    type(0) = 0, type(1) = 1;
    Kokkos::deep_copy(p.x, x);
    Kokkos::deep_copy(p.v, v);
    Kokkos::deep_copy(p.type, type);
    const sp::SoftSphereRepulsion<double> c(1.0, {kSmall, kLarge});
    NeighborList<2, double, Exec> list(c.cutoff(), 0.3);
    const Box<2, double> box = Box<2, double>::cube(10.0, true);
    list.build(p, box);
    p.zero_forces();
    sp::accumulate_kinetic_friction(0.5, c, p, p.v, list, box);
    auto f = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.f);
    if (gap < 0) {
      EXPECT_EQ(f(0, 0), -f(1, 0));
      EXPECT_EQ(f(0, 1), -f(1, 1));
      EXPECT_DOUBLE_EQ(f(0, 0), -0.5 * (0.3 - -0.7));
      EXPECT_DOUBLE_EQ(f(0, 1), -0.5 * (-0.1 - 0.45));
    } else {
      EXPECT_EQ(f(0, 0), 0.0);
      EXPECT_EQ(f(1, 1), 0.0);
    }
  }
}

TEST(MassProportionalDrag, IsMinusZetaMassVelocityAndFreeAtZero) {
  Packing<3> s(10, 5.0, 9);
  s.p.zero_forces();
  sp::accumulate_mass_proportional_drag(0.0, s.p, s.p.v);
  for (double fi : s.forces()) EXPECT_EQ(fi, 0.0);
  sp::accumulate_mass_proportional_drag(0.3, s.p, s.p.v);
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.p.v);
  auto m = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.p.mass);
  const auto f = s.forces();
  for (int i = 0; i < 10; ++i)
    for (int d = 0; d < 3; ++d) EXPECT_DOUBLE_EQ(f[std::size_t(i) * 3 + d], -0.3 * m(i) * v(i, d));
  EXPECT_THROW(sp::accumulate_mass_proportional_drag(-1.0, s.p, s.p.v), std::invalid_argument);
  EXPECT_THROW(sp::accumulate_kinetic_friction(double(NAN), s.contacts, s.p, s.p.v, s.list, s.box), std::invalid_argument);
}

}  // namespace
}  // namespace mesoflow
