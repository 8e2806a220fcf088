// The soft-particle many-body terms of the hopper study (kernels/sp/): the bidisperse soft-sphere
// repulsion (eq. 2) is minus the gradient of its energy (central finite differences, 2D and 3D, full
// and half lists agree); kinetic friction (eq. 6) acts only between overlapping particles, pair by
// pair equal and opposite, conserves total momentum and dissipates exactly −(μ/2) Σ |v_m − v_n|²;
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
// Σ_m F_m·v_m = −μ Σ_{m<n} |v_m − v_n|² Θ(1 − r_mn/σ_mn), and Σ_m F_m = 0 to round-off.
template <int D>
void expect_friction_conserves_momentum_and_dissipates() {
  Packing<D> s(120, D == 2 ? 8.0 : 4.2, 7);
  const double mu = 0.7;
  s.p.zero_forces();
  sp::accumulate_kinetic_friction(mu, s.contacts, s.p, s.p.v, s.list, s.box);
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
      double r2 = 0;
      for (int d = 0; d < D; ++d) {
        double dx = x(i, d) - x(j, d);
        dx -= s.box.length[d] * std::round(dx / s.box.length[d]);
        r2 += dx * dx;
      }
      const double sij = s.contacts.contact[type(i)][type(j)];
      if (r2 >= sij * sij) continue;
      ++contacts;
      for (int d = 0; d < D; ++d) brute[std::size_t(i) * D + d] -= mu * (v(i, d) - v(j, d));
      if (i < j)
        for (int d = 0; d < D; ++d) expected_power -= mu * (v(i, d) - v(j, d)) * (v(i, d) - v(j, d));
    }
  for (int i = 0; i < n; ++i)
    for (int d = 0; d < D; ++d) {
      EXPECT_NEAR(f(i, d), brute[std::size_t(i) * D + d], 1e-12) << "particle " << i;
      power += f(i, d) * v(i, d);
      total[d] += f(i, d);
      magnitude += std::abs(f(i, d));
    }
  std::cout << "[ friction ] " << D << "D: " << contacts / 2 << " contacts, |Σ F| = "
            << std::sqrt([&] { double t = 0; for (double c : total) t += c * c; return t; }()) << " (Σ|F| = " << magnitude
            << "), power " << power << " vs " << expected_power << "\n";
  EXPECT_GT(contacts, n);  // dense: several contacts per particle
  for (int d = 0; d < D; ++d) EXPECT_LE(std::abs(total[d]), 1e-13 * magnitude);
  EXPECT_LT(power, 0.0);
  EXPECT_NEAR(power, expected_power, 1e-12 * std::abs(expected_power));
}

TEST(KineticFriction, ConservesMomentumAndDissipates2D) { expect_friction_conserves_momentum_and_dissipates<2>(); }
TEST(KineticFriction, ConservesMomentumAndDissipates3D) { expect_friction_conserves_momentum_and_dissipates<3>(); }

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
