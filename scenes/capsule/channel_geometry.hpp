// channel_geometry.hpp — the fluid domains of the capsule paper (sph-microcapsules-constriction §3,
// Fig. 1a; §4.1) as unions of axis-aligned boxes, and the wall particles around them.
//
// A ChannelGeometry is a domain [0, L_x) × [0, L_y) × [0, L_z), periodic or walled per axis, and a
// fluid region inside it: the union of `fluid` boxes (all of the domain when empty). Everything
// within the domain but outside the fluid region is solid, as is everything beyond a walled axis's
// ends. Built on the simple cubic lattice of spacing Δx (sites at (i + ½)Δx; on walled axes the
// lattice continues past the ends), a site is
//   fluid  if it lies strictly inside a fluid box,
//   wall   if it lies in the solid within the wall reach (one kernel support) of the fluid region,
//   — (dropped) otherwise.
// Every wall site carries what Morris' no-slip walls need (no_slip_walls.hpp): its depth d_B below
// the fluid region's surface, the distance to the nearest fluid-region point q, and the unit normal
// (q − p)/|q − p| pointing into the fluid. At a plane wall this is the exact plane geometry; next
// to an edge of the constriction it is the direction to the edge.
//
// The two scenes of the paper:
//   constriction (§3, Fig. 1a): L = 7d × 2d × 2d, periodic in x, walls bounding y and z; the inlet
//     x ∈ [0, 3d), the constriction x ∈ [3d, 5d) of width t_c = η d in y (centred, full depth 2d in z:
//     §4.2's "expansion along the z axis inside the constriction as a result of the non-confined
//     space"), the outlet x ∈ [5d, 7d). The constriction's side blocks are rounded to whole lattice
//     layers so that every wall surface lies half-way between sites (the effective η is reported).
//   shear (§4.1): L = 5d × 4d × 4d, periodic in x and z, walls bounding y that slide at ∓V along x
//     (bottom −V, top +V: shear rate γ̇ = 2V/L_y).
// And the periodic box of the scene tests: no walls.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace mesoflow::capsule {

// An axis-aligned box [lo, hi] of the fluid region; on a periodic axis it may wrap (lo < 0 or
// hi > L), and hi − lo ≥ L spans the axis.
struct FluidBox {
  std::array<double, 3> lo{}, hi{};
};

struct ChannelGeometry {
  std::array<double, 3> length{};                  // the domain's edges L
  std::array<bool, 3> walled{false, false, false};  // walls beyond 0 and L on this axis
  std::vector<FluidBox> fluid;                      // the fluid region; empty: the whole domain
  double wall_speed = 0;  // walls on the low side of y move at −V x̂, on the high side +V x̂ (shear)
  std::string kind = "periodic";
  double constriction_width = 0;  // t_c (constriction scenes)
  double constriction_begin = 0, constriction_end = 0;  // its x range

  bool inside_domain_axis(int d, double p) const {
    return walled[std::size_t(d)] ? p >= 0 && p < length[std::size_t(d)] : true;
  }

  // The distance from p to the fluid region (0 inside) and the nearest fluid point q.
  struct Nearest {
    double distance = std::numeric_limits<double>::infinity();
    std::array<double, 3> point{};
    bool inside = false;  // strictly inside some fluid box
  };
  Nearest nearest_fluid(const std::array<double, 3>& p) const {
    Nearest best;
    auto consider = [&](const std::array<double, 3>& lo, const std::array<double, 3>& hi) {
      double d2 = 0;
      bool inside = true;
      std::array<double, 3> q{};
      for (std::size_t a = 0; a < 3; ++a) {
        const double c = 0.5 * (lo[a] + hi[a]), h = 0.5 * (hi[a] - lo[a]);
        double delta = p[a] - c;
        if (!walled[a]) {
          if (h >= 0.5 * length[a]) {  // spans the periodic axis
            q[a] = p[a];
            continue;
          }
          delta -= length[a] * std::floor(delta / length[a] + 0.5);
        }
        const double excess = std::abs(delta) - h;
        if (excess >= 0) inside = false;
        const double e = std::max(excess, 0.0);
        q[a] = p[a] - (delta > 0 ? e : -e);
        d2 += e * e;
      }
      const double dist = std::sqrt(d2);
      if (inside && !best.inside) {
        best = {0.0, p, true};
      } else if (!best.inside && dist < best.distance) {
        best = {dist, q, false};
      }
    };
    if (fluid.empty()) {
      std::array<double, 3> lo{}, hi = length;
      consider(lo, hi);
    } else {
      for (const auto& b : fluid) consider(b.lo, b.hi);
    }
    return best;
  }
};

// The lattice sites of a geometry: fluid sites, and wall sites with their Morris geometry.
struct ChannelSites {
  std::vector<std::array<double, 3>> fluid;
  std::vector<std::array<double, 3>> wall;
  std::vector<std::array<double, 3>> wall_normal;  // unit, into the fluid
  std::vector<double> wall_depth;                  // d_B ≥ 0 below the fluid region's surface
  std::vector<double> wall_velocity_x;             // the wall's prescribed velocity along x
  std::array<int, 3> wall_layers{};                // lattice layers beyond each end of a walled axis
};

inline ChannelSites channel_sites(const ChannelGeometry& g, double spacing, double wall_reach) {
  ChannelSites s;
  std::array<long, 3> first{}, last{};
  for (std::size_t a = 0; a < 3; ++a) {
    const long n = std::lround(g.length[a] / spacing);
    if (std::abs(double(n) * spacing - g.length[a]) > 1e-9 * g.length[a])
      throw std::invalid_argument("capsule channel: edge " + std::to_string(g.length[a]) + " along axis " +
                                  std::to_string(a) + " is not a whole number of lattice spacings " +
                                  std::to_string(spacing));
    const int layers = g.walled[a] ? int(std::ceil(wall_reach / spacing - 1e-9)) : 0;
    s.wall_layers[a] = layers;
    first[a] = -layers;
    last[a] = n + layers;
  }
  for (long i = first[0]; i < last[0]; ++i)
    for (long j = first[1]; j < last[1]; ++j)
      for (long k = first[2]; k < last[2]; ++k) {
        const std::array<double, 3> p{(double(i) + 0.5) * spacing, (double(j) + 0.5) * spacing,
                                      (double(k) + 0.5) * spacing};
        const auto near = g.nearest_fluid(p);
        bool in_domain = true;
        for (int a = 0; a < 3; ++a) in_domain = in_domain && g.inside_domain_axis(a, p[std::size_t(a)]);
        if (near.inside && in_domain) {
          s.fluid.push_back(p);
          continue;
        }
        if (near.distance > wall_reach + 1e-9 * spacing) continue;
        std::array<double, 3> n{};
        for (std::size_t a = 0; a < 3; ++a) n[a] = (near.point[a] - p[a]) / near.distance;
        s.wall.push_back(p);
        s.wall_normal.push_back(n);
        s.wall_depth.push_back(near.distance);
        s.wall_velocity_x.push_back(g.wall_speed == 0 ? 0.0 : (p[1] < 0.5 * g.length[1] ? -g.wall_speed : g.wall_speed));
      }
  return s;
}

// The fully periodic box of n sites per axis.
inline ChannelGeometry periodic_channel(const std::array<int, 3>& sites, double spacing) {
  ChannelGeometry g;
  for (std::size_t a = 0; a < 3; ++a) g.length[a] = sites[a] * spacing;
  return g;
}

// The constriction channel of §3 for a capsule of diameter `diameter` (d, a whole number of
// spacings) and η = t_c/d; the side blocks are rounded to whole lattice layers.
inline ChannelGeometry constriction_channel(double diameter, double eta, double spacing) {
  const long n_d = std::lround(diameter / spacing);
  if (n_d < 2 || std::abs(double(n_d) * spacing - diameter) > 1e-9 * diameter)
    throw std::invalid_argument("capsule channel: the capsule diameter d must be a whole number (>= 2) of lattice "
                                "spacings, got d/dx = " + std::to_string(diameter / spacing));
  if (!(eta > 0 && eta <= 2))
    throw std::invalid_argument("capsule channel: eta = t_c/d must be in (0, 2], got " + std::to_string(eta));
  ChannelGeometry g;
  g.kind = "constriction";
  const double d = double(n_d) * spacing;
  g.length = {7 * d, 2 * d, 2 * d};
  g.walled = {false, true, true};
  const long block = std::lround((2.0 * double(n_d) - eta * double(n_d)) / 2.0);  // layers per side block
  if (block < 0 || 2 * block >= 2 * n_d)
    throw std::invalid_argument("capsule channel: eta leaves no open constriction at this resolution");
  g.constriction_width = (2.0 * double(n_d) - 2.0 * double(block)) * spacing;
  g.constriction_begin = 3 * d;
  g.constriction_end = 5 * d;
  // Outlet + inlet (one box across the periodic seam) and the constriction's open slot.
  g.fluid.push_back({{5 * d, 0, 0}, {10 * d, 2 * d, 2 * d}});
  g.fluid.push_back({{3 * d - 1e-9 * d, double(block) * spacing, 0}, {5 * d + 1e-9 * d, 2 * d - double(block) * spacing, 2 * d}});
  return g;
}

// The simple-shear cell of §4.1: 5d × 4d × 4d (by default), walls bounding y sliding at ∓V.
inline ChannelGeometry shear_channel(const std::array<double, 3>& length, double wall_speed) {
  ChannelGeometry g;
  g.kind = "shear";
  g.length = length;
  g.walled = {false, true, false};
  g.wall_speed = wall_speed;
  return g;
}

// Fully developed laminar flow in a rectangular duct of sides w × h (pressure gradient G, viscosity
// μ), the classical double series (White, Viscous Fluid Flow, 3rd ed., eq. 3-48 and 3-49):
// the mean velocity ū = κ_mean G/μ and the centre velocity u_max = κ_max G/μ.
struct DuctFlow {
  double mean_coefficient = 0;  // κ_mean (length²)
  double max_coefficient = 0;   // κ_max (length²)
  double peak_to_mean() const { return max_coefficient / mean_coefficient; }
};

inline DuctFlow rectangular_duct(double w, double h) {
  constexpr double pi = 3.14159265358979323846;
  const double a = 0.5 * std::max(w, h), b = 0.5 * std::min(w, h);  // half-sides, a ≥ b
  double series_q = 0, series_max = 0;
  for (int i = 1; i < 400; i += 2) {
    const double arg = i * pi * a / (2 * b);
    series_q += std::tanh(arg) / std::pow(i, 5);
    const double sech = arg > 700 ? 0.0 : 1.0 / std::cosh(arg);
    series_max += (((i - 1) / 2) % 2 == 0 ? 1.0 : -1.0) * (1 - sech) / std::pow(i, 3);
  }
  DuctFlow f;
  // Q = (4 b³ a G/(3 μ)) [1 − (192 b/(π⁵ a)) Σ tanh(iπa/2b)/i⁵], mean = Q/(4ab);
  // u(0, 0) = (16 b² G/(μ π³)) Σ (−1)^((i−1)/2) (1 − sech(iπa/2b))/i³ (x across the short side).
  f.mean_coefficient = (b * b / 3.0) * (1 - 192 * b / (std::pow(pi, 5) * a) * series_q);
  f.max_coefficient = 16 * b * b / std::pow(pi, 3) * series_max;
  return f;
}

}  // namespace mesoflow::capsule
