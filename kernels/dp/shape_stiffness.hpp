// shape_stiffness.hpp — the stiffness of kernels/dp/stability.hpp that depends most on the
// polygon's current shape, measured on the device:
//   area mode (capillary eq. 1): the Hessian of (k_a/2)(a − a0)² is, up to a term ∝ (a − a0), the
//     rank-one k_a ∇a ∇aᵀ, with ∇_i a = ½ J (r_{i+1} − r_{i−1}) (J: rotation by −90°), so its
//     eigenvalue is k_a Σ_i |∇_i a|² = (k_a/4) Σ_i |r_{i+1} − r_{i−1}|². The static estimate takes
//     the regular polygon's Σ|∇a|² ≈ P l0; a droplet whose vertices slide along its interface
//     (weak segment springs, no drag) leaves some edges long and Σ|∇a|² grows: 3.9 P l0 measured
//     at K_a = 10⁶, Γ = 0.16, K_l/Γ = 10⁻³ resting on a wall after 2.4 t0, where the run turned
//     unstable at the static limit's Δt (docs/stability.md).
// The line-tension mode of a crowded edge (ω² = 4γ/(l m)) is left to the static estimate's l0/20
// allowance: the force of line tension on a vertex is γ times a sum of unit vectors, bounded
// whatever l is, so a crowded edge jitters with an energy of order γ l instead of growing — the
// paper's runs pass the orifice with edges of 10⁻⁵ l0 and stay bounded — whereas the area force
// k_a (a − a0) ∇a grows with the displacement.
// measure_area_gradient_squared returns the largest Σ|∇a|² over the bodies: one reduction over the
// bodies, cheap enough to run every hundred steps.
#pragma once

#include "../common/kernel_launch.hpp"
#include "polygons.hpp"

#include "kernels/common/kokkos_compat.hpp"
#include "kernels/common/particles.hpp"

namespace mesoflow::dp {

// Σ_i |∇_i a|² = ¼ Σ_i |r_{i+1} − r_{i−1}|² of body b (device code; offset: the bodies' first
// vertices, x: positions).
template <class Offset, class X>
KOKKOS_INLINE_FUNCTION double body_area_gradient_squared(const Offset& offset, const X& x, int b) {
  const int begin = offset(b), n = offset(b + 1) - begin;
  double sum = 0;
  for (int i = begin; i < begin + n; ++i) {
    const int next = next_vertex(i, 1, begin, n), prev = prev_vertex(i, 1, begin, n);
    const double dx = double(x(next, 0)) - double(x(prev, 0));
    const double dy = double(x(next, 1)) - double(x(prev, 1));
    sum += 0.25 * (dx * dx + dy * dy);
  }
  return sum;
}

namespace shape_stiffness_detail {
struct Unweighted {
  KOKKOS_INLINE_FUNCTION double operator()(int) const { return 1.0; }
};
template <class ExecSpace>
struct PerBodyWeight {
  Kokkos::View<double*, ExecSpace> weight;
  KOKKOS_INLINE_FUNCTION double operator()(int b) const { return weight(b); }
};

// The largest weight(b) Σ_i |∇_i a|² over the bodies.
template <class Real, class ExecSpace, class Weight>
double largest_weighted(const Polygons<Real, ExecSpace>& polygons, const Particles<2, Real, ExecSpace>& p,
                        const Weight& weight) {
  const auto offset = polygons.offset;
  const auto x = p.x;
  double largest_sum = 0;
  mesoflow::launch::parallel_reduce(
      "mesoflow::dp::area_gradient_squared", Kokkos::RangePolicy<ExecSpace>(0, polygons.num_bodies()),
      KOKKOS_LAMBDA(const int b, double& largest) {
        const double sum = body_area_gradient_squared(offset, x, b) * weight(b);
        if (sum > largest) largest = sum;
      },
      Kokkos::Max<double>(largest_sum));
  return largest_sum;
}
}  // namespace shape_stiffness_detail

// The largest Σ_i |∇_i a|² (length²) over the bodies.
template <class Real, class ExecSpace>
double measure_area_gradient_squared(const Polygons<Real, ExecSpace>& polygons,
                                     const Particles<2, Real, ExecSpace>& p) {
  return shape_stiffness_detail::largest_weighted(polygons, p, shape_stiffness_detail::Unweighted{});
}

// The largest w_b Σ_i |∇_i a|² over the bodies, w_b = weight(b): bodies stepped at their own Δt_b
// weigh (Δt_b/Δt_ref)², so that one comparison at Δt_ref checks every body at its own step.
template <class Real, class ExecSpace>
double measure_area_gradient_squared(const Polygons<Real, ExecSpace>& polygons, const Particles<2, Real, ExecSpace>& p,
                                     const Kokkos::View<double*, ExecSpace>& weight) {
  return shape_stiffness_detail::largest_weighted(polygons, p, shape_stiffness_detail::PerBodyWeight<ExecSpace>{weight});
}

}  // namespace mesoflow::dp
