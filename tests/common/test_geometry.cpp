// test_geometry.cpp — signed-distance walls and obstacles (kernels/common/geometry.hpp).
//
// Every primitive is checked at random points against the definition of a signed distance: the
// reconstruction x = point + distance·normal, a unit normal, a nearest point that lies on the surface, a
// distance equal to the brute-force minimum over a dense sampling of the surface, and a sign that agrees
// with an independent membership test. Then: finite-difference gradients (double), known values, the
// wedge's apex, face and inside regions, the orifice wedges, and the composite's choice of the nearest
// shape. Queries run in a parallel_for on each backend; the checks run on the host.
#include <gtest/gtest.h>

#include "kernels/common/geometry.hpp"
#include "test_types.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <functional>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace {

using mesoflow::Geometry;
using mesoflow::Shape;
using mesoflow::SurfacePoint;
using mesoflow::Vec;
using mesoflow::testing::eps;

template <class Config>
class GeometryTest : public ::testing::Test {};
TYPED_TEST_SUITE(GeometryTest, mesoflow::testing::BackendsAndPrecisions);

constexpr double kPi = 3.14159265358979323846;

// Test coordinates stay below ~10 in magnitude, most below 4: round-off in a query is a few eps times that.
template <class Real>
double tolerance() {
  return 100 * eps<Real>() * 4;
}

template <class Real>
Vec<2, Real> v2(double x, double y) {
  return Vec<2, Real>{{Real(x), Real(y)}};
}

template <class Real>
Vec<3, Real> v3(double x, double y, double z) {
  return Vec<3, Real>{{Real(x), Real(y), Real(z)}};
}

template <class To, int D, class From>
Vec<D, To> convert(const Vec<D, From>& v) {
  Vec<D, To> r;
  for (int d = 0; d < D; ++d) r[d] = To(v[d]);
  return r;
}

template <int D>
double norm(const Vec<D, double>& v) {
  return std::sqrt(mesoflow::norm2(v));
}

template <int D>
Vec<D, double> unit(const Vec<D, double>& v) {
  return (1 / norm(v)) * v;
}

template <int D>
std::string str(const Vec<D, double>& v) {
  std::ostringstream s;
  s.precision(17);
  s << "(";
  for (int d = 0; d < D; ++d) s << (d ? ", " : "") << v[d];
  s << ")";
  return s.str();
}

// Queries `surface` (anything with a KOKKOS_INLINE_FUNCTION query(x)) at every point, in a parallel_for
// on ExecSpace.
template <class ExecSpace, class Surface, int D, class Real>
std::vector<SurfacePoint<D, Real>> query_on_device(const Surface& surface,
                                                   const std::vector<Vec<D, Real>>& points) {
  using memory_space = typename ExecSpace::memory_space;
  const int n = static_cast<int>(points.size());
  Kokkos::View<Vec<D, Real>*, memory_space> x("mesoflow::test_geometry::x", n);
  Kokkos::View<SurfacePoint<D, Real>*, memory_space> result("mesoflow::test_geometry::result", n);
  const auto x_host = Kokkos::create_mirror_view(x);
  for (int i = 0; i < n; ++i) x_host(i) = points[i];
  Kokkos::deep_copy(x, x_host);
  Kokkos::parallel_for(
      "mesoflow::test_geometry::query", Kokkos::RangePolicy<ExecSpace>(0, n),
      KOKKOS_LAMBDA(const int i) { result(i) = surface.query(x(i)); });
  const auto result_host = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), result);
  return std::vector<SurfacePoint<D, Real>>(result_host.data(), result_host.data() + n);
}

// The composite of a Geometry's shapes, as a surface for query_on_device.
template <int D, class Real, class ShapeView>
struct NearestOf {
  ShapeView shapes;
  int n;

  KOKKOS_INLINE_FUNCTION SurfacePoint<D, Real> query(const Vec<D, Real>& x) const {
    return mesoflow::nearest_surface(shapes.data(), n, x);
  }
};

template <class ExecSpace, int D, class Real>
std::vector<SurfacePoint<D, Real>> query_scene_on_device(const std::vector<Shape<D, Real>>& shapes,
                                                         const std::vector<Vec<D, Real>>& points) {
  using scene = Geometry<D, Real, ExecSpace>;
  const scene geometry(shapes);
  const NearestOf<D, Real, typename scene::shape_view> nearest{geometry.shapes(), geometry.size()};
  return query_on_device<ExecSpace>(nearest, points);
}

// A dense sampling of a surface (in double): every surface point in the sampled window lies within
// `resolution` of a sample.
template <int D>
struct SurfaceSamples {
  double resolution;
  std::vector<Vec<D, double>> points;

  // start + s·direction for s in [0, length] (direction a unit vector).
  void add_segment(const Vec<D, double>& start, const Vec<D, double>& direction, double length) {
    const int n = static_cast<int>(std::ceil(length / resolution));
    for (int k = 0; k <= n; ++k) points.push_back(start + (length * k / n) * direction);
  }

  // The circle center + radius·(cos φ u + sin φ v) (u, v orthonormal).
  void add_circle(const Vec<D, double>& center, const Vec<D, double>& u, const Vec<D, double>& v,
                  double radius) {
    const int n = static_cast<int>(std::ceil(2 * kPi * radius / resolution));
    for (int k = 0; k < n; ++k) {
      const double phi = 2 * kPi * k / n;
      points.push_back(center + (radius * std::cos(phi)) * u + (radius * std::sin(phi)) * v);
    }
  }
};

SurfaceSamples<3> sample_plane(const Vec<3, double>& origin, const Vec<3, double>& normal, double half_width,
                               double resolution) {
  const Vec<3, double> n = unit(normal);
  const Vec<3, double> t1 = unit(mesoflow::geometry_detail::any_perpendicular(n));
  const Vec<3, double> t2 = mesoflow::geometry_detail::cross(n, t1);
  SurfaceSamples<3> surface{resolution, {}};
  const int steps = static_cast<int>(std::ceil(2 * half_width / resolution));
  for (int k = 0; k <= steps; ++k)
    surface.add_segment(origin + (-half_width + 2 * half_width * k / steps) * t1 + (-half_width) * t2, t2,
                        2 * half_width);
  return surface;
}

SurfaceSamples<3> sample_sphere(const Vec<3, double>& center, double radius, double resolution) {
  SurfaceSamples<3> surface{resolution, {}};
  const int rings = static_cast<int>(std::ceil(kPi * radius / resolution));
  for (int k = 0; k <= rings; ++k) {
    const double theta = kPi * k / rings;
    const double ring_radius = radius * std::sin(theta);
    const Vec<3, double> ring_center = center + v3<double>(0, 0, radius * std::cos(theta));
    if (ring_radius < 0.5 * resolution)
      surface.points.push_back(ring_center);
    else
      surface.add_circle(ring_center, v3<double>(1, 0, 0), v3<double>(0, 1, 0), ring_radius);
  }
  return surface;
}

SurfaceSamples<3> sample_cylinder(const Vec<3, double>& origin, const Vec<3, double>& axis, double radius,
                                  double half_length, double resolution) {
  const Vec<3, double> k = unit(axis);
  const Vec<3, double> u = mesoflow::geometry_detail::any_perpendicular(k);
  const Vec<3, double> v = mesoflow::geometry_detail::cross(k, u);
  SurfaceSamples<3> surface{resolution, {}};
  const int steps = static_cast<int>(std::ceil(2 * half_length / resolution));
  for (int s = 0; s <= steps; ++s)
    surface.add_circle(origin + (-half_length + 2 * half_length * s / steps) * k, u, v, radius);
  return surface;
}

// 200 uniform points in [−2.5, 2.5]^D and 100 within 0.01 (per axis) of surface samples in that box.
template <int D, class Real>
std::vector<Vec<D, Real>> test_points(const SurfaceSamples<D>& surface, unsigned seed) {
  constexpr double half_box = 2.5;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> in_box(-half_box, half_box);
  std::uniform_real_distribution<double> offset(-0.01, 0.01);
  std::vector<Vec<D, Real>> points;
  for (int i = 0; i < 200; ++i) {
    Vec<D, double> x;
    for (int d = 0; d < D; ++d) x[d] = in_box(rng);
    points.push_back(convert<Real>(x));
  }
  std::vector<Vec<D, double>> nearby;
  for (const auto& s : surface.points) {
    bool inside = true;
    for (int d = 0; d < D; ++d) inside = inside && std::fabs(s[d]) <= half_box;
    if (inside) nearby.push_back(s);
  }
  if (nearby.empty()) return points;
  std::uniform_int_distribution<std::size_t> pick(0, nearby.size() - 1);
  for (int i = 0; i < 100; ++i) {
    Vec<D, double> x = nearby[pick(rng)];
    for (int d = 0; d < D; ++d) x[d] += offset(rng);
    points.push_back(convert<Real>(x));
  }
  return points;
}

// Checks a shape at random points against the definition of its signed distance; `in_solid` is an
// independent membership test of the solid side.
template <class ExecSpace, int D, class Real, class InSolid>
void expect_signed_distance(const Shape<D, Real>& shape, const SurfaceSamples<D>& surface,
                            const InSolid& in_solid, unsigned seed) {
  const double tol = tolerance<Real>();
  const std::vector<Vec<D, Real>> points = test_points<D, Real>(surface, seed);
  const auto result = query_on_device<ExecSpace>(shape, points);
  std::vector<Vec<D, Real>> nearest;
  for (const auto& s : result) nearest.push_back(s.point);
  const auto at_nearest = query_on_device<ExecSpace>(shape, nearest);

  int signs_checked = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec<D, double> x = convert<double>(points[i]);
    SCOPED_TRACE("x = " + str(x));
    const double d = result[i].distance;
    const Vec<D, double> p = convert<double>(result[i].point);
    const Vec<D, double> n = convert<double>(result[i].normal);
    EXPECT_NEAR(norm(x - (p + d * n)), 0.0, tol);
    EXPECT_NEAR(norm(n), 1.0, tol);
    EXPECT_NEAR(at_nearest[i].distance, 0.0, tol) << "nearest point " << str(p) << " is off the surface";

    double brute2 = std::numeric_limits<double>::max();
    for (const auto& s : surface.points) brute2 = std::min(brute2, mesoflow::norm2(x - s));
    const double brute = std::sqrt(brute2);
    EXPECT_LE(std::fabs(d), brute + tol);
    EXPECT_LE(brute, std::fabs(d) + surface.resolution + tol);
    if (brute > surface.resolution + tol) {
      EXPECT_EQ(d < 0, in_solid(x)) << "distance " << d;
      ++signs_checked;
    }
  }
  EXPECT_GT(signs_checked, 100);
}

// One query with its known answer.
template <int D>
struct Known {
  Vec<D, double> x;
  double distance;
  Vec<D, double> point;
  Vec<D, double> normal;
};

template <class ExecSpace, int D, class Real>
void expect_known(const Shape<D, Real>& shape, const std::vector<Known<D>>& cases) {
  const double tol = tolerance<Real>();
  std::vector<Vec<D, Real>> points;
  for (const auto& c : cases) points.push_back(convert<Real>(c.x));
  const auto result = query_on_device<ExecSpace>(shape, points);
  for (std::size_t i = 0; i < cases.size(); ++i) {
    SCOPED_TRACE("x = " + str(cases[i].x));
    EXPECT_NEAR(result[i].distance, cases[i].distance, tol);
    EXPECT_NEAR(norm(convert<double>(result[i].point) - cases[i].point), 0.0, tol)
        << "point " << str(convert<double>(result[i].point));
    EXPECT_NEAR(norm(convert<double>(result[i].normal) - cases[i].normal), 0.0, tol)
        << "normal " << str(convert<double>(result[i].normal));
  }
}

double cross2(const Vec<2, double>& a, const Vec<2, double>& b) { return a[0] * b[1] - a[1] * b[0]; }

// x strictly inside the convex cone spanned by the rays from apex along edge_a and edge_b.
bool in_wedge(const Vec<2, double>& x, const Vec<2, double>& apex, const Vec<2, double>& edge_a,
              const Vec<2, double>& edge_b) {
  const Vec<2, double> r = x - apex;
  const double turn = cross2(edge_a, edge_b) > 0 ? 1.0 : -1.0;
  return turn * cross2(edge_a, r) > 0 && turn * cross2(r, edge_b) > 0;
}

Vec<2, double> direction(double degrees) {
  return v2<double>(std::cos(degrees * kPi / 180), std::sin(degrees * kPi / 180));
}

TYPED_TEST(GeometryTest, HalfSpaceMatchesBruteForce) {
  using Exec = typename TypeParam::exec;
  using Real = typename TypeParam::real;

  const Vec<2, double> origin2 = v2<double>(0.3, -0.2), normal2 = unit(v2<double>(1, 2));
  SurfaceSamples<2> line{0.005, {}};
  line.add_segment(origin2 + (-8.0) * mesoflow::geometry_detail::quarter_turn(normal2),
                   mesoflow::geometry_detail::quarter_turn(normal2), 16);
  expect_signed_distance<Exec>(
      Shape<2, Real>::half_space(convert<Real>(origin2), v2<Real>(1, 2)), line,
      [&](const Vec<2, double>& x) { return mesoflow::dot(x - origin2, normal2) < 0; }, 11);

  const Vec<3, double> origin3 = v3<double>(0.1, 0.2, -0.3), normal3 = unit(v3<double>(1, -2, 2));
  expect_signed_distance<Exec>(
      Shape<3, Real>::half_space(convert<Real>(origin3), v3<Real>(1, -2, 2)),
      sample_plane(origin3, normal3, 6.0, 0.04),
      [&](const Vec<3, double>& x) { return mesoflow::dot(x - origin3, normal3) < 0; }, 12);
}

TYPED_TEST(GeometryTest, SegmentMatchesBruteForce) {
  using Exec = typename TypeParam::exec;
  using Real = typename TypeParam::real;
  const Vec<2, double> a = v2<double>(-1.0, -0.5), b = v2<double>(1.2, 0.7);
  SurfaceSamples<2> surface{0.002, {}};
  surface.add_segment(a, unit(b - a), norm(b - a));
  const Vec<2, double> left = mesoflow::geometry_detail::quarter_turn(b - a);

  expect_signed_distance<Exec>(
      Shape<2, Real>::segment(convert<Real>(a), convert<Real>(b)), surface,
      [&](const Vec<2, double>& x) { return mesoflow::dot(x - a, left) < 0; }, 21);
  expect_signed_distance<Exec>(
      Shape<2, Real>::segment(convert<Real>(a), convert<Real>(b), true), surface,
      [&](const Vec<2, double>& x) { return mesoflow::dot(x - a, left) > 0; }, 22);
}

TYPED_TEST(GeometryTest, WedgeMatchesBruteForce) {
  using Exec = typename TypeParam::exec;
  using Real = typename TypeParam::real;
  struct Case {
    Vec<2, double> apex;
    double angle_a, angle_b;  // directions of the edges, in degrees
    bool inverted;
  };
  const Case cases[] = {{v2<double>(0.2, -0.3), 20, 80, false},     // acute, 60°
                        {v2<double>(-0.1, 0.4), 335, 200, false},   // obtuse, 135°, edges clockwise
                        {v2<double>(0.3, 0.1), 250, 295, true},     // 45°, fluid inside
                        {v2<double>(-0.4, -0.2), 10, 189, false}};  // 179°, nearly a half-plane
  unsigned seed = 31;
  for (const Case& c : cases) {
    const Vec<2, double> edge_a = direction(c.angle_a), edge_b = direction(c.angle_b);
    SurfaceSamples<2> surface{0.002, {}};
    surface.add_segment(c.apex, edge_a, 10);
    surface.add_segment(c.apex, edge_b, 10);
    SCOPED_TRACE("wedge " + std::to_string(c.angle_a) + " to " + std::to_string(c.angle_b) + " degrees");
    expect_signed_distance<Exec>(
        Shape<2, Real>::wedge(convert<Real>(c.apex), convert<Real>(edge_a), convert<Real>(edge_b),
                              c.inverted),
        surface, [&](const Vec<2, double>& x) { return in_wedge(x, c.apex, edge_a, edge_b) != c.inverted; },
        seed++);
  }
}

TYPED_TEST(GeometryTest, DiskMatchesBruteForce) {
  using Exec = typename TypeParam::exec;
  using Real = typename TypeParam::real;
  const Vec<2, double> center = v2<double>(0.1, 0.2);
  for (const bool inverted : {false, true}) {
    const double radius = inverted ? 1.5 : 0.8;
    SurfaceSamples<2> surface{0.002, {}};
    surface.add_circle(center, v2<double>(1, 0), v2<double>(0, 1), radius);
    SCOPED_TRACE(inverted ? "container" : "obstacle");
    expect_signed_distance<Exec>(
        Shape<2, Real>::disk(convert<Real>(center), Real(radius), inverted), surface,
        [&](const Vec<2, double>& x) { return (norm(x - center) < radius) != inverted; }, 41 + inverted);
  }
}

TYPED_TEST(GeometryTest, SphereMatchesBruteForce) {
  using Exec = typename TypeParam::exec;
  using Real = typename TypeParam::real;
  const Vec<3, double> center = v3<double>(0.1, -0.2, 0.3);
  for (const bool inverted : {false, true}) {
    const double radius = inverted ? 1.6 : 1.0;
    SCOPED_TRACE(inverted ? "container" : "obstacle");
    expect_signed_distance<Exec>(
        Shape<3, Real>::sphere(convert<Real>(center), Real(radius), inverted),
        sample_sphere(center, radius, 0.02),
        [&](const Vec<3, double>& x) { return (norm(x - center) < radius) != inverted; }, 51 + inverted);
  }
}

TYPED_TEST(GeometryTest, CylinderMatchesBruteForce) {
  using Exec = typename TypeParam::exec;
  using Real = typename TypeParam::real;
  const Vec<3, double> origin = v3<double>(0.2, -0.1, 0.3), axis = v3<double>(1, 1, 0.5);
  const Vec<3, double> k = unit(axis);
  for (const bool inverted : {false, true}) {
    const double radius = inverted ? 1.3 : 0.7;
    const auto radial = [&](const Vec<3, double>& x) {
      const Vec<3, double> r = x - origin;
      return norm(r - mesoflow::dot(r, k) * k);
    };
    SCOPED_TRACE(inverted ? "pipe" : "pillar");
    expect_signed_distance<Exec>(
        Shape<3, Real>::cylinder(convert<Real>(origin), convert<Real>(axis), Real(radius), inverted),
        sample_cylinder(origin, axis, radius, 6.0, 0.03),
        [&](const Vec<3, double>& x) { return (radial(x) < radius) != inverted; }, 61 + inverted);
  }
}

// A shape and the set where its distance is smooth enough for central differences: farther than
// kSmoothMargin (much wider than the difference step) from medial axes, from the boundaries of a corner's
// region and from a segment's back-side jump.
constexpr double kSmoothMargin = 1e-3;

bool clear_of_kink(double signed_gap) { return std::fabs(signed_gap) > kSmoothMargin; }

template <int D>
struct SmoothCase {
  std::string name;
  Shape<D, double> shape;
  std::function<bool(const Vec<D, double>&)> smooth_at;
};

template <class ExecSpace, int D>
void expect_gradient_is_normal(const std::vector<SmoothCase<D>>& cases, unsigned seed) {
  constexpr double step = 1e-6;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> in_box(-2.5, 2.5);
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    std::vector<Vec<D, double>> points, stencil;
    while (points.size() < 200) {
      Vec<D, double> x;
      for (int d = 0; d < D; ++d) x[d] = in_box(rng);
      if (!c.smooth_at(x)) continue;
      points.push_back(x);
      for (int d = 0; d < D; ++d)
        for (const double sign : {1.0, -1.0}) {
          Vec<D, double> y = x;
          y[d] += sign * step;
          stencil.push_back(y);
        }
    }
    const auto at_points = query_on_device<ExecSpace>(c.shape, points);
    const auto at_stencil = query_on_device<ExecSpace>(c.shape, stencil);
    for (std::size_t i = 0; i < points.size(); ++i) {
      Vec<D, double> gradient;
      for (int d = 0; d < D; ++d)
        gradient[d] = (at_stencil[2 * D * i + 2 * d].distance - at_stencil[2 * D * i + 2 * d + 1].distance) /
                      (2 * step);
      EXPECT_LE(norm(gradient - at_points[i].normal), 1e-6)
          << "x = " << str(points[i]) << ", gradient " << str(gradient) << ", normal "
          << str(at_points[i].normal);
    }
  }
}

// Finite-difference gradients need double precision: this suite runs on every backend in double.
template <class ExecSpace>
class GeometryGradientTest : public ::testing::Test {};
#if defined(KOKKOS_ENABLE_OPENMP) && defined(KOKKOS_ENABLE_SERIAL)
using GradientBackends = ::testing::Types<Kokkos::Serial, Kokkos::OpenMP>;
#else
using GradientBackends = ::testing::Types<Kokkos::DefaultExecutionSpace>;
#endif
TYPED_TEST_SUITE(GeometryGradientTest, GradientBackends);

TYPED_TEST(GeometryGradientTest, GradientIsNormal) {
  using Exec = TypeParam;
  {
    using mesoflow::dot;
    const auto everywhere = [](const auto&) { return true; };
    const auto off_center = [](const auto& center) {
      return [center](const auto& x) { return clear_of_kink(norm(x - center)); };
    };

    const Vec<2, double> a = v2<double>(-1.0, -0.5), b = v2<double>(1.2, 0.7);
    const auto segment = mesoflow::Segment<double>::between(a, b);
    const auto segment_smooth = [segment](const Vec<2, double>& x) {
      const double ab = norm(segment.b - segment.a);
      const double along = dot(x - segment.a, segment.b - segment.a) / ab;
      return clear_of_kink(dot(x - segment.a, segment.normal)) && clear_of_kink(along) &&
             clear_of_kink(along - ab);
    };
    const auto wedge_smooth = [](const mesoflow::Wedge<double>& w) {
      return [w](const Vec<2, double>& x) {
        const Vec<2, double> r = x - w.apex;
        const double h0 = dot(r, w.normal[0]), h1 = dot(r, w.normal[1]);
        return clear_of_kink(h0) && clear_of_kink(h1) && clear_of_kink(h0 - h1) &&
               clear_of_kink(dot(r, w.edge[0])) && clear_of_kink(dot(r, w.edge[1]));
      };
    };
    const Vec<2, double> apex = v2<double>(0.2, -0.3), disk_center = v2<double>(0.1, 0.2);
    const auto acute = mesoflow::Wedge<double>::from_edges(apex, direction(20), direction(80));
    const auto obtuse = mesoflow::Wedge<double>::from_edges(apex, direction(335), direction(200));
    expect_gradient_is_normal<Exec, 2>(
        {{"half-plane", Shape<2, double>::half_space(v2<double>(0.3, -0.2), v2<double>(1, 2)), everywhere},
         {"segment", Shape<2, double>::segment(a, b), segment_smooth},
         {"flipped segment", Shape<2, double>::segment(a, b, true), segment_smooth},
         {"acute wedge", Shape<2, double>::wedge(apex, direction(20), direction(80)), wedge_smooth(acute)},
         {"obtuse wedge", Shape<2, double>::wedge(apex, direction(335), direction(200)),
          wedge_smooth(obtuse)},
         {"inverted wedge", Shape<2, double>::wedge(apex, direction(20), direction(80), true),
          wedge_smooth(acute)},
         {"disk", Shape<2, double>::disk(disk_center, 0.8), off_center(disk_center)},
         {"container disk", Shape<2, double>::disk(disk_center, 1.5, true), off_center(disk_center)}},
        71);

    const Vec<3, double> center = v3<double>(0.1, -0.2, 0.3), origin = v3<double>(0.2, -0.1, 0.3);
    const Vec<3, double> axis = unit(v3<double>(1, 1, 0.5));
    const auto off_axis = [origin, axis](const Vec<3, double>& x) {
      const Vec<3, double> r = x - origin;
      return clear_of_kink(norm(r - dot(r, axis) * axis));
    };
    expect_gradient_is_normal<Exec, 3>(
        {{"half-space", Shape<3, double>::half_space(origin, v3<double>(1, -2, 2)), everywhere},
         {"sphere", Shape<3, double>::sphere(center, 1.0), off_center(center)},
         {"container sphere", Shape<3, double>::sphere(center, 1.6, true), off_center(center)},
         {"pillar", Shape<3, double>::cylinder(origin, axis, 0.7), off_axis},
         {"pipe", Shape<3, double>::cylinder(origin, axis, 1.3, true), off_axis}},
        72);
  }
}

TYPED_TEST(GeometryTest, KnownSignsAndDistances) {
  using Exec = typename TypeParam::exec;
  using Real = typename TypeParam::real;
  using S2 = Shape<2, Real>;
  using S3 = Shape<3, Real>;
  const double r2 = std::sqrt(2.0);
  const auto p2 = v2<double>;
  const auto p3 = v3<double>;

  // Floor y = 1, fluid above.
  expect_known<Exec>(S2::half_space(v2<Real>(0, 1), v2<Real>(0, 2)),
                     std::vector<Known<2>>{{p2(3, 2.5), 1.5, p2(3, 1), p2(0, 1)},
                                           {p2(-1, 0.25), -0.75, p2(-1, 1), p2(0, 1)}});
  // Ceiling z = 0, fluid below.
  expect_known<Exec>(S3::half_space(v3<Real>(0, 0, 0), v3<Real>(0, 0, -1)),
                     std::vector<Known<3>>{{p3(1, 2, -3), 3, p3(1, 2, 0), p3(0, 0, -1)},
                                           {p3(0, 0, 0.5), -0.5, p3(0, 0, 0), p3(0, 0, -1)}});
  // Segment (0,0)–(2,0): fluid on the left (above); beyond the ends the normal points from the end to x
  // (fluid side) or from x to the end (back side).
  expect_known<Exec>(S2::segment(v2<Real>(0, 0), v2<Real>(2, 0)),
                     std::vector<Known<2>>{{p2(1, 0.5), 0.5, p2(1, 0), p2(0, 1)},
                                           {p2(1, -0.25), -0.25, p2(1, 0), p2(0, 1)},
                                           {p2(3, 1), r2, p2(2, 0), p2(1 / r2, 1 / r2)},
                                           {p2(-1, -1), -r2, p2(0, 0), p2(1 / r2, 1 / r2)},
                                           {p2(-2, 0), 2, p2(0, 0), p2(-1, 0)},
                                           {p2(1.5, 0), 0, p2(1.5, 0), p2(0, 1)}});
  expect_known<Exec>(S2::segment(v2<Real>(0, 0), v2<Real>(2, 0), true),
                     std::vector<Known<2>>{{p2(1, 0.5), -0.5, p2(1, 0), p2(0, -1)},
                                           {p2(3, -1), r2, p2(2, 0), p2(1 / r2, -1 / r2)}});
  // Obstacle disk and circular container.
  expect_known<Exec>(S2::disk(v2<Real>(1, 1), Real(0.5)),
                     std::vector<Known<2>>{{p2(3, 1), 1.5, p2(1.5, 1), p2(1, 0)},
                                           {p2(1, 1.25), -0.25, p2(1, 1.5), p2(0, 1)},
                                           {p2(1, 1), -0.5, p2(1.5, 1), p2(1, 0)}});
  expect_known<Exec>(
      S2::disk(v2<Real>(0, 0), Real(2), true),
      std::vector<Known<2>>{{p2(1, 0), 1, p2(2, 0), p2(-1, 0)}, {p2(0, 3), -1, p2(0, 2), p2(0, -1)}});
  expect_known<Exec>(S3::sphere(v3<Real>(0, 0, 1), Real(1)),
                     std::vector<Known<3>>{{p3(0, 0, 3), 1, p3(0, 0, 2), p3(0, 0, 1)},
                                           {p3(0.5, 0, 1), -0.5, p3(1, 0, 1), p3(1, 0, 0)}});
  expect_known<Exec>(S3::sphere(v3<Real>(0, 0, 0), Real(3), true),
                     std::vector<Known<3>>{{p3(0, 2, 0), 1, p3(0, 3, 0), p3(0, -1, 0)},
                                           {p3(0, 0, -4), -1, p3(0, 0, -3), p3(0, 0, 1)}});
  // Pillar and pipe along z.
  expect_known<Exec>(S3::cylinder(v3<Real>(0, 0, 0), v3<Real>(0, 0, 5), Real(1)),
                     std::vector<Known<3>>{{p3(3, 0, 7), 2, p3(1, 0, 7), p3(1, 0, 0)},
                                           {p3(0, 0.5, -4), -0.5, p3(0, 1, -4), p3(0, 1, 0)}});
  expect_known<Exec>(S3::cylinder(v3<Real>(0, 0, 0), v3<Real>(0, 0, 1), Real(2), true),
                     std::vector<Known<3>>{{p3(0, 1, 10), 1, p3(0, 2, 10), p3(0, -1, 0)},
                                           {p3(3, 0, 0), -1, p3(2, 0, 0), p3(-1, 0, 0)}});

  // On the axis the normal is some unit vector perpendicular to it, and x = point + distance·normal.
  const auto on_axis = query_on_device<Exec>(S3::cylinder(v3<Real>(1, 2, 3), v3<Real>(1, 1, 1), Real(0.5)),
                                             std::vector<Vec<3, Real>>{v3<Real>(2, 3, 4)});
  const double tol = tolerance<Real>();
  const Vec<3, double> n = convert<double>(on_axis[0].normal);
  EXPECT_NEAR(on_axis[0].distance, -0.5, tol);
  EXPECT_NEAR(norm(n), 1.0, tol);
  EXPECT_NEAR(mesoflow::dot(n, v3<double>(1, 1, 1)), 0.0, tol);
  EXPECT_NEAR(norm(convert<double>(on_axis[0].point) + (-0.5) * n - p3(2, 3, 4)), 0.0, tol);
}

TYPED_TEST(GeometryTest, WedgeApexFacesAndInside) {
  using Exec = typename TypeParam::exec;
  using Real = typename TypeParam::real;
  using S2 = Shape<2, Real>;
  const double r2 = std::sqrt(2.0), r5 = std::sqrt(5.0), r125 = std::sqrt(1.25);
  const auto p2 = v2<double>;
  const Vec<2, double> n0 = p2(0, -1), n1 = p2(-1 / r2, 1 / r2);

  // 45° wedge: apex at the origin, faces along +x (outward normal −y) and along the diagonal.
  const S2 acute = S2::wedge(v2<Real>(0, 0), v2<Real>(1, 0), v2<Real>(1, 1));
  expect_known<Exec>(acute,
                     std::vector<Known<2>>{// inside, nearest to face 0 / face 1
                                           {p2(2, 0.5), -0.5, p2(2, 0), n0},
                                           {p2(3, 2.5), -0.5 / r2, p2(2.75, 2.75), n1},
                                           // on the faces and at the apex
                                           {p2(1.5, 0), 0, p2(1.5, 0), n0},
                                           {p2(1, 1), 0, p2(1, 1), n1},
                                           {p2(0, 0), 0, p2(0, 0), n0},
                                           // outside, facing a face
                                           {p2(3, -2), 2, p2(3, 0), n0},
                                           {p2(1, 3), r2, p2(2, 2), n1},
                                           // outside, beyond face 1 but on the solid side of face 0's line
                                           {p2(5, 6), 1 / r2, p2(5.5, 5.5), n1},
                                           // in the apex's Voronoi region: below-left and above-left
                                           {p2(-1, -0.5), r125, p2(0, 0), p2(-1 / r125, -0.5 / r125)},
                                           {p2(-1, 0.5), r125, p2(0, 0), p2(-1 / r125, 0.5 / r125)},
                                           // near the apex: face 0 region, apex region, inside
                                           {p2(1e-3, -1e-3), 1e-3, p2(1e-3, 0), n0},
                                           {p2(-1e-3, -2e-3), r5 * 1e-3, p2(0, 0), p2(-1 / r5, -2 / r5)},
                                           {p2(1e-3, 2e-4), -2e-4, p2(1e-3, 0), n0}});

  // On the boundary between a face's region and the apex's region both answers coincide.
  expect_known<Exec>(acute,
                     std::vector<Known<2>>{{p2(0, -1), 1, p2(0, 0), n0}, {p2(-1, 1), r2, p2(0, 0), n1}});

  // The same wedge with the fluid inside.
  expect_known<Exec>(S2::wedge(v2<Real>(0, 0), v2<Real>(1, 0), v2<Real>(1, 1), true),
                     std::vector<Known<2>>{{p2(2, 0.5), 0.5, p2(2, 0), p2(0, 1)},
                                           {p2(-1, -0.5), -r125, p2(0, 0), p2(1 / r125, 0.5 / r125)}});

  // 135° wedge given with its edges clockwise: faces along +x and along (−1, 1).
  const Vec<2, double> m1 = p2(-1 / r2, -1 / r2);
  expect_known<Exec>(S2::wedge(v2<Real>(0, 0), v2<Real>(-1, 1), v2<Real>(1, 0)),
                     std::vector<Known<2>>{{p2(-2, -0.5), 2.5 / r2, p2(-0.75, 0.75), m1},
                                           {p2(0.5, 2), -2.5 / r2, p2(-0.75, 0.75), m1},
                                           {p2(0.5, 0.2), -0.2, p2(0.5, 0), n0},
                                           {p2(-1, -1), r2, p2(0, 0), m1},
                                           {p2(2, -1), 1, p2(2, 0), n0}});

  // On the inside bisector (a medial axis) either face is a valid answer.
  const double half = 22.5 * kPi / 180;
  const auto on_bisector = query_on_device<Exec>(
      acute, std::vector<Vec<2, Real>>{v2<Real>(2 * std::cos(half), 2 * std::sin(half))});
  const double tol = tolerance<Real>();
  const auto& s = on_bisector[0];
  EXPECT_NEAR(s.distance, -2 * std::sin(half), tol);
  EXPECT_NEAR(norm(convert<double>(s.point) + double(s.distance) * convert<double>(s.normal) -
                   p2(2 * std::cos(half), 2 * std::sin(half))),
              0.0, tol);
}

TYPED_TEST(GeometryTest, OrificeWedges) {
  using Exec = typename TypeParam::exec;
  using Real = typename TypeParam::real;
  const double tol = tolerance<Real>();
  const auto p2 = v2<double>;

  for (const double degrees : {45.0, 60.0}) {
    SCOPED_TRACE("wall angle " + std::to_string(degrees));
    const double angle = degrees * kPi / 180, s = std::sin(angle), c = std::cos(angle);
    const auto wedges = mesoflow::orifice_wedges(Real(0.6), Real(1), Real(2), Real(angle));
    const std::vector<Shape<2, Real>> scene(wedges.begin(), wedges.end());
    const Vec<2, double> left_apex = p2(0.7, 2), right_apex = p2(1.3, 2);
    const Vec<2, double> up_left = p2(-s, c), up_right = p2(s, c);      // converging faces, from the apexes
    const Vec<2, double> into_left = p2(c, s), into_right = p2(-c, s);  // their normals, into the hopper

    const std::vector<Known<2>> cases = {
        {p2(0.95, 2), 0.25, left_apex, p2(1, 0)},  // in the orifice, nearer its left end
        {left_apex, 0, left_apex, p2(0, -1)},
        {right_apex, 0, right_apex, p2(0, -1)},
        {left_apex + 1.0 * up_left, 0, left_apex + 1.0 * up_left, into_left},
        {left_apex + 1.0 * up_left + 0.2 * into_left, 0.2, left_apex + 1.0 * up_left, into_left},
        {right_apex + 1.5 * up_right + 0.1 * into_right, 0.1, right_apex + 1.5 * up_right, into_right},
        {p2(0, 1.5), 0.5, p2(0, 2), p2(0, -1)},     // downstream of the left wedge
        {p2(2, 1.5), 0.5, p2(2, 2), p2(0, -1)},     // downstream of the right wedge
        {p2(-1, 2.2), -0.2, p2(-1, 2), p2(0, -1)},  // inside the left wedge, under its downstream face
        {p2(0.9, 1), std::sqrt(1.04), left_apex, (1 / std::sqrt(1.04)) * p2(0.2, -1)}};  // below the orifice
    std::vector<Vec<2, Real>> points;
    for (const auto& k : cases) points.push_back(convert<Real>(k.x));
    const auto result = query_scene_on_device<Exec>(scene, points);
    for (std::size_t i = 0; i < cases.size(); ++i) {
      SCOPED_TRACE("x = " + str(cases[i].x));
      EXPECT_NEAR(result[i].distance, cases[i].distance, tol);
      EXPECT_NEAR(norm(convert<double>(result[i].point) - cases[i].point), 0.0, tol);
      EXPECT_NEAR(norm(convert<double>(result[i].normal) - cases[i].normal), 0.0, tol);
    }
  }
  EXPECT_THROW(mesoflow::orifice_wedges(Real(0.6), Real(1), Real(2), Real(kPi / 2)), std::invalid_argument);
  EXPECT_THROW(mesoflow::orifice_wedges(Real(0.6), Real(1), Real(2), Real(0)), std::invalid_argument);
  EXPECT_THROW(mesoflow::orifice_wedges(Real(0), Real(1), Real(2)), std::invalid_argument);
}

// Checks that the composite returns, at each point, the query of the expected shape, and that no shape
// is nearer.
template <class ExecSpace, int D, class Real>
void expect_nearest_shape(const std::vector<Shape<D, Real>>& scene,
                          const std::vector<std::pair<Vec<D, double>, int>>& cases) {
  const double tol = tolerance<Real>();
  std::vector<Vec<D, Real>> points;
  for (const auto& c : cases) points.push_back(convert<Real>(c.first));
  const auto result = query_scene_on_device<ExecSpace>(scene, points);
  for (std::size_t i = 0; i < cases.size(); ++i) {
    SCOPED_TRACE("x = " + str(cases[i].first) + ", expected shape " + std::to_string(cases[i].second));
    const SurfacePoint<D, Real> expected = scene[cases[i].second].query(points[i]);
    EXPECT_NEAR(result[i].distance, expected.distance, tol);
    EXPECT_NEAR(norm(convert<double>(result[i].point) - convert<double>(expected.point)), 0.0, tol);
    EXPECT_NEAR(norm(convert<double>(result[i].normal) - convert<double>(expected.normal)), 0.0, tol);
    for (std::size_t j = 0; j < scene.size(); ++j) {
      if (static_cast<int>(j) == cases[i].second) continue;
      EXPECT_LT(expected.distance, scene[j].query(points[i]).distance) << "shape " << j << " is nearer";
    }
  }
}

TYPED_TEST(GeometryTest, NearestSurfacePicksNearestShape) {
  using Exec = typename TypeParam::exec;
  using Real = typename TypeParam::real;
  const auto p2 = v2<double>;
  const auto p3 = v3<double>;

  // 2D silo: side walls at x = ±3, an orifice of width 1 at y = 0, an obstacle above it.
  const auto wedges = mesoflow::orifice_wedges(Real(1), Real(0), Real(0));
  const std::vector<Shape<2, Real>> silo = {Shape<2, Real>::half_space(v2<Real>(-3, 0), v2<Real>(1, 0)),
                                            Shape<2, Real>::half_space(v2<Real>(3, 0), v2<Real>(-1, 0)),
                                            wedges[0], wedges[1],
                                            Shape<2, Real>::disk(v2<Real>(0, 1.5), Real(0.3))};
  expect_nearest_shape<Exec>(silo, {{p2(0, 1.0), 4},
                                    {p2(0, 3), 4},
                                    {p2(-2.8, 3), 0},
                                    {p2(2.9, 5), 1},
                                    {p2(0.1, 0), 3},
                                    {p2(-1, 0.8), 2},
                                    {p2(-2, 0.5), 2},    // inside the left wedge
                                    {p2(3.5, -1), 1}});  // behind the right wall

  // 3D cylindrical hopper: a pipe of radius 2 along z on a flat base z = 0, a spherical obstacle.
  const std::vector<Shape<3, Real>> hopper = {
      Shape<3, Real>::cylinder(v3<Real>(0, 0, 0), v3<Real>(0, 0, 1), Real(2), true),
      Shape<3, Real>::half_space(v3<Real>(0, 0, 0), v3<Real>(0, 0, 1)),
      Shape<3, Real>::sphere(v3<Real>(0, 0, 1.5), Real(0.5))};
  expect_nearest_shape<Exec>(hopper, {{p3(0, 0, 0.2), 1},
                                      {p3(0, 0, 2.3), 2},
                                      {p3(1.9, 0, 3), 0},
                                      {p3(0, 0.5, -0.3), 1},
                                      {p3(2.5, 0, 1), 0},
                                      {p3(0.1, 0, 1.6), 2}});
}

TYPED_TEST(GeometryTest, EmptySceneIsAllFluid) {
  using Exec = typename TypeParam::exec;
  using Real = typename TypeParam::real;
  const auto result = query_scene_on_device<Exec>(std::vector<Shape<2, Real>>{},
                                                  std::vector<Vec<2, Real>>{v2<Real>(0.5, -0.25)});
  EXPECT_EQ(result[0].distance, std::numeric_limits<Real>::max());
  EXPECT_EQ(result[0].point[0], Real(0.5));
  EXPECT_EQ(result[0].point[1], Real(-0.25));
  const auto unset = query_on_device<Exec>(Shape<2, Real>(), std::vector<Vec<2, Real>>{v2<Real>(1, 1)});
  EXPECT_EQ(unset[0].distance, std::numeric_limits<Real>::max());
}

TYPED_TEST(GeometryTest, ShapeMatchesPrimitive) {
  using Exec = typename TypeParam::exec;
  using Real = typename TypeParam::real;
  const double tol = tolerance<Real>();

  const auto expect_same = [tol](const auto& a, const auto& b) {
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
      EXPECT_NEAR(a[i].distance, b[i].distance, tol);
      EXPECT_NEAR(norm(convert<double>(a[i].point) - convert<double>(b[i].point)), 0.0, tol);
      EXPECT_NEAR(norm(convert<double>(a[i].normal) - convert<double>(b[i].normal)), 0.0, tol);
    }
  };
  const auto points2 = test_points<2, Real>(SurfaceSamples<2>{1.0, {}}, 81);
  const auto points3 = test_points<3, Real>(SurfaceSamples<3>{1.0, {}}, 82);
  const auto a = v2<Real>(-1, -0.5), b = v2<Real>(1.2, 0.7), c = v2<Real>(0.1, 0.2);

  expect_same(query_on_device<Exec>(Shape<2, Real>::half_space(c, v2<Real>(1, 2)), points2),
              query_on_device<Exec>(mesoflow::HalfSpace<2, Real>::through(c, v2<Real>(1, 2)), points2));
  expect_same(query_on_device<Exec>(Shape<2, Real>::segment(a, b, true), points2),
              query_on_device<Exec>(mesoflow::Segment<Real>::between(a, b, true), points2));
  expect_same(query_on_device<Exec>(Shape<2, Real>::wedge(c, a, b, true), points2),
              query_on_device<Exec>(mesoflow::Wedge<Real>::from_edges(c, a, b, true), points2));
  expect_same(query_on_device<Exec>(Shape<2, Real>::disk(c, Real(1.5), true), points2),
              query_on_device<Exec>(mesoflow::Disk<Real>{c, Real(1.5), true}, points2));

  const auto o = v3<Real>(0.2, -0.1, 0.3), k = v3<Real>(1, 1, 0.5);
  expect_same(query_on_device<Exec>(Shape<3, Real>::half_space(o, k), points3),
              query_on_device<Exec>(mesoflow::HalfSpace<3, Real>::through(o, k), points3));
  expect_same(query_on_device<Exec>(Shape<3, Real>::sphere(o, Real(0.9)), points3),
              query_on_device<Exec>(mesoflow::Sphere<Real>{o, Real(0.9), false}, points3));
  expect_same(query_on_device<Exec>(Shape<3, Real>::cylinder(o, k, Real(1.3), true), points3),
              query_on_device<Exec>(mesoflow::Cylinder<Real>::around(o, k, Real(1.3), true), points3));
}

TYPED_TEST(GeometryTest, RejectsInvalidShapes) {
  using Real = typename TypeParam::real;
  using S2 = Shape<2, Real>;
  using S3 = Shape<3, Real>;
  const Real nan = std::numeric_limits<Real>::quiet_NaN();
  EXPECT_THROW(S2::half_space(v2<Real>(0, 0), v2<Real>(0, 0)), std::invalid_argument);
  EXPECT_THROW(S3::half_space(v3<Real>(0, 0, 0), v3<Real>(0, nan, 1)), std::invalid_argument);
  EXPECT_THROW(S2::segment(v2<Real>(1, 1), v2<Real>(1, 1)), std::invalid_argument);
  EXPECT_THROW(S2::wedge(v2<Real>(0, 0), v2<Real>(1, 0), v2<Real>(2, 0)), std::invalid_argument);
  EXPECT_THROW(S2::wedge(v2<Real>(0, 0), v2<Real>(1, 0), v2<Real>(-1, 0)), std::invalid_argument);
  EXPECT_THROW(S2::wedge(v2<Real>(0, 0), v2<Real>(0, 0), v2<Real>(0, 1)), std::invalid_argument);
  EXPECT_THROW(S2::disk(v2<Real>(0, 0), Real(0)), std::invalid_argument);
  EXPECT_THROW(S2::disk(v2<Real>(0, 0), nan), std::invalid_argument);
  EXPECT_THROW(S3::sphere(v3<Real>(0, 0, 0), Real(-1)), std::invalid_argument);
  EXPECT_THROW(S3::cylinder(v3<Real>(0, 0, 0), v3<Real>(0, 0, 0), Real(1)), std::invalid_argument);
  EXPECT_THROW(S3::cylinder(v3<Real>(0, 0, 0), v3<Real>(0, 0, 1), Real(0)), std::invalid_argument);
}

}  // namespace
