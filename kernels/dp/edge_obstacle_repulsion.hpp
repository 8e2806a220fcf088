// edge_obstacle_repulsion.hpp — repulsion between the edges of deformable polygons and circular
// obstacles: the harmonic law of eq. 3 (capillary-droplet study) with the distance taken from the
// obstacle's surface to the whole edge, a circulo-line of width δ, instead of to the vertex centres:
//   U = Σ_edges e Σ_obstacles o (ε_w/2)(1 − 2d_eo/δ)² Θ(1 − 2d_eo/δ),
//   d_eo = min_{0≤t≤1} |r_i + t (r_i+1 − r_i) − c_o| − σ_ob/2,
// e the edge from vertex i to i+1, c_o the obstacle centre. The force at the foot q = r_i + t l of the
// perpendicular (or at the nearer end, where t is clamped) is f = (2ε_w/δ)(1 − 2d/δ) u, u the unit
// vector from c_o to q; vertex i gets (1 − t) f and vertex i+1 gets t f, the exact gradient (envelope
// theorem: ∂d/∂r_i = (1 − t) u, ∂d/∂r_i+1 = t u; d is C¹ away from the segment itself).
//
// Why edges (a deviation from eq. 3, on by a scene flag, docs/droplets.md finding 7): with the
// vertices alone, only the segment springs hold two neighbouring vertices together, so below
// K_l·N_v ≈ 1.2 an obstacle pressed by the droplet's weight pushes two vertices apart and passes
// through the interface. Against a whole edge it meets the same repulsion wherever it touches, so
// the droplet's outline stays impenetrable at the paper's K_l/Γ = 10⁻³. On a straight run of edges
// the two laws give the same contact stiffness per unit length; at a vertex touched from outside
// both of its edges clamp to it, which doubles the stiffness there (kernels/dp/stability.hpp counts
// two contacts per vertex in this mode).
//
// One pass over the vertices; vertex i sums its own force from its two edges (i−1 → i and i → i+1),
// so each edge is evaluated by both its vertices: deterministic, no atomics. Edge i → i+1's energy is
// counted at vertex i. Obstacles come from a BodyObstacleQuery (body_obstacle_list.hpp): exact, the
// candidates or the grid. Positions are unwrapped (a droplet is never split across the box).
#pragma once

#include "../common/kernel_launch.hpp"
#include "polygons.hpp"

#include "kernels/common/body_obstacle_list.hpp"
#include "kernels/common/harmonic_surface_repulsion.hpp"
#include "kernels/common/kokkos_compat.hpp"
#include "kernels/common/particles.hpp"
#include "kernels/common/vec.hpp"

namespace mesoflow::dp {

namespace edge_obstacle_detail {

// The contact of edge a → a + l with an obstacle whose centre is at a + ac (radius R): false without
// one; otherwise the force f on the edge's foot point, the foot's parameter t and the energy.
template <class Real>
KOKKOS_INLINE_FUNCTION bool contact(const Vec<2, Real>& l, const Vec<2, Real>& ac, Real radius,
                                    const HarmonicSurfaceRepulsion<Real>& law, Vec<2, Real>& f, Real& t,
                                    Real& energy) {
  const Real l2 = norm2(l);
  t = l2 > Real(0) ? dot(ac, l) / l2 : Real(0);
  t = t < Real(0) ? Real(0) : (t > Real(1) ? Real(1) : t);
  const Vec<2, Real> gap = t * l - ac;  // from the centre to the foot
  const Real rho2 = norm2(gap);
  if (!(rho2 > Real(0))) return false;  // the centre on the edge: no direction (never reached in practice)
  const Real rho = kmath::sqrt(rho2);
  Real f_n;
  if (!law.contact(rho - radius, f_n, energy)) return false;
  f = (f_n / rho) * gap;
  return true;
}

}  // namespace edge_obstacle_detail

template <class Real, class ExecSpace>
struct EdgeObstacleKernel {
  using vector_view = typename Particles<2, Real, ExecSpace>::vector_view;
  using int_view = Kokkos::View<int*, ExecSpace>;

  int_view offset, body;
  vector_view x, f;
  BodyObstacleQuery<Real, ExecSpace> obstacles;
  HarmonicSurfaceRepulsion<Real> law;

  // Adds edge a → b's force on one of its ends (weight: the end's share, 1 − t at a, t at b) to fi;
  // adds the edge's energy when `count_energy`.
  KOKKOS_INLINE_FUNCTION void edge(int bd, const Vec<2, Real>& a, const Vec<2, Real>& b, bool at_start,
                                   bool count_energy, Vec<2, Real>& fi, double& energy) const {
    const Vec<2, Real> l = b - a;
    const Real radius = obstacles.obstacles.radius();
    const Vec<2, Real> mid = a + Real(0.5) * l;
    const Real reach = Real(0.5) * kmath::sqrt(norm2(l)) + radius + law.range;
    obstacles.for_each_centre_within(bd, mid, reach, [&](const Vec<2, Real>& dr) {
      // dr = mid − c, so c − a = l/2 − dr
      const Vec<2, Real> ac = Real(0.5) * l - dr;
      Vec<2, Real> fc;
      Real t, u;
      if (!edge_obstacle_detail::contact(l, ac, radius, law, fc, t, u)) return;
      fi += (at_start ? Real(1) - t : t) * fc;
      if (count_energy) energy += double(u);
    });
  }

  KOKKOS_INLINE_FUNCTION void operator()(int i, double& energy) const {
    const int bd = body(i), begin = offset(bd), n = offset(bd + 1) - begin;
    const Vec<2, Real> xi = Vec<2, Real>::load(x, i);
    const Vec<2, Real> xn = Vec<2, Real>::load(x, next_vertex(i, 1, begin, n));
    const Vec<2, Real> xp = Vec<2, Real>::load(x, prev_vertex(i, 1, begin, n));
    Vec<2, Real> fi = Vec<2, Real>::zero();
    edge(bd, xi, xn, true, true, fi, energy);
    edge(bd, xp, xi, false, false, fi, energy);
    for (int d = 0; d < 2; ++d) f(i, d) += fi[d];
  }
};

// Adds the edge–obstacle repulsion of every polygon of `polygons` (vertices [0, num_vertices())) to
// p.f and returns its energy. `obstacles`: the scene's BodyObstacleList query (after update()),
// built over the same bodies; `law`: ε_w and δ of eq. 3.
template <class Real, class ExecSpace>
double accumulate_edge_obstacle_forces(const Polygons<Real, ExecSpace>& polygons,
                                       const Particles<2, Real, ExecSpace>& p,
                                       const BodyObstacleQuery<Real, ExecSpace>& obstacles,
                                       const HarmonicSurfaceRepulsion<Real>& law) {
  const EdgeObstacleKernel<Real, ExecSpace> kernel{polygons.offset, polygons.body, p.x, p.f, obstacles, law};
  double energy = 0;
  mesoflow::launch::parallel_reduce("mesoflow::dp::edge_obstacle_repulsion",
                                    Kokkos::RangePolicy<ExecSpace>(0, polygons.num_vertices()), kernel, energy);
  return energy;
}

}  // namespace mesoflow::dp
