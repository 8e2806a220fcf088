// soft_particle_scene.hpp — a scene of soft-particle (SP) droplets falling under gravity through
// walls and obstacles (capillary-droplets §2.3): one particle per droplet, the disk–surface
// repulsion of eq. 8 and the drag F = −ζ_sp v with ζ_sp = b∞ (eq. 10), integrated by the same
// modified velocity Verlet as the DP scene (eq. 11). Mirrors DropletScene's API (relax, step,
// time, dt) so that the obstacle-ensemble driver runs either model.
//
// Units as in droplet_scene.hpp: σ (the SP droplet diameter), g, ρ; t0 = √(σ/g); M = πσ²ρ/4 = π/4,
// ε_w = E_w, b∞ = M/V_t (eq. 15).
//
// Many droplets (replicas) share one scene, one particle each; they do not interact. Droplet b sees
// the obstacles of array droplet_array[b] of the scene's ObstacleArray, so each replica evolves
// bitwise as it would alone.
//
// Eq. 8 is a pairwise droplet–obstacle energy, so the scene sums it over every obstacle the droplet
// overlaps (ObstacleArray::for_each_within), not only the nearest: with the nearest alone the force
// jumps where the nearest obstacle changes, and a droplet squeezed between two obstacles chatters
// across that line at speeds ~10⁻⁶ σ/t0 instead of coming to rest (measured), so E_k/E_t never
// reaches App. C's clogging threshold. Obstacles only: the scene refuses walls.
#pragma once

#include "scenes/common/nan_watchdog.hpp"
#include "scenes/common/term_list.hpp"
#include "scenes/droplets/droplet_scene.hpp"
#include "kernels/common/fire.hpp"
#include "kernels/common/obstacle_array.hpp"
#include "kernels/common/surface_force.hpp"
#include "kernels/common/velocity_verlet.hpp"
#include "kernels/sp/gravity.hpp"
#include "kernels/sp/obstacle_repulsion.hpp"
#include "kernels/sp/viscous_drag.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace mesoflow::droplets {

struct SoftParticleParameters {
  double wall_energy = 10.0;     // E_w = ε_w/(gρσ³), eq. 8; the paper scans 10⁻¹ < E_w < 10²
  double terminal_speed = 0.08;  // V_t = Mg/(b∞√(σg)), eq. 15
  double dt = 0;                 // Δt/t0; 0: the paper's 10⁻³, or the stability limit if smaller
  double gravity_angle = -90.0;  // direction of g in degrees from +x
  bool force_dt = false;         // run a dt above the stability limit (a warning instead of an error)

  void validate() const {
    auto require = [](bool ok, const char* name, const char* range, double value) {
      if (!ok)
        throw std::invalid_argument(std::string("soft-particle scene: ") + name + " must be " + range + ", got " +
                                    std::to_string(value));
    };
    require(std::isfinite(wall_energy) && wall_energy >= 0, "wall energy E_w", "finite and >= 0", wall_energy);
    require(std::isfinite(terminal_speed) && terminal_speed > 0, "terminal speed V_t", "finite and > 0",
            terminal_speed);
    require(std::isfinite(dt) && dt >= 0, "time step dt", "finite and >= 0 (0: automatic)", dt);
    require(gravity_angle >= -360 && gravity_angle <= 360, "gravity angle", "in [-360, 360] degrees", gravity_angle);
  }
};

// The explicit limit of an SP droplet, in the form of kernels/dp/stability.hpp (Δt ≤ 1/ω and
// Δt ≤ 1/ν): the contact of eq. 8 has stiffness 4ε_w/σ², so ω = √(4E_w/M); the drag rate is
// ν = b∞/M = 1/V_t. The term is the one that sets the limit, for error messages.
inline cli::TimeStepLimit soft_particle_limit(const SoftParticleParameters& par) {
  const double omega = std::sqrt(4.0 * par.wall_energy / droplet_mass);
  const double by_contact = omega > 0 ? 1.0 / omega : HUGE_VAL;
  if (by_contact < par.terminal_speed)
    return {by_contact, "wall repulsion E_w (ω = " + std::to_string(omega) + "/t0)"};
  return {par.terminal_speed, "drag b∞ (rate 1/V_t = " + std::to_string(1 / par.terminal_speed) + "/t0)"};
}

inline double soft_particle_max_dt(const SoftParticleParameters& par) { return soft_particle_limit(par).max_dt; }

inline double resolve_time_step(const SoftParticleParameters& par) {
  const auto limit = soft_particle_limit(par);
  if (par.dt == 0) return std::min(paper_dt, limit.max_dt);
  cli::check_time_step("soft-particle scene", par.dt, limit, par.force_dt);
  return par.dt;
}

template <class Real, class ExecSpace = Kokkos::DefaultExecutionSpace>
class SoftParticleScene {
 public:
  using particles_type = Particles<2, Real, ExecSpace>;

  // One droplet per entry of `centres`, droplet b in obstacle array droplet_array[b].
  SoftParticleScene(const SoftParticleParameters& par, const Surfaces<Real, ExecSpace>& surfaces,
                    const std::vector<Vec<2, double>>& centres, const std::vector<int>& droplet_array)
      : par_((par.validate(), par)),
        dt_(resolve_time_step(par)),
        surfaces_(surfaces),
        vv_(Real(dt_)),
        p_(centres.size(), "soft_particles"),
        array_("mesoflow::soft_particle_scene::droplet_array", centres.size()),
        b_inf_(droplet_mass / par.terminal_speed) {
    if (centres.empty()) throw std::invalid_argument("soft-particle scene: no droplets");
    if (surfaces.num_walls() > 0) throw std::invalid_argument("soft-particle scene: walls are not supported, obstacles only");
    if (droplet_array.size() != centres.size())
      throw std::invalid_argument("soft-particle scene: " + std::to_string(droplet_array.size()) +
                                  " obstacle arrays for " + std::to_string(centres.size()) + " droplets");
    const auto x = Kokkos::create_mirror_view(p_.x);
    const auto array = Kokkos::create_mirror_view(array_);
    for (std::size_t b = 0; b < centres.size(); ++b) {
      if (droplet_array[b] < 0 || droplet_array[b] >= surfaces.obstacles().num_arrays())
        throw std::invalid_argument("soft-particle scene: obstacle array " + std::to_string(droplet_array[b]) +
                                    " outside [0, " + std::to_string(surfaces.obstacles().num_arrays()) + ")");
      for (int d = 0; d < 2; ++d) x(b, d) = Real(centres[b][d]);
      array(b) = droplet_array[b];
    }
    Kokkos::deep_copy(p_.x, x);
    Kokkos::deep_copy(array_, array);
    Kokkos::deep_copy(p_.mass, Real(droplet_mass));
    const double angle = par.gravity_angle * dp::pi / 180.0;
    gravity_ = Vec<2, Real>{{Real(std::cos(angle)), Real(std::sin(angle))}};
    declare_terms();
  }
  // The term list's launches hold `this`: a scene stays where it was built.
  SoftParticleScene(const SoftParticleScene&) = delete;
  SoftParticleScene& operator=(const SoftParticleScene&) = delete;

  // Minimizes eq. 8's energy by FIRE without gravity or drag: removes the overlaps with the
  // obstacles that the initial placement leaves (§2.4).
  FireResult relax(int max_iterations = 20000, double force_tolerance = 1e-6) {
    FireParameters fire;
    fire.dt_start = dt_;
    fire.dt_max = std::max(dt_, 0.5 * soft_particle_max_dt(par_));
    fire.max_iterations = max_iterations;
    fire.force_tolerance = force_tolerance;
    const FireResult result = fire_minimize(p_, [&] { return conservative_forces(false); }, fire);
    compute_step_forces();
    return result;
  }

  // f ← the forces a step evaluates (gravity, eq. 8, eq. 10) at the current positions and
  // velocities, which velocity Verlet's next half kick uses: call after changing the state outside
  // step() (relax() does; so must whoever places droplets with place_droplet()).
  void compute_step_forces() { terms_.evaluate(p_.v); }

  // One modified velocity-Verlet step: gravity, eq. 8 and eq. 10 (the term list, declare_terms()).
  void step() {
    vv_.first_half(p_);
    terms_.evaluate(vv_.velocity_for_forces(p_));
    vv_.second_half(p_);
    ++steps_;
  }

  // f ← −∇U (gravity if on, eq. 8) at the current positions; returns eq. 8's energy.
  double conservative_forces(bool with_gravity) {
    gravity_forces(with_gravity);
    return obstacle_forces(p_.v, Real(0));
  }

  // Droplet b's centre (host copy, setup only).
  Vec<2, double> droplet_centre(int b) const {
    const auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p_.x);
    return Vec<2, double>{{double(x(b, 0)), double(x(b, 1))}};
  }

  // Moves droplet b to `centre`, at rest; setup only (then compute_step_forces()).
  void place_droplet(int b, const Vec<2, double>& centre) {
    const auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p_.x);
    const auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p_.v);
    for (int d = 0; d < 2; ++d) {
      x(b, d) = Real(centre[d]);
      v(b, d) = Real(0);
    }
    Kokkos::deep_copy(p_.x, x);
    Kokkos::deep_copy(p_.v, v);
  }

  // The NaN watchdog's view of the scene (scenes/common/nan_watchdog.hpp): x, v, f and the step
  // counter; each term of the term list alone. The scene must outlive it.
  watchdog::Watched watched() {
    watchdog::Watched w = watchdog::watch_particles(p_);
    w.step = [this] { step(); };
    w.steps = [this] { return steps_; };
    w.set_steps = [this](long long s) { steps_ = s; };
    w.terms = terms_.watchdog_terms();
    w.particle = [](long long i) { return "droplet " + std::to_string(i); };
    return w;
  }

  // The scene's components: the droplets, the obstacles and the launches of a step with their terms.
  std::vector<std::string> components() const {
    std::vector<std::string> c{std::to_string(p_.size()) + " soft-particle droplet(s)"};
    if (surfaces_.obstacles().size() > 0) c.push_back(std::to_string(surfaces_.obstacles().size()) + " obstacles");
    for (auto& line : terms_.components()) c.push_back(std::move(line));
    return c;
  }

  const scene::TermList<const typename particles_type::vector_view&>& terms() const { return terms_; }

  const particles_type& particles() const { return p_; }
  const SoftParticleParameters& parameters() const { return par_; }
  long long steps() const { return steps_; }
  double time() const { return double(steps_) * dt_; }
  double dt() const { return dt_; }
  double far_drag() const { return b_inf_; }

 private:
  // The scene's terms, declared once: the step, the watchdog and the summaries read this list.
  // Two launches: gravity (sets f, so it clears the last step's forces) and the obstacle loop (one
  // pass over the obstacles near each droplet serves eq. 8, summed, and eq. 10's drag).
  void declare_terms() {
    using vector_view = typename particles_type::vector_view;
    terms_.term({"gravity", "eq. 4", false, true, [this] { gravity_forces(true); }});
    terms_.term({"obstacle repulsion E_sp", "eq. 8", false, par_.wall_energy != 0, [this] {
                   p_.zero_forces();
                   obstacle_forces(p_.v, Real(0));
                 }});
    terms_.term({"drag b∞", "eq. 10", true, true, [this] {
                   p_.zero_forces();
                   accumulate_surface_forces(ParticleArraySurfaces<Real, ExecSpace>{surfaces_, array_}, p_, p_.v,
                                             sp::ObstacleRepulsion<Real>(Real(0), Real(1)),
                                             sp::ViscousDrag<Real>(Real(b_inf_)));
                 }});
    terms_.launch("gravity (one kernel)", {"gravity"}, [this](const vector_view&) { gravity_forces(true); });
    terms_.launch("obstacle loop (one kernel)", {"obstacle repulsion E_sp", "drag b∞"},
                  [this](const vector_view& u) { obstacle_forces(u, Real(b_inf_)); });
  }

  // f += eq. 8 summed over every obstacle of the droplet's array that it overlaps, and the drag of
  // eq. 10 with coefficient `drag` at velocity `velocity`; returns eq. 8's energy.
  double obstacle_forces(const typename particles_type::vector_view& velocity, Real drag_coefficient) {
    return accumulate_surface_forces(ParticleArraySurfaces<Real, ExecSpace>{surfaces_, array_}, p_, velocity,
                                     sp::ObstacleRepulsion<Real>(Real(par_.wall_energy), Real(1)),
                                     sp::ViscousDrag<Real>(drag_coefficient));
  }

  // f ← M g (or 0): kernels/sp/gravity.hpp.
  void gravity_forces(bool with_gravity) {
    sp::set_gravity_forces(p_, with_gravity ? gravity_ : Vec<2, Real>::zero());
  }

  SoftParticleParameters par_;
  double dt_;
  Surfaces<Real, ExecSpace> surfaces_;
  VelocityVerlet<2, Real, ExecSpace> vv_;
  particles_type p_;
  Kokkos::View<int*, ExecSpace> array_;
  double b_inf_;
  Vec<2, Real> gravity_;
  scene::TermList<const typename particles_type::vector_view&> terms_;
  long long steps_ = 0;
};

}  // namespace mesoflow::droplets
