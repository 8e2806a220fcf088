// Uniform vertex drag of the DP hopper (hopper-flows eq. 11, kernels/dp/vertex_drag.hpp): each polygon
// vertex gets −(ζ/N_v) v with its own polygon's N_v, added to what is there; free particles after the
// polygons are untouched; the power is −Σ (ζ/N_v)|v|²; ζ = 0 changes nothing; bad ζ is refused.
#include "kernels/dp/vertex_drag.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

namespace mesoflow::dp {
namespace {

using Exec = Kokkos::DefaultExecutionSpace;

struct Polygons3 {
  // Bodies of 16, 8 and 24 vertices, then 5 free particles.
  std::vector<int> counts{16, 8, 24};
  Polygons<double, Exec> polygons =
      Polygons<double, Exec>::from_vertex_counts(counts, {0.5, 1.0, 0.8}, {0.16, 0.35, 0.13});
  Particles<2, double, Exec> p{std::size_t(48 + 5), "vertex_drag"};
  std::vector<double> v0, f0;

  Polygons3() {
    assign_bodies(polygons, p);
    std::mt19937 gen(5);
    std::normal_distribution<double> g(0, 1);
    auto v = Kokkos::create_mirror_view(p.v);
    auto f = Kokkos::create_mirror_view(p.f);
    for (std::size_t i = 0; i < p.size(); ++i)
      for (int d = 0; d < 2; ++d) {
        v(i, d) = g(gen);
        f(i, d) = g(gen);
        v0.push_back(v(i, d));
        f0.push_back(f(i, d));
      }
    Kokkos::deep_copy(p.v, v);
    Kokkos::deep_copy(p.f, f);
  }
  int vertex_count_of(std::size_t i) const { return i < 16 ? 16 : i < 24 ? 8 : i < 48 ? 24 : 0; }
};

TEST(VertexDrag, AddsMinusZetaOverNvTimesVelocity) {
  Polygons3 s;
  const double zeta = 0.7;
  accumulate_vertex_drag(zeta, s.polygons, s.p, s.p.v);
  const auto f = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.p.f);
  double power = 0, expected_power = 0, worst = 0;
  for (std::size_t i = 0; i < s.p.size(); ++i) {
    const int nv = s.vertex_count_of(i);
    for (int d = 0; d < 2; ++d) {
      const double v = s.v0[2 * i + d], added = f(i, d) - s.f0[2 * i + d];
      const double expected = nv > 0 ? -zeta / nv * v : 0.0;
      worst = std::max(worst, std::abs(added - expected));
      power += added * v;
      if (nv > 0) expected_power -= zeta / nv * v * v;
    }
  }
  EXPECT_LT(worst, 1e-15);
  EXPECT_LT(power, 0);
  EXPECT_NEAR(power, expected_power, 1e-14 * std::abs(expected_power));
}

TEST(VertexDrag, RigidTranslationFeelsMinusZetaVPerPolygon) {
  Polygons3 s;
  Kokkos::deep_copy(s.p.v, 1.5);
  Kokkos::deep_copy(s.p.f, 0.0);
  accumulate_vertex_drag(0.4, s.polygons, s.p, s.p.v);
  const auto f = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.p.f);
  for (int b = 0; b < 3; ++b) {
    double total = 0;
    for (int i = s.polygons.first_vertex(b); i < s.polygons.first_vertex(b) + s.polygons.num_vertices(b); ++i)
      total += f(i, 0);
    EXPECT_NEAR(total, -0.4 * 1.5, 1e-15) << "polygon " << b;
  }
}

TEST(VertexDrag, ZeroZetaIsANoOpAndBadZetaIsRefused) {
  Polygons3 s;
  accumulate_vertex_drag(0.0, s.polygons, s.p, s.p.v);
  const auto f = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.p.f);
  for (std::size_t i = 0; i < s.p.size(); ++i)
    for (int d = 0; d < 2; ++d) EXPECT_EQ(f(i, d), s.f0[2 * i + d]);
  EXPECT_THROW(accumulate_vertex_drag(-1.0, s.polygons, s.p, s.p.v), std::invalid_argument);
  EXPECT_THROW(accumulate_vertex_drag(double(NAN), s.polygons, s.p, s.p.v), std::invalid_argument);
  Particles<2, double, Exec> too_few(10);
  EXPECT_THROW(accumulate_vertex_drag(1.0, s.polygons, too_few, too_few.v), std::invalid_argument);
}

}  // namespace
}  // namespace mesoflow::dp
