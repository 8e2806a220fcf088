// The DP shape energy (capillary-droplets eqs. 1–2, hopper-flows eq. 8) and gravity on deformable
// polygons: every term's force is minus the gradient of its energy (central differences), the
// energies match a host reference, the shape terms exert no net force or torque on a body, regular
// polygons give the analytic forces and observables, the loop adds to existing forces, float agrees
// with double, and the body state (area, perimeter, centre of mass) is right for known shapes.
#include "kernels/dp/area_force.hpp"
#include "kernels/dp/bending_force.hpp"
#include "kernels/dp/gravity.hpp"
#include "kernels/dp/line_tension.hpp"
#include "kernels/dp/polygons.hpp"
#include "kernels/dp/segment_spring_force.hpp"
#include "kernels/dp/shape_forces.hpp"
#include "test_types.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace mesoflow::dp {
namespace {

// ---- Scene: three bodies of different sizes and vertex counts, then two free particles ----------

const std::vector<int> kVertexCounts = {7, 16, 33};
const std::vector<double> kAreas = {1.0, 0.6, 1.4};
const std::vector<Vec<2, double>> kCentres = {{{0.0, 0.0}}, {{3.0, 1.0}}, {{-2.5, 4.0}}};
constexpr int kFreeParticles = 2;

// Scene-wide coefficients, of sizes that give every term forces of order one.
constexpr double kArea = 20.0, kSpring = 1.5, kTension = 0.7, kBend = 0.4, kGx = 0.3, kGy = -1.1;

template <class Real>
AreaElasticity<Real> area_term() {
  return {Real(kArea)};
}
template <class Real>
SegmentSprings<Real> spring_term() {
  return {Real(kSpring)};
}
template <class Real>
LineTension<Real> tension_term() {
  return {Real(kTension)};
}
template <class Real>
Bending<Real> bending_term() {
  return {Real(kBend)};
}
template <class Real>
Gravity<Real> gravity_term() {
  return {make_vec2(Real(kGx), Real(kGy))};
}

template <class Real, class Exec>
struct Scene {
  Polygons<Real, Exec> polygons;
  BodyState<Real, Exec> state;
  Particles<2, Real, Exec> p;
};

// Regular polygons of area a0 (rotated by a different angle each), each vertex moved radially and
// tangentially by up to `deformation` × its edge length (fixed seed); l0 = l0_scale × the regular
// polygon's edge. Vertex masses M/N_v ± 20 % with M = a0, random velocities.
template <class Real, class Exec>
Scene<Real, Exec> make_scene(double deformation, double l0_scale, unsigned seed = 2024) {
  std::vector<Real> a0, l0;
  for (std::size_t b = 0; b < kVertexCounts.size(); ++b) {
    a0.push_back(Real(kAreas[b]));
    l0.push_back(Real(l0_scale * regular_polygon_edge(kAreas[b], kVertexCounts[b])));
  }
  const auto polygons = Polygons<Real, Exec>::from_vertex_counts(kVertexCounts, a0, l0);
  const int nv = polygons.num_vertices();
  Scene<Real, Exec> s{polygons, BodyState<Real, Exec>(polygons.num_bodies()),
                      Particles<2, Real, Exec>(nv + kFreeParticles, "dp_scene")};
  assign_bodies(s.polygons, s.p);

  Kokkos::View<double* [2], Kokkos::LayoutLeft, Kokkos::HostSpace> xd("mesoflow::dp_test::unrounded_x", nv + kFreeParticles);
  auto x = Kokkos::create_mirror_view(s.p.x);
  auto v = Kokkos::create_mirror_view(s.p.v);
  auto m = Kokkos::create_mirror_view(s.p.mass);
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int b = 0; b < s.polygons.num_bodies(); ++b) {
    const int n = s.polygons.num_vertices(b), begin = s.polygons.first_vertex(b);
    place_regular_polygon(s.polygons, b, xd, kCentres[b], 0.37 * (b + 1));
    const double edge = regular_polygon_edge(kAreas[b], n);
    for (int i = begin; i < begin + n; ++i) {
      const double rx = xd(i, 0) - kCentres[b][0], ry = xd(i, 1) - kCentres[b][1];
      const double r = std::hypot(rx, ry);
      const double radial = deformation * edge * u(gen), tangential = deformation * edge * u(gen);
      xd(i, 0) += (radial * rx - tangential * ry) / r;
      xd(i, 1) += (radial * ry + tangential * rx) / r;
      m(i) = Real(kAreas[b] / n * (1.0 + 0.2 * u(gen)));
    }
  }
  for (int i = nv; i < nv + kFreeParticles; ++i) {
    xd(i, 0) = 8.0 + i;
    xd(i, 1) = -3.0;
    m(i) = Real(1);
  }
  for (int i = 0; i < nv + kFreeParticles; ++i)
    for (int d = 0; d < 2; ++d) {
      x(i, d) = Real(xd(i, d));
      v(i, d) = Real(u(gen));
    }
  Kokkos::deep_copy(s.p.x, x);
  Kokkos::deep_copy(s.p.v, v);
  Kokkos::deep_copy(s.p.mass, m);
  update_body_state(s.polygons, s.p, s.state);
  return s;
}

// A host copy that never aliases the device View (create_mirror always allocates).
template <class View>
auto to_host(const View& v) {
  auto h = Kokkos::create_mirror(v);
  Kokkos::deep_copy(h, v);
  return h;
}

// f ← the terms' forces at the current positions (body state refreshed first); returns the energy.
template <class Real, class Exec, class... Terms>
double compute_forces(const Scene<Real, Exec>& s, const Terms&... terms) {
  s.p.zero_forces();
  update_body_state(s.polygons, s.p, s.state);
  return accumulate_shape_forces(s.polygons, s.state, s.p, terms...);
}

template <class Real, class Exec, class... Terms>
double energy_of(const Scene<Real, Exec>& s, const Terms&... terms) {
  update_body_state(s.polygons, s.p, s.state);
  return shape_energy(s.polygons, s.state, s.p, terms...);
}

double norm(double x, double y) { return std::hypot(x, y); }

std::string scientific(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2e", value);
  return text;
}

// ---- Finite-difference gradients (double, every backend) -----------------------------------------

// Central differences of the total energy, step h, at every coordinate of every polygon vertex;
// returns max over vertices i and axes d of |F_num − F_id| / max(1, |F_i|), |F_i| the norm of the
// vertex's analytic force (records it as a test property too).
template <class Exec, class... Terms>
double max_gradient_error(const Terms&... terms) {
  auto s = make_scene<double, Exec>(0.2, 1.05);
  compute_forces(s, terms...);
  const auto f = to_host(s.p.f);
  auto x = to_host(s.p.x);
  const double h = 1e-6;
  double max_rel = 0;
  for (int i = 0; i < s.polygons.num_vertices(); ++i)
    for (int d = 0; d < 2; ++d) {
      const double x0 = x(i, d);
      x(i, d) = x0 + h;
      Kokkos::deep_copy(s.p.x, x);
      const double e_plus = energy_of(s, terms...);
      x(i, d) = x0 - h;
      Kokkos::deep_copy(s.p.x, x);
      const double e_minus = energy_of(s, terms...);
      x(i, d) = x0;
      const double numeric = -(e_plus - e_minus) / (2 * h);
      max_rel = std::max(max_rel, std::abs(numeric - f(i, d)) / std::max(1.0, norm(f(i, 0), f(i, 1))));
    }
  Kokkos::deep_copy(s.p.x, x);
  ::testing::Test::RecordProperty("max_relative_error", scientific(max_rel));
  return max_rel;
}

template <class ExecSpace>
class DpShapeGradientTest : public ::testing::Test {};
#if defined(KOKKOS_ENABLE_OPENMP) && defined(KOKKOS_ENABLE_SERIAL)
using GradientBackends = ::testing::Types<Kokkos::Serial, Kokkos::OpenMP>;
#else
using GradientBackends = ::testing::Types<Kokkos::DefaultExecutionSpace>;
#endif
TYPED_TEST_SUITE(DpShapeGradientTest, GradientBackends);

constexpr double kGradientTolerance = 1e-6;

TYPED_TEST(DpShapeGradientTest, AreaElasticityForceIsMinusEnergyGradient) {
  EXPECT_LT(max_gradient_error<TypeParam>(area_term<double>()), kGradientTolerance);
}
TYPED_TEST(DpShapeGradientTest, SegmentSpringForceIsMinusEnergyGradient) {
  EXPECT_LT(max_gradient_error<TypeParam>(spring_term<double>()), kGradientTolerance);
}
TYPED_TEST(DpShapeGradientTest, LineTensionForceIsMinusEnergyGradient) {
  EXPECT_LT(max_gradient_error<TypeParam>(tension_term<double>()), kGradientTolerance);
}
TYPED_TEST(DpShapeGradientTest, BendingForceIsMinusEnergyGradient) {
  EXPECT_LT(max_gradient_error<TypeParam>(bending_term<double>()), kGradientTolerance);
}
TYPED_TEST(DpShapeGradientTest, GravityForceIsMinusEnergyGradient) {
  EXPECT_LT(max_gradient_error<TypeParam>(gravity_term<double>()), kGradientTolerance);
}
TYPED_TEST(DpShapeGradientTest, AllTermsTogetherForceIsMinusEnergyGradient) {
  EXPECT_LT(max_gradient_error<TypeParam>(area_term<double>(), spring_term<double>(), tension_term<double>(),
                                          bending_term<double>(), gravity_term<double>()),
            kGradientTolerance);
}

// ---- Energies against a host reference -----------------------------------------------------------

struct ReferenceEnergies {
  double area = 0, springs = 0, tension = 0, bending = 0, gravity = 0;
};

// Eqs. 1, 2 (γP) and 8 and U_g = −Σ M_i g·r_i, summed on the host in double from the stored data.
template <class Real, class Exec>
ReferenceEnergies reference_energies(const Scene<Real, Exec>& s) {
  const auto x = to_host(s.p.x);
  const auto m = to_host(s.p.mass);
  ReferenceEnergies e;
  for (int b = 0; b < s.polygons.num_bodies(); ++b) {
    const int n = s.polygons.num_vertices(b), begin = s.polygons.first_vertex(b);
    const double a0 = s.polygons.preferred_area(b), l0 = s.polygons.preferred_edge(b);
    double area = 0;
    std::vector<double> len(n), ux(n), uy(n);
    for (int k = 0; k < n; ++k) {
      const int i = begin + k, j = begin + (k + 1) % n;
      area += 0.5 * (double(x(i, 0)) * x(j, 1) - double(x(j, 0)) * x(i, 1));
      const double ex = double(x(j, 0)) - x(i, 0), ey = double(x(j, 1)) - x(i, 1);
      len[k] = norm(ex, ey);
      ux[k] = ex / len[k];
      uy[k] = ey / len[k];
      e.gravity -= m(i) * (kGx * x(i, 0) + kGy * x(i, 1));
    }
    e.area += 0.5 * kArea * (area - a0) * (area - a0);
    for (int k = 0; k < n; ++k) {
      const int k1 = (k + 1) % n;
      e.springs += 0.5 * kSpring * n * (len[k] - l0) * (len[k] - l0);
      e.tension += kTension * len[k];
      const double dx = ux[k] - ux[k1], dy = uy[k] - uy[k1];
      e.bending += kBend / (2.0 * n) * (dx * dx + dy * dy) / (l0 * l0);
    }
  }
  return e;
}

template <class T>
class DpShapeTest : public ::testing::Test {};
TYPED_TEST_SUITE(DpShapeTest, testing::BackendsAndPrecisions);

TYPED_TEST(DpShapeTest, EnergiesMatchHostReference) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  const auto s = make_scene<Real, Exec>(0.2, 1.05);
  const ReferenceEnergies ref = reference_energies(s);
  const double tol = 1e3 * testing::eps<Real>();
  EXPECT_NEAR(energy_of(s, area_term<Real>()), ref.area, tol * (1 + ref.area));
  EXPECT_NEAR(energy_of(s, spring_term<Real>()), ref.springs, tol * (1 + ref.springs));
  EXPECT_NEAR(energy_of(s, tension_term<Real>()), ref.tension, tol * (1 + ref.tension));
  EXPECT_NEAR(energy_of(s, bending_term<Real>()), ref.bending, tol * (1 + ref.bending));
  EXPECT_NEAR(energy_of(s, gravity_term<Real>()), ref.gravity, tol * (1 + std::abs(ref.gravity)));
  EXPECT_GT(ref.area, 1e-3);  // the scene is deformed enough for every term to matter
  EXPECT_GT(ref.springs, 1e-3);
  EXPECT_GT(ref.bending, 1e-3);
}

TYPED_TEST(DpShapeTest, EnergyOnlyPathEqualsSumOfTermEnergiesAndLeavesForces) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  const auto s = make_scene<Real, Exec>(0.2, 1.05);
  const double parts = energy_of(s, area_term<Real>()) + energy_of(s, spring_term<Real>()) +
                       energy_of(s, tension_term<Real>()) + energy_of(s, bending_term<Real>()) +
                       energy_of(s, gravity_term<Real>());
  Kokkos::deep_copy(s.p.f, Real(0.25));
  const double all = energy_of(s, area_term<Real>(), spring_term<Real>(), tension_term<Real>(), bending_term<Real>(),
                               gravity_term<Real>());
  EXPECT_NEAR(all, parts, 1e-12 * (1 + std::abs(parts)));
  const auto f = to_host(s.p.f);
  for (std::size_t i = 0; i < s.p.size(); ++i)
    for (int d = 0; d < 2; ++d) ASSERT_EQ(f(i, d), Real(0.25));
  const double with_forces = accumulate_shape_forces(s.polygons, s.state, s.p, area_term<Real>(), spring_term<Real>(),
                                                     tension_term<Real>(), bending_term<Real>(), gravity_term<Real>());
  EXPECT_DOUBLE_EQ(with_forces, all);
  EXPECT_EQ(energy_of(s), 0.0);  // no terms: nothing to do
}

TYPED_TEST(DpShapeTest, AccumulateAddsToExistingForcesAndSkipsFreeParticles) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  const auto s = make_scene<Real, Exec>(0.2, 1.05);
  compute_forces(s, area_term<Real>(), spring_term<Real>(), tension_term<Real>(), bending_term<Real>(),
                 gravity_term<Real>());
  const auto alone = to_host(s.p.f);
  Kokkos::deep_copy(s.p.f, Real(1.5));  // another term's contribution
  for (int pass = 0; pass < 2; ++pass)
    accumulate_shape_forces(s.polygons, s.state, s.p, area_term<Real>(), spring_term<Real>(), tension_term<Real>(),
                            bending_term<Real>(), gravity_term<Real>());
  const auto both = to_host(s.p.f);
  const int nv = s.polygons.num_vertices();
  for (int i = 0; i < nv; ++i)
    for (int d = 0; d < 2; ++d)
      EXPECT_NEAR(double(both(i, d)), 1.5 + 2.0 * alone(i, d),
                  10 * testing::eps<Real>() * (1.5 + 2.0 * std::abs(alone(i, d))));
  for (int i = nv; i < nv + kFreeParticles; ++i)
    for (int d = 0; d < 2; ++d) EXPECT_EQ(both(i, d), Real(1.5));
}

// ---- Symmetries -----------------------------------------------------------------------------------

// Shape terms (not gravity) are invariant under translations and rotations of a body: Σ_i F_i = 0
// and Σ_i (r_i − c) × F_i = 0 per body, to round-off of the force magnitudes.
template <class Real, class Exec, class... Terms>
void expect_no_net_force_or_torque(const Scene<Real, Exec>& s, const Terms&... terms) {
  compute_forces(s, terms...);
  const auto f = to_host(s.p.f);
  const auto x = to_host(s.p.x);
  for (int b = 0; b < s.polygons.num_bodies(); ++b) {
    const int n = s.polygons.num_vertices(b), begin = s.polygons.first_vertex(b);
    double c[2] = {0, 0};
    for (int i = begin; i < begin + n; ++i)
      for (int d = 0; d < 2; ++d) c[d] += double(x(i, d)) / n;
    double total[2] = {0, 0}, torque = 0, force_scale = 0, torque_scale = 0;
    for (int i = begin; i < begin + n; ++i) {
      const double rx = x(i, 0) - c[0], ry = x(i, 1) - c[1];
      total[0] += f(i, 0);
      total[1] += f(i, 1);
      torque += rx * f(i, 1) - ry * f(i, 0);
      force_scale += norm(f(i, 0), f(i, 1));
      torque_scale += norm(rx, ry) * norm(f(i, 0), f(i, 1));
    }
    const double tol = 64 * testing::eps<Real>();
    EXPECT_NEAR(total[0], 0.0, tol * force_scale) << "body " << b;
    EXPECT_NEAR(total[1], 0.0, tol * force_scale) << "body " << b;
    EXPECT_NEAR(torque, 0.0, tol * torque_scale) << "body " << b;
  }
}

TYPED_TEST(DpShapeTest, ShapeTermsExertNoNetForceOrTorquePerBody) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  const auto s = make_scene<Real, Exec>(0.2, 1.05);
  expect_no_net_force_or_torque(s, area_term<Real>());
  expect_no_net_force_or_torque(s, spring_term<Real>());
  expect_no_net_force_or_torque(s, tension_term<Real>());
  expect_no_net_force_or_torque(s, bending_term<Real>());
  expect_no_net_force_or_torque(s, area_term<Real>(), spring_term<Real>(), tension_term<Real>(), bending_term<Real>());
}

// Bitwise equal to the host's forces on host backends; within the FMA-contraction bound on a device
// (testing::agrees_with_host): per vertex about 2 N_v operations for its body's area and perimeter
// sums and 100 for its own terms, at the scale of the largest term (the regular-polygon force scales
// of the test below, with N_v = 33 and the smallest edge, plus Γ and gravity).
TYPED_TEST(DpShapeTest, ForcesAgreeWithTheHostOnEveryBackend) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  const auto a = make_scene<Real, Exec>(0.2, 1.05);
  const auto b = make_scene<Real, Kokkos::DefaultHostExecutionSpace>(0.2, 1.05);
  compute_forces(a, area_term<Real>(), spring_term<Real>(), tension_term<Real>(), bending_term<Real>(),
                 gravity_term<Real>());
  compute_forces(b, area_term<Real>(), spring_term<Real>(), tension_term<Real>(), bending_term<Real>(),
                 gravity_term<Real>());
  const auto fa = to_host(a.p.f);
  const auto fb = to_host(b.p.f);
  double scale = 0;
  int max_vertices = 0;
  for (std::size_t k = 0; k < kAreas.size(); ++k) {
    const int n = kVertexCounts[k];
    const double l0 = regular_polygon_edge(kAreas[k], n);
    scale = std::max(scale, kArea * kAreas[k] * l0 + kSpring * n * l0 + 2 * kBend / (n * l0 * l0 * l0) + kTension +
                                std::abs(kGx) + std::abs(kGy));
    max_vertices = std::max(max_vertices, n);
  }
  const int operations = 2 * max_vertices + 100;
  for (std::size_t i = 0; i < a.p.size(); ++i)
    for (int d = 0; d < 2; ++d)
      ASSERT_TRUE((testing::agrees_with_host<Exec, Real>(fa(i, d), fb(i, d), operations, scale)))
          << "vertex " << i << " axis " << d;
}

// ---- Regular polygons: analytic forces ------------------------------------------------------------

TYPED_TEST(DpShapeTest, RegularPolygonAtItsReferenceShapeFeelsNoAreaSpringOrBendingForce) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  const auto s = make_scene<Real, Exec>(0.0, 1.0);
  const double tol = 1e3 * testing::eps<Real>();
  for (int b = 0; b < s.polygons.num_bodies(); ++b) {
    const int n = s.polygons.num_vertices(b);
    const double l0 = s.polygons.preferred_edge(b);
    // Force scales of a unit relative deformation: k_a a0 l0 (area), k_l N_v l0 (springs),
    // k_b / (N_v l0²) · 2/l0 (bending).
    const double scale = kArea * kAreas[b] * l0 + kSpring * n * l0 + 2 * kBend / (n * l0 * l0 * l0);
    compute_forces(s, area_term<Real>(), spring_term<Real>(), bending_term<Real>());
    const auto f = to_host(s.p.f);
    for (int i = s.polygons.first_vertex(b); i < s.polygons.first_vertex(b) + n; ++i)
      EXPECT_LT(norm(f(i, 0), f(i, 1)), tol * scale) << "body " << b << " vertex " << i;
  }
  // The bending energy of a regular polygon: N corners of |û_j − û_{j+1}|² = 4 sin²(π/N), so
  // U_b = 2 k_b sin²(π/N) / l0² (a stationary point: the force vanishes above).
  double bending = 0;
  for (int b = 0; b < s.polygons.num_bodies(); ++b) {
    const double sn = std::sin(pi / s.polygons.num_vertices(b)), l0 = s.polygons.preferred_edge(b);
    bending += 2 * kBend * sn * sn / (l0 * l0);
  }
  EXPECT_NEAR(energy_of(s, bending_term<Real>()), bending, 1e2 * testing::eps<Real>() * bending);
  EXPECT_NEAR(energy_of(s, area_term<Real>(), spring_term<Real>()), 0.0, 1e-6);
}

TYPED_TEST(DpShapeTest, LineTensionOnRegularPolygonPointsInwardWithMagnitude2GammaSinPiOverN) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  const auto s = make_scene<Real, Exec>(0.0, 1.0);
  const double energy = compute_forces(s, tension_term<Real>());
  const auto f = to_host(s.p.f);
  const auto x = to_host(s.p.x);
  // Positions are rounded to Real: unit edge vectors carry that error over the edge length.
  const double tol = 1e3 * testing::eps<Real>();
  double perimeter = 0;
  for (int b = 0; b < s.polygons.num_bodies(); ++b) {
    const int n = s.polygons.num_vertices(b);
    const double magnitude = 2 * kTension * std::sin(pi / n);
    for (int i = s.polygons.first_vertex(b); i < s.polygons.first_vertex(b) + n; ++i) {
      const double rx = x(i, 0) - kCentres[b][0], ry = x(i, 1) - kCentres[b][1], r = norm(rx, ry);
      EXPECT_NEAR(f(i, 0), -magnitude * rx / r, tol * kTension) << "body " << b << " vertex " << i;
      EXPECT_NEAR(f(i, 1), -magnitude * ry / r, tol * kTension) << "body " << b << " vertex " << i;
    }
    perimeter += n * regular_polygon_edge(kAreas[b], n);
  }
  EXPECT_NEAR(energy, kTension * perimeter, tol * kTension * perimeter);
}

TYPED_TEST(DpShapeTest, RegularPolygonHasAreaA0EdgeL0AndShapeParameterNOverPiTanPiOverN) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  const auto s = make_scene<Real, Exec>(0.0, 1.0);
  const BodyObservables o = body_observables(s.state);
  const double tol = 1e2 * testing::eps<Real>();
  for (int b = 0; b < s.polygons.num_bodies(); ++b) {
    const int n = s.polygons.num_vertices(b);
    EXPECT_NEAR(o.area[b], kAreas[b], tol * kAreas[b]);
    EXPECT_NEAR(o.perimeter[b], n * regular_polygon_edge(kAreas[b], n), tol * o.perimeter[b]);
    const double expected = n / pi * std::tan(pi / n);
    EXPECT_NEAR(o.shape_parameter[b], expected, tol * expected);
    // l0 = sqrt(4 a0 N tan(π/N)) / N is the regular polygon's edge: (N l0)² / (4π a0) = 𝒜.
    const double l0 = regular_polygon_edge(kAreas[b], n);
    EXPECT_NEAR(n * n * l0 * l0 / (4 * pi * kAreas[b]), expected, 1e-14);
  }
  EXPECT_GT(o.shape_parameter[0], o.shape_parameter[1]);  // fewer vertices: further from a circle
  EXPECT_GT(o.shape_parameter[1], o.shape_parameter[2]);
  EXPECT_GT(o.shape_parameter[2], 1.0);
}

// ---- Body state of known shapes ---------------------------------------------------------------------

// A 2 × 2 square at (10, −5) and a 3-4-5 right triangle at the origin, with integer coordinates
// (exact in float), and a rotated copy of the square.
template <class Real, class Exec>
Scene<Real, Exec> known_shapes() {
  Scene<Real, Exec> s{Polygons<Real, Exec>::from_vertex_counts({4, 3, 4}, {Real(4), Real(6), Real(4)},
                                                               {Real(2), Real(4), Real(2)}),
                      BodyState<Real, Exec>(3), Particles<2, Real, Exec>(11)};
  assign_bodies(s.polygons, s.p);
  auto x = Kokkos::create_mirror_view(s.p.x);
  auto v = Kokkos::create_mirror_view(s.p.v);
  auto m = Kokkos::create_mirror_view(s.p.mass);
  const double pts[11][2] = {{9, -6}, {11, -6}, {11, -4}, {9, -4}, {0, 0}, {3, 0}, {0, 4}};
  for (int i = 0; i < 7; ++i) {
    x(i, 0) = Real(pts[i][0]);
    x(i, 1) = Real(pts[i][1]);
  }
  // Body 2: the square rotated by 0.3 rad about (−7, 2.5) — area 4 and perimeter 8 all the same.
  place_regular_polygon(s.polygons, 2, x, Vec<2, double>{{-7.0, 2.5}}, 0.3);
  for (int i = 0; i < 11; ++i) {
    m(i) = Real(i < 4 ? 1 + i : 1);  // square: masses 1, 2, 3, 4
    v(i, 0) = Real(i < 7 ? 0.5 : -1.0);
    v(i, 1) = Real(i < 4 ? i : 2.0);
  }
  Kokkos::deep_copy(s.p.x, x);
  Kokkos::deep_copy(s.p.v, v);
  Kokkos::deep_copy(s.p.mass, m);
  update_body_state(s.polygons, s.p, s.state);
  return s;
}

TYPED_TEST(DpShapeTest, AreaPerimeterAndCentreOfMassOfKnownShapes) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  const auto s = known_shapes<Real, Exec>();
  const BodyObservables o = body_observables(s.state);
  EXPECT_EQ(o.area[0], 4.0);
  EXPECT_EQ(o.perimeter[0], 8.0);
  EXPECT_EQ(o.area[1], 6.0);
  EXPECT_EQ(o.perimeter[1], 12.0);
  EXPECT_NEAR(o.shape_parameter[0], 4.0 / pi, 1e-15);
  EXPECT_NEAR(o.shape_parameter[1], 144.0 / (24.0 * pi), 1e-15);
  const double tol = 1e2 * testing::eps<Real>();
  EXPECT_NEAR(o.area[2], 4.0, tol * 4);
  EXPECT_NEAR(o.perimeter[2], 8.0, tol * 8);
  // Square with masses 1, 2, 3, 4 at (9,−6), (11,−6), (11,−4), (9,−4): Σ m r / 10.
  EXPECT_NEAR(o.com[0][0], (9 + 22 + 33 + 36) / 10.0, tol * 10);
  EXPECT_NEAR(o.com[0][1], (-6 - 12 - 12 - 16) / 10.0, tol * 10);
  EXPECT_NEAR(o.com[1][0], 1.0, tol);
  EXPECT_NEAR(o.com[1][1], 4.0 / 3.0, tol);
  EXPECT_NEAR(o.com[2][0], -7.0, tol * 10);
  EXPECT_NEAR(o.com[2][1], 2.5, tol * 10);
  // Velocities: square v = (0.5, i) with masses 1..4 → (0.5, (0·1 + 1·2 + 2·3 + 3·4)/10 = 2).
  EXPECT_NEAR(o.com_velocity[0][0], 0.5, tol);
  EXPECT_NEAR(o.com_velocity[0][1], 2.0, tol);
  EXPECT_NEAR(o.speed[0], std::hypot(0.5, 2.0), tol);
  EXPECT_NEAR(o.speed[2], std::hypot(1.0, 2.0), tol);
  const auto mass = to_host(s.state.mass);
  EXPECT_EQ(double(mass(0)), 10.0);
  EXPECT_EQ(double(mass(1)), 3.0);
}

// ---- Float against double ---------------------------------------------------------------------------

template <class ExecSpace>
class DpShapePrecisionTest : public ::testing::Test {};
TYPED_TEST_SUITE(DpShapePrecisionTest, GradientBackends);

// Same positions and masses (those of the float scene) in both precisions; all terms.
TYPED_TEST(DpShapePrecisionTest, FloatForcesAgreeWithDouble) {
  using Exec = TypeParam;
  const auto sf = make_scene<float, Exec>(0.2, 1.05);
  const auto sd = make_scene<double, Exec>(0.2, 1.05);
  const auto xf = to_host(sf.p.x);
  const auto mf = to_host(sf.p.mass);
  auto xd = Kokkos::create_mirror_view(sd.p.x);
  auto md = Kokkos::create_mirror_view(sd.p.mass);
  for (std::size_t i = 0; i < sf.p.size(); ++i) {
    md(i) = mf(i);
    for (int d = 0; d < 2; ++d) xd(i, d) = xf(i, d);
  }
  Kokkos::deep_copy(sd.p.x, xd);
  Kokkos::deep_copy(sd.p.mass, md);
  const double ef = compute_forces(sf, area_term<float>(), spring_term<float>(), tension_term<float>(),
                                   bending_term<float>(), gravity_term<float>());
  const double ed = compute_forces(sd, area_term<double>(), spring_term<double>(), tension_term<double>(),
                                   bending_term<double>(), gravity_term<double>());
  const auto ff = to_host(sf.p.f);
  const auto fd = to_host(sd.p.f);
  double max_rel = 0;
  for (int i = 0; i < sf.polygons.num_vertices(); ++i)
    for (int d = 0; d < 2; ++d)
      max_rel = std::max(max_rel, std::abs(ff(i, d) - fd(i, d)) / std::max(1.0, norm(fd(i, 0), fd(i, 1))));
  ::testing::Test::RecordProperty("max_relative_difference", scientific(max_rel));
  EXPECT_LT(max_rel, 1e-5);
  EXPECT_NEAR(ef, ed, 1e-5 * (1 + std::abs(ed)));
}

// ---- Topology -----------------------------------------------------------------------------------------

TEST(DpShapePolygons, NeighboursWrapAroundWithinTheBody) {
  // Body of 5 vertices starting at particle 10.
  EXPECT_EQ(next_vertex(10, 1, 10, 5), 11);
  EXPECT_EQ(next_vertex(14, 1, 10, 5), 10);
  EXPECT_EQ(next_vertex(13, 2, 10, 5), 10);
  EXPECT_EQ(next_vertex(14, 2, 10, 5), 11);
  EXPECT_EQ(prev_vertex(10, 1, 10, 5), 14);
  EXPECT_EQ(prev_vertex(11, 2, 10, 5), 14);
  EXPECT_EQ(prev_vertex(12, 2, 10, 5), 10);
  EXPECT_EQ(next_vertex(12, 5, 10, 5), 12);
  EXPECT_EQ(prev_vertex(12, 5, 10, 5), 12);
  // A triangle: two steps forward is one step back.
  for (int i = 0; i < 3; ++i) EXPECT_EQ(next_vertex(i, 2, 0, 3), prev_vertex(i, 1, 0, 3));
}

TEST(DpShapePolygons, LayoutAndBodyIds) {
  using Exec = Kokkos::DefaultExecutionSpace;
  const auto polys = Polygons<double, Exec>::from_vertex_counts({3, 5, 4}, {1.0, 2.0, 3.0}, {0.5, 0.6, 0.7});
  EXPECT_EQ(polys.num_bodies(), 3);
  EXPECT_EQ(polys.num_vertices(), 12);
  EXPECT_EQ(polys.first_vertex(1), 3);
  EXPECT_EQ(polys.num_vertices(1), 5);
  EXPECT_EQ(polys.preferred_area(2), 3.0);
  EXPECT_EQ(polys.preferred_edge(0), 0.5);
  Particles<2, double, Exec> p(14);
  assign_bodies(polys, p);
  const auto body = to_host(p.body);
  const int expected[14] = {0, 0, 0, 1, 1, 1, 1, 1, 2, 2, 2, 2, -1, -1};
  for (int i = 0; i < 14; ++i) EXPECT_EQ(body(i), expected[i]) << "particle " << i;
  const auto offset = to_host(polys.offset);
  EXPECT_EQ(offset(0), 0);
  EXPECT_EQ(offset(3), 12);

  const auto uniform = Polygons<float, Exec>::uniform(4, 16, 1.0f, 0.25f);
  EXPECT_EQ(uniform.num_vertices(), 64);
  EXPECT_EQ(uniform.first_vertex(3), 48);
  EXPECT_EQ(uniform.preferred_edge(3), 0.25f);
}

TEST(DpShapePolygons, RejectsInvalidBodies) {
  using P = Polygons<double, Kokkos::DefaultExecutionSpace>;
  EXPECT_THROW(P::uniform(0, 16, 1.0, 0.2), std::invalid_argument);
  EXPECT_THROW(P::uniform(2, 2, 1.0, 0.2), std::invalid_argument);
  EXPECT_THROW(P::uniform(2, 16, -1.0, 0.2), std::invalid_argument);
  EXPECT_THROW(P::uniform(2, 16, 1.0, 0.0), std::invalid_argument);
  EXPECT_THROW(P::from_vertex_counts({5, 6}, {1.0}, {0.2, 0.2}), std::invalid_argument);
  const auto polys = P::uniform(2, 16, 1.0, 0.2);
  Particles<2, double, Kokkos::DefaultExecutionSpace> too_few(20);
  EXPECT_THROW(assign_bodies(polys, too_few), std::invalid_argument);
  BodyState<double, Kokkos::DefaultExecutionSpace> wrong_state(3);
  Particles<2, double, Kokkos::DefaultExecutionSpace> p(32);
  EXPECT_THROW(update_body_state(polys, p, wrong_state), std::invalid_argument);
  EXPECT_THROW(accumulate_shape_forces(polys, wrong_state, p, LineTension<double>{1.0}), std::invalid_argument);
}

TEST(DpShapePolygons, RegularPolygonEdgeIsThePaperFormula) {
  // l0 = sqrt(4 a0 N_v tan(π/N_v)) / N_v (capillary-droplets §2.4); a square of area 4 has edge 2,
  // and large N_v tends to the circle's 2π r / N_v.
  EXPECT_NEAR(regular_polygon_edge(4.0, 4), 2.0, 1e-15);
  EXPECT_NEAR(regular_polygon_edge(std::sqrt(3.0) / 4.0, 3), 1.0, 1e-15);
  EXPECT_NEAR(regular_polygon_edge(pi, 100000) * 100000, 2 * pi, 1e-8);
}

}  // namespace
}  // namespace mesoflow::dp
