// obstacle_array.hpp — random arrays of circular obstacles in a periodic rectangle (the obstacle
// arrays of the capillary-droplet study, §2.1): a maximal Poisson-disk generator on the host, an
// obstacle cell list whose nearest-obstacle query costs O(1) whatever the box size, and `Surfaces`,
// the one query kernels make for "the distance d_i to the nearest surface" of eqs. 3, 6 and 8
// (walls from geometry.hpp and obstacles together).
//
// Signed distances follow geometry.hpp: d > 0 in the fluid, the normal points into the fluid, and
// x = point + d·normal for the x that was queried (not folded into the box).
#pragma once

#include "box.hpp"
#include "geometry.hpp"
#include "kokkos_compat.hpp"
#include "random.hpp"
#include "vec.hpp"

#include <Kokkos_Core.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace mesoflow {

namespace obstacle_detail {

// Candidates Bridson's algorithm draws around an active point before retiring it (Bridson 2007's k).
constexpr int poisson_disk_attempts = 30;

// Uniform darts thrown into a void left by Bridson's algorithm before a vertex of it is taken.
constexpr int void_darts = 64;

// The sampler keeps centres (1 + separation_margin)(σ_ob + w_ob) apart, so that round-off in the void
// filling (centres placed on the rims of exclusion disks) never brings two closer than σ_ob + w_ob.
constexpr double separation_margin = 1e-10;

inline void require_positive(double value, const std::string& what) {
  if (!(value > 0) || !std::isfinite(value))
    throw std::invalid_argument(what + " must be finite and > 0, got " + std::to_string(value));
}

// Background grid of Bridson's algorithm on the periodic rectangle [0, L_x) × [0, L_y): cells with a
// diagonal shorter than the exclusion radius r, so a cell holds at most one centre.
class PoissonDiskGrid {
 public:
  PoissonDiskGrid(double length_x, double length_y, double r) : r_(r), r2_(r * r) {
    const double length[2] = {length_x, length_y};
    for (int d = 0; d < 2; ++d) {
      length_[d] = length[d];
      n_[d] = int(std::ceil(1.01 * std::sqrt(2.0) * length[d] / r));  // width ≤ r/(1.01√2)
      width_[d] = length[d] / n_[d];
      reach_[d] = int(std::ceil(r / width_[d]));
    }
    occupant_.assign(std::size_t(n_[0]) * std::size_t(n_[1]), -1);
  }

  const std::vector<Vec<2, double>>& points() const { return points_; }
  int cells(int d) const { return n_[d]; }
  bool occupied(int cx, int cy) const { return occupant_[index(cx, cy)] >= 0; }

  // True if no centre lies closer than r to p (minimum image).
  bool fits(const Vec<2, double>& p) const {
    bool clear = true;
    for_neighbors(cell_of(p, 0), cell_of(p, 1), [&](int j) {
      Vec<2, double> dr = p - points_[j];
      for (int d = 0; d < 2; ++d) dr[d] -= length_[d] * std::floor(dr[d] / length_[d] + 0.5);
      clear = clear && norm2(dr) >= r2_;
    });
    return clear;
  }

  void insert(const Vec<2, double>& p) {
    occupant_[index(cell_of(p, 0), cell_of(p, 1))] = int(points_.size());
    points_.push_back(p);
  }

  // p folded into the box.
  Vec<2, double> wrap(Vec<2, double> p) const {
    for (int d = 0; d < 2; ++d) {
      p[d] -= length_[d] * std::floor(p[d] / length_[d]);
      if (p[d] >= length_[d]) p[d] = 0;
    }
    return p;
  }

  // Fills the empty cell (cx, cy) if any point of it (closed) is at least r from every centre.
  //
  // The set U of such points is compact and, where it is not empty, contains a vertex of the
  // arrangement of the cell's edges and the exclusion circles: U lies outside every disk, so an extreme
  // point of U in any direction is never inside a circular arc, nor (for a generic direction) inside
  // an edge. So U is empty unless one of the cell's corners, the circles' intersections with the edges
  // or with each other is free, and the free vertices span U's bounding box. The new centre is the
  // first of up to `void_darts` uniform darts in that box that lands in U, or else a free vertex;
  // once a centre, it covers the whole cell (the cell's diagonal is shorter than r).
  template <class Uniform>
  void fill_void(int cx, int cy, Uniform&& u01) {
    const Vec<2, double> lo{{cx * width_[0], cy * width_[1]}};
    const Vec<2, double> hi{{lo[0] + width_[0], lo[1] + width_[1]}};
    const Vec<2, double> middle = 0.5 * (lo + hi);
    const double half_diagonal = 0.5 * std::sqrt(width_[0] * width_[0] + width_[1] * width_[1]);
    const double near2 = (r_ + half_diagonal) * (r_ + half_diagonal);
    // Every image of a nearby centre whose exclusion disk reaches into the cell (boxes shorter than 2r
    // see a centre through more than one image).
    std::vector<Vec<2, double>> disks;
    for_neighbors(cx, cy, [&](int j) {
      for (int sx = -1; sx <= 1; ++sx)
        for (int sy = -1; sy <= 1; ++sy) {
          const Vec<2, double> image{{points_[j][0] + sx * length_[0], points_[j][1] + sy * length_[1]}};
          if (norm2(image - middle) < near2) disks.push_back(image);
        }
    });
    const double free2 = r2_ * (1 - 1e-12);  // vertices on a rim are free up to round-off
    std::vector<Vec<2, double>> free_vertices;
    const auto consider = [&](const Vec<2, double>& q) {
      if (q[0] < lo[0] || q[0] > hi[0] || q[1] < lo[1] || q[1] > hi[1]) return;
      for (const Vec<2, double>& c : disks)
        if (norm2(q - c) < free2) return;
      free_vertices.push_back(q);
    };
    for (int corner = 0; corner < 4; ++corner)
      consider(Vec<2, double>{{(corner & 1) ? hi[0] : lo[0], (corner & 2) ? hi[1] : lo[1]}});
    for (const Vec<2, double>& c : disks)
      for (int d = 0; d < 2; ++d)
        for (const double edge : {lo[d], hi[d]}) {
          const double along = edge - c[d];
          if (std::abs(along) > r_) continue;
          const double across = std::sqrt(r2_ - along * along);
          for (const double sign : {-1.0, 1.0}) {
            Vec<2, double> q;
            q[d] = edge;
            q[1 - d] = c[1 - d] + sign * across;
            consider(q);
          }
        }
    for (std::size_t a = 0; a < disks.size(); ++a)
      for (std::size_t b = a + 1; b < disks.size(); ++b) {
        const Vec<2, double> ab = disks[b] - disks[a];
        const double gap2 = norm2(ab);
        if (gap2 == 0 || gap2 > 4 * r2_) continue;
        const Vec<2, double> mid = disks[a] + 0.5 * ab;
        const double h = std::sqrt(r2_ / gap2 - 0.25);  // half-chord / |ab|
        const Vec<2, double> across{{-ab[1] * h, ab[0] * h}};
        consider(mid + across);
        consider(mid - across);
      }
    if (free_vertices.empty()) return;

    Vec<2, double> box_lo = free_vertices[0], box_hi = free_vertices[0];
    for (const Vec<2, double>& q : free_vertices)
      for (int d = 0; d < 2; ++d) {
        box_lo[d] = std::min(box_lo[d], q[d]);
        box_hi[d] = std::max(box_hi[d], q[d]);
      }
    for (int dart = 0; dart < void_darts; ++dart) {
      const Vec<2, double> q{{box_lo[0] + u01() * (box_hi[0] - box_lo[0]), box_lo[1] + u01() * (box_hi[1] - box_lo[1])}};
      bool clear = true;
      for (const Vec<2, double>& c : disks) clear = clear && norm2(q - c) >= r2_;
      if (clear) {
        insert(wrap(q));
        return;
      }
    }
    insert(wrap(free_vertices[0]));
  }

 private:
  std::size_t index(int cx, int cy) const { return std::size_t(cy) * std::size_t(n_[0]) + std::size_t(cx); }

  int cell_of(const Vec<2, double>& p, int d) const {
    const int c = int(p[d] / width_[d]);
    return c < 0 ? 0 : (c >= n_[d] ? n_[d] - 1 : c);
  }

  // Calls visit(j) for the centre j of every occupied cell within reach of (cx, cy), each cell once.
  template <class Visit>
  void for_neighbors(int cx, int cy, Visit&& visit) const {
    int lo[2], hi[2];
    for (int d = 0; d < 2; ++d) {
      const bool all = 2 * reach_[d] + 1 >= n_[d];
      lo[d] = all ? 0 : (d == 0 ? cx : cy) - reach_[d];
      hi[d] = all ? n_[d] - 1 : (d == 0 ? cx : cy) + reach_[d];
    }
    for (int oy = lo[1]; oy <= hi[1]; ++oy)
      for (int ox = lo[0]; ox <= hi[0]; ++ox) {
        const int j = occupant_[index((ox + n_[0]) % n_[0], (oy + n_[1]) % n_[1])];
        if (j >= 0) visit(j);
      }
  }

  double r_, r2_;
  double length_[2], width_[2];
  int n_[2], reach_[2];
  std::vector<int> occupant_;
  std::vector<Vec<2, double>> points_;
};

}  // namespace obstacle_detail

// Centres of circular obstacles of diameter σ_ob in the periodic rectangle [0, L_x) × [0, L_y), at
// least σ_ob + w_ob apart under the minimum image (so surfaces are at least w_ob apart), sampled until
// no further centre fits: a maximal Poisson-disk sample.
//
// Bridson's algorithm (SIGGRAPH 2007 sketch "Fast Poisson disk sampling in arbitrary dimensions") on a
// periodic background grid: from a random active centre, draw up to k = 30 candidates uniformly (by
// area) in the annulus [r, 2r) around it and keep the first that fits; an active centre whose k
// candidates all fail is retired. Bridson's sample is not maximal (filling the small voids it leaves
// adds about one centre in ten), so a final sweep visits every empty grid cell in random order, finds
// any void left exactly and places a centre uniformly within it (see fill_void): afterwards no point of
// the box is σ_ob + w_ob or more from every centre. At the paper's σ_ob = 0.3σ, w_ob = σ this gives
// ≈ 0.687 centres per (σ_ob + w_ob)² and takes under a second for L = 500σ (10⁵ obstacles).
//
// Reproducible from the seed on every platform: std::mt19937_64's output is fixed by the standard,
// turned into doubles bit by bit (uniform_from_bits) and used with IEEE-exact operations only (no
// trigonometry). The order of the returned centres is the order they were placed in.
inline std::vector<Vec<2, double>> poisson_disk_obstacles(double length_x, double length_y, double sigma_ob,
                                                          double w_ob, std::uint64_t seed) {
  using obstacle_detail::require_positive;
  require_positive(length_x, "poisson_disk_obstacles: L_x");
  require_positive(length_y, "poisson_disk_obstacles: L_y");
  require_positive(sigma_ob, "poisson_disk_obstacles: sigma_ob");
  if (!(w_ob >= 0) || !std::isfinite(w_ob))
    throw std::invalid_argument("poisson_disk_obstacles: w_ob must be finite and >= 0, got " + std::to_string(w_ob));
  const double separation = sigma_ob + w_ob;
  if (length_x < separation || length_y < separation)
    throw std::invalid_argument("poisson_disk_obstacles: the box (" + std::to_string(length_x) + " x " +
                                std::to_string(length_y) + ") must be at least sigma_ob + w_ob = " +
                                std::to_string(separation) + " along each axis (an obstacle's own images)");

  const double r = separation * (1 + obstacle_detail::separation_margin);
  obstacle_detail::PoissonDiskGrid grid(length_x, length_y, r);
  std::mt19937_64 engine(seed);
  const auto u01 = [&engine] { return 1.0 - uniform_from_bits<double>(engine()); };  // [0, 1)

  std::vector<int> active;
  grid.insert(Vec<2, double>{{u01() * length_x, u01() * length_y}});
  active.push_back(0);
  while (!active.empty()) {
    const std::size_t slot = std::min(std::size_t(u01() * double(active.size())), active.size() - 1);
    const Vec<2, double> from = grid.points()[std::size_t(active[slot])];
    bool placed = false;
    for (int attempt = 0; attempt < obstacle_detail::poisson_disk_attempts && !placed; ++attempt) {
      double ux, uy, q;
      do {  // a direction, uniform on the circle, by rejection from the square
        ux = 2 * u01() - 1;
        uy = 2 * u01() - 1;
        q = ux * ux + uy * uy;
      } while (!(q > 0 && q <= 1));
      const double scale = r * std::sqrt(1 + 3 * u01()) / std::sqrt(q);
      const Vec<2, double> candidate = grid.wrap(Vec<2, double>{{from[0] + scale * ux, from[1] + scale * uy}});
      if (grid.fits(candidate)) {
        active.push_back(int(grid.points().size()));
        grid.insert(candidate);
        placed = true;
      }
    }
    if (!placed) {
      active[slot] = active.back();
      active.pop_back();
    }
  }
  // Every empty cell, in random order (a Fisher–Yates shuffle) so that no part of the box is filled
  // first.
  const int nx = grid.cells(0), ncell = grid.cells(0) * grid.cells(1);
  std::vector<int> empty;
  for (int k = 0; k < ncell; ++k)
    if (!grid.occupied(k % nx, k / nx)) empty.push_back(k);
  for (std::size_t i = empty.size(); i > 1; --i)
    std::swap(empty[i - 1], empty[std::min(std::size_t(u01() * double(i)), i - 1)]);
  for (const int k : empty)
    if (!grid.occupied(k % nx, k / nx)) grid.fill_void(k % nx, k / nx, u01);
  return grid.points();
}

// As poisson_disk_obstacles, but sparser: `count` centres placed one after another uniformly in the
// box, each rejected and redrawn while it comes closer than σ_ob + w_ob to one already placed (random
// sequential addition). The minimum gap w_ob is the same; the number density, which the maximal
// sample fixes at its densest, is the caller's (e.g. from an obstacle area fraction φ:
// count = φ L_x L_y / (π σ_ob²/4)). Throws std::invalid_argument when `count` centres do not fit:
// random sequential addition jams near 0.547 of the area at separation σ_ob + w_ob, and this stops
// after 1000 rejections in a row. Reproducible from the seed like poisson_disk_obstacles.
inline std::vector<Vec<2, double>> random_sequential_obstacles(double length_x, double length_y, double sigma_ob,
                                                               double w_ob, std::size_t count, std::uint64_t seed) {
  using obstacle_detail::require_positive;
  require_positive(length_x, "random_sequential_obstacles: L_x");
  require_positive(length_y, "random_sequential_obstacles: L_y");
  require_positive(sigma_ob, "random_sequential_obstacles: sigma_ob");
  if (!(w_ob >= 0) || !std::isfinite(w_ob))
    throw std::invalid_argument("random_sequential_obstacles: w_ob must be finite and >= 0, got " +
                                std::to_string(w_ob));
  const double separation = sigma_ob + w_ob;
  if (length_x < separation || length_y < separation)
    throw std::invalid_argument("random_sequential_obstacles: the box must be at least sigma_ob + w_ob = " +
                                std::to_string(separation) + " along each axis");
  obstacle_detail::PoissonDiskGrid grid(length_x, length_y, separation * (1 + obstacle_detail::separation_margin));
  std::mt19937_64 engine(seed);
  const auto u01 = [&engine] { return 1.0 - uniform_from_bits<double>(engine()); };  // [0, 1)
  constexpr int max_rejections_in_a_row = 1000;
  while (grid.points().size() < count) {
    int rejected = 0;
    Vec<2, double> candidate{{u01() * length_x, u01() * length_y}};
    while (!grid.fits(candidate)) {
      if (++rejected == max_rejections_in_a_row)
        throw std::invalid_argument("random_sequential_obstacles: only " + std::to_string(grid.points().size()) +
                                    " of " + std::to_string(count) + " obstacles fit at the minimum gap w_ob = " +
                                    std::to_string(w_ob) + "; lower the obstacle fraction");
      candidate = Vec<2, double>{{u01() * length_x, u01() * length_y}};
    }
    grid.insert(candidate);
  }
  return grid.points();
}

// Identical circular obstacles in a periodic rectangle, binned once into a CSR cell list (cells of
// width ≥ `cell_width`, centres sorted by cell and, within a cell, by input order), with an exact
// nearest-obstacle query for kernels.
//
// Several independent arrays ("arrays", one per replica of an ensemble) can share one object: they
// have the same box, diameter and cell grid, and array a owns the cells [a·n_cells, (a+1)·n_cells)
// of one concatenated CSR list. nearest(a, x) and for_each_within(a, ...) see array a only;
// nearest(x) and for_each_within(x, ...) are those of array 0 (the single-array API).
//
// The query searches rings of cells outward from the query's cell and stops when the nearest a ring
// can hold is farther than the best obstacle found. With `cell_width` = σ_ob + w_ob and a maximal
// sample (every point lies within σ_ob + w_ob of a centre), the search ends after the 3 × 3 cells
// around the query: O(1) at fixed obstacle density, whatever the box size. Sparser arrays search
// further and still answer exactly.
//
// A plain copyable object (Views and scalars). Its queries (nearest, for_each_within, ...) live in
// ObstacleArrayQuery, its base: kernels capture query() (about 150 bytes), not the owning object.
// Default constructed, it holds no obstacles and nearest(x) is no_surface(x).
// The device part of an ObstacleArray: what a kernel needs to query it, and nothing it would
// have to own — scalars and two pointers into its Views (about 140 bytes in double), so that kernels
// capture this small handle (ObstacleArray::query()) instead of the owning object
// (kernels/common/kernel_launch.hpp). Valid while the ObstacleArray it came from (or a copy) lives.
template <class Real, class ExecSpace = Kokkos::DefaultExecutionSpace>
class ObstacleArrayQuery {
 public:
  using execution_space = ExecSpace;
  using memory_space = typename ExecSpace::memory_space;

  KOKKOS_INLINE_FUNCTION Real radius() const { return radius_; }
  // Width of the grid cells: for a maximal Poisson-disk array (poisson_disk_obstacles with
  // cell width σ_ob + w_ob) every point lies within this distance of an obstacle centre.
  KOKKOS_INLINE_FUNCTION Real cell_width() const { return min_width_; }

  // Calls visit(centre_image) for every obstacle whose nearest periodic image to x lies within
  // `radius` of x (centre_image: that image's position, x − centre_image the minimum-image
  // separation). Visits each obstacle at most once; for setup work (candidate lists), not hot loops.
  template <class Visitor>
  KOKKOS_INLINE_FUNCTION void for_each_within(const Vec<2, Real>& x, Real radius, Visitor&& visit) const {
    for_each_within(0, x, radius, visit);
  }

  // for_each_within(x, radius, visit) over the obstacles of array `array` only.
  template <class Visitor>
  KOKKOS_INLINE_FUNCTION void for_each_within(int array, const Vec<2, Real>& x, Real radius, Visitor&& visit) const {
    if (num_obstacles_ == 0) return;
    const int base = array * cells_per_array_;
    int home[2], first[2], count[2];
    for (int d = 0; d < 2; ++d) {
      Real u = (x[d] - lo_[d]) * inv_width_[d];
      u -= Real(n_[d]) * kmath::floor(u / Real(n_[d]));
      const int c = int(kmath::floor(u));
      home[d] = c < 0 ? 0 : (c >= n_[d] ? n_[d] - 1 : c);
      const int reach = int(kmath::floor(radius * inv_width_[d])) + 1;
      first[d] = 2 * reach + 1 >= n_[d] ? 0 : home[d] - reach;  // the whole axis when it wraps onto itself
      count[d] = 2 * reach + 1 >= n_[d] ? n_[d] : 2 * reach + 1;
    }
    const Real radius2 = radius * radius;
    for (int oy = 0; oy < count[1]; ++oy)
      for (int ox = 0; ox < count[0]; ++ox) {
        const int cx = ((first[0] + ox) % n_[0] + n_[0]) % n_[0];
        const int cy = ((first[1] + oy) % n_[1] + n_[1]) % n_[1];
        const int k = base + cx + n_[0] * cy;
        for (int s = cell_offset_[k]; s < cell_offset_[k + 1]; ++s) {
          Vec<2, Real> dr{{x[0] - centers_[2 * s + 0], x[1] - centers_[2 * s + 1]}};
          for (int d = 0; d < 2; ++d) dr[d] -= length_[d] * kmath::floor(dr[d] * inv_length_[d] + Real(0.5));
          if (norm2(dr) < radius2) visit(x - dr);
        }
      }
  }

  // The surface of one obstacle as seen from x, dr = x − the obstacle's centre image: signed
  // distance, surface point, outward normal.
  KOKKOS_INLINE_FUNCTION SurfacePoint<2, Real> surface_of(const Vec<2, Real>& x, const Vec<2, Real>& dr) const {
    const Real rho = kmath::sqrt(norm2(dr));
    const Vec<2, Real> outward = rho > Real(0) ? (Real(1) / rho) * dr : geometry_detail::unit_axis<2, Real>(0);
    const Real distance = rho - radius_;
    return {distance, x - distance * outward, outward};
  }

  // nearest(array, x), also calling visit(s) for the surface s of every obstacle of the array at
  // signed distance < reach from x (for_each_within's order).
  template <class Visit>
  KOKKOS_INLINE_FUNCTION SurfacePoint<2, Real> nearest_within(int array, const Vec<2, Real>& x, Real reach,
                                                              Visit&& visit) const {
    for_each_within(array, x, reach + radius_, [&](const Vec<2, Real>& image) {
      const SurfacePoint<2, Real> s = surface_of(x, x - image);
      if (s.distance < reach) visit(s);
    });
    return nearest(array, x);
  }

  // Signed distance to the nearest obstacle's surface at x (any x: periodic images are taken), the
  // nearest surface point and the normal there, pointing out of the obstacle. Ties go to the obstacle
  // found first (inner rings first, cell order within a ring).
  KOKKOS_INLINE_FUNCTION SurfacePoint<2, Real> nearest(const Vec<2, Real>& x) const {
    int examined;
    return nearest_examined(0, x, examined);
  }

  // nearest(x) among the obstacles of array `array` only (no_surface(x) if it has none).
  KOKKOS_INLINE_FUNCTION SurfacePoint<2, Real> nearest(int array, const Vec<2, Real>& x) const {
    int examined;
    return nearest_examined(array, x, examined);
  }

  // nearest(x), also counting the obstacles whose distance it computed (the cost of the query).
  KOKKOS_INLINE_FUNCTION SurfacePoint<2, Real> nearest_examined(const Vec<2, Real>& x, int& examined) const {
    return nearest_examined(0, x, examined);
  }

  KOKKOS_INLINE_FUNCTION SurfacePoint<2, Real> nearest_examined(int array, const Vec<2, Real>& x,
                                                                int& examined) const {
    examined = 0;
    if (num_obstacles_ == 0) return no_surface(x);
    const int base = array * cells_per_array_;
    if (cell_offset_[base] == cell_offset_[base + cells_per_array_]) return no_surface(x);
    // Cell of x folded into the box, and the distance from x to that cell's nearest edge.
    int home[2];
    Real gap = min_width_;
    Vec<2, Real> folded;  // x folded into the box
    Real fraction[2];     // position of x within its home cell, in cell widths
    for (int d = 0; d < 2; ++d) {
      Real u = (x[d] - lo_[d]) * inv_width_[d];
      u -= Real(n_[d]) * kmath::floor(u / Real(n_[d]));
      folded[d] = lo_[d] + u / inv_width_[d];
      const int c = int(kmath::floor(u));
      home[d] = c < 0 ? 0 : (c >= n_[d] ? n_[d] - 1 : c);
      const Real inside = u - Real(home[d]);
      fraction[d] = inside;
      const Real edge = (inside < Real(0.5) ? inside : Real(1) - inside) / inv_width_[d];
      gap = edge < gap ? edge : gap;
    }
    gap = gap > Real(0) ? gap : Real(0);

    Real best_r2 = Kokkos::reduction_identity<Real>::min();
    Vec<2, Real> best_dr = Vec<2, Real>::zero();
    // Ring k: the cells whose offset from home has Chebyshev norm k, offsets clipped per axis to
    // [−⌊(n−1)/2⌋, ⌊n/2⌋] so that every cell is visited once. Every image of a centre in ring k lies
    // at least (k − 1)·width + gap from x.
    for (int k = 0; k <= max_ring_; ++k) {
      if (k > 0) {
        const Real reach = Real(k - 1) * min_width_ + gap;
        if (reach * reach > best_r2) break;
      }
      int lo[2], hi[2];
      for (int d = 0; d < 2; ++d) {
        const int below = (n_[d] - 1) / 2, above = n_[d] / 2;
        lo[d] = k < below ? -k : -below;
        hi[d] = k < above ? k : above;
      }
      for (int oy = lo[1]; oy <= hi[1]; ++oy) {
        if (oy == -k || oy == k) {
          for (int ox = lo[0]; ox <= hi[0]; ++ox) scan_cell(base, folded, home, fraction, ox, oy, best_r2, best_dr, examined);
        } else {
          if (lo[0] == -k) scan_cell(base, folded, home, fraction, -k, oy, best_r2, best_dr, examined);
          if (hi[0] == k) scan_cell(base, folded, home, fraction, k, oy, best_r2, best_dr, examined);
        }
      }
    }
    const Real rho = kmath::sqrt(best_r2);
    const Vec<2, Real> outward = rho > Real(0) ? (Real(1) / rho) * best_dr : geometry_detail::unit_axis<2, Real>(0);
    const Real distance = rho - radius_;
    return {distance, x - distance * outward, outward};
  }

 protected:
  // Minimum-image separations from x to the centres of the cell at offset (ox, oy) from home; keeps
  // the shortest (the first of equals).
  KOKKOS_INLINE_FUNCTION void scan_cell(int base, const Vec<2, Real>& x, const int (&home)[2], const Real (&fraction)[2],
                                        int ox, int oy, Real& best_r2, Vec<2, Real>& best_dr, int& examined) const {
    // The cell `o` cells from home, wrapped once (|o| < n), and the image shift of its centres.
    // While (|o| + 1) cells fit in half the box on both axes that image is the minimum image;
    // beyond, each centre gets the minimum image explicitly (small boxes, far rings).
    const int offset[2] = {ox, oy};
    int c[2];
    Vec<2, Real> image = x;  // x moved by minus the shift, so dr = image − centre
    bool nearest_image = true;
    for (int d = 0; d < 2; ++d) {
      c[d] = home[d] + offset[d];
      if (c[d] < 0) {
        c[d] += n_[d];
        image[d] += length_[d];
      } else if (c[d] >= n_[d]) {
        c[d] -= n_[d];
        image[d] -= length_[d];
      }
      const int reach = offset[d] < 0 ? 1 - offset[d] : 1 + offset[d];
      nearest_image = nearest_image && 2 * reach <= n_[d];
    }
    if (nearest_image) {  // skip a cell whose every point is farther than the best centre so far
      Real gap2 = 0;
      for (int d = 0; d < 2; ++d) {
        const Real cells = offset[d] < 0 ? fraction[d] - Real(offset[d] + 1)
                                         : (offset[d] > 0 ? Real(offset[d]) - fraction[d] : Real(0));
        const Real g = cells / inv_width_[d];
        gap2 += g * g;
      }
      if (gap2 >= best_r2) return;
    }
    const int k = base + c[0] + n_[0] * c[1];
    for (int s = cell_offset_[k]; s < cell_offset_[k + 1]; ++s) {
      Vec<2, Real> dr{{image[0] - centers_[2 * s + 0], image[1] - centers_[2 * s + 1]}};
      if (!nearest_image)
        for (int d = 0; d < 2; ++d) dr[d] -= length_[d] * kmath::floor(dr[d] * inv_length_[d] + Real(0.5));
      const Real r2 = norm2(dr);
      ++examined;
      if (r2 < best_r2) {
        best_r2 = r2;
        best_dr = dr;
      }
    }
  }

  int num_arrays_ = 1;
  int num_obstacles_ = 0;
  int cells_per_array_ = 1;
  Real radius_ = 0;
  int n_[2] = {1, 1};
  Real lo_[2] = {};
  Real length_[2] = {Real(1), Real(1)};
  Real inv_length_[2] = {Real(1), Real(1)};
  Real inv_width_[2] = {Real(1), Real(1)};
  Real min_width_ = Real(1);
  int max_ring_ = 0;
  const int* cell_offset_ = nullptr;  // CSR offsets of the cells (ObstacleArray's Views, device memory)
  const Real* centers_ = nullptr;     // centres in cell order, row-major: [2 s + d]
};

template <class Real, class ExecSpace = Kokkos::DefaultExecutionSpace>
class ObstacleArray : public ObstacleArrayQuery<Real, ExecSpace> {
 public:
  using Query = ObstacleArrayQuery<Real, ExecSpace>;
  using execution_space = ExecSpace;
  using memory_space = typename ExecSpace::memory_space;
  using center_view = Kokkos::View<const Real* [2], Kokkos::LayoutRight, memory_space>;
  using offset_view = Kokkos::View<const int*, memory_space>;

  ObstacleArray() = default;

  // Obstacles of diameter `diameter` centred at `centers` (folded into the box) in `box`, which must be
  // periodic along both axes.
  ObstacleArray(const Box<2, Real>& box, const std::vector<Vec<2, double>>& centers, Real diameter,
                Real cell_width)
      : ObstacleArray(box, std::vector<std::vector<Vec<2, double>>>{centers}, diameter, cell_width, SeveralArrays{}) {}

  // One independent array per entry of `arrays` (array a: the centres arrays[a]), all in `box`.
  static ObstacleArray from_arrays(const Box<2, Real>& box, const std::vector<std::vector<Vec<2, double>>>& arrays,
                                   Real diameter, Real cell_width) {
    return ObstacleArray(box, arrays, diameter, cell_width, SeveralArrays{});
  }

 private:
  struct SeveralArrays {};
  ObstacleArray(const Box<2, Real>& box, const std::vector<std::vector<Vec<2, double>>>& arrays, Real diameter,
                Real cell_width, SeveralArrays)
      {
    num_arrays_ = int(arrays.size());
    radius_ = Real(0.5) * diameter;
    if (arrays.empty()) throw std::invalid_argument("obstacle_array: no arrays (pass one, possibly empty)");
    obstacle_detail::require_positive(double(diameter), "obstacle_array: diameter");
    obstacle_detail::require_positive(double(cell_width), "obstacle_array: cell width");
    if (!box.periodic[0] || !box.periodic[1])
      throw std::invalid_argument("obstacle_array: the box must be periodic along both axes");
    const double cells[2] = {std::floor(double(box.length[0]) / double(cell_width)),
                             std::floor(double(box.length[1]) / double(cell_width))};
    if (cells[0] * cells[1] > 1.0e9)
      throw std::invalid_argument("obstacle_array: cell width " + std::to_string(cell_width) +
                                  " gives more than 1e9 cells; pass sigma_ob + w_ob");
    for (int d = 0; d < 2; ++d) {
      n_[d] = cells[d] < 1.0 ? 1 : int(cells[d]);
      lo_[d] = box.lo[d];
      length_[d] = box.length[d];
      inv_length_[d] = box.inv_length[d];
      inv_width_[d] = Real(n_[d]) / box.length[d];
    }
    min_width_ = std::min(box.length[0] / Real(n_[0]), box.length[1] / Real(n_[1]));
    max_ring_ = std::max(n_[0] / 2, n_[1] / 2);

    // Counting sort on the host, in (array, input) order within each cell: built once, deterministic.
    cells_per_array_ = n_[0] * n_[1];
    const std::size_t ncell = std::size_t(cells_per_array_) * arrays.size();
    std::vector<Vec<2, Real>> folded;
    std::vector<std::size_t> cell_of;
    std::vector<int> count(ncell + 1, 0);
    for (std::size_t a = 0; a < arrays.size(); ++a)
      for (std::size_t i = 0; i < arrays[a].size(); ++i) {
        Vec<2, Real> q;
        for (int d = 0; d < 2; ++d) {
          if (!std::isfinite(arrays[a][i][d]))
            throw std::invalid_argument("obstacle_array: centre " + std::to_string(i) + " of array " +
                                        std::to_string(a) + " is not finite");
          q[d] = Real(arrays[a][i][d]);
        }
        box.wrap(q);
        int c[2];
        home_cell(q, c);
        folded.push_back(q);
        cell_of.push_back(a * std::size_t(cells_per_array_) + std::size_t(c[0] + n_[0] * c[1]));
        ++count[cell_of.back() + 1];
      }
    if (folded.size() > std::size_t(1) << 30)
      throw std::invalid_argument("obstacle_array: more than 2^30 obstacles in all");
    num_obstacles_ = int(folded.size());
    for (std::size_t k = 0; k < ncell; ++k) count[k + 1] += count[k];

    Kokkos::View<int*, memory_space> offset("mesoflow::obstacle_array::cell_offset", ncell + 1);
    Kokkos::View<Real* [2], Kokkos::LayoutRight, memory_space> binned("mesoflow::obstacle_array::centers",
                                                                      folded.size());
    const auto offset_host = Kokkos::create_mirror_view(offset);
    const auto binned_host = Kokkos::create_mirror_view(binned);
    for (std::size_t k = 0; k <= ncell; ++k) offset_host(k) = count[k];
    array_first_ = Kokkos::View<int*, Kokkos::HostSpace>("mesoflow::obstacle_array::array_first", arrays.size() + 1);
    for (std::size_t a = 0; a <= arrays.size(); ++a) array_first_(a) = count[a * std::size_t(cells_per_array_)];
    for (std::size_t i = 0; i < folded.size(); ++i) {
      const int slot = count[cell_of[i]]++;
      for (int d = 0; d < 2; ++d) binned_host(slot, d) = folded[i][d];
    }
    Kokkos::deep_copy(offset, offset_host);
    Kokkos::deep_copy(binned, binned_host);
    cell_offset_owner_ = offset;
    centers_owner_ = binned;
    this->cell_offset_ = offset.data();
    this->centers_ = binned.data();
  }

 public:
  // Obstacles in all arrays together.
  int size() const { return num_obstacles_; }
  int num_arrays() const { return num_arrays_; }
  // Obstacles in array a (host).
  int size(int array) const { return num_obstacles_ == 0 ? 0 : array_first_(array + 1) - array_first_(array); }
  int cells(int d) const { return n_[d]; }
  // Centres folded into the box, in cell order (array by array).
  center_view centers() const { return centers_owner_; }
  // The small handle kernels capture (see ObstacleArrayQuery).
  KOKKOS_INLINE_FUNCTION Query query() const { return Query(*this); }
  // Array a's centres are centers()[first_obstacle(a), first_obstacle(a + 1)) (host).
  int first_obstacle(int array) const { return num_obstacles_ == 0 ? 0 : array_first_(array); }

  Real box_length(int d) const { return length_[d]; }

 private:
  void home_cell(const Vec<2, Real>& folded, int (&c)[2]) const {
    for (int d = 0; d < 2; ++d) {
      const int k = int(std::floor((folded[d] - lo_[d]) * inv_width_[d]));
      c[d] = k < 0 ? 0 : (k >= n_[d] ? n_[d] - 1 : k);
    }
  }

  using Query::num_arrays_;
  using Query::num_obstacles_;
  using Query::cells_per_array_;
  using Query::radius_;
  using Query::n_;
  using Query::lo_;
  using Query::length_;
  using Query::inv_length_;
  using Query::inv_width_;
  using Query::min_width_;
  using Query::max_ring_;
  offset_view cell_offset_owner_;  // the allocations the query's pointers point into
  center_view centers_owner_;
  Kokkos::View<int*, Kokkos::HostSpace> array_first_;  // first obstacle of each array, and the total
};

// nearest_surface(shapes, n, x), also calling visit(s) for every shape at signed distance < reach
// from x, in order: each wall shape is one surface of a pairwise term.
template <class Real, class Visit>
KOKKOS_INLINE_FUNCTION SurfacePoint<2, Real> walls_nearest_within(const Shape<2, Real>* shapes, int n,
                                                                  const Vec<2, Real>& x, Real reach, Visit&& visit) {
  SurfacePoint<2, Real> nearest = no_surface(x);
  for (int i = 0; i < n; ++i) {
    const SurfacePoint<2, Real> s = shapes[i].query(x);
    if (s.distance < reach) visit(s);
    if (s.distance < nearest.distance) nearest = s;
  }
  return nearest;
}

// Every surface of a 2D scene: walls (geometry.hpp shapes: wedges, half-planes, segments, disks…) and
// an optional obstacle array. nearest(x) is the nearer of the two — the d_i of eqs. 3 and 6 and the d
// of eq. 8. Copy it into kernels like an ObstacleArray. Default constructed, it has no surface.
template <class Real, class ExecSpace = Kokkos::DefaultExecutionSpace>
class Surfaces {
 public:
  using execution_space = ExecSpace;
  using shape_view = typename Geometry<2, Real, ExecSpace>::shape_view;

  Surfaces() = default;

  explicit Surfaces(const std::vector<Shape<2, Real>>& walls,
                    const ObstacleArray<Real, ExecSpace>& obstacles = ObstacleArray<Real, ExecSpace>())
      : obstacles_(obstacles) {
    const Geometry<2, Real, ExecSpace> geometry(walls);
    walls_ = geometry.shapes();
    num_walls_ = geometry.size();
  }

  explicit Surfaces(const ObstacleArray<Real, ExecSpace>& obstacles) : obstacles_(obstacles) {}

  int num_walls() const { return num_walls_; }
  shape_view walls() const { return walls_; }
  const ObstacleArray<Real, ExecSpace>& obstacles() const { return obstacles_; }

  // The form the surface-force loop calls (particle index unused here).
  KOKKOS_INLINE_FUNCTION SurfacePoint<2, Real> nearest(int, const Vec<2, Real>& x) const { return nearest(x); }

  // The nearest surface at x: walls first, an obstacle only if strictly nearer.
  KOKKOS_INLINE_FUNCTION SurfacePoint<2, Real> nearest(const Vec<2, Real>& x) const { return nearest_in_array(0, x); }

  // As nearest(x), with the obstacles of array `array` of a multi-array ObstacleArray.
  KOKKOS_INLINE_FUNCTION SurfacePoint<2, Real> nearest_in_array(int array, const Vec<2, Real>& x) const {
    const SurfacePoint<2, Real> wall = nearest_surface(walls_.data(), num_walls_, x);
    const SurfacePoint<2, Real> obstacle = obstacles_.nearest(array, x);
    return obstacle.distance < wall.distance ? obstacle : wall;
  }

  // The form of the surface-force loop for pairwise terms: nearest(x), calling visit(s) for every
  // wall and every obstacle at signed distance < reach from x (walls first, in order).
  template <class Visit>
  KOKKOS_INLINE_FUNCTION SurfacePoint<2, Real> nearest_within(int, const Vec<2, Real>& x, Real reach,
                                                              Visit&& visit) const {
    return nearest_within_in_array(0, x, reach, visit);
  }

  // As nearest_within, with the obstacles of array `array` of a multi-array ObstacleArray.
  template <class Visit>
  KOKKOS_INLINE_FUNCTION SurfacePoint<2, Real> nearest_within_in_array(int array, const Vec<2, Real>& x, Real reach,
                                                                       Visit&& visit) const {
    const SurfacePoint<2, Real> wall = walls_nearest_within(walls_.data(), num_walls_, x, reach, visit);
    const SurfacePoint<2, Real> obstacle = obstacles_.nearest_within(array, x, reach, visit);
    return obstacle.distance < wall.distance ? obstacle : wall;
  }

 private:
  shape_view walls_;
  int num_walls_ = 0;
  ObstacleArray<Real, ExecSpace> obstacles_;
};

// Surface query for the surface-force loop when each particle is a replica in its own obstacle
// array (soft-particle ensembles): the walls and array(i)'s obstacles for particle i.
template <class Real, class ExecSpace = Kokkos::DefaultExecutionSpace>
struct ParticleArraySurfaces {
  Surfaces<Real, ExecSpace> surfaces;
  Kokkos::View<const int*, ExecSpace> array;  // obstacle array of each particle

  KOKKOS_INLINE_FUNCTION SurfacePoint<2, Real> nearest(int i, const Vec<2, Real>& x) const {
    return surfaces.nearest_in_array(array(i), x);
  }

  template <class Visit>
  KOKKOS_INLINE_FUNCTION SurfacePoint<2, Real> nearest_within(int i, const Vec<2, Real>& x, Real reach,
                                                              Visit&& visit) const {
    return surfaces.nearest_within_in_array(array(i), x, reach, visit);
  }
};

}  // namespace mesoflow
