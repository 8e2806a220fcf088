// droplet_scene.hpp — a scene of 2D deformable-polygon (DP) droplets falling under gravity past
// walls and obstacles (capillary-droplets §2): composes the DP kernels, owns the state, steps it.
// Shared by the droplet drivers, their tests and benchmarks; physics stays in kernels/.
//
// Units (capillary-droplets §2.2): length σ (undeformed droplet diameter), acceleration g, areal
// mass density ρ; time t0 = √(σ/g). So a0 = πσ²/4, M = ρ a0 = π/4, and the paper's dimensionless
// numbers are the coefficients: γ = Γ, k_a = K_a, k_l = K_l, ε_w = E_w, and the far-field drag
// follows from the terminal speed, V_t = Mg/(b∞√(σg)) (eq. 15) ⇒ b∞ = M / V_t.
//
// Many droplets ("replicas") can share one scene: their vertices are one particle set and every
// kernel runs over all of them at once. Droplets do not interact with each other. With a multi-array
// ObstacleArray each droplet can have its own obstacle array (an ensemble over random arrays); every
// droplet then evolves bitwise as it would alone in a scene of its array.
#pragma once

#include "kernels/common/body_obstacle_list.hpp"
#include "kernels/common/fire.hpp"
#include "kernels/common/reductions.hpp"
#include "kernels/common/surface_force.hpp"
#include "kernels/common/velocity_verlet.hpp"
#include "kernels/dp/area_force.hpp"
#include "kernels/dp/bending_force.hpp"
#include "kernels/dp/edge_obstacle_repulsion.hpp"
#include "kernels/dp/line_tension.hpp"
#include "kernels/dp/gravity.hpp"
#include "kernels/dp/near_wall_drag.hpp"
#include "kernels/dp/per_body.hpp"
#include "kernels/dp/polygons.hpp"
#include "kernels/dp/segment_spring_force.hpp"
#include "kernels/dp/shape_forces.hpp"
#include "kernels/dp/shape_stiffness.hpp"
#include "scenes/common/nan_watchdog.hpp"
#include "scenes/common/term_list.hpp"
#include "scenes/common/time_step_limit.hpp"
#include "kernels/dp/stability.hpp"
#include "kernels/dp/vertex_wall_repulsion.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace mesoflow::droplets {

// The paper's dimensionless parameters (defaults: the Fig. 2 droplet).
struct DropletParameters {
  int vertices = 256;             // N_v
  double line_tension = 0.16;     // Γ = γ/(gρσ²)
  double area_stiffness = 1e4;    // K_a = k_a σ/(gρ)
  double perimeter_stiffness = 1e-4;  // K_l = k_l/(gρσ); the paper keeps K_l/Γ < 10⁻³ (App. B)
  double bending_stiffness = 0;   // K_b of hopper-flows eq. 8; 0 in the capillary study (no bending term)
  // E_w = ε_w/(gρσ³). The paper's 10⁴ with δ = l0 puts the wall mode at ω ≈ 3·10⁵/t0, far beyond
  // the explicit limit at Δt = 10⁻³ (kernels/dp/stability.hpp); 0.05 keeps it at 6.6·10²/t0 and
  // the overlaps below 1% of δ for the Fig. 2 droplet (docs/droplets.md measures the difference).
  double wall_energy = 0.05;
  double vertex_diameter = 1.0;   // δ/l0, the vertex diameter of eq. 3 in units of the edge length
  // Obstacles repel whole edges (circulo-lines of width δ, kernels/dp/edge_obstacle_repulsion.hpp)
  // instead of the vertices alone (eq. 3 as printed): a deviation that keeps an obstacle from
  // passing between two vertices at small K_l (docs/droplets.md, finding 7). Walls stay eq. 3.
  bool edge_obstacle_contacts = false;
  double near_wall_drag = 0.064;  // b0/b∞
  double terminal_speed = 0.08;   // V_t = Mg/(b∞√(σg)), eq. 15
  double drag_exponent = 4.0 / 3.0;  // α, eq. 6
  // d_min/σ, the floor on the wall distance d_i of eq. 6 (the paper states none; eq. 6 diverges at
  // contact): ζ_i ≤ b∞/N_v (1 + (b0/b∞)(σ/d_min)^α). Issue 25 item 5 sweeps it.
  double drag_floor = 0.01;
  double dt = 0;                  // Δt/t0; 0: the paper's 10⁻³, or the stability limit if smaller
  bool drag = true;               // background-fluid drag (eqs. 5–6); off only to check energy conservation
  bool force_dt = false;          // run a dt above the stability limit (a warning instead of an error)
  // A time step that follows each droplet's shape (issue 25, the wrapping branch at K_a = 10⁴): 0
  // (off) keeps Δt fixed and stops a run whose shape outgrows it (check_shape_time_step); a target
  // τ in (0, 1.8] lets every droplet halve its own Δt while its area mode has ω_area Δt > τ and
  // double it back, up to its initial Δt, while ω_area · 2Δt ≤ τ/2 (DropletScene::adapt_time_steps).
  double shape_dt_target = 0;

  // Throws std::invalid_argument naming the first parameter outside its range.
  void validate() const {
    auto require = [](bool ok, const char* name, const char* range, double value) {
      if (!ok)
        throw std::invalid_argument(std::string("droplet scene: ") + name + " must be " + range + ", got " +
                                    std::to_string(value));
    };
    auto finite_nonnegative = [](double v) { return std::isfinite(v) && v >= 0; };
    require(vertices >= 3, "vertices N_v", ">= 3", vertices);
    require(finite_nonnegative(line_tension), "line tension Γ", "finite and >= 0", line_tension);
    require(finite_nonnegative(area_stiffness), "area stiffness K_a", "finite and >= 0", area_stiffness);
    require(finite_nonnegative(perimeter_stiffness), "perimeter stiffness K_l", "finite and >= 0", perimeter_stiffness);
    require(finite_nonnegative(bending_stiffness), "bending stiffness K_b", "finite and >= 0", bending_stiffness);
    require(finite_nonnegative(wall_energy), "wall energy E_w", "finite and >= 0", wall_energy);
    require(finite_nonnegative(near_wall_drag), "near-wall drag b0/b∞", "finite and >= 0", near_wall_drag);
    require(std::isfinite(terminal_speed) && terminal_speed > 0, "terminal speed V_t", "finite and > 0", terminal_speed);
    require(std::isfinite(drag_exponent) && drag_exponent > 0, "drag exponent α", "finite and > 0", drag_exponent);
    require(std::isfinite(vertex_diameter) && vertex_diameter > 0, "vertex diameter δ/l0", "finite and > 0",
            vertex_diameter);
    require(std::isfinite(drag_floor) && drag_floor > 0 && drag_floor <= 1, "near-wall drag floor d_min/σ",
            "in (0, 1]", drag_floor);
    require(std::isfinite(dt) && dt >= 0, "time step dt", "finite and >= 0 (0: automatic)", dt);
    require(std::isfinite(shape_dt_target) && shape_dt_target >= 0 && shape_dt_target <= 1.8,
            "shape time-step target omega_area dt", "0 (off) or in (0, 1.8]", shape_dt_target);
    require(gravity_angle >= -360 && gravity_angle <= 360, "gravity angle", "in [-360, 360] degrees", gravity_angle);
  }
  double gravity_angle = -90.0;   // direction of g in degrees from +x (−90: along −y)
};

constexpr double droplet_area = dp::pi / 4;  // a0 = πσ²/4
constexpr double droplet_mass = dp::pi / 4;  // M = ρ a0
constexpr double paper_dt = 1e-3;            // Δt/t0 of §2.2

// The explicit stability limit of a droplet with these parameters (kernels/dp/stability.hpp);
// `with_surfaces`: walls or obstacles are present, so the repulsion and near-wall drag act.
// The stiffness inputs of kernels/dp/stability.hpp for the droplets of `par`.
inline dp::StiffnessInputs droplet_stiffness(const DropletParameters& par, bool with_surfaces) {
  const double l0 = dp::regular_polygon_edge(droplet_area, par.vertices);
  const double b_inf = droplet_mass / par.terminal_speed;
  dp::StiffnessInputs s;
  s.vertex_mass = droplet_mass / par.vertices;
  s.edge_length = l0;
  s.perimeter = par.vertices * l0;
  s.vertices = par.vertices;
  // With edge contacts a vertex touched from outside gets the contact of both its edges: twice the
  // stiffness of eq. 3's vertex contact (dp/edge_obstacle_repulsion.hpp).
  s.wall_energy = with_surfaces ? par.wall_energy * (par.edge_obstacle_contacts ? 2.0 : 1.0) : 0.0;
  s.vertex_diameter = par.vertex_diameter * l0;
  s.line_tension = par.line_tension;
  s.perimeter_stiffness = par.perimeter_stiffness;
  s.area_stiffness = par.area_stiffness;
  s.bending_stiffness = par.bending_stiffness;
  const double near = with_surfaces ? par.near_wall_drag * std::pow(1.0 / par.drag_floor, par.drag_exponent) : 0.0;
  s.max_drag = par.drag ? b_inf * (1 + near) : 0.0;
  return s;
}

inline dp::StabilityLimit droplet_stability(const DropletParameters& par, bool with_surfaces) {
  return dp::stability_limit(droplet_stiffness(par, with_surfaces));
}

// Thrown by DropletScene::step when the droplets' current shape puts the stability limit below
// the running Δt (kernels/dp/stability.hpp, stability_limit_for_shape): the run stops before the
// instability, naming the term, the new limit and the shape that set it.
struct ShapeTimeStepExceeded : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The time step a scene runs with: par.dt if given (refused above the stability limit, naming the
// term that sets it, unless par.force_dt), else min(10⁻³ t0, limit).
inline double resolve_time_step(const DropletParameters& par, bool with_surfaces) {
  const auto limit = droplet_stability(par, with_surfaces);
  const double dt_max = limit.max_dt();
  if (par.dt == 0) return std::min(paper_dt, dt_max);
  cli::check_time_step("droplet scene", par.dt, {dt_max, limit.limiting_term()}, par.force_dt);
  return par.dt;
}

template <class Real, class ExecSpace = Kokkos::DefaultExecutionSpace>
class DropletScene {
 public:
  using particles_type = Particles<2, Real, ExecSpace>;

  // `centres`: one droplet per entry, placed as a regular polygon of area a0 (§2.4).
  DropletScene(const DropletParameters& par, const Surfaces<Real, ExecSpace>& surfaces,
               const std::vector<Vec<2, double>>& centres)
      : DropletScene(par, surfaces, centres, std::vector<int>(centres.size(), 0)) {}

  // As above, droplet b in obstacle array droplet_array[b] of surfaces.obstacles().
  DropletScene(const DropletParameters& par, const Surfaces<Real, ExecSpace>& surfaces,
               const std::vector<Vec<2, double>>& centres, const std::vector<int>& droplet_array)
      : DropletScene(std::vector<DropletParameters>(centres.size(), par), surfaces, centres, droplet_array, false) {}

  // Droplets with parameters of their own (a batch mixing the points of a sweep, issue 25 item 3):
  // droplet b has per_body[b]'s Γ, K_l, b0/b∞, V_t and time step (each at its own stability limit,
  // velocity_verlet.hpp's per-particle steps), everything else shared (common_fields_match). Every
  // droplet evolves bitwise as it would alone in a scene of its own parameters and array.
  DropletScene(const std::vector<DropletParameters>& per_body, const Surfaces<Real, ExecSpace>& surfaces,
               const std::vector<Vec<2, double>>& centres, const std::vector<int>& droplet_array)
      : DropletScene(per_body, surfaces, centres, droplet_array, true) {}

 private:
  DropletScene(const std::vector<DropletParameters>& per_body, const Surfaces<Real, ExecSpace>& surfaces,
               const std::vector<Vec<2, double>>& centres, const std::vector<int>& droplet_array, bool mixed)
      : par_((check_per_body(per_body, centres.size()), per_body.front())),
        dt_(largest_time_step(per_body, surfaces.num_walls() > 0 || surfaces.obstacles().size() > 0)),
        polygons_(dp::Polygons<Real, ExecSpace>::uniform(int(centres.size()), par_.vertices, Real(droplet_area),
                                                         Real(dp::regular_polygon_edge(droplet_area, par_.vertices)))),
        state_(int(centres.size())),
        surfaces_(surfaces),
        vv_(Real(dt_)),
        p_(std::size_t(par_.vertices) * centres.size(), "droplets"),
        l0_(dp::regular_polygon_edge(droplet_area, par_.vertices)),
        b_inf_(droplet_mass / par_.terminal_speed) {
    if (centres.empty()) throw std::invalid_argument("droplet scene: no droplets");
    if (droplet_array.size() != centres.size())
      throw std::invalid_argument("droplet scene: " + std::to_string(droplet_array.size()) + " obstacle arrays for " +
                                  std::to_string(centres.size()) + " droplets");
    for (const int a : droplet_array)
      if (a < 0 || a >= surfaces.obstacles().num_arrays())
        throw std::invalid_argument("droplet scene: obstacle array " + std::to_string(a) + " outside [0, " +
                                    std::to_string(surfaces.obstacles().num_arrays()) + ")");
    dp::assign_bodies(polygons_, p_);
    auto x = Kokkos::create_mirror_view(p_.x);
    for (std::size_t b = 0; b < centres.size(); ++b) dp::place_regular_polygon(polygons_, int(b), x, centres[b]);
    Kokkos::deep_copy(p_.x, x);
    Kokkos::deep_copy(p_.mass, Real(droplet_mass / par_.vertices));
    if (surfaces.obstacles().size() > 0) {
      Kokkos::View<int*, ExecSpace> body_array("mesoflow::droplet_scene::droplet_array", centres.size());
      const auto body_array_host = Kokkos::create_mirror_view(body_array);
      for (std::size_t b = 0; b < centres.size(); ++b) body_array_host(b) = droplet_array[b];
      Kokkos::deep_copy(body_array, body_array_host);
      candidates_.emplace(surfaces.obstacles(), polygons_.offset, body_array, Real(candidate_skin));
    }
    const double angle = par_.gravity_angle * dp::pi / 180.0;
    gravity_ = Vec<2, Real>{{Real(std::cos(angle)), Real(std::sin(angle))}};
    // A shape-following step is per droplet: the scene runs the per-droplet machinery.
    mixed_ = mixed || par_.shape_dt_target > 0;
    body_par_ = per_body;
    if (mixed_) upload_body_coefficients();
    declare_terms();
  }

 public:
  // The term list's launches hold `this`: a scene stays where it was built.
  DropletScene(const DropletScene&) = delete;
  DropletScene& operator=(const DropletScene&) = delete;

  // Minimizes the potential energy by FIRE, without drag: without gravity it removes overlaps
  // with walls and obstacles before a run (§2.4); with gravity it finds a droplet's resting shape
  // (the deformation δ_s of Fig. 7b).
  FireResult relax(int max_iterations = 20000, bool with_gravity = false, double force_tolerance = 1e-6) {
    FireParameters fire;
    // FIRE is damped MD: its largest step obeys the same stability limit as the dynamics.
    double smallest_dt = dt_, smallest_limit = droplet_stability(par_, has_surfaces()).max_dt();
    for (std::size_t b = 0; mixed_ && b < body_par_.size(); ++b) {
      smallest_dt = std::min(smallest_dt, body_dt_[b]);
      smallest_limit = std::min(smallest_limit, droplet_stability(body_par_[b], has_surfaces()).max_dt());
    }
    fire.dt_start = smallest_dt;
    fire.dt_max = std::max(smallest_dt, 0.5 * smallest_limit);
    fire.max_iterations = max_iterations;
    fire.force_tolerance = force_tolerance;
    const FireResult result = fire_minimize(p_, [&] { return conservative_forces(with_gravity); }, fire);
    compute_step_forces();
    return result;
  }

  // f ← the forces a step evaluates (shape, gravity, walls and obstacles, drag) at the current
  // positions and velocities. Velocity Verlet's first half kick of the next step uses them, so
  // call this after changing the state outside step() (relax() does; so must whoever places
  // droplets with place_droplet()).
  void compute_step_forces() { step_forces(p_.v); }

  // One modified velocity-Verlet step (kernels/common/velocity_verlet.hpp) with gravity and drag.
  // With a shape-following step (par.shape_dt_target > 0) the droplets' steps are set before the
  // step, every shape_check_interval steps (adapt_time_steps), so that they change only between
  // observations of an ensemble's clocks (ClogDetector::follow_time_steps).
  void step() {
    if (shape_following() && steps_ % shape_check_interval == 0) adapt_time_steps();
    vv_.first_half(p_);
    step_forces(vv_.velocity_for_forces(p_));
    vv_.second_half(p_);
    ++steps_;
    if (!shape_following() && steps_ % shape_check_interval == 0) check_shape_time_step();
  }

  bool shape_following() const { return par_.shape_dt_target > 0; }

  // The shape-following step (par.shape_dt_target = τ > 0): droplet b runs at Δt_b = Δt_b0 / 2^k_b,
  // Δt_b0 its initial step (resolve_time_step) and k_b in [0, max_time_step_level]. From the area
  // mode of its current shape, ω_b = √(k_a max(Σ|∇a|², P l0)/m) (kernels/dp/shape_stiffness.hpp,
  // stability.hpp), k_b rises while ω_b Δt_b > τ and falls while ω_b · 2Δt_b ≤ τ/2 (the hysteresis
  // keeps a droplet at the edge from flipping every check). Every droplet adapts on its own, so a
  // replica's trajectory does not depend on its batch. Throws ShapeTimeStepExceeded when a droplet
  // at the deepest level still has ω_b Δt_b > 1.8, as check_shape_time_step does at a fixed step.
  // Device work plus one reduction read back, every shape_check_interval steps.
  void adapt_time_steps() {
    const dp::StiffnessInputs s = droplet_stiffness(par_, has_surfaces());
    const double k_over_m = s.area_stiffness / s.vertex_mass, floor = s.perimeter * s.edge_length;
    const double target = par_.shape_dt_target;
    const int deepest = max_time_step_level;
    const auto offset = polygons_.offset;
    const auto x = p_.x;
    const auto dt0 = body_dt0_dev_, dt_now = body_dt_dev_;
    const auto level = dt_level_, reached = deepest_level_;
    double worst = 0;
    mesoflow::launch::parallel_reduce(
        "mesoflow::droplet_scene::adapt_time_steps", Kokkos::RangePolicy<ExecSpace>(0, polygons_.num_bodies()),
        KOKKOS_LAMBDA(const int b, double& largest) {
          const double sum = dp::body_area_gradient_squared(offset, x, b);
          const double omega = kmath::sqrt(k_over_m * (sum > floor ? sum : floor));
          int k = level(b);
          while (k < deepest && omega * (dt0(b) / double(1 << k)) > target) ++k;
          while (k > 0 && omega * (dt0(b) / double(1 << (k - 1))) <= 0.5 * target) --k;
          level(b) = k;
          if (k > reached(b)) reached(b) = k;
          dt_now(b) = dt0(b) / double(1 << k);
          const double omega_dt = omega * dt_now(b);
          if (omega_dt > largest) largest = omega_dt;
        },
        Kokkos::Max<double>(worst));
    apply_time_step_levels();
    if (!(worst > area_mode_tolerance)) return;
    std::ostringstream m;
    m.precision(4);
    m << "droplet scene: at step " << steps_ << " a droplet's edges have become so unequal that its area elasticity "
      << "K_a mode has omega dt = " << worst << " > " << area_mode_tolerance << " at its smallest shape-following step "
      << "(initial dt / 2^" << max_time_step_level << "); the run stopped before the instability (lower K_a or "
      << "raise K_l)";
    throw ShapeTimeStepExceeded(m.str());
  }

  // Δt_b = Δt_b0 / 2^k_b for every droplet, and every vertex's step from its droplet's (with
  // shape-following steps; public because CUDA refuses an extended lambda in a private member).
  void apply_time_step_levels() {
    const auto dt0 = body_dt0_dev_, dt_now = body_dt_dev_;
    const auto level = dt_level_;
    mesoflow::launch::parallel_for(
        "mesoflow::droplet_scene::body_time_steps", Kokkos::RangePolicy<ExecSpace>(0, polygons_.num_bodies()),
        KOKKOS_LAMBDA(const int b) { dt_now(b) = dt0(b) / double(1 << level(b)); });
    const auto pdt = particle_dt_;
    const auto body = polygons_.body;
    mesoflow::launch::parallel_for(
        "mesoflow::droplet_scene::particle_time_steps", Kokkos::RangePolicy<ExecSpace>(0, polygons_.num_vertices()),
        KOKKOS_LAMBDA(const int i) { pdt(i) = Real(dt_now(body(i))); });
  }

  // The current step of every droplet (device; with a shape-following step the ensembles' clocks
  // read it, ClogDetector::follow_time_steps). Empty unless the batch is mixed.
  const Kokkos::View<double*, ExecSpace>& body_time_steps() const { return body_dt_dev_; }

  // The deepest level k (Δt = Δt0/2^k) any droplet of this scene has reached (host reduction).
  int deepest_time_step_level() const {
    if (!shape_following()) return 0;
    const auto reached = deepest_level_;
    int out = 0;
    mesoflow::launch::parallel_reduce(
        "mesoflow::droplet_scene::deepest_level", Kokkos::RangePolicy<ExecSpace>(0, polygons_.num_bodies()),
        KOKKOS_LAMBDA(const int b, int& m) {
          if (reached(b) > m) m = reached(b);
        },
        Kokkos::Max<int>(out));
    return out;
  }

  // The stability limit of the droplets' current shape (the static estimate, or stiffer where
  // unequal edges have stiffened the area mode; kernels/dp/stability.hpp) and the largest
  // Σ_i |∇_i a|² that set it.
  std::pair<dp::StabilityLimit, double> shape_stability() const {
    const double gradient = mixed_ ? dp::measure_area_gradient_squared(polygons_, p_, dt_weight_)
                                   : dp::measure_area_gradient_squared(polygons_, p_);
    return {dp::stability_limit_for_shape(droplet_stiffness(par_, has_surfaces()), gradient), gradient};
  }

  // Every shape_check_interval steps: throws ShapeTimeStepExceeded when the area mode of the
  // current shape, ω_area = √(k_a Σ|∇a|²/m), has ω_area Δt > area_mode_tolerance; with
  // par.force_dt, warns once on standard error instead. ω_area is the area mode's own frequency
  // (the mode is rank one; up to k_a (a − a0) ∇²a, small at the K_a of the papers), a lower bound of
  // the largest frequency of the step, and velocity Verlet turns unstable at ω Δt = 2: the run is
  // stopped at 0.9 of that. The summed estimate (an upper bound) is not the criterion: droplets
  // squeezing through an orifice depart far from the regular polygon without blowing up — the Fig. 2
  // droplet reaches Σ|∇a|² = 11.8 P l0 (ω_area Δt = 1.2, summed 1.5), a floppy one (Γ = 0.01)
  // 22 P l0 (ω_area Δt = 1.67, summed 1.8) — and both pass.
  void check_shape_time_step() {
    const auto [limit, gradient] = shape_stability();
    const double omega_dt = limit.omega_area * dt_;
    if (!(omega_dt > area_mode_tolerance)) return;
    std::ostringstream m;
    m.precision(4);
    m << "droplet scene: at step " << steps_ << " (t = " << time()
      << " t0) the droplets' edges have become so unequal (largest sum |grad a|^2 = "
      << gradient / (par_.vertices * l0_ * l0_)
      << " P l0, regular polygon: 1) that the area elasticity K_a mode has omega = " << limit.omega_area << "/t0, omega dt = " << omega_dt << " > " << area_mode_tolerance
      << " at dt = " << dt_ << " (velocity Verlet is unstable at 2); the stability limit of this shape is "
      << limit.max_dt() << " t0";
    if (par_.force_dt) {
      if (!shape_warned_) std::cerr << "warning: " << m.str() << "; running on (" << cli::force_dt_flag << ")\n";
      shape_warned_ = true;
      return;
    }
    m << "; the run stopped before the instability: run it with a smaller --dt (or " << cli::force_dt_flag
      << " to go on)";
    throw ShapeTimeStepExceeded(m.str());
  }

  // f ← −∇U (shape, gravity if on, walls) at the current positions; returns U.
  double conservative_forces(bool with_gravity) {
    double u = shape_forces(with_gravity);
    if (has_surfaces())
      with_surfaces([&](const auto& q) {
        u += accumulate_surface_forces(q, p_, p_.v, repulsion());
        u += edge_obstacle_forces();
      });
    return u;
  }

  // Total energy: kinetic + shape + gravity + walls. The forces are recomputed and then restored,
  // so sampling the energy between steps leaves the dynamics unchanged: the next half kick uses the
  // forces of the last step (or of compute_step_forces()), drag included (velocity_verlet.hpp).
  double total_energy() {
    if (saved_forces_.extent(0) != p_.f.extent(0))
      saved_forces_ = typename particles_type::vector_view("mesoflow::droplets::saved_forces", p_.f.extent(0));
    Kokkos::deep_copy(saved_forces_, p_.f);
    const double e = conservative_forces(true) + kinetic_energy(p_);
    Kokkos::deep_copy(p_.f, saved_forces_);
    return e;
  }

  dp::BodyObservables observables() {
    dp::update_body_state(polygons_, p_, state_);
    return dp::body_observables(state_);
  }

  // Per-droplet state (area, centre of mass, kinetic energy...) at the current positions and
  // velocities, left on the device for kernels (clog detection).
  const dp::BodyState<Real, ExecSpace>& update_body_state() {
    dp::update_body_state(polygons_, p_, state_);
    return state_;
  }

  // Droplet b's vertex positions (host copy, for setup: moving relaxed droplets between scenes).
  std::vector<Vec<2, double>> droplet_vertices(int b) const {
    const auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p_.x);
    std::vector<Vec<2, double>> out;
    for (int i = polygons_.first_vertex(b); i < polygons_.first_vertex(b) + polygons_.num_vertices(b); ++i)
      out.push_back(Vec<2, double>{{double(x(i, 0)), double(x(i, 1))}});
    return out;
  }

  // Moves droplet b's vertices to `vertices` (N_v of them) at rest; setup only (then
  // compute_step_forces()).
  void place_droplet(int b, const std::vector<Vec<2, double>>& vertices) {
    if (int(vertices.size()) != polygons_.num_vertices(b))
      throw std::invalid_argument("droplet scene: " + std::to_string(vertices.size()) + " vertices for droplet " +
                                  std::to_string(b) + " of " + std::to_string(polygons_.num_vertices(b)));
    const auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p_.x);
    const auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p_.v);
    for (int k = 0; k < polygons_.num_vertices(b); ++k) {
      const int i = polygons_.first_vertex(b) + k;
      for (int d = 0; d < 2; ++d) {
        x(i, d) = Real(vertices[std::size_t(k)][d]);
        v(i, d) = Real(0);
      }
    }
    Kokkos::deep_copy(p_.x, x);
    Kokkos::deep_copy(p_.v, v);
  }

  // The NaN watchdog's view of the scene (scenes/common/nan_watchdog.hpp): the state a step reads
  // (x, v and the forces of the last step, which the first half-step uses), the step counter, and
  // every force term of step() alone. The scene must outlive the returned value.
  watchdog::Watched watched() {
    watchdog::Watched w = watchdog::watch_particles(p_);
    w.step = [this] { step(); };
    w.steps = [this] { return steps_; };
    w.set_steps = [this](long long s) { steps_ = s; };
    w.terms = terms_.watchdog_terms();
    w.particle = [this](long long i) {
      for (int b = 0; b < polygons_.num_bodies(); ++b)
        if (i < polygons_.first_vertex(b) + polygons_.num_vertices(b))
          return "vertex " + std::to_string(i - polygons_.first_vertex(b)) + " of droplet " + std::to_string(b);
      return "vertex " + std::to_string(i);
    };
    return w;
  }

  // The scene's components, each with what it costs: the terms a step evaluates and the kernels it
  // launches (run summaries list them; terms with zero coefficients are absent or free).
  std::vector<std::string> components() const {
    std::vector<std::string> c{std::to_string(polygons_.num_bodies()) + " droplet(s) of " +
                               std::to_string(par_.vertices) + " vertices"};
    if (surfaces_.num_walls() > 0) c.push_back(std::to_string(surfaces_.num_walls()) + " walls");
    if (surfaces_.obstacles().size() > 0)
      c.push_back(std::to_string(surfaces_.obstacles().size()) + " obstacles (candidate lists per droplet)");
    for (auto& line : terms_.components()) c.push_back(std::move(line));
    return c;
  }

  const scene::TermList<const typename Particles<2, Real, ExecSpace>::vector_view&>& terms() const { return terms_; }

  const particles_type& particles() const { return p_; }
  const dp::Polygons<Real, ExecSpace>& polygons() const { return polygons_; }
  const DropletParameters& parameters() const { return par_; }
  long long steps() const { return steps_; }
  // steps·Δt; with shape-following steps each droplet keeps its own clock (ClogDetector::follow_time_steps).
  double time() const {
    if (shape_following())
      throw std::logic_error("droplet scene: time() with shape-following steps (each droplet has its own clock)");
    return double(steps_) * dt_;
  }
  double dt() const { return dt_; }
  // Droplet b's time step (the scene's dt() unless the batch is mixed).
  double dt(int b) const {
    if (!mixed_) return dt_;
    if (!shape_following()) return body_dt_.at(std::size_t(b));
    if (b < 0 || b >= polygons_.num_bodies()) throw std::out_of_range("droplet scene: no droplet " + std::to_string(b));
    return Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), body_dt_dev_)(b);  // setup and refills only
  }
  bool mixed() const { return mixed_; }
  const DropletParameters& parameters(int b) const { return body_par_.at(std::size_t(b)); }

  // Mixed batches: puts a new droplet in slot b — parameters `par` (sharing the common fields),
  // obstacle array `array`, vertices `vertices` at rest. Host setup between steps; then
  // refresh_forces() with every slot refilled.
  void replace_droplet(int b, const DropletParameters& par, int array, const std::vector<Vec<2, double>>& vertices) {
    if (!mixed_) throw std::logic_error("droplet scene: replace_droplet needs a scene of per-droplet parameters");
    if (b < 0 || b >= polygons_.num_bodies())
      throw std::invalid_argument("droplet scene: droplet " + std::to_string(b) + " outside [0, " +
                                  std::to_string(polygons_.num_bodies()) + ")");
    par.validate();
    check_common_fields(par_, par);
    body_par_[std::size_t(b)] = par;
    if (shape_following()) {  // the new droplet starts at its initial step
      const auto level = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), dt_level_);
      level(b) = 0;
      Kokkos::deep_copy(dt_level_, level);
    }
    upload_body_coefficients();
    place_droplet(b, vertices);
    if (candidates_) candidates_->reassign(b, array);
  }

  // The forces of the droplets `bodies` at their current state, as compute_step_forces() gives them,
  // the other droplets' forces untouched (they keep those of their last step).
  void refresh_forces(const std::vector<int>& bodies) {
    if (bodies.empty()) return;
    if (scratch_forces_.extent(0) != p_.f.extent(0))
      scratch_forces_ = typename particles_type::vector_view("mesoflow::droplet_scene::scratch_forces", p_.f.extent(0));
    Kokkos::deep_copy(scratch_forces_, p_.f);
    compute_step_forces();
    Kokkos::View<int*, ExecSpace> refreshed("mesoflow::droplet_scene::refreshed", std::size_t(polygons_.num_bodies()));
    const auto h = Kokkos::create_mirror_view(refreshed);
    for (const int b : bodies) h(b) = 1;
    Kokkos::deep_copy(refreshed, h);
    const auto f = p_.f, saved = scratch_forces_;
    const auto body = polygons_.body;
    mesoflow::launch::parallel_for(
        "mesoflow::droplet_scene::restore_forces", Kokkos::RangePolicy<ExecSpace>(0, polygons_.num_vertices()),
        KOKKOS_LAMBDA(int i) {
          if (!refreshed(body(i)))
            for (int d = 0; d < 2; ++d) f(i, d) = saved(i, d);
        });
  }

  // A droplet's whole dynamic state: vertex positions, velocities and the forces of its last step,
  // and its obstacle candidates' reference disk (moving a droplet between batches, bitwise).
  struct DropletState {
    std::vector<double> x, v, f;
    std::array<double, 3> reference{};
    int dt_level = 0, deepest_dt_level = 0;  // shape-following step: its level now and the deepest reached
  };
  std::vector<DropletState> export_droplets() const {
    const auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p_.x);
    const auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p_.v);
    const auto f = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p_.f);
    std::vector<std::array<double, 3>> disks;
    if (candidates_) disks = candidates_->references();
    std::vector<DropletState> out(std::size_t(polygons_.num_bodies()));
    if (shape_following()) {
      const auto level = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), dt_level_);
      const auto reached = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), deepest_level_);
      for (int b = 0; b < polygons_.num_bodies(); ++b) {
        out[std::size_t(b)].dt_level = level(b);
        out[std::size_t(b)].deepest_dt_level = reached(b);
      }
    }
    for (int b = 0; b < polygons_.num_bodies(); ++b) {
      DropletState& s = out[std::size_t(b)];
      for (int i = polygons_.first_vertex(b); i < polygons_.first_vertex(b) + polygons_.num_vertices(b); ++i)
        for (int d = 0; d < 2; ++d) {
          s.x.push_back(double(x(i, d)));
          s.v.push_back(double(v(i, d)));
          s.f.push_back(double(f(i, d)));
        }
      if (candidates_) s.reference = disks[std::size_t(b)];
    }
    return out;
  }
  // Sets every droplet's state from `states` (one per droplet, from export_droplets of a scene of
  // the same droplets) and the step count: the scene continues them bitwise. Host setup.
  void import_droplets(const std::vector<DropletState>& states, long long steps) {
    if (int(states.size()) != polygons_.num_bodies())
      throw std::invalid_argument("droplet scene: " + std::to_string(states.size()) + " droplet states for " +
                                  std::to_string(polygons_.num_bodies()) + " droplets");
    const auto x = Kokkos::create_mirror_view(p_.x);
    const auto v = Kokkos::create_mirror_view(p_.v);
    const auto f = Kokkos::create_mirror_view(p_.f);
    std::vector<std::array<double, 3>> disks;
    for (int b = 0; b < polygons_.num_bodies(); ++b) {
      const DropletState& s = states[std::size_t(b)];
      if (int(s.x.size()) != 2 * polygons_.num_vertices(b) || s.v.size() != s.x.size() || s.f.size() != s.x.size())
        throw std::invalid_argument("droplet scene: droplet state of the wrong size for droplet " + std::to_string(b));
      int k = 0;
      for (int i = polygons_.first_vertex(b); i < polygons_.first_vertex(b) + polygons_.num_vertices(b); ++i, ++k)
        for (int d = 0; d < 2; ++d) {
          x(i, d) = Real(s.x[std::size_t(2 * k + d)]);
          v(i, d) = Real(s.v[std::size_t(2 * k + d)]);
          f(i, d) = Real(s.f[std::size_t(2 * k + d)]);
        }
      disks.push_back(s.reference);
    }
    Kokkos::deep_copy(p_.x, x);
    Kokkos::deep_copy(p_.v, v);
    Kokkos::deep_copy(p_.f, f);
    if (candidates_) candidates_->build_at(disks, p_.x);
    if (shape_following()) {
      const auto level = Kokkos::create_mirror_view(dt_level_);
      const auto reached = Kokkos::create_mirror_view(deepest_level_);
      for (int b = 0; b < polygons_.num_bodies(); ++b) {
        level(b) = states[std::size_t(b)].dt_level;
        reached(b) = states[std::size_t(b)].deepest_dt_level;
      }
      Kokkos::deep_copy(dt_level_, level);
      Kokkos::deep_copy(deepest_level_, reached);
      apply_time_step_levels();
    }
    steps_ = steps;
  }
  double far_drag() const { return b_inf_; }
  double edge_length() const { return l0_; }

 private:
  bool has_surfaces() const { return surfaces_.num_walls() > 0 || surfaces_.obstacles().size() > 0; }
  // Whether obstacles repel the droplets' edges (then the surface loop's pairwise term sees the walls only).
  bool edge_contacts() const { return par_.edge_obstacle_contacts && candidates_.has_value(); }
  // Adds the edge–obstacle repulsion (after with_surfaces has updated the candidates); 0 without it.
  double edge_obstacle_forces() {
    if (!edge_contacts()) return 0.0;
    return dp::accumulate_edge_obstacle_forces(polygons_, p_, candidates_->query(), repulsion());
  }

  // Calls use(query) with the surface query of the step: with obstacles, walls plus each droplet's
  // obstacle candidates (rebuilt when a droplet has moved by the skin); otherwise the walls alone.
  template <class Use>
  void with_surfaces(Use&& use) {
    if (!candidates_) {
      use(surfaces_);
      return;
    }
    candidates_->update(p_.x);
    use(BodySurfaces<Real, ExecSpace>{surfaces_.walls(), surfaces_.num_walls(), *candidates_, polygons_.body,
                                      !edge_contacts()});
  }

  // f ← the forces of a step, the velocity-dependent ones (drag) at velocities u: the term list's
  // launches in order (declare_terms()).
  void step_forces(const typename particles_type::vector_view& u) { terms_.evaluate(u); }

  // The scene's terms, declared once: the step, the watchdog and the summaries read this list.
  // Two launches: the shape loop (zeroes f; area, springs, line tension, bending at K_b > 0,
  // gravity) and, with walls, obstacles or drag, the surface loop (one pass over the surfaces near
  // each vertex serves repulsion, summed, and drag, from the nearest surface).
  void declare_terms() {
    const auto shape_term = [this](auto term) {
      return [this, term] {
        p_.zero_forces();
        dp::update_body_state(polygons_, p_, state_);
        dp::accumulate_shape_forces(polygons_, state_, p_, term);
      };
    };
    terms_.term({"area elasticity K_a", "eq. 1", false, true,
                 shape_term(dp::AreaElasticity<Real>{Real(par_.area_stiffness)})});
    if (mixed_) {
      terms_.term({"segment springs K_l", "eq. 1 (per droplet)", false, any_body([](const DropletParameters& b) {
                     return b.perimeter_stiffness != 0;
                   }),
                   shape_term(springs_per_body())});
      terms_.term({"line tension Γ", "eq. 2 (per droplet)", false,
                   any_body([](const DropletParameters& b) { return b.line_tension != 0; }),
                   shape_term(tension_per_body())});
    } else {
      terms_.term({"segment springs K_l", "eq. 1", false, par_.perimeter_stiffness != 0,
                   shape_term(dp::SegmentSprings<Real>{Real(par_.perimeter_stiffness)})});
      terms_.term({"line tension Γ", "eq. 2", false, par_.line_tension != 0,
                   shape_term(dp::LineTension<Real>{Real(par_.line_tension)})});
    }
    terms_.term({"bending K_b", "hopper eq. 8", false, par_.bending_stiffness > 0,
                 shape_term(dp::Bending<Real>{Real(par_.bending_stiffness)})});
    terms_.term({"gravity", "", false, true, shape_term(dp::Gravity<Real>{gravity_})});
    terms_.term({"wall/obstacle repulsion E_w", "eq. 3", false,
                 surfaces_.num_walls() > 0 || (candidates_.has_value() && !edge_contacts()), [this] {
                   p_.zero_forces();
                   with_surfaces([&](const auto& q) { accumulate_surface_forces(q, p_, p_.v, repulsion()); });
                 }});
    terms_.term({"edge-obstacle repulsion E_w", "eq. 3 on edges", false, edge_contacts(), [this] {
                   p_.zero_forces();
                   with_surfaces([&](const auto&) { edge_obstacle_forces(); });
                 }});
    terms_.term({"drag b∞, b0", mixed_ ? "eqs. 5–6 (per droplet)" : "eqs. 5–6", true, par_.drag, [this] {
                   p_.zero_forces();
                   const dp::VertexWallRepulsion<Real> none(Real(0), Real(par_.vertex_diameter * l0_));
                   with_drag([&](const auto& drag) {
                     with_surfaces([&](const auto& q) { accumulate_surface_forces(q, p_, p_.v, none, drag); });
                   });
                 }});
    terms_.launch("shape loop (one kernel)",
                  {"area elasticity K_a", "segment springs K_l", "line tension Γ", "bending K_b", "gravity"},
                  [this](const typename particles_type::vector_view&) { shape_forces(true); });
    terms_.launch("surface loop (one kernel; a second for edge contacts)",
                  {"wall/obstacle repulsion E_w", "edge-obstacle repulsion E_w", "drag b∞, b0"},
                  [this](const typename particles_type::vector_view& u) {
                    if (par_.drag)
                      with_drag([&](const auto& drag) {
                        with_surfaces([&](const auto& q) {
                          accumulate_surface_forces(q, p_, u, repulsion(), drag);
                          edge_obstacle_forces();
                        });
                      });
                    else
                      with_surfaces([&](const auto& q) {
                        accumulate_surface_forces(q, p_, p_.v, repulsion());
                        edge_obstacle_forces();
                      });
                  });
  }

  // f ← −∇(U_shape + U_gravity); returns that energy. One fused loop over the vertices; bending
  // joins it only at K_b > 0 (a compile-time term list, so K_b = 0 costs nothing).
  double shape_forces(bool with_gravity) {
    p_.zero_forces();
    dp::update_body_state(polygons_, p_, state_);
    const Vec<2, Real> g = with_gravity ? gravity_ : Vec<2, Real>::zero();
    const dp::AreaElasticity<Real> area{Real(par_.area_stiffness)};
    if (mixed_) {
      if (par_.bending_stiffness > 0)
        return dp::accumulate_shape_forces(polygons_, state_, p_, area, springs_per_body(), tension_per_body(),
                                           dp::Bending<Real>{Real(par_.bending_stiffness)}, dp::Gravity<Real>{g});
      return dp::accumulate_shape_forces(polygons_, state_, p_, area, springs_per_body(), tension_per_body(),
                                         dp::Gravity<Real>{g});
    }
    const dp::SegmentSprings<Real> springs{Real(par_.perimeter_stiffness)};
    const dp::LineTension<Real> tension{Real(par_.line_tension)};
    if (par_.bending_stiffness > 0)
      return dp::accumulate_shape_forces(polygons_, state_, p_, area, springs, tension,
                                         dp::Bending<Real>{Real(par_.bending_stiffness)}, dp::Gravity<Real>{g});
    return dp::accumulate_shape_forces(polygons_, state_, p_, area, springs, tension, dp::Gravity<Real>{g});
  }

  dp::VertexWallRepulsion<Real> repulsion() const {
    return dp::VertexWallRepulsion<Real>(Real(par_.wall_energy), Real(par_.vertex_diameter * l0_));
  }
  dp::NearWallDrag<Real> drag() const { return drag_of(par_); }
  static dp::NearWallDrag<Real> drag_of(const DropletParameters& par) {
    const double b_inf = droplet_mass / par.terminal_speed;
    return dp::NearWallDrag<Real>(Real(b_inf), Real(par.near_wall_drag * b_inf), Real(1), par.vertices,
                                  Real(par.drag_exponent), Real(par.drag_floor));
  }
  dp::PerBody<dp::SegmentSprings<Real>, ExecSpace> springs_per_body() const { return {spring_terms_}; }
  dp::PerBody<dp::LineTension<Real>, ExecSpace> tension_per_body() const { return {tension_terms_}; }
  // Calls use(drag): the scene's drag term, one for all droplets or one per droplet.
  template <class Use>
  void with_drag(Use&& use) {
    if (mixed_)
      use(dp::PerBodySurfaceTerm<dp::NearWallDrag<Real>, Real, ExecSpace>{polygons_.body, drag_terms_, Real(0)});
    else
      use(drag());
  }
  template <class Pred>
  bool any_body(Pred&& pred) const {
    for (const auto& b : body_par_)
      if (pred(b)) return true;
    return false;
  }

  // The parameters a mixed batch's droplets must share (everything but Γ, K_l, b0/b∞, V_t and Δt);
  // throws std::invalid_argument naming the first that differs.
  static void check_common_fields(const DropletParameters& a, const DropletParameters& b) {
    const auto same = [](bool equal, const char* name) {
      if (!equal)
        throw std::invalid_argument(std::string("droplet scene: droplets of one batch must share ") + name);
    };
    same(a.vertices == b.vertices, "the vertex count N_v");
    same(a.area_stiffness == b.area_stiffness, "the area stiffness K_a");
    same(a.bending_stiffness == b.bending_stiffness, "the bending stiffness K_b");
    same(a.wall_energy == b.wall_energy, "the wall energy E_w");
    same(a.vertex_diameter == b.vertex_diameter, "the vertex diameter");
    same(a.edge_obstacle_contacts == b.edge_obstacle_contacts, "the edge-obstacle contacts");
    same(a.drag_exponent == b.drag_exponent, "the drag exponent");
    same(a.drag_floor == b.drag_floor, "the near-wall drag floor");
    same(a.drag == b.drag, "the drag switch");
    same(a.gravity_angle == b.gravity_angle, "the gravity angle");
    same(a.shape_dt_target == b.shape_dt_target, "the shape time-step target");
  }
  static int check_per_body(const std::vector<DropletParameters>& per_body, std::size_t droplets) {
    if (droplets == 0 || per_body.empty()) throw std::invalid_argument("droplet scene: no droplets");
    if (per_body.size() != droplets)
      throw std::invalid_argument("droplet scene: " + std::to_string(per_body.size()) + " parameter sets for " +
                                  std::to_string(droplets) + " droplets");
    for (const auto& b : per_body) {
      b.validate();
      check_common_fields(per_body.front(), b);
    }
    return 0;
  }
  static double largest_time_step(const std::vector<DropletParameters>& per_body, bool with_surfaces) {
    double dt = 0;
    for (const auto& b : per_body) dt = std::max(dt, resolve_time_step(b, with_surfaces));
    return dt;
  }

  // The per-droplet coefficient Views, their time steps and the (Δt_b/Δt)² weights of the shape check,
  // from body_par_ (setup and refills only).
  void upload_body_coefficients() {
    const int nb = polygons_.num_bodies();
    std::vector<dp::SegmentSprings<Real>> springs;
    std::vector<dp::LineTension<Real>> tension;
    std::vector<dp::NearWallDrag<Real>> drag;
    body_dt_.assign(std::size_t(nb), 0.0);
    for (int b = 0; b < nb; ++b) {
      const DropletParameters& q = body_par_[std::size_t(b)];
      springs.push_back({Real(q.perimeter_stiffness)});
      tension.push_back({Real(q.line_tension)});
      drag.push_back(drag_of(q));
      body_dt_[std::size_t(b)] = resolve_time_step(q, has_surfaces());
    }
    dt_ = *std::max_element(body_dt_.begin(), body_dt_.end());  // the reference of the shape check's weights
    spring_terms_ = dp::per_body_view<dp::SegmentSprings<Real>, ExecSpace>("mesoflow::droplet_scene::springs", springs);
    tension_terms_ = dp::per_body_view<dp::LineTension<Real>, ExecSpace>("mesoflow::droplet_scene::tension", tension);
    drag_terms_ = dp::per_body_view<dp::NearWallDrag<Real>, ExecSpace>("mesoflow::droplet_scene::drag", drag);
    particle_dt_ = Kokkos::View<Real*, ExecSpace>("mesoflow::droplet_scene::particle_dt", p_.size());
    dt_weight_ = Kokkos::View<double*, ExecSpace>("mesoflow::droplet_scene::dt_weight", std::size_t(nb));
    const auto pdt = Kokkos::create_mirror_view(particle_dt_);
    const auto weight = Kokkos::create_mirror_view(dt_weight_);
    for (int b = 0; b < nb; ++b) {
      weight(b) = (body_dt_[std::size_t(b)] / dt_) * (body_dt_[std::size_t(b)] / dt_);
      for (int i = polygons_.first_vertex(b); i < polygons_.first_vertex(b) + polygons_.num_vertices(b); ++i)
        pdt(i) = Real(body_dt_[std::size_t(b)]);
    }
    Kokkos::deep_copy(particle_dt_, pdt);
    Kokkos::deep_copy(dt_weight_, weight);
    vv_.set_particle_time_steps(particle_dt_);
    if (shape_following()) {  // the initial steps, the levels kept (a refill resets its own first)
      if (dt_level_.extent(0) != std::size_t(nb)) {
        dt_level_ = Kokkos::View<int*, ExecSpace>("mesoflow::droplet_scene::dt_level", std::size_t(nb));
        deepest_level_ = Kokkos::View<int*, ExecSpace>("mesoflow::droplet_scene::deepest_dt_level", std::size_t(nb));
        body_dt_dev_ = Kokkos::View<double*, ExecSpace>("mesoflow::droplet_scene::body_dt", std::size_t(nb));
      }
      body_dt0_dev_ = Kokkos::View<double*, ExecSpace>("mesoflow::droplet_scene::body_dt0", std::size_t(nb));
      const auto dt0 = Kokkos::create_mirror_view(body_dt0_dev_);
      for (int b = 0; b < nb; ++b) dt0(b) = body_dt_[std::size_t(b)];
      Kokkos::deep_copy(body_dt0_dev_, dt0);
      apply_time_step_levels();
    }
  }


  DropletParameters par_;  // droplet 0's (every shared field is everyone's)
  double dt_;               // the step (mixed: the largest droplet's; each droplet runs at body_dt_)
  dp::Polygons<Real, ExecSpace> polygons_;
  dp::BodyState<Real, ExecSpace> state_;
  Surfaces<Real, ExecSpace> surfaces_;
  VelocityVerlet<2, Real, ExecSpace> vv_;
  particles_type p_;
  typename particles_type::vector_view saved_forces_;  // total_energy() restores the step's forces from it
  double l0_, b_inf_;
  Vec<2, Real> gravity_;
  std::optional<BodyObstacleList<Real, ExecSpace>> candidates_;  // with obstacles only
  scene::TermList<const typename Particles<2, Real, ExecSpace>::vector_view&> terms_;
  long long steps_ = 0;
  bool shape_warned_ = false;
  // Mixed batches (per-droplet parameters):
  bool mixed_ = false;
  std::vector<DropletParameters> body_par_;
  std::vector<double> body_dt_;
  Kokkos::View<dp::SegmentSprings<Real>*, ExecSpace> spring_terms_;
  Kokkos::View<dp::LineTension<Real>*, ExecSpace> tension_terms_;
  Kokkos::View<dp::NearWallDrag<Real>*, ExecSpace> drag_terms_;
  Kokkos::View<Real*, ExecSpace> particle_dt_;
  Kokkos::View<double*, ExecSpace> dt_weight_;
  // Shape-following steps (par.shape_dt_target > 0): each droplet's initial and current step, its
  // level k (Δt = Δt0/2^k) and the deepest level it has reached.
  Kokkos::View<double*, ExecSpace> body_dt0_dev_, body_dt_dev_;
  Kokkos::View<int*, ExecSpace> dt_level_, deepest_level_;
  typename particles_type::vector_view scratch_forces_;
  static constexpr double candidate_skin = 0.5;  // σ
  static constexpr long long shape_check_interval = 100;
  static constexpr double area_mode_tolerance = 1.8;

 public:
  static constexpr int max_time_step_level = 12;  // the smallest shape-following step: Δt0/4096
};

}  // namespace mesoflow::droplets
