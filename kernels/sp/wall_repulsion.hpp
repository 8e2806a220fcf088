// wall_repulsion.hpp — repulsion between soft particles of several sizes and the walls of a scene
// (hopper study, eq. 3):
//   U_m^w = Σ_walls (ε_w/2)(1 − 2d_w/σ_m)² Θ(1 − 2d_w/σ_m),
// d_w the signed distance from the centre of particle m to a wall shape (kernels/common/geometry.hpp)
// and σ_m its diameter, from its type. Summed over every wall a particle overlaps: in a corner of the
// hopper (side wall and exit wall, or the rim of the orifice) each wall pushes, and the force stays
// continuous where the nearest wall changes. 2D and 3D; one pass over the particles, each summing its
// own walls (deterministic); returns the energy.
//
// Wall candidates (a Verlet list for walls): find_wall_candidates() marks, per particle, the walls
// within σ_m/2 + margin (one bit per wall, at most 32 walls); accumulate_wall_repulsion() with those
// marks queries only the marked walls and skips unmarked particles. The result equals the full sum
// bitwise as long as no particle has moved more than `margin` since the marks were made (a signed
// distance changes no faster than the particle moves); the hopper scene refreshes them at each
// neighbor-list rebuild with margin = skin, every particle then having moved less than skin/2.
#pragma once

#include "../common/kernel_launch.hpp"
#include "kernels/common/geometry.hpp"
#include "kernels/common/kokkos_compat.hpp"
#include "kernels/common/particles.hpp"
#include "kernels/sp/pair_repulsion.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace mesoflow::sp {

constexpr int max_candidate_walls = 32;  // one bit per wall in a candidate mask

namespace wall_detail {
template <int D, class Real, class ExecSpace>
void check_epsilon(Real epsilon_w) {
  if (!(epsilon_w >= Real(0)) || !std::isfinite(double(epsilon_w)))
    throw std::invalid_argument("wall_repulsion: epsilon_w must be finite and >= 0, got " +
                                std::to_string(double(epsilon_w)));
}
}  // namespace wall_detail

// candidates(i) ← bit k set when wall k is within σ_m/2 + margin of particle i (margin ≥ 0).
template <int D, class Real, class ExecSpace>
void find_wall_candidates(Real margin, const SoftSphereRepulsion<Real>& sizes,
                          const Geometry<D, Real, ExecSpace>& walls, const Particles<D, Real, ExecSpace>& p,
                          const Kokkos::View<unsigned*, ExecSpace>& candidates) {
  if (!(margin >= Real(0)) || !std::isfinite(double(margin)))
    throw std::invalid_argument("find_wall_candidates: margin must be finite and >= 0, got " +
                                std::to_string(double(margin)));
  if (walls.size() > max_candidate_walls)
    throw std::invalid_argument("find_wall_candidates: at most " + std::to_string(max_candidate_walls) +
                                " walls, got " + std::to_string(walls.size()));
  if (candidates.extent(0) != p.size())
    throw std::invalid_argument("find_wall_candidates: candidates must have one entry per particle");
  const auto shapes = walls.shapes();
  const int n_walls = walls.size();
  const auto x = p.x;
  const auto type = p.type;
  mesoflow::launch::parallel_for(
      "mesoflow::sp::wall_candidates", Kokkos::RangePolicy<ExecSpace>(0, p.size()), KOKKOS_LAMBDA(int i) {
        const Vec<D, Real> xi = Vec<D, Real>::load(x, i);
        const Real reach = Real(0.5) * sizes.contact[type(i)][type(i)] + margin;
        unsigned mask = 0;
        for (int k = 0; k < n_walls; ++k)
          if (shapes(k).query(xi).distance < reach) mask |= 1u << k;
        candidates(i) = mask;
      });
}

namespace wall_detail {
template <bool use_candidates, int D, class Real, class ExecSpace>
double wall_repulsion(Real epsilon_w, const SoftSphereRepulsion<Real>& sizes, const Geometry<D, Real, ExecSpace>& walls,
                      const Particles<D, Real, ExecSpace>& p, const Kokkos::View<unsigned*, ExecSpace>& candidates) {
  const auto shapes = walls.shapes();
  const int n_walls = walls.size();
  const auto x = p.x;
  const auto f = p.f;
  const auto type = p.type;
  double energy = 0;
  mesoflow::launch::parallel_reduce(
      "mesoflow::sp::wall_repulsion", Kokkos::RangePolicy<ExecSpace>(0, p.size()),
      KOKKOS_LAMBDA(int i, double& acc) {
        unsigned mask = ~0u;
        // `if`, not `if constexpr`: nvcc rejects a KOKKOS_LAMBDA whose first use of a captured
        // variable is inside `if constexpr` (the condition is a compile-time constant all the same).
        if (use_candidates) {
          mask = candidates(i);
          if (mask == 0u) return;
        }
        const Vec<D, Real> xi = Vec<D, Real>::load(x, i);
        const Real diameter = sizes.contact[type(i)][type(i)];
        const Real two_over = Real(2) / diameter, reach = Real(0.5) * diameter;
        Vec<D, Real> fi = Vec<D, Real>::zero();
        for (int k = 0; k < n_walls; ++k) {
          if (!(mask & (1u << (k & 31)))) continue;
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
}  // namespace wall_detail

// `sizes` gives σ_m by type (its diagonal σ_mm); ε_w ≥ 0. Every wall is queried for every particle.
template <int D, class Real, class ExecSpace>
double accumulate_wall_repulsion(Real epsilon_w, const SoftSphereRepulsion<Real>& sizes,
                                 const Geometry<D, Real, ExecSpace>& walls, const Particles<D, Real, ExecSpace>& p) {
  wall_detail::check_epsilon<D, Real, ExecSpace>(epsilon_w);
  if (epsilon_w == Real(0) || walls.size() == 0) return 0.0;  // a term whose coefficient is zero costs nothing
  return wall_detail::wall_repulsion<false>(epsilon_w, sizes, walls, p, Kokkos::View<unsigned*, ExecSpace>());
}

// Only the walls marked in `candidates` (find_wall_candidates, see the file comment).
template <int D, class Real, class ExecSpace>
double accumulate_wall_repulsion(Real epsilon_w, const SoftSphereRepulsion<Real>& sizes,
                                 const Geometry<D, Real, ExecSpace>& walls, const Particles<D, Real, ExecSpace>& p,
                                 const Kokkos::View<unsigned*, ExecSpace>& candidates) {
  wall_detail::check_epsilon<D, Real, ExecSpace>(epsilon_w);
  if (epsilon_w == Real(0) || walls.size() == 0) return 0.0;
  if (walls.size() > max_candidate_walls || candidates.extent(0) != p.size())
    throw std::invalid_argument("wall_repulsion: candidates must come from find_wall_candidates for these particles");
  return wall_detail::wall_repulsion<true>(epsilon_w, sizes, walls, p, candidates);
}

}  // namespace mesoflow::sp
