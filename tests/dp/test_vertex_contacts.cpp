// Contacts between rough deformable polygons (hopper study, eqs. 9 and 12; kernels/dp/vertex_contacts.hpp):
// bidisperse 16-gons overlapping each other, one of them compressed so that its own vertices overlap.
// The repulsion and friction equal a brute force over vertex pairs of different particles (and differ
// from one that counts pairs within a particle), the repulsion is minus the gradient of its energy,
// the friction conserves momentum, and a list without same-body exclusion is refused. The
// finite-difference check runs in double; the rest on Serial and OpenMP in float and double, against
// brute forces in double over the stored values (tolerances in multiples of the precision's ε).
#include "kernels/dp/vertex_contacts.hpp"
#include "kernels/dp/polygons.hpp"
#include "finite_difference.hpp"
#include "test_types.hpp"

#include <cmath>
#include <iostream>
#include <random>
#include <vector>

// Own namespace: this file shares a unity translation unit with others (tests/CMakeLists.txt).
namespace mesoflow::dp::vertex_contacts_test {
namespace {

using Exec = Kokkos::DefaultExecutionSpace;
constexpr int kVertices = 16;

template <class T>
class VertexContactsTest : public ::testing::Test {};
TYPED_TEST_SUITE(VertexContactsTest, mesoflow::testing::BackendsAndPrecisions);

template <class Real = double, class ExecSpace = Exec>
struct Scene {
  static constexpr double L = 6.0;
  Particles<2, Real, ExecSpace> p;
  Box<2, Real> box = Box<2, Real>::cube(Real(L), true);
  VertexContactRepulsion<Real> contacts;
  NeighborList<2, Real, ExecSpace> list;
  PairForce<2, Real, ExecSpace> pair;

  // δ = l0 of a small (σ = 1) and a large (σ = 1.4) 16-gon.
  static std::vector<double> vertex_diameters() {
    return {regular_polygon_edge(0.25 * pi, kVertices), regular_polygon_edge(0.25 * pi * 1.96, kVertices)};
  }

  explicit Scene(BodyExclusion exclusion = BodyExclusion::same_body)
      : p(6 * kVertices, "polygons"),
        contacts(Real(3), vertex_diameters()),
        list(contacts.cutoff(), Real(0.1), NeighborListKind::full, exclusion) {
    const double centres[6][2] = {{1.0, 1.0}, {1.95, 1.1}, {1.4, 1.95}, {3.5, 3.5}, {4.6, 3.6}, {5.6, 3.4}};
    std::mt19937 gen(2);
    std::uniform_real_distribution<double> w(-1, 1), jitter(-0.02, 0.02);
    auto x = Kokkos::create_mirror_view(p.x);
    auto v = Kokkos::create_mirror_view(p.v);
    auto body = Kokkos::create_mirror_view(p.body);
    auto type = Kokkos::create_mirror_view(p.type);
    for (int b = 0; b < 6; ++b) {
      const int t = b % 2;
      const double sigma = t == 0 ? 1.0 : 1.4;
      const double squeeze = b == 3 ? 0.8 : 1.0;  // polygon 3's own neighbouring vertices overlap
      const double R = 0.5 * sigma * squeeze;
      for (int k = 0; k < kVertices; ++k) {
        const int i = b * kVertices + k;
        const double a = 2 * pi * k / kVertices + 0.1 * b;
        x(i, 0) = Real(centres[b][0] + R * std::cos(a) + jitter(gen));
        x(i, 1) = Real(centres[b][1] + R * std::sin(a) + jitter(gen));
        v(i, 0) = Real(w(gen)), v(i, 1) = Real(w(gen));
        body(i) = b;
        type(i) = t;
      }
    }
    Kokkos::deep_copy(p.x, x);
    Kokkos::deep_copy(p.v, v);
    Kokkos::deep_copy(p.body, body);
    Kokkos::deep_copy(p.type, type);
    list.build(p, box);
  }

  double repulsion() {
    p.zero_forces();
    return accumulate_vertex_contacts(contacts, p, list, box, pair);
  }

  // Brute force of eq. 9 (energy) over vertex pairs, of different bodies only or of all.
  double brute_energy(bool count_same_body) const {
    auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.x);
    auto body = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.body);
    auto type = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.type);
    double u = 0;
    const int n = int(p.size());
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j) {
        if (body(i) == body(j) && !count_same_body) continue;
        double dx = double(x(i, 0)) - double(x(j, 0)), dy = double(x(i, 1)) - double(x(j, 1));
        dx -= L * std::round(dx / L), dy -= L * std::round(dy / L);
        const double r = std::sqrt(dx * dx + dy * dy), s = double(contacts.contact[type(i)][type(j)]);
        if (r < s) u += 0.5 * double(contacts.epsilon) * (1 - r / s) * (1 - r / s);
      }
    return u;
  }
};

// The pair energy (ε/2)(1 − r/δ)² of the stored positions: measured |ΔU|/U = 5.2e-9 in float
// (0.04 ε), ≤ 2.1e-16 in double; bound 16 ε.
TYPED_TEST(VertexContactsTest, RepulsionCountsOnlyPairsOfDifferentParticles) {
  using Real = typename TypeParam::real;
  Scene<Real, typename TypeParam::exec> s;
  const double u = s.repulsion();
  const double different = s.brute_energy(false), all = s.brute_energy(true);
  std::cout << "[ contacts ] " << (sizeof(Real) == 4 ? "float" : "double") << ": U_int = " << u << ", brute force "
            << different << " (with same-particle pairs " << all << "), |ΔU|/U = " << std::abs(u - different) / different
            << "\n";
  EXPECT_GT(different, 0.1);
  EXPECT_NEAR(u, different, 16 * testing::eps<Real>() * different);
  EXPECT_GT(all - different, 0.1) << "polygon 3 is compressed: its own vertices overlap";
}

TEST(VertexContacts, RepulsionIsMinusTheEnergyGradient) {
  Scene<> s;
  // h = 10⁻⁸: the force's derivative jumps at contact, an O(h) error for pairs within h of it.
  const auto c = testing::check_gradient(s.p, [&] { return s.repulsion(); }, 1e-8);
  std::cout << "[ fd ] rough DP vertex contacts: max error / max |F| = " << c.max_error << "\n";
  EXPECT_GT(c.max_force, 1.0);
  EXPECT_LE(c.max_error, 1e-6);
}

TYPED_TEST(VertexContactsTest, FrictionConservesMomentumAndSkipsTheSameParticle) {
  using Real = typename TypeParam::real;
  using ExecSpace = typename TypeParam::exec;
  using S = Scene<Real, ExecSpace>;
  S s;
  s.p.zero_forces();
  accumulate_vertex_friction(Real(0.4), s.contacts, s.p, s.p.v, s.list, s.box);
  auto f = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.p.f);
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.p.x);
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.p.v);
  auto body = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.p.body);
  auto type = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.p.type);
  const int n = int(s.p.size());
  double total[2] = {0, 0}, magnitude = 0;
  for (int i = 0; i < n; ++i) {
    double brute[2] = {0, 0};
    for (int j = 0; j < n; ++j) {
      if (j == i || body(i) == body(j)) continue;
      double dx = double(x(i, 0)) - double(x(j, 0)), dy = double(x(i, 1)) - double(x(j, 1));
      dx -= S::L * std::round(dx / S::L), dy -= S::L * std::round(dy / S::L);
      const double sij = double(s.contacts.contact[type(i)][type(j)]);
      if (dx * dx + dy * dy < sij * sij)
        for (int d = 0; d < 2; ++d) brute[d] -= double(Real(0.4)) * (double(v(i, d)) - double(v(j, d)));
    }
    for (int d = 0; d < 2; ++d) {
      // −μ Σ Δv of O(1) velocities over a few contacts: a few ε.
      EXPECT_NEAR(double(f(i, d)), brute[d], 16 * testing::eps<Real>()) << "vertex " << i;
      total[d] += double(f(i, d));
      magnitude += std::abs(double(f(i, d)));
    }
  }
  EXPECT_GT(magnitude, 1.0);
  for (double t : total) EXPECT_LE(std::abs(t), 4 * testing::eps<Real>() * magnitude);
}

TYPED_TEST(VertexContactsTest, RefuseAListThatCountsPairsWithinAParticle) {
  using Real = typename TypeParam::real;
  Scene<Real, typename TypeParam::exec> s(BodyExclusion::none);
  EXPECT_THROW(s.repulsion(), std::invalid_argument);
  EXPECT_THROW(accumulate_vertex_friction(Real(0.4), s.contacts, s.p, s.p.v, s.list, s.box), std::invalid_argument);
}

}  // namespace
}  // namespace mesoflow::dp::vertex_contacts_test
