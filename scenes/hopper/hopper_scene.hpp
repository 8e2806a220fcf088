// hopper_scene.hpp — continuous gravity-driven hopper flow of bidisperse soft particles (SP), 2D and
// 3D (hopper-flows paper §2.1, §2.2, §2.4): composes the SP kernels, owns the state, steps it.
// Shared by the `hopper` driver and its tests; physics stays in kernels/.
//
// Units (§2.2): length σ_avg = (σ_s + σ_l)/2 = 1, acceleration g = 1, mass density ρ = 1 (areal in
// 2D); time t0 = √(σ_avg/g). σ_s = 1/1.2, σ_l = 1.4/1.2; masses M = ρπσ²/4 (2D) or ρπσ³/6 (3D).
// E_sp = ε_sp, E_w = ε_w (eqs. 2–3), ζ/ζ0 and μ/μ0 are the coefficients of eqs. 5–6.
// Gravity along −y (2D) or −z (3D); the orifice is centred at height 0 (kernels/common/geometry.hpp).
//
// Step: modified velocity Verlet (λ = ½) with gravity, E_sp (full neighbor list with skin), E_w,
// friction μ and drag ζ evaluated at the half-step velocity; zero coefficients cost nothing.
// Neighbor upkeep: when the list needs a rebuild, every `sort_every_builds`-th time the particles
// are first reordered into cell order (kernels/common/particle_sort.hpp; `ids()` keeps each
// particle's original index), then the list is rebuilt and each particle's candidate walls (those
// within σ_m/2 + skin) are marked, so the wall term queries only walls a particle can reach.
//
// Continuous flow (§2.4), every `detect_every` steps: one parallel_reduce marks particles whose
// centre first passes below the orifice plane (height 0: they leave the hopper, adding their
// area/volume to the crossed total) and counts those more than 2σ_avg below it. Only when that
// count is nonzero are positions and velocities copied to the host (mirrors made once) and each
// such particle re-inserted: a lateral target is drawn (host RNG keyed on the seed), the highest
// bulk particle within σ_avg of it laterally is the anchor (the highest bulk particle overall if
// that column is empty), and the particle is put in contact with the anchor (centre distance σ_mn
// exactly) in the first direction — straight up, then tilting away by 15° steps — where it overlaps
// no other particle and no wall by more than the contact tolerance 10⁻⁹ (relative, 1 − r/σ_mn and
// 1 − 2d_w/σ_m); it takes the anchor's velocity. The particle count never changes.
#pragma once

#include "scenes/common/nan_watchdog.hpp"
#include "scenes/common/time_step_limit.hpp"
#include "kernels/common/box.hpp"
#include "kernels/common/fire.hpp"
#include "kernels/common/geometry.hpp"
#include "kernels/common/neighbor_list.hpp"
#include "kernels/common/particle_sort.hpp"
#include "kernels/common/pair_force.hpp"
#include "kernels/common/particles.hpp"
#include "kernels/common/reductions.hpp"
#include "kernels/common/velocity_verlet.hpp"
#include "kernels/sp/kinetic_friction.hpp"
#include "kernels/sp/mass_proportional_drag.hpp"
#include "kernels/sp/pair_repulsion.hpp"
#include "kernels/sp/wall_repulsion.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace mesoflow::hopper {

constexpr double sigma_small = 1.0 / 1.2;   // σ_s/σ_avg
constexpr double sigma_large = 1.4 / 1.2;   // σ_l/σ_avg (σ_l/σ_s = 1.4)
constexpr double recycle_depth = 2.0;       // σ_avg below the orifice before re-insertion (§2.4)
constexpr double contact_tolerance = 1e-9;  // largest relative overlap of a re-inserted particle
constexpr double initial_packing = 0.5;     // packing fraction of the random initial placement
constexpr int detect_every = 10;            // steps between crossing/recycling checks
constexpr int sort_every_builds = 20;       // neighbor-list rebuilds between particle sorts
constexpr double pi = 3.14159265358979323846;

struct HopperParameters {
  int particles = 300;           // N, half small, half large
  double hopper_width = 20.0;    // W/σ_avg (3D: cylinder diameter)
  double orifice = 6.0;          // w/σ_avg
  double wall_angle = 90.0;      // θ_w in degrees
  double pair_energy = 100.0;    // E_sp
  double wall_energy = 1e4;      // E_w (§2.2)
  double drag = 0.0;             // ζ/ζ0
  double friction = 0.0;         // μ/μ0
  sp::FrictionComponent friction_component = sp::FrictionComponent::full;  // eq. 6 as printed, or tangential only
  double dt = 1e-3;              // Δt/t0 (§2.2)
  unsigned long long seed = 1;
  bool force_dt = false;         // run a dt above the stability limit (a warning instead of an error)

  // Throws std::invalid_argument naming the first parameter outside its range.
  void validate(int dim) const {
    auto require = [](bool ok, const std::string& name, const std::string& range, double value) {
      if (!ok)
        throw std::invalid_argument("hopper scene: " + name + " must be " + range + ", got " + std::to_string(value));
    };
    require(particles >= 2, "particles N", ">= 2", particles);
    require(std::isfinite(hopper_width) && hopper_width >= 4 * sigma_large, "hopper width W", ">= 4 σ_l", hopper_width);
    require(std::isfinite(orifice) && orifice > 0 && orifice < hopper_width, "orifice w", "in (0, W)", orifice);
    require(std::isfinite(wall_angle) && wall_angle > 0 && wall_angle <= 90, "wall angle θ_w", "in (0, 90] degrees",
            wall_angle);
    require(std::isfinite(pair_energy) && pair_energy > 0, "pair energy E_sp", "finite and > 0", pair_energy);
    require(std::isfinite(wall_energy) && wall_energy >= 0, "wall energy E_w", "finite and >= 0", wall_energy);
    require(std::isfinite(drag) && drag >= 0, "drag ζ", "finite and >= 0", drag);
    require(std::isfinite(friction) && friction >= 0, "friction μ", "finite and >= 0", friction);
    require(std::isfinite(dt) && dt > 0, "time step dt", "finite and > 0", dt);
    cli::check_time_step("hopper scene", dt, stability_limit(dim), force_dt);
  }

  // Explicit limit: Δt ω ≤ 1 for the stiffest contact of a small particle (wall plus z neighbours,
  // z = 6 in 2D, 12 in 3D; half the Verlet limit Δt ω < 2) and Δt ν ≤ 2 for its damping rate
  // ν = z μ/M_s + ζ (the explicit limit of v' = −ν v).
  double max_stable_dt(int dim) const { return stability_limit(dim).max_dt; }

  // The same limit with the term that sets it: the larger of the wall (4E_w/σ_s²) and pair
  // (z E_sp/σ_s²) stiffness when the contact mode binds, else friction or drag.
  cli::TimeStepLimit stability_limit(int dim) const {
    const double z = dim == 2 ? 6 : 12;
    const double m = dim == 2 ? pi / 4 * sigma_small * sigma_small : pi / 6 * std::pow(sigma_small, 3);
    const double k_wall = 4 * wall_energy / (sigma_small * sigma_small);
    const double k_pair = z * pair_energy / (sigma_small * sigma_small);
    const double omega = std::sqrt((k_wall + k_pair) / m), nu = z * friction / m + drag;
    const double by_contacts = 1 / omega, by_damping = nu > 0 ? 2 / nu : HUGE_VAL;
    if (by_damping < by_contacts)
      return {by_damping, std::string(z * friction / m >= drag ? "friction μ" : "drag ζ") + " (damping rate " +
                              std::to_string(nu) + "/t0)"};
    return {by_contacts, std::string(k_pair >= k_wall ? "pair repulsion E_sp" : "wall repulsion E_w") + " (ω = " +
                             std::to_string(omega) + "/t0)"};
  }
};

inline double particle_diameter(int type) { return type == 0 ? sigma_small : sigma_large; }

// Area (2D) or volume (3D) of a particle of diameter s.
template <int D>
double particle_measure(double s) {
  return D == 2 ? pi / 4 * s * s : pi / 6 * s * s * s;
}

template <int D, class Real = double, class ExecSpace = Kokkos::DefaultExecutionSpace>
class HopperScene {
 public:
  using particles_type = Particles<D, Real, ExecSpace>;
  using V = Vec<D, Real>;

  explicit HopperScene(const HopperParameters& par)
      : par_((par.validate(D), par)),
        shapes_(D == 2 ? walls_2d(par) : walls_3d(par)),
        walls_(shapes_),
        contacts_(Real(par.pair_energy), {sigma_small, sigma_large}),
        list_(contacts_.cutoff(), Real(0.3)),
        vv_(Real(par.dt)),
        p_(std::size_t(par.particles), "hopper"),
        outside_("mesoflow::hopper::outside", std::size_t(par.particles)),
        ids_("mesoflow::hopper::id", std::size_t(par.particles)),
        wall_candidates_("mesoflow::hopper::wall_candidates", std::size_t(par.particles)),
        rng_(par.seed ^ 0x9e3779b97f4a7c15ULL) {
    place_randomly();
    number_ids(ids_);
    x_host_ = Kokkos::create_mirror_view(p_.x);
    v_host_ = Kokkos::create_mirror_view(p_.v);
    type_host_ = Kokkos::create_mirror_view(p_.type);
    outside_host_ = Kokkos::create_mirror_view(outside_);
  }

  // FIRE without gravity or dissipation: removes the overlaps of the random placement (§2.4).
  FireResult relax(int max_iterations = 50000) {
    FireParameters fire;
    fire.dt_start = par_.dt;
    fire.dt_max = std::max(par_.dt, 0.5 * par_.max_stable_dt(D));
    fire.max_iterations = max_iterations;
    fire.force_tolerance = 1e-8 * par_.pair_energy;
    const auto result = fire_minimize(p_, [&] { return conservative_forces(false); }, fire);
    if (!result.converged)
      throw std::runtime_error("hopper scene: FIRE did not remove the initial overlaps in " +
                               std::to_string(max_iterations) + " iterations (max |F| " +
                               std::to_string(result.max_force) + ")");
    return result;
  }

  // One step; every detect_every steps, the crossing count and (when needed) recycling.
  void step() {
    vv_.first_half(p_);
    maintain_neighbors();
    const auto velocity = vv_.velocity_for_forces(p_);
    gravity_forces(gravity_on_);
    pair_.accumulate_forces(contacts_, p_, list_, box_);
    sp::accumulate_wall_repulsion(Real(par_.wall_energy), contacts_, walls_, p_, wall_candidates_);
    sp::accumulate_kinetic_friction(Real(par_.friction), contacts_, p_, velocity, list_, box_, par_.friction_component);
    sp::accumulate_mass_proportional_drag(Real(par_.drag), p_, velocity);
    vv_.second_half(p_);
    ++steps_;
    if (steps_ % detect_every == 0) detect_crossings();
  }

  // f ← −∇U (gravity if on, E_sp, E_w); returns U without gravity.
  double conservative_forces(bool with_gravity) {
    maintain_neighbors();
    gravity_forces(with_gravity);
    double u = pair_.accumulate(contacts_, p_, list_, box_);
    u += sp::accumulate_wall_repulsion(Real(par_.wall_energy), contacts_, walls_, p_, wall_candidates_);
    return u;
  }

  // Particles whose centres lie in the region above the orifice of Appendix B: 2D the 2w × w
  // rectangle |x| < w, 0 < y < w; 3D the cylinder of diameter 2w and height w on the orifice.
  int orifice_region_count() const {
    const auto x = p_.x;
    const double w = par_.orifice;
    return int(parallel_sum<1, ExecSpace>(
        "mesoflow::hopper::orifice_region", int(p_.size()), KOKKOS_LAMBDA(int i, double(&acc)[1]) {
          double lateral2 = 0;
          for (int d = 0; d < D - 1; ++d) lateral2 += double(x(i, d)) * double(x(i, d));
          const double h = double(x(i, D - 1));
          if (lateral2 < w * w && h > 0 && h < w) acc[0] += 1;
        })[0]);
  }
  // Area (2D) or volume (3D) of that region.
  double orifice_region_measure() const {
    const double w = par_.orifice;
    return D == 2 ? 2 * w * w : pi * w * w * w;
  }
  // Mean undeformed particle area (2D) or volume (3D), half small and half large: a_avg of Appendix B.
  static double mean_particle_measure() {
    return 0.5 * (particle_measure<D>(sigma_small) + particle_measure<D>(sigma_large));
  }

  // Gravity is on unless a test switches it off (momentum conservation of the contact forces).
  void set_gravity(bool on) { gravity_on_ = on; }

  // Velocities from the host (setup and tests).
  void set_velocities(const std::vector<Vec<D, double>>& v) {
    if (v.size() != p_.size()) throw std::invalid_argument("hopper scene: velocities for the wrong particle count");
    for (std::size_t i = 0; i < v.size(); ++i)
      for (int d = 0; d < D; ++d) v_host_(i, d) = Real(v[i][d]);
    Kokkos::deep_copy(p_.v, v_host_);
  }

  // The NaN watchdog's view of the scene (scenes/common/nan_watchdog.hpp). The state includes what
  // a cell sort permutes (mass, type, ids, outside) and, on the host, the recycling RNG and counters;
  // after a restore the neighbor list and wall candidates are rebuilt. The scene must outlive it.
  watchdog::Watched watched() {
    watchdog::Watched w = watchdog::watch_particles(p_);
    w.state.insert(w.state.end(), {watchdog::Field::of("mass", p_.mass), watchdog::Field::kept("type", p_.type),
                                   watchdog::Field::kept("id", ids_), watchdog::Field::kept("outside", outside_)});
    w.step = [this] { step(); };
    w.steps = [this] { return steps_; };
    w.set_steps = [this](long long s) { steps_ = s; };
    struct HostState {
      std::mt19937_64 rng;
      long long crossings, insertions, last_recycling_step;
      double crossed, last_crossing_time;
    };
    auto saved = std::make_shared<HostState>();
    w.save_host = [this, saved] {
      *saved = {rng_, crossings_, insertions_, last_recycling_step_, crossed_, last_crossing_time_};
    };
    w.restore_host = [this, saved] {
      rng_ = saved->rng;
      crossings_ = saved->crossings;
      insertions_ = saved->insertions;
      last_recycling_step_ = saved->last_recycling_step;
      crossed_ = saved->crossed;
      last_crossing_time_ = saved->last_crossing_time;
    };
    w.after_restore = [this] {
      list_.build(p_, box_);
      sp::find_wall_candidates(list_.skin(), contacts_, walls_, p_, wall_candidates_);
    };
    const auto alone = [this](auto add) {
      return [this, add] {
        p_.zero_forces();
        add();
      };
    };
    w.terms = {{"gravity", [this] { gravity_forces(gravity_on_); }},
               {"pair repulsion E_sp (eq. 2)", alone([this] { pair_.accumulate_forces(contacts_, p_, list_, box_); })},
               {"wall repulsion E_w (eq. 3)", alone([this] {
                  sp::accumulate_wall_repulsion(Real(par_.wall_energy), contacts_, walls_, p_, wall_candidates_);
                })}};
    if (par_.friction > 0)
      w.terms.push_back({"kinetic friction μ (eq. 6)", alone([this] {
                           sp::accumulate_kinetic_friction(Real(par_.friction), contacts_, p_, p_.v, list_, box_,
                                                            par_.friction_component);
                         }),
                         true});
    if (par_.drag > 0)
      w.terms.push_back({"viscous drag ζ (eq. 5)",
                         alone([this] { sp::accumulate_mass_proportional_drag(Real(par_.drag), p_, p_.v); }), true});
    const auto ids = ids_;
    w.particle = [ids](long long i) {
      int id = 0;
      Kokkos::deep_copy(id, Kokkos::subview(ids, i));
      return "particle " + std::to_string(id) + " (stored at " + std::to_string(i) + ")";
    };
    return w;
  }

  const particles_type& particles() const { return p_; }
  // Original index of the particle now stored at each index (particles are sorted in memory).
  const Kokkos::View<int*, ExecSpace>& ids() const { return ids_; }
  int particle_sorts() const { return sorts_; }
  const HopperParameters& parameters() const { return par_; }
  const std::vector<Shape<D, Real>>& walls() const { return shapes_; }
  long long steps() const { return steps_; }
  double time() const { return double(steps_) * par_.dt; }
  double dt() const { return par_.dt; }
  double crossed_measure() const { return crossed_; }          // area (2D) / volume (3D) out of the orifice
  long long crossings() const { return crossings_; }
  double last_crossing_time() const { return last_crossing_time_; }
  long long insertions() const { return insertions_; }
  const std::vector<int>& last_inserted() const { return last_inserted_; }  // of the latest recycling
  long long last_recycling_step() const { return last_recycling_step_; }
  double max_insertion_overlap() const { return max_insertion_overlap_; }   // over all insertions

 private:
  static std::vector<Shape<D, Real>> walls_2d(const HopperParameters& par) {
    if constexpr (D == 2)
      return hopper_walls_2d<Real>(Real(par.hopper_width), Real(par.orifice), Real(par.wall_angle));
    else
      return {};
  }
  static std::vector<Shape<D, Real>> walls_3d(const HopperParameters& par) {
    if constexpr (D == 3)
      return hopper_walls_3d<Real>(Real(par.hopper_width), Real(par.orifice), Real(par.wall_angle));
    else
      return {};
  }

  // Height of the exit wall where it meets the side wall: the lowest height clear of the walls.
  double floor_height() const {
    return 0.5 * (par_.hopper_width - par_.orifice) / std::tan(par_.wall_angle * pi / 180) + sigma_large;
  }
  double inner_radius() const { return 0.5 * par_.hopper_width - 0.5 * sigma_large; }

  // Half small (even index), half large; uniform in a column of the hopper above the exit walls,
  // tall enough for the initial packing fraction; a box for the cell list around it.
  void place_randomly() {
    const int n = par_.particles;
    double total = 0;
    for (int i = 0; i < n; ++i) total += particle_measure<D>(particle_diameter(i % 2));
    const double r = inner_radius();
    const double cross_section = D == 2 ? 2 * r : pi * r * r;
    const double bottom = floor_height(), height = total / (initial_packing * cross_section);
    std::mt19937_64 gen(par_.seed);
    std::uniform_real_distribution<double> u(-1, 1), h(bottom, bottom + height);
    auto x = Kokkos::create_mirror_view(p_.x);
    auto type = Kokkos::create_mirror_view(p_.type);
    auto mass = Kokkos::create_mirror_view(p_.mass);
    for (int i = 0; i < n; ++i) {
      type(i) = i % 2;
      mass(i) = Real(particle_measure<D>(particle_diameter(type(i))));
      double lateral[2] = {0, 0};
      do {
        for (int d = 0; d < D - 1; ++d) lateral[d] = r * u(gen);
      } while (lateral[0] * lateral[0] + lateral[1] * lateral[1] > r * r);
      for (int d = 0; d < D - 1; ++d) x(i, d) = Real(lateral[d]);
      x(i, D - 1) = Real(h(gen));
    }
    Kokkos::deep_copy(p_.x, x);
    Kokkos::deep_copy(p_.type, type);
    Kokkos::deep_copy(p_.mass, mass);
    Real lo[D], len[D];
    bool periodic[D];
    for (int d = 0; d < D - 1; ++d) {
      lo[d] = Real(-0.5 * par_.hopper_width - 1);
      len[d] = Real(par_.hopper_width + 2);
      periodic[d] = false;
    }
    lo[D - 1] = Real(-recycle_depth - 2);
    len[D - 1] = Real(bottom + height + recycle_depth + 4);
    periodic[D - 1] = false;
    box_ = Box<D, Real>(lo, len, periodic);
  }

 public:  // kernels below: nvcc rejects a KOKKOS_LAMBDA in a private member function
  // ids(i) ← i. (Not in the constructor: nvcc rejects a KOKKOS_LAMBDA there.)
  static void number_ids(const Kokkos::View<int*, ExecSpace>& ids) {
    Kokkos::parallel_for(
        "mesoflow::hopper::ids", Kokkos::RangePolicy<ExecSpace>(0, ids.extent(0)), KOKKOS_LAMBDA(int i) { ids(i) = i; });
  }

  // f ← M g (g along −axis D−1) or 0.
  void gravity_forces(bool with_gravity) {
    const auto f = p_.f;
    const auto m = p_.mass;
    const Real g = with_gravity ? Real(1) : Real(0);
    Kokkos::parallel_for(
        "mesoflow::hopper::gravity", Kokkos::RangePolicy<ExecSpace>(0, p_.size()), KOKKOS_LAMBDA(int i) {
          for (int d = 0; d < D - 1; ++d) f(i, d) = Real(0);
          f(i, D - 1) = -g * m(i);
        });
  }

  // Rebuilds the neighbor list when the skin criterion asks for it, sorting the particles into
  // cell order first every sort_every_builds rebuilds, and re-marks the candidate walls.
  void maintain_neighbors() {
    if (!list_.needs_rebuild(p_.x, box_)) return;
    if (list_.num_builds() > 0 && list_.num_builds() % sort_every_builds == 0) {
      sort_particles_by_cell(p_, list_.cells(), outside_, ids_);
      ++sorts_;
    }
    list_.build(p_, box_);
    sp::find_wall_candidates(list_.skin(), contacts_, walls_, p_, wall_candidates_);
  }

  // Marks first passages below the orifice plane, sums their area/volume, counts particles to recycle.
  void detect_crossings() {
    const auto x = p_.x;
    const auto type = p_.type;
    const auto outside = outside_;
    const double small = particle_measure<D>(sigma_small), large = particle_measure<D>(sigma_large);
    const Real depth = Real(-recycle_depth);
    const auto sums = parallel_sum<3, ExecSpace>(
        "mesoflow::hopper::detect_crossings", int(p_.size()), KOKKOS_LAMBDA(int i, double(&acc)[3]) {
          const Real h = x(i, D - 1);
          if (outside(i) == 0 && h < Real(0)) {
            outside(i) = 1;
            acc[0] += type(i) == 0 ? small : large;
            acc[1] += 1;
          }
          if (h < depth) acc[2] += 1;
        });
    if (sums[1] > 0) {
      crossed_ += sums[0];
      crossings_ += (long long)(sums[1]);
      last_crossing_time_ = time();
    }
    if (sums[2] > 0) recycle();
  }

  // Largest relative overlap of particle i at `pos` with every other particle and the walls.
  double overlap_at(int i, const Vec<D, double>& pos) const {
    double worst = 0;
    const double si = particle_diameter(type_host_(i));
    for (int k = 0; k < int(p_.size()); ++k) {
      if (k == i) continue;
      double r2 = 0;
      for (int d = 0; d < D; ++d) r2 += (pos[d] - double(x_host_(k, d))) * (pos[d] - double(x_host_(k, d)));
      const double s = 0.5 * (si + particle_diameter(type_host_(k)));
      if (r2 < s * s) worst = std::max(worst, 1 - std::sqrt(r2) / s);
    }
    V q;
    for (int d = 0; d < D; ++d) q[d] = Real(pos[d]);
    for (const auto& wall : shapes_) {
      const double dist = double(wall.query(q).distance);
      if (dist < 0.5 * si) worst = std::max(worst, 1 - 2 * dist / si);
    }
    return worst;
  }

  // Directions to try around an anchor: straight up, then tilting by 15° steps (3D: 8 azimuths per tilt).
  static std::vector<Vec<D, double>> contact_directions() {
    std::vector<Vec<D, double>> dirs;
    for (int tilt = 0; tilt <= 6; ++tilt) {
      const double a = tilt * pi / 12;
      if constexpr (D == 2) {
        dirs.push_back(Vec<2, double>{{std::sin(a), std::cos(a)}});
        if (tilt > 0) dirs.push_back(Vec<2, double>{{-std::sin(a), std::cos(a)}});
      } else {
        const int azimuths = tilt == 0 ? 1 : 8;
        for (int k = 0; k < azimuths; ++k) {
          const double b = 2 * pi * k / azimuths;
          dirs.push_back(Vec<3, double>{{std::sin(a) * std::cos(b), std::sin(a) * std::sin(b), std::cos(a)}});
        }
      }
    }
    return dirs;
  }

 private:
  // Host re-insertion of every particle more than recycle_depth below the orifice (see file comment).
  void recycle() {
    Kokkos::deep_copy(x_host_, p_.x);
    Kokkos::deep_copy(v_host_, p_.v);
    Kokkos::deep_copy(outside_host_, outside_);
    Kokkos::deep_copy(type_host_, p_.type);
    const int n = int(p_.size());
    last_inserted_.clear();
    for (int i = 0; i < n; ++i)
      if (double(x_host_(i, D - 1)) < -recycle_depth) last_inserted_.push_back(i);
    const auto dirs = contact_directions();
    const double r = inner_radius();
    std::uniform_real_distribution<double> u(-1, 1);
    for (const int i : last_inserted_) {
      double target[2] = {0, 0};
      do {
        for (int d = 0; d < D - 1; ++d) target[d] = r * u(rng_);
      } while (target[0] * target[0] + target[1] * target[1] > r * r);
      // Anchors: bulk particles (inside the hopper, not awaiting re-insertion), those within σ_avg of
      // the target laterally first, each group highest first.
      std::vector<std::pair<double, int>> order;
      for (int k = 0; k < n; ++k) {
        if (outside_host_(k) != 0 || double(x_host_(k, D - 1)) < -recycle_depth) continue;
        double lateral2 = 0;
        for (int d = 0; d < D - 1; ++d) lateral2 += std::pow(double(x_host_(k, d)) - target[d], 2);
        order.emplace_back((lateral2 < 1 ? 1e9 : 0) + double(x_host_(k, D - 1)), k);
      }
      std::sort(order.begin(), order.end(), [](const auto& a, const auto& b) {
        return a.first != b.first ? a.first > b.first : a.second < b.second;
      });
      bool placed = false;
      for (const auto& [key, j] : order) {
        const double s = 0.5 * (particle_diameter(type_host_(i)) + particle_diameter(type_host_(j)));
        for (const auto& dir : dirs) {
          Vec<D, double> pos;
          for (int d = 0; d < D; ++d) pos[d] = double(x_host_(j, d)) + s * dir[d];
          const double overlap = overlap_at(i, pos);
          if (overlap > contact_tolerance) continue;
          for (int d = 0; d < D; ++d) {
            x_host_(i, d) = Real(pos[d]);
            v_host_(i, d) = v_host_(j, d);
          }
          outside_host_(i) = 0;
          max_insertion_overlap_ = std::max(max_insertion_overlap_, overlap);
          placed = true;
          break;
        }
        if (placed) break;
      }
      if (!placed) throw std::runtime_error("hopper scene: no place to re-insert particle " + std::to_string(i));
      ++insertions_;
    }
    Kokkos::deep_copy(p_.x, x_host_);
    Kokkos::deep_copy(p_.v, v_host_);
    Kokkos::deep_copy(outside_, outside_host_);
    last_recycling_step_ = steps_;
  }

  HopperParameters par_;
  std::vector<Shape<D, Real>> shapes_;
  Geometry<D, Real, ExecSpace> walls_;
  sp::SoftSphereRepulsion<Real> contacts_;
  NeighborList<D, Real, ExecSpace> list_;
  PairForce<D, Real, ExecSpace> pair_;
  VelocityVerlet<D, Real, ExecSpace> vv_;
  particles_type p_;
  Box<D, Real> box_;
  Kokkos::View<int*, ExecSpace> outside_;  // 1 once a particle has left through the orifice
  Kokkos::View<int*, ExecSpace> ids_;      // original index of each stored particle
  Kokkos::View<unsigned*, ExecSpace> wall_candidates_;
  typename particles_type::vector_view::HostMirror x_host_, v_host_;
  typename particles_type::int_view::HostMirror type_host_;
  typename Kokkos::View<int*, ExecSpace>::HostMirror outside_host_;
  std::mt19937_64 rng_;
  bool gravity_on_ = true;
  int sorts_ = 0;
  long long steps_ = 0, crossings_ = 0, insertions_ = 0, last_recycling_step_ = -1;
  double crossed_ = 0, last_crossing_time_ = 0, max_insertion_overlap_ = 0;
  std::vector<int> last_inserted_;
};

}  // namespace mesoflow::hopper
