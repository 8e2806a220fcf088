// split_body_force.hpp — the periodic-Poiseuille drive of a fully periodic MPC box (Backer et al.,
// J. Chem. Phys. 122, 154503 (2005)): the body acceleration +g along x in the lower half of the
// gradient axis, −g in the upper half. Applied as the velocity kick v_x ← v_x ± g h before a
// streaming step with g = 0, it is eq. (B.1) with a position-dependent g. The steady profile in each
// half is u(y) = ±(ρ g / 2η) y′ (L/2 − y′), which gives η from the fitted curvature without walls.
#pragma once

#include "../common/kernel_launch.hpp"
#include "collision_grid.hpp"

#include "kernels/common/kokkos_compat.hpp"

#include <stdexcept>
#include <string>

namespace mesoflow::mpc {

// x, v: particle rows; g: the acceleration magnitude; axis: the gradient axis (≠ 0, the flow axis).
template <int D, class Real, class ExecSpace>
void kick_split_body_force(const Kokkos::View<Real* [D], Kokkos::LayoutLeft, ExecSpace>& x,
                           const Kokkos::View<Real* [D], Kokkos::LayoutLeft, ExecSpace>& v, Real g, Real h,
                           const CollisionGrid<D, Real>& grid, int axis) {
  static_assert(D >= 2, "a split body force needs a gradient axis besides the flow axis");
  if (axis < 1 || axis >= D)
    throw std::invalid_argument("split body force: gradient axis must be in [1, " + std::to_string(D - 1) +
                                "] (axis 0 is the flow), got " + std::to_string(axis));
  const Real lo = grid.lo[axis], length = grid.length[axis], dv = g * h;
  mesoflow::launch::parallel_for(
      "mesoflow::mpc::split_body_force", Kokkos::RangePolicy<ExecSpace>(0, x.extent(0)), KOKKOS_LAMBDA(const int i) {
        Real s = (x(i, axis) - lo) / length;
        s -= kmath::floor(s);
        v(i, 0) += s < Real(0.5) ? dv : -dv;
      });
}

}  // namespace mesoflow::mpc
