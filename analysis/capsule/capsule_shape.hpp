// capsule_shape.hpp — the capsule measures of sph-microcapsules-constriction §4 from the outer
// layer of the membrane (host code on a copy of its vertices):
//
//   D_∞,Λ (§4, Figs. 5, 9): the capsule's largest extent along axis Λ = x, y, z over its initial
//     diameter 2a ("maximum elongation ... normalized by its initial diameter").
//   C_f, C_r (§4, Fig. 2): the curvatures of the frontal tip and the rear tail in the xy-plane
//     through the channel's centre, normalised by the initial radius, C = a/R; positive where the
//     outline is convex, negative where concave (the rear's indentation at large Ca). The outline is
//     the exact section of the outer-layer triangle mesh by the plane z = z_0 (one point per edge
//     crossing the plane); near the channel axis y_0 a circle is fitted to the outline points of
//     each end within a window |y − y_0| < w (default half the outline's half-width: ½a for the
//     sphere, narrower where the constriction squeezes the capsule; widened until it holds 5
//     points), and
//     C = ±a/R_circle, positive where the circle's centre lies inside the capsule (convex).
//   D_xy, θ (§4.1, the shear validation): the Taylor deformation (L − B)/(L + B), L and B the
//     extents along the principal axes of the xy block of the gyration tensor, and the inclination θ
//     of the major axis to the flow direction x, in (−π/2, π/2].
//   Pearson's r (eq. 17) of a measure against Ca across a sweep.
#pragma once

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <utility>
#include <vector>

namespace mesoflow::capsule {

// Extents along x, y, z of the points, each over `diameter`.
inline std::array<double, 3> deformation_indices(const std::vector<Eigen::Vector3d>& y, double diameter) {
  std::array<double, 3> out{};
  for (int a = 0; a < 3; ++a) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const auto& p : y) {
      lo = std::min(lo, p[a]);
      hi = std::max(hi, p[a]);
    }
    out[std::size_t(a)] = (hi - lo) / diameter;
  }
  return out;
}

// The section of a closed triangle mesh by the plane z = z0: one (x, y) point per mesh edge that
// crosses it (edges with one end strictly below and one at or above).
inline std::vector<Eigen::Vector2d> midplane_section(const std::vector<Eigen::Vector3d>& y,
                                                     const std::vector<std::array<int, 3>>& triangles, double z0) {
  std::map<std::pair<int, int>, Eigen::Vector2d> crossings;
  for (const auto& t : triangles)
    for (int e = 0; e < 3; ++e) {
      int i = t[std::size_t(e)], j = t[std::size_t((e + 1) % 3)];
      if (i > j) std::swap(i, j);
      const Eigen::Vector3d& a = y[std::size_t(i)];
      const Eigen::Vector3d& b = y[std::size_t(j)];
      const bool a_below = a[2] < z0, b_below = b[2] < z0;
      if (a_below == b_below) continue;
      const double s = (z0 - a[2]) / (b[2] - a[2]);
      crossings.emplace(std::make_pair(i, j), Eigen::Vector2d(a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])));
    }
  std::vector<Eigen::Vector2d> out;
  out.reserve(crossings.size());
  for (const auto& [edge, p] : crossings) out.push_back(p);
  return out;
}

// The curvature of one end of a section outline (side +1: the front, the points with x > x_c;
// −1: the rear), at the channel axis y = y0, times `radius`; convex positive. A circle is fitted to
// the points of that end within the window |y − y0| < w, w = window_fraction × the outline's
// half-width in y (widened until it holds 5 points; Kåsa's algebraic fit: exact on a circle);
// the end is convex where the circle's centre lies on the capsule's side of the outline. NaN if
// fewer than 3 points lie on that end near the axis.
inline double tip_curvature(const std::vector<Eigen::Vector2d>& section, double x_c, double y0, int side,
                            double radius, double window_fraction = 0.5) {
  double y_lo = std::numeric_limits<double>::infinity(), y_hi = -y_lo;
  for (const auto& p : section) {
    y_lo = std::min(y_lo, p[1]);
    y_hi = std::max(y_hi, p[1]);
  }
  double w = window_fraction * 0.5 * (y_hi - y_lo);
  std::vector<Eigen::Vector2d> pts;
  for (int widen = 0; widen < 8; ++widen, w *= 1.25) {
    pts.clear();
    for (const auto& p : section)
      if (side * (p[0] - x_c) > 0 && std::abs(p[1] - y0) < w) pts.push_back(p);
    if (pts.size() >= 5 || w > 1.5 * radius) break;
  }
  if (pts.size() < 3) return std::numeric_limits<double>::quiet_NaN();
  // x² + y² + D x + E y + F = 0 in coordinates about the points' mean (conditioning).
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : pts) mean += p;
  mean /= double(pts.size());
  Eigen::MatrixXd A(pts.size(), 3);
  Eigen::VectorXd b(pts.size());
  for (std::size_t k = 0; k < pts.size(); ++k) {
    const Eigen::Vector2d q = pts[k] - mean;
    A(Eigen::Index(k), 0) = q[0];
    A(Eigen::Index(k), 1) = q[1];
    A(Eigen::Index(k), 2) = 1;
    b[Eigen::Index(k)] = -q.squaredNorm();
  }
  const Eigen::Vector3d c = A.colPivHouseholderQr().solve(b);
  const Eigen::Vector2d centre = mean + Eigen::Vector2d(-0.5 * c[0], -0.5 * c[1]);
  const double r2 = 0.25 * (c[0] * c[0] + c[1] * c[1]) - c[2];
  if (!(r2 > 0) || !std::isfinite(r2)) return 0.0;  // collinear points: a flat end
  const double R = std::sqrt(r2);
  // The circle's point on the axis on the data's side; convex if the centre lies behind it
  // (toward the capsule's inside).
  const double h = std::sqrt(std::max(0.0, r2 - (y0 - centre[1]) * (y0 - centre[1])));
  const double x_a = centre[0] + h, x_b = centre[0] - h;
  const double x_tip = std::abs(x_a - mean[0]) < std::abs(x_b - mean[0]) ? x_a : x_b;
  const bool convex = side > 0 ? centre[0] < x_tip : centre[0] > x_tip;
  return (convex ? 1.0 : -1.0) * radius / R;
}

struct ShearPlaneShape {
  double taylor = 0;       // D_xy = (L − B)/(L + B)
  double inclination = 0;  // θ of the major axis to x, radians in (−π/2, π/2]
  double length = 0, breadth = 0;
};

inline ShearPlaneShape shear_plane_shape(const std::vector<Eigen::Vector3d>& y) {
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  for (const auto& p : y) c += p.head<2>();
  c /= double(y.size());
  Eigen::Matrix2d g = Eigen::Matrix2d::Zero();
  for (const auto& p : y) {
    const Eigen::Vector2d r = p.head<2>() - c;
    g += r * r.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(g / double(y.size()));
  auto extent = [&](const Eigen::Vector2d& axis) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const auto& p : y) {
      const double q = (p.head<2>() - c).dot(axis);
      lo = std::min(lo, q);
      hi = std::max(hi, q);
    }
    return hi - lo;
  };
  ShearPlaneShape s;
  const Eigen::Vector2d major = eig.eigenvectors().col(1);  // eigenvalues ascend
  s.length = extent(major);
  s.breadth = extent(eig.eigenvectors().col(0));
  s.taylor = (s.length - s.breadth) / (s.length + s.breadth);
  constexpr double pi = 3.14159265358979323846;
  double theta = std::atan2(major[1], major[0]);
  if (theta > pi / 2) theta -= pi;
  if (theta <= -pi / 2) theta += pi;
  s.inclination = theta;
  return s;
}

// The measures of one constriction sample from its outer layer y (lattice units; d the capsule's
// diameter, a its radius): D_∞,x,y,z, the outline of the xy-plane through the channel's centre
// (z = d), and C_f, C_r at the channel axis y = d.
struct SampleShape {
  std::array<double, 3> D{};
  std::vector<Eigen::Vector2d> section;
  double cf = 0, cr = 0;
};

inline SampleShape sample_shape(const std::vector<Eigen::Vector3d>& y, const std::vector<std::array<int, 3>>& triangles,
                                double x_c, double d, double a) {
  SampleShape m;
  m.D = deformation_indices(y, d);
  m.section = midplane_section(y, triangles, d);
  m.cf = tip_curvature(m.section, x_c, d, +1, a);
  m.cr = tip_curvature(m.section, x_c, d, -1, a);
  return m;
}

// Pearson's r of eq. (17); NaN with fewer than two points or no spread.
inline double pearson_r(const std::vector<double>& x, const std::vector<double>& y) {
  const std::size_t n = std::min(x.size(), y.size());
  double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
  std::size_t m = 0;
  for (std::size_t k = 0; k < n; ++k) {
    if (!std::isfinite(x[k]) || !std::isfinite(y[k])) continue;
    sx += x[k];
    sy += y[k];
    sxx += x[k] * x[k];
    syy += y[k] * y[k];
    sxy += x[k] * y[k];
    ++m;
  }
  const double nn = double(m);
  const double den = std::sqrt(nn * sxx - sx * sx) * std::sqrt(nn * syy - sy * sy);
  if (m < 2 || !(den > 0)) return std::numeric_limits<double>::quiet_NaN();
  return (nn * sxy - sx * sy) / den;
}

// The value of y where x first reaches x_target (linear interpolation between samples of a
// series x that increases on the whole); NaN if it never does.
inline double value_at(const std::vector<double>& x, const std::vector<double>& y, double x_target) {
  for (std::size_t k = 1; k < x.size() && k < y.size(); ++k)
    if (x[k - 1] < x_target && x[k] >= x_target) {
      const double s = (x_target - x[k - 1]) / (x[k] - x[k - 1]);
      return y[k - 1] + s * (y[k] - y[k - 1]);
    }
  return std::numeric_limits<double>::quiet_NaN();
}

}  // namespace mesoflow::capsule
