// deformation.hpp — the deformation δ_s of a droplet under its own weight (capillary-droplets
// §4.2, Fig. 7b): a droplet rests next to a flat wall without gravity, gravity is switched on, and
// δ_s is the distance its centre of mass sinks toward the wall. It maps λ(Γ) of the DP model and
// λ(E_w) of the SP model onto one axis (Fig. 7c, 9b). Shared by the `deformation` driver and tests.
//
// Units as in droplet_scene.hpp: length σ, acceleration g, areal mass density ρ; M = π/4.
// Frame: the wall is the half-plane y < 0, gravity along −y.
//
// SP (eq. 8 on a flat wall, d the height of the centre): the wall pushes with
// (2ε_w/σ)(1 − 2d/σ) = Mg at rest, so δ_s = σ/2 − d = πσ/(16 E_w); FIRE reproduces it.
// DP: FIRE without gravity (§2.4), then FIRE with gravity (DropletScene::relax) to the resting
// shape; no closed form. Besides the vertex centre of mass (the paper's δ_s) the result reports the
// area centroid, the drop of the droplet's top and the spread of edge lengths: line tension gives
// no tangential force, so only the segment springs (K_l) keep the vertices from sliding down the
// sides toward the wall, and a small K_l/Γ lets the vertex mass gather there (Appendix B).
#pragma once

#include "kernels/common/kernel_launch.hpp"
#include "scenes/droplets/droplet_scene.hpp"
#include "kernels/common/geometry.hpp"
#include "kernels/sp/obstacle_repulsion.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace mesoflow::droplets {

// δ_s/σ of an SP droplet on a flat wall: Mg = (2ε_w/σ)(1 − 2d/σ) with M = π/4 (eq. 8).
inline double sp_sinking_depth_exact(double wall_energy) { return dp::pi / (16.0 * wall_energy); }

struct DeformationResult {
  double sinking_depth = 0;      // δ_s/σ: drop of the vertex centre of mass (SP: of the centre)
  double centroid_sinking = 0;   // DP: drop of the area centroid /σ
  double top_sinking = 0;        // DP: drop of the highest vertex /σ
  double shape_parameter = 1;    // DP: 𝒜 at rest with gravity
  double area = 0;               // DP: a/a0 at rest with gravity
  double edge_ratio = 1;         // DP: longest over shortest edge at rest with gravity
  double wall_overlap = 0;       // largest overlap with the wall, (δ/2 − d_i)/σ (SP: (σ/2 − d)/σ)
  // ΔU_0/(Mg δ_s): energy stored in shape and wall (U without gravity, final − initial) over the
  // work done by gravity. Both states are minima, so 0 ≤ ratio ≤ 1; in the linear (small-load)
  // regime Clapeyron's theorem gives exactly 1/2 (SP: 1/2 at every E_w).
  double stored_energy_ratio = 0;
  int iterations_free = 0;       // FIRE iterations without gravity
  int iterations_gravity = 0;    // FIRE iterations with gravity
  double max_force = 0;          // max |F_i| at the end (gravity on)
  bool converged = false;        // both minimizations reached the force tolerance
};

struct DeformationSettings {
  int max_iterations = 200000;     // per FIRE minimization
  double force_tolerance = 1e-7;   // on max_i |F_i|, in units of ρσ²g (Mg = π/4)
};

namespace deformation_detail {

inline Surfaces<double, Kokkos::DefaultExecutionSpace> flat_wall() {
  const auto wall = Shape<2, double>::half_space(Vec<2, double>{{0.0, 0.0}}, Vec<2, double>{{0.0, 1.0}});
  return Surfaces<double, Kokkos::DefaultExecutionSpace>(std::vector<Shape<2, double>>{wall});
}

struct PolygonGeometry {
  double centroid_y = 0, top = 0, bottom = 0, edge_ratio = 1;
};

// Area centroid (ȳ = Σ (y_i + y_{i+1})(x_i y_{i+1} − x_{i+1} y_i) / 6a), extreme heights, edge spread.
template <class HostX>
PolygonGeometry polygon_geometry(const HostX& x, int n) {
  PolygonGeometry g;
  double twice_area = 0, moment = 0, shortest = HUGE_VAL, longest = 0;
  g.top = -HUGE_VAL;
  g.bottom = HUGE_VAL;
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    const double cross = x(i, 0) * x(j, 1) - x(j, 0) * x(i, 1);
    twice_area += cross;
    moment += (x(i, 1) + x(j, 1)) * cross;
    const double l = std::hypot(x(j, 0) - x(i, 0), x(j, 1) - x(i, 1));
    shortest = std::min(shortest, l);
    longest = std::max(longest, l);
    g.top = std::max(g.top, double(x(i, 1)));
    g.bottom = std::min(g.bottom, double(x(i, 1)));
  }
  g.centroid_y = moment / (3.0 * twice_area);
  g.edge_ratio = longest / shortest;
  return g;
}

}  // namespace deformation_detail

// DP droplet: starts as the regular polygon of §2.4 with its lowest edge just touching the wall
// (d = δ/2), relaxes without gravity, then with gravity.
inline DeformationResult dp_deformation(const DropletParameters& par, const DeformationSettings& settings = {}) {
  using Exec = Kokkos::DefaultExecutionSpace;
  par.validate();
  if (par.vertices % 4 != 0)
    throw std::invalid_argument("deformation: vertices N_v must be a multiple of 4 (an edge at the bottom), got " +
                                std::to_string(par.vertices));
  const double l0 = dp::regular_polygon_edge(droplet_area, par.vertices);
  const double circumradius = std::sqrt(2.0 * droplet_area / (par.vertices * std::sin(2.0 * dp::pi / par.vertices)));
  const double half_vertex = 0.5 * par.vertex_diameter * l0;  // δ/2
  // An edge, not a vertex, at the bottom: a polygon on a vertex would also roll onto an edge under
  // gravity, a drop of R(1 − cos π/N_v) that is faceting, not deformation.
  const double apothem = circumradius * std::cos(dp::pi / par.vertices);
  const Vec<2, double> centre{{0.0, apothem + half_vertex}};
  DropletScene<double, Exec> scene(par, deformation_detail::flat_wall(), {centre});
  {
    auto x0 = Kokkos::create_mirror_view(scene.particles().x);
    dp::place_regular_polygon(scene.polygons(), 0, x0, centre, dp::pi / par.vertices);
    Kokkos::deep_copy(scene.particles().x, x0);
  }
  DeformationResult r;
  const auto free = scene.relax(settings.max_iterations, false, settings.force_tolerance);
  r.iterations_free = free.iterations;
  const auto before = scene.observables();
  const double u0_before = scene.conservative_forces(false);
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), scene.particles().x);
  const auto shape_before = deformation_detail::polygon_geometry(x, par.vertices);

  const auto loaded = scene.relax(settings.max_iterations, true, settings.force_tolerance);
  r.iterations_gravity = loaded.iterations;
  r.max_force = loaded.max_force;
  r.converged = free.converged && loaded.converged;
  const auto after = scene.observables();
  const double u0_after = scene.conservative_forces(false);
  Kokkos::deep_copy(x, scene.particles().x);
  const auto shape_after = deformation_detail::polygon_geometry(x, par.vertices);

  r.sinking_depth = before.com[0][1] - after.com[0][1];
  r.centroid_sinking = shape_before.centroid_y - shape_after.centroid_y;
  r.top_sinking = shape_before.top - shape_after.top;
  r.shape_parameter = after.shape_parameter[0];
  r.area = after.area[0] / droplet_area;
  r.edge_ratio = shape_after.edge_ratio;
  r.wall_overlap = std::max(0.0, half_vertex - shape_after.bottom);
  r.stored_energy_ratio = (u0_after - u0_before) / (droplet_mass * r.sinking_depth);
  return r;
}

// SP droplet (eqs. 8–9): one disk of diameter σ and mass M = π/4 whose centre starts at d = σ/2
// (touching the wall); FIRE with U = Mg y + U_w. Without gravity it is already at rest.
inline DeformationResult sp_deformation(double wall_energy, const DeformationSettings& settings = {}) {
  using Exec = Kokkos::DefaultExecutionSpace;
  if (!(std::isfinite(wall_energy) && wall_energy > 0))
    throw std::invalid_argument("deformation: wall energy E_w must be finite and > 0, got " +
                                std::to_string(wall_energy));
  Particles<2, double, Exec> p(1, "sp_droplet");
  Kokkos::deep_copy(p.mass, droplet_mass);
  auto x = Kokkos::create_mirror_view(p.x);
  x(0, 0) = 0.0;
  x(0, 1) = 0.5;
  Kokkos::deep_copy(p.x, x);
  const auto wall = deformation_detail::flat_wall();
  const sp::ObstacleRepulsion<double> repulsion(wall_energy, 1.0);
  const auto f = p.f, pos = p.x;
  const auto forces = [&] {
    p.zero_forces();
    double u = accumulate_surface_forces(wall, p, p.v, repulsion);
    double ug = 0;
    mesoflow::launch::parallel_reduce(
        "mesoflow::deformation::sp_gravity", Kokkos::RangePolicy<Exec>(0, 1),
        KOKKOS_LAMBDA(int i, double& acc) {
          f(i, 1) -= droplet_mass;  // M g along −y
          acc += droplet_mass * pos(i, 1);
        },
        ug);
    return u + ug;
  };
  FireParameters fire;
  // The stiffest mode: ω² = (4ε_w/σ²)/M; FIRE's largest step stays at a fifth of 2/ω.
  const double omega = std::sqrt(4.0 * wall_energy / droplet_mass);
  fire.dt_start = std::min(1e-3, 0.04 / omega);
  fire.dt_max = 0.4 / omega;
  fire.max_iterations = settings.max_iterations;
  fire.force_tolerance = settings.force_tolerance;
  const auto result = fire_minimize(p, forces, fire);
  Kokkos::deep_copy(x, p.x);
  DeformationResult r;
  r.sinking_depth = 0.5 - x(0, 1);
  r.centroid_sinking = r.top_sinking = r.sinking_depth;
  r.wall_overlap = r.sinking_depth;
  const double overlap = 2.0 * r.sinking_depth;  // 1 − 2d/σ
  r.stored_energy_ratio = 0.5 * wall_energy * overlap * overlap / (droplet_mass * r.sinking_depth);
  r.iterations_gravity = result.iterations;
  r.max_force = result.max_force;
  r.converged = result.converged;
  return r;
}

}  // namespace mesoflow::droplets
