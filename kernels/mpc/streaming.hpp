// streaming.hpp — the MPC streaming step, eq. (B.1): v ← v + g h (optional body acceleration g,
// the driving force of the paper's channel flow), then r ← r + h v. Positions are wrapped on the
// grid's periodic axes only; walled axes are left to the boundary code (bounce-back).
#pragma once

#include "../common/kernel_launch.hpp"
#include "collision_grid.hpp"

#include "kernels/common/kokkos_compat.hpp"

#include <cstddef>

namespace mesoflow::mpc {

// (Kokkos::Array's size is a std::size_t: written as std::size_t(D) so that D is deduced from the
// other arguments.)

// One particle's streaming step; positions wrap by one period (|h v| below the box length).
template <int D, class Real>
KOKKOS_INLINE_FUNCTION void stream_particle(Real (&x)[D], Real (&v)[D], Real h,
                                            const Kokkos::Array<Real, std::size_t(D)>& g,
                                            const CollisionGrid<D, Real>& grid) {
  for (int d = 0; d < D; ++d) {
    v[d] += g[d] * h;
    x[d] += h * v[d];
    if (grid.periodic[d]) {
      const Real lo = grid.lo[d], length = grid.length[d];
      if (x[d] >= lo + length) {
        x[d] -= length;
      } else if (x[d] < lo) {
        x[d] += length;
        if (x[d] >= lo + length) x[d] = lo;  // rounded up onto the far face: its periodic image
      }
    }
  }
}

template <int D, class Real, class ExecSpace>
void stream(const Kokkos::View<Real* [D], Kokkos::LayoutLeft, ExecSpace>& x,
            const Kokkos::View<Real* [D], Kokkos::LayoutLeft, ExecSpace>& v, Real h,
            const Kokkos::Array<Real, std::size_t(D)>& body_acceleration, const CollisionGrid<D, Real>& grid) {
  const auto g = body_acceleration;
  const auto cells = grid;
  mesoflow::launch::parallel_for(
      "mesoflow::mpc::stream", Kokkos::RangePolicy<ExecSpace>(0, x.extent(0)), KOKKOS_LAMBDA(const int i) {
        Real xi[D], vi[D];
        for (int d = 0; d < D; ++d) {
          xi[d] = x(i, d);
          vi[d] = v(i, d);
        }
        stream_particle(xi, vi, h, g, cells);
        for (int d = 0; d < D; ++d) {
          x(i, d) = xi[d];
          v(i, d) = vi[d];
        }
      });
}

}  // namespace mesoflow::mpc
