// wall_mirror_particles.hpp — virtual wall particles by reflection. Where a wall cuts a collision
// cell, the part of the cell inside the wall is filled with the mirror images of the solvent
// particles in the adjacent slab of fluid, with reversed velocities,
//   y' = 2 y_wall − y,   v' = 2 u_wall − v = −v   (walls at rest).
// This is the same reflection that bounce-back applies to a particle crossing the wall
// (wall_bounce_back.hpp).
//
// Appendix B's alternative (Lamura et al., Europhys. Lett. 56, 319 (2001); WallVirtualParticles in
// virtual_particles.hpp) fills that part with Maxwell–Boltzmann particles at the wall velocity:
// a fluid at rest inside the wall. The no-slip extension of a sheared fluid is not at rest there:
// it keeps its velocity gradient through the wall plane, u(−y) = −u(y). With particles at rest,
// the mean velocity of a cell cut at depth s is too large by ≈ u'(0) s²/2a. The no-slip plane
// moves ≈ 0.1a into the wall, a slip of 3.7–4.1% of u_max in the Poiseuille test of
// tests/mpc/test_mpc_walls.cpp. The mirror images carry the gradient through the wall plane; the
// same test measures a slip of −0.03 … +0.42% of u_max with them (five seeds), and η 0.6% closer
// to eq. (B.3) (+1.7 … +2.5% against +2.3 … +3.0%).
// (Bolintineanu et al., PRE 86, 066703 (2012), analyse the residual slip of the Lamura scheme.)
//
// Geometry. With the grid shift s = shift_1, the bottom row of cells covers y ∈ [lo − s, lo − s + a).
// Its part [lo − s, lo) lies in the wall and receives the images of the solvent in [lo, lo + s).
// The row containing the top wall y_t = lo + L reaches y_t + w_t (w_t as in virtual_particles.hpp).
// Its part (y_t, y_t + w_t) receives the images of (y_t − w_t, y_t]. Each image lies in its source
// particle's column of cells, across the wall plane. The images have the solvent's own density and
// temperature.
//
// Count. The number of images depends on the data. One parallel_scan over the solvent selects the
// slab particles in index order (the same rows for any thread count) and returns their number to
// the host: one scalar per step. The expected count is n (s + w_t)/a per column of cells, at most
// 2n. The capacity adds ten standard deviations of a Poisson count to that bound. A larger count
// is an error, never truncated.
#pragma once

#include "../common/kernel_launch.hpp"
#include "kernels/common/kokkos_compat.hpp"
#include "kernels/mpc/collision_grid.hpp"
#include "kernels/mpc/wall_bounce_back.hpp"

#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>

namespace mesoflow::mpc {

template <int D, class Real, class ExecSpace>
class WallMirrorParticles {
 public:
  using vector_view = Kokkos::View<Real* [D], Kokkos::LayoutLeft, ExecSpace>;

  // `density`: n, solvent particles per cell (a^D); `mass`: the solvent's m. The walls are those of
  // ChannelWalls on `grid` (axis 1 walled), at least two cells apart.
  WallMirrorParticles(const CollisionGrid<D, Real>& grid, Real density, Real mass)
      : mass_(mass), capacity_(capacity(grid, checked_density(density))) {
    if (!(mass > Real(0)) || !std::isfinite(double(mass)))
      throw std::invalid_argument("wall mirror particles: mass must be finite and > 0, got " +
                                  std::to_string(double(mass)));
    if (grid.periodic[1]) throw std::invalid_argument("wall mirror particles: axis 1 of the grid must be walled");
    if (!(double(grid.length[1]) >= 2 * double(grid.a)))
      throw std::invalid_argument("wall mirror particles: channel width " + std::to_string(double(grid.length[1])) +
                                  " must be at least two cells, " + std::to_string(2 * double(grid.a)) +
                                  " (the two source slabs must not overlap)");
    v_before_ = vector_view(Kokkos::ViewAllocateWithoutInitializing("mesoflow::mpc::wall_mirror::v_before"),
                            capacity_);
  }

  // Rows needed at most: 2n per column of cells (s + w_t ≤ 2a) plus ten Poisson deviations.
  static std::size_t capacity(const CollisionGrid<D, Real>& grid, Real density) {
    checked_density(density);
    std::size_t columns = 1;
    for (int d = 0; d < D; ++d)
      if (d != 1) columns *= std::size_t(grid.n[d]);
    const double mean = 2.0 * double(density) * double(columns);
    return std::size_t(std::ceil(mean + 10.0 * std::sqrt(mean))) + 32;
  }
  std::size_t capacity() const { return capacity_; }
  // Images made by the last generate().
  std::size_t count() const { return count_; }

  // Fills rows [offset, offset + count()) of xv, vv with the images of the solvent rows
  // [0, n_solvent) of (x, v), for the current shift of `grid`, and returns count().
  std::size_t generate(const CollisionGrid<D, Real>& grid, const vector_view& x, const vector_view& v,
                       std::size_t n_solvent, const vector_view& xv, const vector_view& vv, std::size_t offset) {
    const double a = double(grid.a), L = double(grid.length[1]), s = double(grid.shift[1]), y0 = double(grid.lo[1]);
    const double k_top = std::floor((L + s) / a);
    double w_top = (k_top + 1) * a - s - L;
    if (!(w_top < a)) w_top = 0;
    const Real bottom = grid.lo[1], top = Real(y0 + L);
    // Source slabs: [bottom, bottom_edge) and (top_edge, top].
    const Real bottom_edge = Real(y0 + s), top_edge = Real(y0 + L - w_top);
    const bool has_top = w_top > 0;
    const std::size_t rows = xv.extent(0) < vv.extent(0) ? xv.extent(0) : vv.extent(0);
    const std::size_t room = offset < rows ? rows - offset : 0;
    const std::size_t limit = room < capacity_ ? room : capacity_;
    const auto vb = v_before_;
    std::size_t total = 0;
    mesoflow::launch::parallel_scan(
        "mesoflow::mpc::wall_mirror::generate", Kokkos::RangePolicy<ExecSpace>(0, n_solvent),
        KOKKOS_LAMBDA(const std::size_t i, std::size_t& slot, const bool final) {
          const Real y = x(i, 1);
          const bool near_bottom = y < bottom_edge;
          const bool near_top = has_top && y > top_edge;
          if (!near_bottom && !near_top) return;
          if (final && slot < limit) {
            const std::size_t q = offset + slot;
            for (int d = 0; d < D; ++d) {
              xv(q, d) = d == 1 ? (near_bottom ? Real(2) * bottom - y : Real(2) * top - y) : x(i, d);
              vv(q, d) = -v(i, d);
              vb(slot, d) = -v(i, d);
            }
          }
          ++slot;
        },
        total);
    if (total > limit)
      throw std::length_error("wall mirror particles: " + std::to_string(total) +
                              " solvent particles lie within the cut depth of the walls, more than the " +
                              std::to_string(limit) + " rows available (capacity " + std::to_string(capacity_) +
                              " for the density n): the solvent is far denser near a wall than n");
    count_ = total;
    middle_ = Real(y0 + 0.5 * L);
    return total;
  }

  // After the collision: the momentum change of rows [offset, offset + count()) of vv goes to the
  // wall each image lies behind (ChannelWalls::momentum()).
  void transfer(const vector_view& xv, const vector_view& vv, std::size_t offset,
                const ChannelWalls<D, Real, ExecSpace>& walls) const {
    const auto vb = v_before_;
    const double m = double(mass_);
    const Real middle = middle_;
    walls.accumulate("mesoflow::mpc::wall_mirror::transfer", int(count_),
                     KOKKOS_LAMBDA(int q, double(&acc)[2 * D]) {
                       const int wall = xv(offset + q, 1) < middle ? 0 : 1;
                       for (int d = 0; d < D; ++d)
                         acc[wall * D + d] += m * (double(vv(offset + q, d)) - double(vb(q, d)));
                     });
  }

 private:
  static Real checked_density(Real density) {
    if (!(density > Real(0)) || !std::isfinite(double(density)))
      throw std::invalid_argument("wall mirror particles: density n must be finite and > 0, got " +
                                  std::to_string(double(density)));
    return density;
  }

  Real mass_;
  std::size_t capacity_ = 0, count_ = 0;
  Real middle_ = Real(0);
  vector_view v_before_;
};

}  // namespace mesoflow::mpc
