// Uniform vertex drag of the DP hopper (hopper-flows eq. 11, kernels/dp/vertex_drag.hpp): each polygon
// vertex gets −(ζ/N_v) v with its own polygon's N_v, added to what is there; free particles after the
// polygons are untouched; the power is −Σ (ζ/N_v)|v|²; ζ = 0 changes nothing; bad ζ is refused.
// Serial and OpenMP, float and double: tolerances are multiples of the precision's round-off.
#include "kernels/dp/vertex_drag.hpp"
#include "test_types.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

namespace mesoflow::dp {
namespace {

template <class T>
class VertexDragTest : public ::testing::Test {};
TYPED_TEST_SUITE(VertexDragTest, mesoflow::testing::BackendsAndPrecisions);

template <class Real, class Exec>
struct Polygons3 {
  // Bodies of 16, 8 and 24 vertices, then 5 free particles.
  std::vector<int> counts{16, 8, 24};
  Polygons<Real, Exec> polygons =
      Polygons<Real, Exec>::from_vertex_counts(counts, {Real(0.5), Real(1.0), Real(0.8)}, {Real(0.16), Real(0.35), Real(0.13)});
  Particles<2, Real, Exec> p{std::size_t(48 + 5), "vertex_drag"};
  std::vector<double> v0, f0;  // the stored (Real) values

  Polygons3() {
    assign_bodies(polygons, p);
    std::mt19937 gen(5);
    std::normal_distribution<double> g(0, 1);
    auto v = Kokkos::create_mirror_view(p.v);
    auto f = Kokkos::create_mirror_view(p.f);
    for (std::size_t i = 0; i < p.size(); ++i)
      for (int d = 0; d < 2; ++d) {
        v(i, d) = Real(g(gen));
        f(i, d) = Real(g(gen));
        v0.push_back(double(v(i, d)));
        f0.push_back(double(f(i, d)));
      }
    Kokkos::deep_copy(p.v, v);
    Kokkos::deep_copy(p.f, f);
  }
  int vertex_count_of(std::size_t i) const { return i < 16 ? 16 : i < 24 ? 8 : i < 48 ? 24 : 0; }
};

TYPED_TEST(VertexDragTest, AddsMinusZetaOverNvTimesVelocity) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  Polygons3<Real, Exec> s;
  const Real zeta = Real(0.7);
  accumulate_vertex_drag(zeta, s.polygons, s.p, s.p.v);
  const auto f = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.p.f);
  double power = 0, expected_power = 0, worst = 0, scale = 0;
  for (std::size_t i = 0; i < s.p.size(); ++i) {
    const int nv = s.vertex_count_of(i);
    for (int d = 0; d < 2; ++d) {
      const double v = s.v0[2 * i + d], added = double(f(i, d)) - s.f0[2 * i + d];
      const double expected = nv > 0 ? -double(zeta) / nv * v : 0.0;
      worst = std::max(worst, std::abs(added - expected));
      scale = std::max(scale, std::abs(double(f(i, d))));
      power += added * v;
      if (nv > 0) expected_power -= double(zeta) / nv * v * v;
    }
  }
  // f + c v rounds once to the precision of f (c = −ζ/N_v itself to its own precision).
  EXPECT_LT(worst, 4 * testing::eps<Real>() * scale);
  EXPECT_LT(power, 0);
  EXPECT_NEAR(power, expected_power, 64 * testing::eps<Real>() * std::abs(expected_power));
}

TYPED_TEST(VertexDragTest, RigidTranslationFeelsMinusZetaVPerPolygon) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  Polygons3<Real, Exec> s;
  Kokkos::deep_copy(s.p.v, Real(1.5));
  Kokkos::deep_copy(s.p.f, Real(0));
  accumulate_vertex_drag(Real(0.4), s.polygons, s.p, s.p.v);
  const auto f = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.p.f);
  for (int b = 0; b < 3; ++b) {
    double total = 0;
    for (int i = s.polygons.first_vertex(b); i < s.polygons.first_vertex(b) + s.polygons.num_vertices(b); ++i)
      total += double(f(i, 0));
    // N_v equal terms −(ζ/N_v)·1.5, each rounded: relative error a few ε (0.4 itself is rounded in float).
    EXPECT_NEAR(total, -0.4 * 1.5, 8 * testing::eps<Real>() * 0.6) << "polygon " << b;
  }
}

TYPED_TEST(VertexDragTest, ZeroZetaIsANoOpAndBadZetaIsRefused) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  Polygons3<Real, Exec> s;
  accumulate_vertex_drag(Real(0), s.polygons, s.p, s.p.v);
  const auto f = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.p.f);
  for (std::size_t i = 0; i < s.p.size(); ++i)
    for (int d = 0; d < 2; ++d) EXPECT_EQ(double(f(i, d)), s.f0[2 * i + d]);
  EXPECT_THROW(accumulate_vertex_drag(Real(-1), s.polygons, s.p, s.p.v), std::invalid_argument);
  EXPECT_THROW(accumulate_vertex_drag(Real(NAN), s.polygons, s.p, s.p.v), std::invalid_argument);
  Particles<2, Real, Exec> too_few(10);
  EXPECT_THROW(accumulate_vertex_drag(Real(1), s.polygons, too_few, too_few.v), std::invalid_argument);
}

}  // namespace
}  // namespace mesoflow::dp
