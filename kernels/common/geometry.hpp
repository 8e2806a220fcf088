// geometry.hpp — signed-distance walls and obstacles for use inside kernels: half-spaces, one-sided
// wall segments, wedges, disks/spheres and cylinders, and a tagged-union Shape to build scenes of them.
//
// Convention, for every query at a point x:
//   d(x) > 0 in the fluid (where particles live), d(x) < 0 inside the solid, d(x) = 0 on the surface;
//   the query returns d, the nearest surface point p and the unit normal n at p pointing into the fluid,
//   with x = p + d n.
// n is the gradient of d wherever d is differentiable. Where the nearest point is a corner (a wedge's
// apex, a segment's end), n is the direction from the corner towards x (its opposite for a point behind
// a segment), so the relation still holds. On a medial axis (the nearest point is not unique) one of the
// nearest points is returned; at the centre of a disk or sphere, or on a cylinder's axis, n is an
// arbitrary fixed direction.
//
// Everything queried in kernels is a plain struct with KOKKOS_INLINE_FUNCTION members: no virtual
// calls, no host pointers. Named constructors of Shape validate their arguments (on the host) and throw
// std::invalid_argument; the primitives' own factories assume valid arguments.
#pragma once

#include "kokkos_compat.hpp"
#include "vec.hpp"

#include <Kokkos_Core.hpp>

#include <array>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace mesoflow {

// Result of a distance query: signed distance, nearest surface point, unit normal into the fluid there.
template <int D, class Real>
struct SurfacePoint {
  Real distance;        // > 0 in the fluid, < 0 in the solid
  Vec<D, Real> point;   // nearest point on the surface
  Vec<D, Real> normal;  // unit normal at `point`, into the fluid: x = point + distance * normal
};

// The same surface seen with solid and fluid swapped: d → −d, n → −n, the nearest point unchanged.
template <int D, class Real>
KOKKOS_INLINE_FUNCTION SurfacePoint<D, Real> complement(SurfacePoint<D, Real> s) {
  s.distance = -s.distance;
  s.normal *= Real(-1);
  return s;
}

// The answer where there is no surface at all: x is fluid and the distance is the largest finite Real
// (point = x, normal = first axis; x = point + distance * normal does not hold).
template <int D, class Real>
KOKKOS_INLINE_FUNCTION SurfacePoint<D, Real> no_surface(const Vec<D, Real>& x) {
  SurfacePoint<D, Real> s{Kokkos::reduction_identity<Real>::min(), x, Vec<D, Real>::zero()};
  s.normal[0] = Real(1);
  return s;
}

namespace geometry_detail {

constexpr double pi = 3.14159265358979323846;

template <int D, class Real>
KOKKOS_INLINE_FUNCTION Real length(const Vec<D, Real>& v) {
  return kmath::sqrt(norm2(v));
}

template <int D, class Real>
KOKKOS_INLINE_FUNCTION Vec<D, Real> unit(const Vec<D, Real>& v) {
  return (Real(1) / length(v)) * v;
}

template <int D, class Real>
KOKKOS_INLINE_FUNCTION Vec<D, Real> unit_axis(int axis) {
  Vec<D, Real> e = Vec<D, Real>::zero();
  e[axis] = Real(1);
  return e;
}

// v rotated by +90° (counter-clockwise).
template <class Real>
KOKKOS_INLINE_FUNCTION Vec<2, Real> quarter_turn(const Vec<2, Real>& v) {
  return Vec<2, Real>{{-v[1], v[0]}};
}

// z component of a × b: > 0 when b lies counter-clockwise from a.
template <class Real>
KOKKOS_INLINE_FUNCTION Real cross(const Vec<2, Real>& a, const Vec<2, Real>& b) {
  return a[0] * b[1] - a[1] * b[0];
}

template <class Real>
KOKKOS_INLINE_FUNCTION Vec<3, Real> cross(const Vec<3, Real>& a, const Vec<3, Real>& b) {
  return Vec<3, Real>{{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}};
}

// A unit vector perpendicular to the unit vector k: k × (the coordinate axis least aligned with k).
template <class Real>
KOKKOS_INLINE_FUNCTION Vec<3, Real> any_perpendicular(const Vec<3, Real>& k) {
  int axis = 0;
  if (kmath::fabs(k[1]) < kmath::fabs(k[axis])) axis = 1;
  if (kmath::fabs(k[2]) < kmath::fabs(k[axis])) axis = 2;
  return unit(cross(k, unit_axis<3, Real>(axis)));
}

// The coordinates of r (relative to a point on an axis of unit direction `axis`) in its meridian
// half-plane: the distance `along` the axis, the distance `rho` from it, and the unit `outward`
// direction (a fixed perpendicular on the axis). (axis × r) × axis = r − (r·axis) axis, but
// perpendicular to the axis to round-off in its own size even where r lies within round-off of the
// axis and the radial part is noise.
template <class Real>
struct Meridian {
  Real along, rho;
  Vec<3, Real> outward;
};
template <class Real>
KOKKOS_INLINE_FUNCTION Meridian<Real> meridian(const Vec<3, Real>& r, const Vec<3, Real>& axis) {
  const Vec<3, Real> radial = cross(cross(axis, r), axis);
  const Real rho = length(radial);
  return {dot(r, axis), rho, rho > Real(0) ? (Real(1) / rho) * radial : any_perpendicular(axis)};
}

}  // namespace geometry_detail

// Half-space bounded by a plane (3D) or a line (2D); the fluid lies on the side `normal` points to.
template <int D, class Real>
struct HalfSpace {
  Vec<D, Real> origin;  // a point on the boundary
  Vec<D, Real> normal;  // unit normal, into the fluid

  // The half-space whose boundary passes through `point`, fluid towards `direction` (non-zero, any length).
  KOKKOS_INLINE_FUNCTION static HalfSpace through(const Vec<D, Real>& point, const Vec<D, Real>& direction) {
    return HalfSpace{point, geometry_detail::unit(direction)};
  }

  KOKKOS_INLINE_FUNCTION SurfacePoint<D, Real> query(const Vec<D, Real>& x) const {
    const Real height = dot(x - origin, normal);
    return {height, x - height * normal, normal};
  }
};

// A finite wall of zero thickness from a to b in 2D, with one fluid side.
//
// The fluid side is the side of `normal` = (b − a) rotated by +90° (to the left walking from a to b),
// or the opposite side for a flipped segment. |d| is the Euclidean distance to the nearest point of the
// segment; its sign is the side of x relative to the segment's line (points on the line count as fluid).
// d therefore jumps from +|d| to −|d| across the line's extensions beyond a and b: use segments where
// particles cannot get around the ends (ends buried in other solids, a container closed by walls).
template <class Real>
struct Segment {
  Vec<2, Real> a;
  Vec<2, Real> b;
  Vec<2, Real> normal;  // unit normal of the segment's line, into the fluid

  // The segment a–b, fluid on its left (walking from a to b) or, flipped, on its right; requires a ≠ b.
  KOKKOS_INLINE_FUNCTION static Segment between(const Vec<2, Real>& a, const Vec<2, Real>& b,
                                                bool flipped = false) {
    const Vec<2, Real> left = geometry_detail::unit(geometry_detail::quarter_turn(b - a));
    return Segment{a, b, flipped ? Real(-1) * left : left};
  }

  KOKKOS_INLINE_FUNCTION SurfacePoint<2, Real> query(const Vec<2, Real>& x) const {
    const Vec<2, Real> ab = b - a;
    const Vec<2, Real> r = x - a;
    const Real along = dot(r, ab);
    const Real height = dot(r, normal);  // signed distance to the segment's line
    if (along > Real(0) && along < norm2(ab)) return {height, x - height * normal, normal};

    const Vec<2, Real> end = along <= Real(0) ? a : b;
    const Vec<2, Real> from_end = x - end;
    const Real gap = geometry_detail::length(from_end);
    if (gap == Real(0)) return {Real(0), end, normal};
    const Real side = height >= Real(0) ? Real(1) : Real(-1);
    return {side * gap, end, (side / gap) * from_end};
  }
};

// A solid wedge in 2D: the convex region between two rays leaving `apex` (opening angle strictly between
// 0° and 180°), i.e. the intersection of the two half-planes bounded by the rays' lines.
//
// Exact signed distance. Inside, the larger (least negative) of the two face heights, the nearest point
// being the foot on that face. Outside, the smallest of: the height above a face whose foot lies on its
// ray (and which x faces), and the distance to the apex. `inverted` makes the wedge fluid and the rest
// of the plane solid.
template <class Real>
struct Wedge {
  Vec<2, Real> apex;
  Vec<2, Real> edge[2];    // unit directions of the two faces, away from the apex
  Vec<2, Real> normal[2];  // unit outward normal of face i: perpendicular to edge[i], away from edge[1 − i]
  bool inverted;

  // The wedge between the rays apex + s·edge_a and apex + s·edge_b (s ≥ 0); the edges are non-zero and
  // not parallel (the opening angle is the one below 180°).
  KOKKOS_INLINE_FUNCTION static Wedge from_edges(const Vec<2, Real>& apex, const Vec<2, Real>& edge_a,
                                                 const Vec<2, Real>& edge_b, bool inverted = false) {
    using namespace geometry_detail;
    Wedge w;
    w.apex = apex;
    w.edge[0] = unit(edge_a);
    w.edge[1] = unit(edge_b);
    const Real turn = cross(w.edge[0], w.edge[1]) > Real(0) ? Real(1) : Real(-1);
    w.normal[0] = (-turn) * quarter_turn(w.edge[0]);
    w.normal[1] = turn * quarter_turn(w.edge[1]);
    w.inverted = inverted;
    return w;
  }

  KOKKOS_INLINE_FUNCTION SurfacePoint<2, Real> query(const Vec<2, Real>& x) const {
    const Vec<2, Real> r = x - apex;
    const Real height[2] = {dot(r, normal[0]), dot(r, normal[1])};
    SurfacePoint<2, Real> s;
    if (height[0] <= Real(0) && height[1] <= Real(0)) {
      const int face = height[0] >= height[1] ? 0 : 1;
      s = {height[face], x - height[face] * normal[face], normal[face]};
    } else {
      const Real apex_distance = geometry_detail::length(r);  // > 0: x is outside
      s = {apex_distance, apex, (Real(1) / apex_distance) * r};
      for (int face = 0; face < 2; ++face)
        if (height[face] > Real(0) && dot(r, edge[face]) > Real(0) && height[face] < s.distance)
          s = {height[face], x - height[face] * normal[face], normal[face]};
    }
    return inverted ? complement(s) : s;
  }
};

// A disk (2D) or sphere (3D): solid inside (an obstacle, a pillar's cross-section) or, inverted, fluid
// inside (a circular or spherical container). At the centre the normal is the first coordinate axis.
template <int D, class Real>
struct Ball {
  Vec<D, Real> center;
  Real radius;
  bool inverted;

  KOKKOS_INLINE_FUNCTION SurfacePoint<D, Real> query(const Vec<D, Real>& x) const {
    const Vec<D, Real> r = x - center;
    const Real rho = geometry_detail::length(r);
    const Vec<D, Real> outward = rho > Real(0) ? (Real(1) / rho) * r : geometry_detail::unit_axis<D, Real>(0);
    const SurfacePoint<D, Real> s{rho - radius, center + radius * outward, outward};
    return inverted ? complement(s) : s;
  }
};

template <class Real>
using Disk = Ball<2, Real>;
template <class Real>
using Sphere = Ball<3, Real>;

// An infinite circular cylinder in 3D: solid inside (a pillar) or, inverted, fluid inside (a pipe, a
// cylindrical hopper). On the axis the normal is a fixed direction perpendicular to it.
template <class Real>
struct Cylinder {
  Vec<3, Real> origin;  // a point on the axis
  Vec<3, Real> axis;    // unit direction of the axis
  Real radius;
  bool inverted;

  // The cylinder of `radius` around the line through `point` along `direction` (non-zero, any length).
  KOKKOS_INLINE_FUNCTION static Cylinder around(const Vec<3, Real>& point, const Vec<3, Real>& direction,
                                                Real radius, bool inverted = false) {
    return Cylinder{point, geometry_detail::unit(direction), radius, inverted};
  }

  KOKKOS_INLINE_FUNCTION SurfacePoint<3, Real> query(const Vec<3, Real>& x) const {
    const auto m = geometry_detail::meridian(x - origin, axis);
    const SurfacePoint<3, Real> s{m.rho - radius, origin + m.along * axis + radius * m.outward, m.outward};
    return inverted ? complement(s) : s;
  }
};

// A 2D wedge revolved about an axis in 3D: in every meridian half-plane (ρ ≥ 0 from the axis, z along
// it) the solid is the same wedge (apex, edge 0, edge 1 in (ρ, z) coordinates, kept in ρ ≥ 0). The flat
// base of a cylindrical hopper with a circular orifice of diameter w is the wedge with apex (w/2, 0)
// between the base plane (1, 0) and a downward face; a conical base tilts the first edge. The nearest
// point of a solid of revolution lies in the query's own meridian half-plane, so the 2D wedge distance
// is exact. On the axis the meridian is a fixed direction perpendicular to it.
template <class Real>
struct RevolvedWedge {
  Vec<3, Real> origin;  // a point on the axis, z = 0
  Vec<3, Real> axis;    // unit direction of the axis (+z)
  Wedge<Real> profile;  // in (ρ, z)

  KOKKOS_INLINE_FUNCTION SurfacePoint<3, Real> query(const Vec<3, Real>& x) const {
    const auto m = geometry_detail::meridian(x - origin, axis);
    const SurfacePoint<2, Real> p = profile.query(Vec<2, Real>{{m.rho, m.along}});
    return {p.distance, origin + p.point[1] * axis + p.point[0] * m.outward,
            p.normal[0] * m.outward + p.normal[1] * axis};
  }
};

// Tags of Shape::kind.
struct ShapeKind {
  enum : int { none = 0, half_space, segment, wedge, ball, cylinder, revolved_wedge };
};

// One primitive of a scene as a tagged union, so that a scene is a plain array of Shapes (a
// Kokkos::View<Shape*>) queried without virtual dispatch. Build it with the named constructors.
//
// Layout of p (vectors take D entries):
//   half_space  origin, unit normal                                 (2D and 3D)
//   segment     a, b, unit normal                                   (2D)
//   wedge       apex, unit edge 0, unit edge 1, normal 0, normal 1  (2D)
//   ball        center, radius                                      (disk in 2D, sphere in 3D)
//   cylinder    origin, unit axis, radius                           (3D)
//   revolved_wedge origin, unit axis, (ρ, z) apex, unit edge 0, unit edge 1 (3D)
// A kind that does not exist in D dimensions (a segment in 3D) is treated as no surface.
// `inverted` swaps solid and fluid for every kind (d → −d, n → −n). A default Shape (kind none) is no
// surface at all: its query is no_surface(x).
template <int D, class Real>
struct Shape {
  int kind = ShapeKind::none;
  Real p[12] = {};
  bool inverted = false;

  Shape() = default;

  // Half-space bounded by the plane (line) through `point`, fluid towards `normal` (any length).
  static Shape half_space(const Vec<D, Real>& point, const Vec<D, Real>& normal) {
    require_nonzero(normal, "half_space: normal");
    const HalfSpace<D, Real> h = HalfSpace<D, Real>::through(point, normal);
    Shape s(ShapeKind::half_space, false);
    s.set_vec(0, h.origin);
    s.set_vec(D, h.normal);
    return s;
  }

  // One-sided wall segment a–b, fluid on its left walking from a to b (on its right if flipped).
  static Shape segment(const Vec<2, Real>& a, const Vec<2, Real>& b, bool flipped = false) {
    static_assert(D == 2, "mesoflow: a segment is a 2D shape");
    require_nonzero(b - a, "segment: b - a");
    const Segment<Real> g = Segment<Real>::between(a, b, flipped);
    Shape s(ShapeKind::segment, false);
    s.set_vec(0, g.a);
    s.set_vec(2, g.b);
    s.set_vec(4, g.normal);
    return s;
  }

  // Solid wedge between the rays from `apex` along `edge_a` and `edge_b` (fluid inside if inverted).
  static Shape wedge(const Vec<2, Real>& apex, const Vec<2, Real>& edge_a, const Vec<2, Real>& edge_b,
                     bool inverted = false) {
    static_assert(D == 2, "mesoflow: a wedge is a 2D shape");
    require_nonzero(edge_a, "wedge: edge_a");
    require_nonzero(edge_b, "wedge: edge_b");
    const Wedge<Real> w = Wedge<Real>::from_edges(apex, edge_a, edge_b);
    if (geometry_detail::cross(w.edge[0], w.edge[1]) == Real(0))
      throw std::invalid_argument(
          "wedge: the edges are parallel; the opening angle must lie strictly between 0 and 180 degrees");
    Shape s(ShapeKind::wedge, inverted);
    s.set_vec(0, w.apex);
    s.set_vec(2, w.edge[0]);
    s.set_vec(4, w.edge[1]);
    s.set_vec(6, w.normal[0]);
    s.set_vec(8, w.normal[1]);
    return s;
  }

  // Solid disk (fluid inside if inverted).
  static Shape disk(const Vec<2, Real>& center, Real radius, bool inverted = false) {
    static_assert(D == 2, "mesoflow: a disk is a 2D shape (use sphere in 3D)");
    return ball(center, radius, inverted, "disk");
  }

  // Solid sphere (fluid inside if inverted).
  static Shape sphere(const Vec<3, Real>& center, Real radius, bool inverted = false) {
    static_assert(D == 3, "mesoflow: a sphere is a 3D shape (use disk in 2D)");
    return ball(center, radius, inverted, "sphere");
  }

  // Solid infinite cylinder around the line through `point` along `axis` (fluid inside if inverted).
  static Shape cylinder(const Vec<3, Real>& point, const Vec<3, Real>& axis, Real radius,
                        bool inverted = false) {
    static_assert(D == 3, "mesoflow: a cylinder is a 3D shape");
    require_nonzero(axis, "cylinder: axis");
    require_positive(radius, "cylinder: radius");
    const Cylinder<Real> c = Cylinder<Real>::around(point, axis, radius);
    Shape s(ShapeKind::cylinder, inverted);
    s.set_vec(0, c.origin);
    s.set_vec(3, c.axis);
    s.p[6] = c.radius;
    return s;
  }

  // The solid of revolution of the 2D wedge (apex, edge_a, edge_b), given in (ρ, z) coordinates around
  // the axis through `origin` along `axis` (fluid inside if inverted); the wedge must lie in ρ ≥ 0.
  static Shape revolved_wedge(const Vec<3, Real>& origin, const Vec<3, Real>& axis, const Vec<2, Real>& apex,
                              const Vec<2, Real>& edge_a, const Vec<2, Real>& edge_b, bool inverted = false) {
    static_assert(D == 3, "mesoflow: a revolved wedge is a 3D shape");
    require_nonzero(axis, "revolved_wedge: axis");
    require_nonzero(edge_a, "revolved_wedge: edge_a");
    require_nonzero(edge_b, "revolved_wedge: edge_b");
    const Wedge<Real> w = Wedge<Real>::from_edges(apex, edge_a, edge_b);
    if (geometry_detail::cross(w.edge[0], w.edge[1]) == Real(0))
      throw std::invalid_argument("revolved_wedge: the edges are parallel");
    if (!(apex[0] >= Real(0)) || w.edge[0][0] < Real(0) || w.edge[1][0] < Real(0))
      throw std::invalid_argument("revolved_wedge: the wedge must lie at rho >= 0 (apex and edges pointing away from the axis)");
    Shape s(ShapeKind::revolved_wedge, inverted);
    const Vec<3, Real> k = geometry_detail::unit(axis);
    s.set_vec(0, origin);
    s.set_vec(3, k);
    s.p[6] = apex[0], s.p[7] = apex[1];
    s.p[8] = w.edge[0][0], s.p[9] = w.edge[0][1];
    s.p[10] = w.edge[1][0], s.p[11] = w.edge[1][1];
    return s;
  }

  KOKKOS_INLINE_FUNCTION SurfacePoint<D, Real> query(const Vec<D, Real>& x) const {
    SurfacePoint<D, Real> s;
    switch (kind) {
      case ShapeKind::half_space:
        s = HalfSpace<D, Real>{vec_at(0), vec_at(D)}.query(x);
        break;
      case ShapeKind::ball:
        s = Ball<D, Real>{vec_at(0), p[D], false}.query(x);
        break;
      case ShapeKind::segment:
        if constexpr (D == 2)
          s = Segment<Real>{vec_at(0), vec_at(2), vec_at(4)}.query(x);
        else
          return no_surface(x);
        break;
      case ShapeKind::wedge:
        if constexpr (D == 2)
          s = Wedge<Real>{vec_at(0), {vec_at(2), vec_at(4)}, {vec_at(6), vec_at(8)}, false}.query(x);
        else
          return no_surface(x);
        break;
      case ShapeKind::cylinder:
        if constexpr (D == 3)
          s = Cylinder<Real>{vec_at(0), vec_at(3), p[6], false}.query(x);
        else
          return no_surface(x);
        break;
      case ShapeKind::revolved_wedge:
        if constexpr (D == 3)
          s = RevolvedWedge<Real>{vec_at(0), vec_at(3),
                                  Wedge<Real>::from_edges(Vec<2, Real>{{p[6], p[7]}}, Vec<2, Real>{{p[8], p[9]}},
                                                          Vec<2, Real>{{p[10], p[11]}})}
                  .query(x);
        else
          return no_surface(x);
        break;
      default:
        return no_surface(x);
    }
    return inverted ? complement(s) : s;
  }

  // The vector stored in p[offset], ..., p[offset + D − 1].
  KOKKOS_INLINE_FUNCTION Vec<D, Real> vec_at(int offset) const {
    Vec<D, Real> v;
    for (int d = 0; d < D; ++d) v[d] = p[offset + d];
    return v;
  }

 private:
  Shape(int kind_, bool inverted_) : kind(kind_), inverted(inverted_) {}

  void set_vec(int offset, const Vec<D, Real>& v) {
    for (int d = 0; d < D; ++d) p[offset + d] = v[d];
  }

  static Shape ball(const Vec<D, Real>& center, Real radius, bool inverted, const char* what) {
    require_positive(radius, std::string(what) + ": radius");
    Shape s(ShapeKind::ball, inverted);
    s.set_vec(0, center);
    s.p[D] = radius;
    return s;
  }

  static void require_positive(Real value, const std::string& what) {
    if (!(value > Real(0)) || !std::isfinite(value))
      throw std::invalid_argument(what + " must be finite and > 0, got " + std::to_string(value));
  }

  template <int N>
  static void require_nonzero(const Vec<N, Real>& v, const std::string& what) {
    require_positive(std::sqrt(norm2(v)), what + " length");
  }
};

// The nearest surface of a scene of n shapes at x: the query with the smallest signed distance. The
// scene's solid is the union of the shapes' solids (an inverted shape contributes its outside), and its
// fluid the intersection of their fluids. The distance is exact in the fluid; inside overlapping solids
// it is an upper bound on the true (negative) distance. Ties go to the first shape; n = 0 gives
// no_surface(x). In a kernel: nearest_surface(shapes.data(), n, x) with shapes a Kokkos::View<Shape*>.
template <int D, class Real>
KOKKOS_INLINE_FUNCTION SurfacePoint<D, Real> nearest_surface(const Shape<D, Real>* shapes, int n,
                                                             const Vec<D, Real>& x) {
  SurfacePoint<D, Real> nearest = no_surface(x);
  for (int i = 0; i < n; ++i) {
    const SurfacePoint<D, Real> s = shapes[i].query(x);
    if (s.distance < nearest.distance) nearest = s;
  }
  return nearest;
}

// The two wedges of a 2D orifice (a hopper exit, or the narrow channel of the capillary-droplet
// experiments: two 45° wedges forming an orifice of width w). Flow is along −y: the orifice spans
// [center_x − w/2, center_x + w/2] on the line y = y_orifice, the fluid upstream lies at y > y_orifice.
// Each wedge has its apex at an end of the orifice, a downstream face in the line y = y_orifice pointing
// away from the orifice, and an upstream (converging) face that meets the flow direction at
// `wall_angle` (the hopper angle θ_w, 0 < θ_w < π/2; the opening angle of each wedge is π/2 − θ_w).
// Returns {left wedge, right wedge}; both extend to infinity.
template <class Real>
std::array<Shape<2, Real>, 2> orifice_wedges(Real w, Real center_x, Real y_orifice,
                                             Real wall_angle = Real(geometry_detail::pi / 4)) {
  if (!(w > Real(0)))
    throw std::invalid_argument("orifice_wedges: width must be > 0, got " + std::to_string(w));
  if (!(wall_angle > Real(0) && wall_angle < Real(geometry_detail::pi / 2)))
    throw std::invalid_argument("orifice_wedges: wall angle must lie strictly between 0 and pi/2, got " +
                                std::to_string(wall_angle));
  const Real s = std::sin(wall_angle);
  const Real c = std::cos(wall_angle);
  const Real half = Real(0.5) * w;
  using V = Vec<2, Real>;
  return {{Shape<2, Real>::wedge(V{{center_x - half, y_orifice}}, V{{Real(-1), Real(0)}}, V{{-s, c}}),
           Shape<2, Real>::wedge(V{{center_x + half, y_orifice}}, V{{Real(1), Real(0)}}, V{{s, c}})}};
}

// The walls of the hopper study (hopper paper §2.1), gravity along −y (2D) or −z (3D), the orifice
// centred on the axis at height 0. 2D: two side walls W apart (x = ±W/2) that meet the exit walls at
// the angle θ_w; the exit walls leave an orifice of width w. 3D: a cylinder of diameter W with a base
// at angle θ_w to the side wall (θ_w = 90°: flat) holding a circular orifice of diameter w. Each exit
// wall is a solid wedge whose upstream face is the wall and whose downstream face leaves the orifice
// rim 30° below it, so that nothing but the wall itself touches the flow and particles fall freely past
// the orifice. 0 < θ_w ≤ 90°, 0 < w < W.
constexpr double hopper_exit_wall_opening = 30.0;  // degrees between an exit wall and its downstream face

namespace geometry_detail {
// Checks W, w, θ_w and returns the directions, in the meridian (outward, up), of an exit wall and of
// its downstream face, leaving the orifice rim.
template <class Real>
std::array<Vec<2, Real>, 2> hopper_exit_wall(Real W, Real w, Real theta_w_degrees) {
  if (!(W > Real(0)) || !std::isfinite(W)) throw std::invalid_argument("hopper: width W must be finite and > 0");
  if (!(w > Real(0) && w < W)) throw std::invalid_argument("hopper: orifice w must lie in (0, W), got " + std::to_string(w));
  if (!(theta_w_degrees > Real(0) && theta_w_degrees <= Real(90)))
    throw std::invalid_argument("hopper: wall angle theta_w must lie in (0, 90] degrees, got " +
                                std::to_string(theta_w_degrees));
  const double theta = double(theta_w_degrees) * pi / 180;
  const double below = theta + hopper_exit_wall_opening * pi / 180;
  return {{Vec<2, Real>{{Real(std::sin(theta)), Real(std::cos(theta))}},
           Vec<2, Real>{{Real(std::sin(below)), Real(std::cos(below))}}}};
}
}  // namespace geometry_detail

template <class Real>
std::vector<Shape<2, Real>> hopper_walls_2d(Real W, Real w, Real theta_w_degrees) {
  using V = Vec<2, Real>;
  const auto [wall, under] = geometry_detail::hopper_exit_wall(W, w, theta_w_degrees);  // right rim
  const Real half = Real(0.5) * W, rim = Real(0.5) * w;
  return {Shape<2, Real>::half_space(V{{-half, Real(0)}}, V{{Real(1), Real(0)}}),
          Shape<2, Real>::half_space(V{{half, Real(0)}}, V{{Real(-1), Real(0)}}),
          Shape<2, Real>::wedge(V{{-rim, Real(0)}}, V{{-wall[0], wall[1]}}, V{{-under[0], under[1]}}),
          Shape<2, Real>::wedge(V{{rim, Real(0)}}, wall, under)};
}

template <class Real>
std::vector<Shape<3, Real>> hopper_walls_3d(Real W, Real w, Real theta_w_degrees) {
  using V3 = Vec<3, Real>;
  const auto [wall, under] = geometry_detail::hopper_exit_wall(W, w, theta_w_degrees);  // in (ρ, z)
  const V3 origin{{Real(0), Real(0), Real(0)}}, axis{{Real(0), Real(0), Real(1)}};
  return {Shape<3, Real>::cylinder(origin, axis, Real(0.5) * W, true),
          Shape<3, Real>::revolved_wedge(origin, axis, Vec<2, Real>{{Real(0.5) * w, Real(0)}}, wall, under)};
}

// Host-side owner of a scene: copies the shapes to ExecSpace's memory once, at construction, and hands
// the View to kernels (copy `shapes()` and `size()` into locals before the lambda).
template <int D, class Real, class ExecSpace = Kokkos::DefaultExecutionSpace>
class Geometry {
 public:
  using shape_type = Shape<D, Real>;
  using execution_space = ExecSpace;
  using memory_space = typename ExecSpace::memory_space;
  using shape_view = Kokkos::View<const shape_type*, memory_space>;

  explicit Geometry(const std::vector<shape_type>& shapes) {
    Kokkos::View<shape_type*, memory_space> device("mesoflow::geometry::shapes", shapes.size());
    const auto host = Kokkos::create_mirror_view(device);
    for (std::size_t i = 0; i < shapes.size(); ++i) host(i) = shapes[i];
    Kokkos::deep_copy(device, host);
    shapes_ = device;
  }

  shape_view shapes() const { return shapes_; }
  int size() const { return static_cast<int>(shapes_.extent(0)); }

 private:
  shape_view shapes_;
};

}  // namespace mesoflow
