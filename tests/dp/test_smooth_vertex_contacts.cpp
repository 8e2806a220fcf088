// Contacts between nearly smooth deformable polygons (hopper study, Appendix A;
// kernels/dp/smooth_vertex_contacts.hpp): bidisperse 16-gons pressed lightly against each other
// (circulo-line edges of width 0.1 l0). The energy equals a brute force of Appendix A's rule over every
// (vertex, edge) pair of different particles; the forces are minus its gradient; each contact
// exchanges no net force; lists without same-body exclusion or too short for the longest edge are
// refused. The finite-difference check runs in double; the rest on Serial and OpenMP in float and
// double, against the brute force in double over the stored positions.
// Kinetic friction on the same contacts (kernels/dp/smooth_vertex_friction.hpp): every vertex's force
// equals a brute force of eq. 12 over (vertex, edge) contacts with the material point's velocity at
// the edge parameter, full and tangential; the total is zero; the power is −μ Σ|Δv|² (≤ 0); a rigid
// translation is not damped.
#include "kernels/dp/smooth_vertex_contacts.hpp"
#include "kernels/dp/smooth_vertex_friction.hpp"
#include "finite_difference.hpp"
#include "test_types.hpp"

#include <cmath>
#include <iostream>
#include <random>
#include <utility>
#include <vector>

// Own namespace: this file shares a unity translation unit with others (tests/CMakeLists.txt).
namespace mesoflow::dp::smooth_vertex_contacts_test {
namespace {

using Exec = Kokkos::DefaultExecutionSpace;
using V2 = Vec<2, double>;
constexpr int kVertices = 16;
constexpr double kL = 8.0;

template <class T>
class SmoothVertexContactsTest : public ::testing::Test {};
TYPED_TEST_SUITE(SmoothVertexContactsTest, mesoflow::testing::BackendsAndPrecisions);

template <class Real = double, class ExecSpace = Exec>
struct Scene {
  Polygons<Real, ExecSpace> polygons;
  Particles<2, Real, ExecSpace> p;
  Box<2, Real> box = Box<2, Real>::cube(Real(kL), true);
  sp::SoftSphereRepulsion<Real> widths;
  NeighborList<2, Real, ExecSpace> list;

  static double edge(double sigma) { return regular_polygon_edge(0.25 * pi * sigma * sigma, kVertices); }

  explicit Scene(double width_over_l0, BodyExclusion exclusion = BodyExclusion::same_body, double cutoff = 0)
      : polygons(Polygons<Real, ExecSpace>::from_vertex_counts(
            std::vector<int>(6, kVertices),
            {Real(0.25 * pi), Real(0.25 * pi * 1.96), Real(0.25 * pi), Real(0.25 * pi * 1.96), Real(0.25 * pi),
             Real(0.25 * pi * 1.96)},
            {Real(edge(1)), Real(edge(1.4)), Real(edge(1)), Real(edge(1.4)), Real(edge(1)), Real(edge(1.4))})),
        p(6 * kVertices, "polygons"),
        widths(Real(5), {width_over_l0 * edge(1.0), width_over_l0 * edge(1.4)}),
        list(Real(cutoff > 0 ? cutoff : 1.3 * edge(1.4) + double(widths.cutoff())), Real(0.05), NeighborListKind::full,
             exclusion) {
    assign_bodies(polygons, p);
    // Three touching pairs (small–large), the gap between their circumscribed circles slightly
    // negative so that edges and vertices press lightly; rotations differ so contacts are both
    // vertex–edge (Fig. 9a) and vertex–cap (Fig. 9b); the last pair straddles the periodic boundary.
    const double centres[6][2] = {{2.0, 2.0}, {3.18, 2.0}, {2.0, 5.0}, {2.0, 6.18}, {7.6, 4.0}, {0.78, 4.0}};
    std::mt19937 gen(8);
    std::uniform_real_distribution<double> jitter(-0.01, 0.01);
    auto x = Kokkos::create_mirror_view(p.x);
    auto type = Kokkos::create_mirror_view(p.type);
    for (int b = 0; b < 6; ++b) {
      const double R = 0.5 * (b % 2 == 0 ? 1.0 : 1.4) / std::cos(pi / kVertices) * 1.0;
      for (int k = 0; k < kVertices; ++k) {
        const int i = b * kVertices + k;
        const double a = 2 * pi * k / kVertices + 0.13 * b;
        const double xi = centres[b][0] + R * std::cos(a) + jitter(gen);
        x(i, 0) = Real(xi - kL * std::floor(xi / kL));
        x(i, 1) = Real(centres[b][1] + R * std::sin(a) + jitter(gen));
        type(i) = b % 2;
      }
    }
    Kokkos::deep_copy(p.x, x);
    Kokkos::deep_copy(p.type, type);
    list.build(p, box);
  }

  double energy() {
    p.zero_forces();
    return accumulate_smooth_vertex_contacts(widths, polygons, p, list, box);
  }

  // Random vertex velocities in [−1, 1]² (seed 3), plus `drift` on every vertex.
  void set_velocities(V2 drift = V2::zero()) {
    std::mt19937 gen(3);
    std::uniform_real_distribution<double> u(-1, 1);
    auto v = Kokkos::create_mirror_view(p.v);
    for (std::size_t i = 0; i < p.size(); ++i)
      for (int d = 0; d < 2; ++d) v(i, d) = Real(u(gen) + drift[d]);
    Kokkos::deep_copy(p.v, v);
  }

  // Eq. 12 on the circulo-line contacts, from the kernel (forces of a zeroed p.f).
  void friction(double mu, sp::FrictionComponent c) {
    p.zero_forces();
    accumulate_smooth_vertex_friction(Real(mu), widths, polygons, p, p.v, list, box, c);
  }

  // The same by brute force over every (vertex, edge) pair of different particles, in double; also
  // returns Σ|Δv_damped|² over the contacts and their count.
  std::vector<V2> brute_friction(double mu, bool tangential, double& dissipation, int& contacts) const {
    auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.x);
    auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.v);
    auto type = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.type);
    auto wrap = [](V2 w) {
      for (int d = 0; d < 2; ++d) w[d] -= kL * std::round(w[d] / kL);
      return w;
    };
    auto vel = [&](int i) { return V2{{double(v(i, 0)), double(v(i, 1))}}; };
    const int n = int(p.size());
    std::vector<V2> f(std::size_t(n), V2::zero());
    dissipation = 0, contacts = 0;
    for (int q = 0; q < n; ++q)
      for (int a = 0; a < n; ++a) {
        if (q / kVertices == a / kVertices) continue;
        const int b = (a / kVertices) * kVertices + (a % kVertices + 1) % kVertices;
        const V2 l = wrap(V2{{double(x(b, 0)) - double(x(a, 0)), double(x(b, 1)) - double(x(a, 1))}});
        const V2 aq = wrap(V2{{double(x(q, 0)) - double(x(a, 0)), double(x(q, 1)) - double(x(a, 1))}});
        double t = dot(aq, l) / norm2(l);
        const V2 gap = t >= 0 && t <= 1 ? aq - t * l : aq;
        if (!(t >= 0 && t <= 1)) t = 0;
        const double d = std::sqrt(norm2(gap)), w = double(widths.contact[type(q)][type(a)]);
        if (!(d < w)) continue;
        V2 dv = vel(q) - ((1 - t) * vel(a) + t * vel(b));
        if (tangential) {
          const V2 u = (1 / d) * gap;
          dv -= dot(dv, u) * u;
        }
        f[std::size_t(q)] -= mu * dv;
        f[std::size_t(a)] += ((1 - t) * mu) * dv;
        f[std::size_t(b)] += (t * mu) * dv;
        dissipation += norm2(dv);
        ++contacts;
      }
    return f;
  }

  // Appendix A's rule by brute force over every (vertex, edge) pair of different particles.
  double brute_energy() const {
    auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.x);
    auto type = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.type);
    auto wrap = [](V2 v) {
      for (int d = 0; d < 2; ++d) v[d] -= kL * std::round(v[d] / kL);
      return v;
    };
    double u = 0;
    const int n = int(p.size());
    for (int q = 0; q < n; ++q)
      for (int a = 0; a < n; ++a) {
        if (q / kVertices == a / kVertices) continue;
        const int b = (a / kVertices) * kVertices + (a % kVertices + 1) % kVertices;
        const V2 l = wrap(V2{{double(x(b, 0)) - double(x(a, 0)), double(x(b, 1)) - double(x(a, 1))}});
        const V2 aq = wrap(V2{{double(x(q, 0)) - double(x(a, 0)), double(x(q, 1)) - double(x(a, 1))}});
        const double t = dot(aq, l) / norm2(l);
        const double d = std::sqrt(t >= 0 && t <= 1 ? norm2(aq - t * l) : norm2(aq));
        const double w = double(widths.contact[type(q)][type(a)]);
        if (d < w) u += 0.5 * double(widths.epsilon) * (1 - d / w) * (1 - d / w);
      }
    return u;
  }
};

// The line width δ = 0.1 l0 ≈ 0.02 is small against the coordinates (up to L = 8), so the kernel's
// distances could be off by ~ε·L, the energy by up to ~ε·L/δ relative. Measured far less:
// |ΔU|/U = 9.0e-8 (δ = 0.1 l0), 5.6e-8 (0.3 l0) in float (≤ 0.8 ε), ≤ 2.1e-16 in double; bound 16 ε.
TYPED_TEST(SmoothVertexContactsTest, EnergyFollowsAppendixA) {
  using Real = typename TypeParam::real;
  for (double width : {0.1, 0.3}) {  // the paper's δ = 0.1 l0, and a wider line with more contacts
    Scene<Real, typename TypeParam::exec> s(width);
    const double u = s.energy(), brute = s.brute_energy();
    const double relative = std::abs(u - brute) / brute, scale = testing::eps<Real>() * kL / (width * Scene<>::edge(1.0));
    std::cout << "[ smooth ] " << (sizeof(Real) == 4 ? "float" : "double") << ", δ = " << width << " l0: U = " << u
              << ", brute force " << brute << ", |ΔU|/U = " << relative << " = " << relative / scale << " ε L/δ\n";
    EXPECT_GT(brute, 1e-3);
    EXPECT_LE(relative, 16 * testing::eps<Real>());
  }
}

// The largest component of the total force Σ_i F_i, and Σ_i |F_i| (componentwise), in double.
template <class P>
std::pair<double, double> net_force(const P& p) {
  auto f = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.f);
  double total[2] = {0, 0}, magnitude = 0;
  for (std::size_t i = 0; i < f.extent(0); ++i)
    for (int d = 0; d < 2; ++d) {
      total[d] += double(f(i, d));
      magnitude += std::abs(double(f(i, d)));
    }
  return {std::max(std::abs(total[0]), std::abs(total[1])), magnitude};
}

// Each contact's reaction is shared by the edge's two vertices: Σ F = 0 to the precision's round-off
// (measured |Σ F|/Σ|F| = 2.0e-17 in double, 1.1e-8 in float).
TYPED_TEST(SmoothVertexContactsTest, ExchangesNoNetForce) {
  using Real = typename TypeParam::real;
  Scene<Real, typename TypeParam::exec> s(0.3);
  s.energy();
  const auto [net, magnitude] = net_force(s.p);
  std::cout << "[ smooth ] " << (sizeof(Real) == 4 ? "float" : "double") << ": |Σ F| = " << net
            << " (Σ|F| = " << magnitude << ")\n";
  EXPECT_GT(magnitude, 0.1);
  EXPECT_LE(net, 2 * testing::eps<Real>() * magnitude);
}

TEST(SmoothVertexContacts, ForceIsMinusTheGradient) {
  Scene<> s(0.3);
  s.energy();
  auto f = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.p.f);
  double scale = 0;
  for (std::size_t i = 0; i < f.extent(0); ++i)
    for (int d = 0; d < 2; ++d) scale = std::max(scale, std::abs(f(i, d)));
  // h = 10⁻⁸: the force's derivative jumps at contact and at t = 0, 1.
  const auto c = testing::check_gradient(s.p, [&] { return s.energy(); }, 1e-8);
  const double worst = c.max_error;
  std::cout << "[ fd ] smooth DP contacts: max error / max |F| = " << worst << ", |F|max = " << scale << "\n";
  EXPECT_GT(scale, 0.1);
  EXPECT_LE(worst, 1e-6);
}

TYPED_TEST(SmoothVertexContactsTest, RefusesListsThatCannotHoldTheContacts) {
  using S = Scene<typename TypeParam::real, typename TypeParam::exec>;
  S without_exclusion(0.1, BodyExclusion::none);
  EXPECT_THROW(without_exclusion.energy(), std::invalid_argument);
  S too_short(0.1, BodyExclusion::same_body, 0.5 * S::edge(1.4));
  EXPECT_THROW(too_short.energy(), std::invalid_argument);
}

// Eq. 12 on the circulo-line contacts: each vertex's force against the brute force (in double over
// the stored state; bound 64 ε of the largest force), Σ F = 0, and the power Σ F·v equal to
// −μ Σ|Δv|² over the contacts, negative. Both the full and the tangential relative velocity.
TYPED_TEST(SmoothVertexContactsTest, FrictionDampsTheVertexAgainstTheEdgesMaterialPoint) {
  using Real = typename TypeParam::real;
  Scene<Real, typename TypeParam::exec> s(0.3);
  s.set_velocities();
  const double mu = 0.7;
  for (bool tangential : {false, true}) {
    s.friction(mu, tangential ? sp::FrictionComponent::tangential : sp::FrictionComponent::full);
    double dissipation = 0;
    int contacts = 0;
    const auto brute = s.brute_friction(mu, tangential, dissipation, contacts);
    auto f = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.p.f);
    auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.p.v);
    const auto [net, magnitude] = net_force(s.p);
    double worst = 0, largest = 0, power = 0;
    for (std::size_t i = 0; i < f.extent(0); ++i)
      for (int d = 0; d < 2; ++d) {
        worst = std::max(worst, std::abs(double(f(i, d)) - brute[i][d]));
        largest = std::max(largest, std::abs(brute[i][d]));
        power += double(f(i, d)) * double(v(i, d));
      }
    std::cout << "[ smooth friction ] " << (sizeof(Real) == 4 ? "float" : "double") << (tangential ? ", tangential" : ", full")
              << ": " << contacts << " contacts, max |F − brute| / max|F| = " << worst / largest
              << ", |Σ F| = " << net << ", power " << power
              << " against −μ Σ|Δv|² = " << -mu * dissipation << "\n";
    EXPECT_GE(contacts, 6);
    EXPECT_GT(largest, 0.1);
    EXPECT_LE(worst, 64 * testing::eps<Real>() * largest);
    EXPECT_LE(net, 4 * testing::eps<Real>() * magnitude);
    EXPECT_LT(power, 0);
    EXPECT_NEAR(power, -mu * dissipation, 64 * testing::eps<Real>() * mu * dissipation);
  }
}

// A rigid translation of the whole scene moves every vertex with its contact partners: no friction.
TYPED_TEST(SmoothVertexContactsTest, FrictionLeavesARigidTranslationAlone) {
  using Real = typename TypeParam::real;
  Scene<Real, typename TypeParam::exec> s(0.3);
  auto v = Kokkos::create_mirror_view(s.p.v);
  for (std::size_t i = 0; i < s.p.size(); ++i) v(i, 0) = Real(0.8), v(i, 1) = Real(-0.3);
  Kokkos::deep_copy(s.p.v, v);
  s.friction(2.0, sp::FrictionComponent::full);
  auto f = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.p.f);
  double largest = 0;
  for (std::size_t i = 0; i < f.extent(0); ++i)
    for (int d = 0; d < 2; ++d) largest = std::max(largest, std::abs(double(f(i, d))));
  EXPECT_LE(largest, 64 * testing::eps<Real>() * 2.0);  // (1 − t) v + t v rounds to v within ε
  // and a list without same-body exclusion is refused, as for the contacts
  Scene<Real, typename TypeParam::exec> without(0.1, BodyExclusion::none);
  EXPECT_THROW(without.friction(1.0, sp::FrictionComponent::full), std::invalid_argument);
}

}  // namespace
}  // namespace mesoflow::dp::smooth_vertex_contacts_test
