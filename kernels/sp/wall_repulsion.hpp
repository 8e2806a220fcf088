// wall_repulsion.hpp — repulsion between soft particles of several sizes and the walls of a scene
// (hopper study, eq. 3):
//   U_m^w = Σ_walls (ε_w/2)(1 − 2d_w/σ_m)² Θ(1 − 2d_w/σ_m),
// d_w the signed distance from the centre of particle m to a wall shape (kernels/common/geometry.hpp)
// and σ_m its diameter, from its type. Summed over every wall a particle overlaps: in a corner of the
// hopper (side wall and exit wall, or the rim of the orifice) each wall pushes, and the force stays
// continuous where the nearest wall changes. 2D and 3D; one pass over the particles, each summing its
// own walls (deterministic); returns the energy.
#pragma once

#include "kernels/common/geometry.hpp"
#include "kernels/common/kokkos_compat.hpp"
#include "kernels/common/particles.hpp"
#include "kernels/sp/pair_repulsion.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace mesoflow::sp {

// `sizes` gives σ_m by type (its diagonal σ_mm); ε_w ≥ 0.
template <int D, class Real, class ExecSpace>
double accumulate_wall_repulsion(Real epsilon_w, const SoftSphereRepulsion<Real>& sizes,
                                 const Geometry<D, Real, ExecSpace>& walls, const Particles<D, Real, ExecSpace>& p) {
  if (!(epsilon_w >= Real(0)) || !std::isfinite(double(epsilon_w)))
    throw std::invalid_argument("wall_repulsion: epsilon_w must be finite and >= 0, got " +
                                std::to_string(double(epsilon_w)));
  if (epsilon_w == Real(0) || walls.size() == 0) return 0.0;  // a term whose coefficient is zero costs nothing
  const auto shapes = walls.shapes();
  const int n_walls = walls.size();
  const auto x = p.x;
  const auto f = p.f;
  const auto type = p.type;
  double energy = 0;
  Kokkos::parallel_reduce(
      "mesoflow::sp::wall_repulsion", Kokkos::RangePolicy<ExecSpace>(0, p.size()),
      KOKKOS_LAMBDA(int i, double& acc) {
        const Vec<D, Real> xi = Vec<D, Real>::load(x, i);
        const Real diameter = sizes.contact[type(i)][type(i)];
        const Real two_over = Real(2) / diameter, reach = Real(0.5) * diameter;
        Vec<D, Real> fi = Vec<D, Real>::zero();
        for (int k = 0; k < n_walls; ++k) {
          const SurfacePoint<D, Real> s = shapes(k).query(xi);
          if (!(s.distance < reach)) continue;
          const Real overlap = Real(1) - two_over * s.distance;
          fi += (epsilon_w * two_over * overlap) * s.normal;
          acc += double(Real(0.5) * epsilon_w * overlap * overlap);
        }
        for (int d = 0; d < D; ++d) f(i, d) += fi[d];
      },
      energy);
  return energy;
}

}  // namespace mesoflow::sp
