// collision_grid.hpp — the MPC collision cells of edge Δx with a random shift every step
// (Appendix B; Ihle & Kroll, PRE 63, 020201 (2001): the shift restores Galilean invariance).
//
// Cell k on axis d covers [lo_d − shift_d + k a, lo_d − shift_d + (k+1) a). A periodic axis has
// length/a cells and wraps; a walled axis has ceil(length/a) + 1 cells, so that the shifted grid
// still covers [lo_d, lo_d + length_d]. Cells are numbered with axis 0 fastest.
#pragma once

#include "kernels/common/kokkos_compat.hpp"
#include "kernels/common/random.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

namespace mesoflow::mpc {

// Random-stream tags of the MPC kernels (stream_tag::user and up are free for modules).
// Real particles' thermostat velocities use particle_stream (tag `particle`), cells' rotation axes
// use cell_stream (tag `cell`).
namespace mpc_stream_tag {
constexpr std::uint32_t grid_shift = stream_tag::user + 8;        // (seed, step, grid_shift, 0)
constexpr std::uint32_t virtual_particle = stream_tag::user + 9;  // (seed, step, virtual_particle, row)
}  // namespace mpc_stream_tag

template <int D, class Real>
struct CollisionGrid {
  Real a;                             // cell edge Δx
  Real inv_a;                         // 1 / a
  Kokkos::Array<Real, D> lo, length;  // domain [lo, lo + length) per axis
  Kokkos::Array<int, D> periodic;     // 1 periodic, 0 walled
  Kokkos::Array<int, D> n;            // cells per axis
  Kokkos::Array<Real, D> shift;       // current shift, components in [0, a)

  int num_cells() const {
    int total = 1;
    for (int d = 0; d < D; ++d) total *= n[d];
    return total;
  }

  // Exact floor for |t| < 2^31 without a libm call.
  KOKKOS_INLINE_FUNCTION static int floor_to_int(Real t) {
    const int k = static_cast<int>(t);
    return k - (t < static_cast<Real>(k) ? 1 : 0);
  }

  // Cell coordinate along axis d of the coordinate x and its offset from the cell's lower face,
  // in [0, a). The offset is computed as (x − lo + shift) − k a and the cell is corrected by one
  // where rounding put the quotient on the other side of a face, so the cell and the offset always
  // agree. Periodic axes wrap the cell by one period (positions within one box length of the
  // domain); walled axes clamp it into [0, n) (a particle outside the walls, which the boundary
  // code moves back, keeps an offset outside [0, a)).
  KOKKOS_FORCEINLINE_FUNCTION int axis_cell(Real x, int d, Real& local) const {
    const Real u = (x - lo[d]) + shift[d];
    int k = floor_to_int(u * inv_a);
    Real r = u - static_cast<Real>(k) * a;
    if (r < Real(0)) {
      --k;
      r = u - static_cast<Real>(k) * a;
    } else if (r >= a) {
      ++k;
      r = u - static_cast<Real>(k) * a;
    }
    if (periodic[d]) {
      if (k >= n[d]) k -= n[d];
      else if (k < 0) k += n[d];
    } else if (k < 0) {
      r += static_cast<Real>(k) * a;
      k = 0;
    } else if (k >= n[d]) {
      r += static_cast<Real>(k - (n[d] - 1)) * a;
      k = n[d] - 1;
    }
    local = r;
    return k;
  }

  // Cell index of the point x; local = x − the cell's lower corner (with the periodic image of the
  // corner nearest x, so local is in [0, a)^D inside the domain).
  KOKKOS_FORCEINLINE_FUNCTION int locate(const Real (&x)[D], Real (&local)[D]) const {
    int cell = axis_cell(x[D - 1], D - 1, local[D - 1]);
    for (int d = D - 2; d >= 0; --d) cell = cell * n[d] + axis_cell(x[d], d, local[d]);
    return cell;
  }

  // Lower corner of a cell, unwrapped: lo − shift + k a per axis.
  KOKKOS_INLINE_FUNCTION void lower_corner(int cell, Real (&corner)[D]) const {
    for (int d = 0; d < D; ++d) {
      const int k = cell % n[d];
      cell /= n[d];
      corner[d] = lo[d] - shift[d] + static_cast<Real>(k) * a;
    }
  }

  // shift_d uniform in [0, a) from the stream (seed, step, grid_shift, 0); host side.
  void draw_shift(std::uint64_t seed, std::uint64_t step) {
    RandomStream rs(seed, step, mpc_stream_tag::grid_shift, 0);
    for (int d = 0; d < D; ++d) shift[d] = rs.uniform_in<Real>(Real(0), a);
  }
};

// A grid of cells of edge a over [lo, lo + length), shift zero. Periodic axes need length a
// multiple of a (to relative round-off 16 ε); throws std::invalid_argument naming the axis otherwise.
template <int D, class Real>
CollisionGrid<D, Real> make_collision_grid(Real a, const Kokkos::Array<Real, D>& lo,
                                           const Kokkos::Array<Real, D>& length,
                                           const Kokkos::Array<int, D>& periodic) {
  if (!(a > Real(0)) || !std::isfinite(double(a)))
    throw std::invalid_argument("collision grid: cell size a must be > 0, got " + std::to_string(double(a)));
  CollisionGrid<D, Real> g;
  g.a = a;
  g.inv_a = Real(1) / a;
  for (int d = 0; d < D; ++d) {
    if (!(length[d] > Real(0)) || !std::isfinite(double(length[d])))
      throw std::invalid_argument("collision grid: length[" + std::to_string(d) + "] must be > 0, got " +
                                  std::to_string(double(length[d])));
    g.lo[d] = lo[d];
    g.length[d] = length[d];
    g.periodic[d] = periodic[d] ? 1 : 0;
    g.shift[d] = Real(0);
    const double cells = double(length[d]) / double(a);
    if (cells > 1.0e8)
      throw std::invalid_argument("collision grid: length[" + std::to_string(d) + "]/a = " + std::to_string(cells) +
                                  " cells, more than 1e8");
    if (g.periodic[d]) {
      const double whole = std::round(cells);
      if (whole < 1.0 || std::fabs(cells - whole) > 16.0 * std::numeric_limits<Real>::epsilon() * whole)
        throw std::invalid_argument("collision grid: periodic axis " + std::to_string(d) + " has length " +
                                    std::to_string(double(length[d])) + ", not a multiple of the cell size a = " +
                                    std::to_string(double(a)));
      g.n[d] = int(whole);
    } else {
      g.n[d] = int(std::ceil(cells - 16.0 * std::numeric_limits<Real>::epsilon() * cells)) + 1;
    }
  }
  return g;
}

// The same with D and Real deduced from the arguments (Kokkos::Array's size is a std::size_t, which
// an int template parameter does not deduce from).
template <class Real, std::size_t N>
CollisionGrid<int(N), Real> make_collision_grid(Real a, const Kokkos::Array<Real, N>& lo,
                                                const Kokkos::Array<Real, N>& length,
                                                const Kokkos::Array<int, N>& periodic) {
  return make_collision_grid<int(N), Real>(a, lo, length, periodic);
}

}  // namespace mesoflow::mpc
