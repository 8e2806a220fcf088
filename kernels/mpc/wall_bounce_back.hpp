// wall_bounce_back.hpp — no-slip planar walls for the MPC solvent: bounce-back of the streaming
// step, v' = −v (Appendix B, "v' = −v + 2 v_b" with resting walls v_b = 0; Lamura et al.,
// Europhys. Lett. 56, 319 (2001)).
//
// The walls bound axis 1 (y) of a CollisionGrid at y = lo_1 (bottom) and y = lo_1 + length_1
// (top); the other axes are periodic (x the channel axis, z in 3D). bounce_back() runs after
// mpc::stream, which already moved every particle by h v along a straight line (the body force
// kick comes first, so the old position is exactly x − h v). A particle found beyond a wall
// crossed it a time t_r = (y − y_wall)/v_y ago; it is returned along its path: back to the
// crossing point, velocity reversed, streamed for the remaining t_r,
//   x' = x − 2 t_r v,   v' = −v,
// which puts it at the mirror image y' = 2 y_wall − y across the wall. Its momentum change
// −2 m v goes to the wall (momentum(): Σ 2 m v per wall since construction or reset_momentum(),
// the time integral of the force the fluid exerts on the wall — the wall shear stress times area
// is its x component per unit time).
//
// Per-wall sums are Kokkos reductions (static schedule): deterministic at a fixed thread count.
#pragma once

#include "../common/kernel_launch.hpp"
#include "kernels/common/kokkos_compat.hpp"
#include "kernels/common/reductions.hpp"
#include "kernels/mpc/collision_grid.hpp"

#include <array>
#include <stdexcept>
#include <string>

namespace mesoflow::mpc {

// The walls' geometry (device-copyable): y ∈ [bottom, top] is the inside.
template <int D, class Real>
struct ChannelWallPlanes {
  Real bottom, top;
  Kokkos::Array<Real, D> lo, length;  // periodic box of the other axes (for wrapping)

  // Returns the particle to the channel (see the file comment) and the wall it bounced on, 0
  // (bottom) or 1 (top), or −1 if it is inside. A particle beyond a wall that is not moving
  // towards it (impossible after a streaming step from inside) is mirrored with t_r = 0.
  KOKKOS_INLINE_FUNCTION int bounce(Real (&x)[D], Real (&v)[D], Real h) const {
    int wall = -1;
    Real y_wall = Real(0);
    if (x[1] < bottom) {
      wall = 0;
      y_wall = bottom;
    } else if (x[1] > top) {
      wall = 1;
      y_wall = top;
    }
    if (wall < 0) return wall;
    Real t_r = Real(0);
    if ((wall == 0 && v[1] < Real(0)) || (wall == 1 && v[1] > Real(0))) {
      t_r = (x[1] - y_wall) / v[1];
      t_r = t_r > h ? h : t_r;
    }
    const Real penetration = x[1] - y_wall;
    for (int d = 0; d < D; ++d) {
      if (d != 1) {
        x[d] -= Real(2) * t_r * v[d];
        x[d] -= length[d] * kmath::floor((x[d] - lo[d]) / length[d]);
        if (x[d] >= lo[d] + length[d]) x[d] = lo[d];
      }
      v[d] = -v[d];
    }
    x[1] = y_wall - penetration;
    return wall;
  }
};

template <int D, class Real, class ExecSpace>
class ChannelWalls {
 public:
  using vector_view = Kokkos::View<Real* [D], Kokkos::LayoutLeft, ExecSpace>;
  // Row 0: bottom wall, row 1: top wall; momentum taken up, in units of m Δx/τ.
  using momentum_view = Kokkos::View<double[2][D], ExecSpace>;

  // Walls of a grid whose axis 1 is walled and every other axis periodic; `mass` is the solvent
  // particle mass m.
  ChannelWalls(const CollisionGrid<D, Real>& grid, Real mass)
      : mass_(mass),
        momentum_("mesoflow::mpc::walls::momentum"),
        scratch_("mesoflow::mpc::walls::scratch") {
    if (grid.periodic[1]) throw std::invalid_argument("channel walls: axis 1 of the grid must be walled");
    for (int d = 0; d < D; ++d)
      if (d != 1 && !grid.periodic[d])
        throw std::invalid_argument("channel walls: axis " + std::to_string(d) + " of the grid must be periodic");
    if (!(mass > Real(0))) throw std::invalid_argument("channel walls: mass must be > 0");
    planes_.bottom = grid.lo[1];
    planes_.top = grid.lo[1] + grid.length[1];
    for (int d = 0; d < D; ++d) {
      planes_.lo[d] = grid.lo[d];
      planes_.length[d] = grid.length[d];
    }
  }

  // Bounce-back of every row of (x, v) after a streaming step of length h; adds the momentum
  // the walls take up to momentum().
  void bounce_back(const vector_view& x, const vector_view& v, Real h) const {
    const auto planes = planes_;
    const double two_m = 2.0 * double(mass_);
    accumulate("mesoflow::mpc::walls::bounce_back", int(x.extent(0)),
               KOKKOS_LAMBDA(int i, double(&acc)[2 * D]) {
                 Real xi[D], vi[D];
                 for (int d = 0; d < D; ++d) {
                   xi[d] = x(i, d);
                   vi[d] = v(i, d);
                 }
                 const int wall = planes.bounce(xi, vi, h);
                 if (wall < 0) return;
                 for (int d = 0; d < D; ++d) {
                   acc[wall * D + d] -= two_m * double(vi[d]);  // −Δp = −m (v' − v) = −2 m v'
                   x(i, d) = xi[d];
                   v(i, d) = vi[d];
                 }
               });
  }

  // Adds Σ_i acc_i to momentum() for i in [0, n), where body(i, double (&acc)[2 D]) adds item i's
  // contribution to the bottom (acc[0..D)) and top (acc[D..2D)) walls. One reduction (static
  // schedule, deterministic at a fixed thread count) and a one-item kernel; no host transfer.
  template <class Body>
  void accumulate(const std::string& label, int n, const Body& body) const {
    mesoflow::launch::parallel_reduce(label, Kokkos::RangePolicy<ExecSpace>(0, n), SumArrayFunctor<2 * D, Body>{body},
                            scratch_);
    const auto total = momentum_;
    const auto s = scratch_;
    mesoflow::launch::parallel_for(
        "mesoflow::mpc::walls::add_momentum", Kokkos::RangePolicy<ExecSpace>(0, 1), KOKKOS_LAMBDA(int) {
          for (int w = 0; w < 2; ++w)
            for (int d = 0; d < D; ++d) total(w, d) += s().v[w * D + d];
        });
  }

  // Host copy of the accumulated momentum (a transfer: for output steps, not every step).
  std::array<std::array<double, D>, 2> momentum() const {
    const auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), momentum_);
    std::array<std::array<double, D>, 2> out;
    for (int w = 0; w < 2; ++w)
      for (int d = 0; d < D; ++d) out[w][d] = h(w, d);
    return out;
  }
  void reset_momentum() const { Kokkos::deep_copy(momentum_, 0.0); }

 private:
  ChannelWallPlanes<D, Real> planes_;
  Real mass_;
  momentum_view momentum_;
  Kokkos::View<SumArray<2 * D>, ExecSpace> scratch_;
};

}  // namespace mesoflow::mpc
