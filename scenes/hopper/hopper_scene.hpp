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
// Continuous flow (§2.4, scenes/hopper/recycling.hpp, shared with the DP hopper), every
// `detect_every` steps: particles whose centre first passes below the orifice plane leave the
// hopper; once some are more than 2σ_avg below it, positions and velocities are copied to the host
// (mirrors made once) and each is re-inserted in contact with an anchor (centre distance σ_mn
// exactly) where it overlaps no other particle and no wall by more than the contact tolerance 10⁻⁹
// (relative, 1 − r/σ_mn and 1 − 2d_w/σ_m); it takes the anchor's velocity.
#pragma once

#include "kernels/common/kernel_launch.hpp"
#include "scenes/common/nan_watchdog.hpp"
#include "scenes/common/term_list.hpp"
#include "kernels/sp/contact_number.hpp"
#include "scenes/hopper/recycling.hpp"
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
#include "kernels/sp/gravity.hpp"
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
constexpr double initial_packing = 0.5;     // packing fraction of the random initial placement
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
        recycler_(par.seed) {
    place_randomly();
    number_ids(ids_);
    x_host_ = Kokkos::create_mirror_view(p_.x);
    v_host_ = Kokkos::create_mirror_view(p_.v);
    type_host_ = Kokkos::create_mirror_view(p_.type);
    outside_host_ = Kokkos::create_mirror_view(outside_);
    contact_number_ = Kokkos::View<int*, ExecSpace>("mesoflow::hopper::contact_number", std::size_t(par.particles));
    contact_number_host_ = Kokkos::create_mirror_view(contact_number_);
    declare_terms();
  }
  // The term list's launches hold `this`: a scene stays where it was built.
  HopperScene(const HopperScene&) = delete;
  HopperScene& operator=(const HopperScene&) = delete;

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
    terms_.evaluate(vv_.velocity_for_forces(p_));
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

  // Positions from the host (tests). The neighbor list and wall candidates follow at the next step
  // (the skin criterion sees the move); nothing is reordered before then.
  void set_positions(const std::vector<Vec<D, double>>& x) {
    if (x.size() != p_.size()) throw std::invalid_argument("hopper scene: positions for the wrong particle count");
    for (std::size_t i = 0; i < x.size(); ++i)
      for (int d = 0; d < D; ++d) x_host_(i, d) = Real(x[i][d]);
    Kokkos::deep_copy(p_.x, x_host_);
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
    auto saved = std::make_shared<Recycler::State>();
    w.save_host = [this, saved] { *saved = recycler_.state(); };
    w.restore_host = [this, saved] { recycler_.restore(*saved); };
    w.after_restore = [this] {
      list_.build(p_, box_);
      sp::find_wall_candidates(list_.skin(), contacts_, walls_, p_, wall_candidates_);
    };
    w.terms = terms_.watchdog_terms();
    const auto ids = ids_;
    w.particle = [ids](long long i) {
      int id = 0;
      Kokkos::deep_copy(id, Kokkos::subview(ids, i));
      return "particle " + std::to_string(id) + " (stored at " + std::to_string(i) + ")";
    };
    return w;
  }

  // The scene's components: particles, walls and the launches of a step with their terms.
  std::vector<std::string> components() const {
    std::vector<std::string> c{std::to_string(p_.size()) + " soft particles (" + std::to_string(D) + "D, bidisperse)",
                               std::to_string(shapes_.size()) + " walls (candidate walls per particle)"};
    for (auto& line : terms_.components()) c.push_back(std::move(line));
    return c;
  }
  const scene::TermList<const typename particles_type::vector_view&>& terms() const { return terms_; }

  const particles_type& particles() const { return p_; }
  // Original index of the particle now stored at each index (particles are sorted in memory).
  const Kokkos::View<int*, ExecSpace>& ids() const { return ids_; }
  int particle_sorts() const { return sorts_; }
  const HopperParameters& parameters() const { return par_; }
  const std::vector<Shape<D, Real>>& walls() const { return shapes_; }
  long long steps() const { return steps_; }
  double time() const { return double(steps_) * par_.dt; }
  double dt() const { return par_.dt; }
  double crossed_measure() const { return recycler_.state().crossed; }  // area (2D) / volume (3D) out of the orifice
  long long crossings() const { return recycler_.state().crossings; }
  double last_crossing_time() const { return recycler_.state().last_crossing_time; }
  long long insertions() const { return recycler_.state().insertions; }
  const std::vector<int>& last_inserted() const { return recycler_.state().last_inserted; }  // of the latest recycling
  long long last_recycling_step() const { return recycler_.state().last_recycling_step; }
  double max_insertion_overlap() const { return recycler_.state().max_insertion_overlap; }  // over all insertions

 private:
  // The scene's terms, declared once: the step, the watchdog and the summaries read this list.
  // One launch per term, in the step's order; gravity comes first and sets f (it clears the last
  // step's forces), friction and drag take the half-step velocity.
  void declare_terms() {
    using vector_view = typename particles_type::vector_view;
    const auto alone = [this](auto add) {
      return [this, add] {
        p_.zero_forces();
        add();
      };
    };
    terms_.term({"gravity", "eq. 4", false, true, [this] { gravity_forces(gravity_on_); }});
    terms_.term({"pair repulsion E_sp", "eq. 2", false, par_.pair_energy != 0,
                 alone([this] { pair_.accumulate_forces(contacts_, p_, list_, box_); })});
    terms_.term({"wall repulsion E_w", "eq. 3", false, par_.wall_energy != 0, alone([this] {
                   sp::accumulate_wall_repulsion(Real(par_.wall_energy), contacts_, walls_, p_, wall_candidates_);
                 })});
    terms_.term({"kinetic friction μ", "eq. 6", true, par_.friction > 0, alone([this] {
                   sp::accumulate_kinetic_friction(Real(par_.friction), contacts_, p_, p_.v, list_, box_,
                                                    par_.friction_component);
                 })});
    terms_.term({"viscous drag ζ", "eq. 5", true, par_.drag > 0,
                 alone([this] { sp::accumulate_mass_proportional_drag(Real(par_.drag), p_, p_.v); })});
    terms_.launch("gravity (one kernel)", {"gravity"}, [this](const vector_view&) { gravity_forces(gravity_on_); });
    terms_.launch("pair loop (full neighbor list)", {"pair repulsion E_sp"},
                  [this](const vector_view&) { pair_.accumulate_forces(contacts_, p_, list_, box_); });
    terms_.launch("wall loop (candidate walls)", {"wall repulsion E_w"}, [this](const vector_view&) {
      sp::accumulate_wall_repulsion(Real(par_.wall_energy), contacts_, walls_, p_, wall_candidates_);
    });
    terms_.launch("friction loop (full neighbor list)", {"kinetic friction μ"}, [this](const vector_view& u) {
      sp::accumulate_kinetic_friction(Real(par_.friction), contacts_, p_, u, list_, box_, par_.friction_component);
    });
    terms_.launch("drag (one kernel)", {"viscous drag ζ"},
                  [this](const vector_view& u) { sp::accumulate_mass_proportional_drag(Real(par_.drag), p_, u); });
  }

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
    mesoflow::launch::parallel_for(
        "mesoflow::hopper::ids", Kokkos::RangePolicy<ExecSpace>(0, ids.extent(0)), KOKKOS_LAMBDA(int i) { ids(i) = i; });
  }

  // f ← M g (g along −axis D−1) or 0 (kernels/sp/gravity.hpp). Off, the vertical component is −0,
  // as the scene's gravity has always given.
  void gravity_forces(bool with_gravity) {
    V g = V::zero();
    g[D - 1] = -(with_gravity ? Real(1) : Real(0));
    sp::set_gravity_forces(p_, g);
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

  // A particle's height and area/volume, for count_crossings (recycling.hpp).
  struct CrossingBody {
    typename particles_type::vector_view x;
    typename particles_type::int_view type;
    double small, large;
    KOKKOS_INLINE_FUNCTION Real height(int i) const { return x(i, D - 1); }
    KOKKOS_INLINE_FUNCTION double measure(int i) const { return type(i) == 0 ? small : large; }
  };

  // Marks first passages below the orifice plane, sums their area/volume, recycles when needed.
  void detect_crossings() {
    const auto sums = count_crossings<Real>(
        "mesoflow::hopper::detect_crossings", int(p_.size()), outside_,
        CrossingBody{p_.x, p_.type, particle_measure<D>(sigma_small), particle_measure<D>(sigma_large)});
    if (recycler_.record_crossings(sums, time())) recycle();
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

 private:
  // Host re-insertion of every particle more than recycle_depth below the orifice (recycling.hpp).
  // Anchors are bulk particles (inside the hopper, not awaiting re-insertion), those held in the
  // packing first: touching at least two particles or walls (kernels/sp/contact_number.hpp); the
  // re-inserted particle takes the mean velocity of the anchor's neighbourhood. Before issue 27 it
  // took the velocity of the highest bulk particle itself, which could be flying above the pile: at
  // weak dissipation (μ/μ0 = 1, E_sp = 10⁴, w = 10) every re-insertion copied one particle's
  // agitation, the top of the pile heated up without bound and the flow starved (docs/hopper.md).
  // Anchors held in the packing alone slowed the runaway; the mean velocity stops it.
  void recycle() {
    if (list_.num_builds() == 0) maintain_neighbors();
    sp::count_contacts(contacts_, walls_, p_, list_, box_, contact_number_);
    Kokkos::deep_copy(contact_number_host_, contact_number_);
    Kokkos::deep_copy(x_host_, p_.x);
    Kokkos::deep_copy(v_host_, p_.v);
    Kokkos::deep_copy(outside_host_, outside_);
    Kokkos::deep_copy(type_host_, p_.type);
    const int n = int(p_.size());
    std::vector<int> below;
    std::vector<char> moved(std::size_t(n), 0);  // re-inserted now: their contact numbers are from below
    for (int i = 0; i < n; ++i)
      if (double(x_host_(i, D - 1)) < -recycle_depth) {
        below.push_back(i);
        moved[std::size_t(i)] = 1;
      }
    const auto anchor = [&](int k) {
      Recycler::Anchor a{outside_host_(k) == 0 && !(double(x_host_(k, D - 1)) < -recycle_depth),
                         {0, 0},
                         double(x_host_(k, D - 1)),
                         !moved[std::size_t(k)] && contact_number_host_(k) >= min_anchor_contacts};
      for (int d = 0; d < D - 1; ++d) a.lateral[d] = double(x_host_(k, d));
      return a;
    };
    // In contact with anchor j (centre distance σ_mn), taking its neighbourhood's mean velocity.
    const auto try_place = [&](int i, int j, const Vec<D, double>& dir) -> std::optional<double> {
      const double s = 0.5 * (particle_diameter(type_host_(i)) + particle_diameter(type_host_(j)));
      Vec<D, double> pos;
      for (int d = 0; d < D; ++d) pos[d] = double(x_host_(j, d)) + s * dir[d];
      const double overlap = overlap_at(i, pos);
      if (overlap > contact_tolerance) return std::nullopt;
      for (int d = 0; d < D; ++d) x_host_(i, d) = Real(pos[d]);
      // The velocity: the mean of the anchor's and its bulk neighbours' within 2σ_avg (hopper-flows
      // §2.4: "the same speed as neighboring particles"), the local flow without the anchor's own
      // agitation (see above).
      Vec<D, double> mean = Vec<D, double>::zero();
      int count = 0;
      for (int k = 0; k < n; ++k) {
        if (k == i || outside_host_(k) != 0) continue;
        double r2 = 0;
        for (int d = 0; d < D; ++d) r2 += std::pow(double(x_host_(k, d)) - double(x_host_(j, d)), 2);
        if (r2 >= 4.0) continue;
        for (int d = 0; d < D; ++d) mean[d] += double(v_host_(k, d));
        ++count;
      }
      for (int d = 0; d < D; ++d) v_host_(i, d) = Real(mean[d] / count);
      outside_host_(i) = 0;
      return overlap;
    };
    recycler_.reinsert<D>(below, inner_radius(), n, anchor, try_place, "hopper scene: no place to re-insert particle ",
                          steps_);
    Kokkos::deep_copy(p_.x, x_host_);
    Kokkos::deep_copy(p_.v, v_host_);
    Kokkos::deep_copy(outside_, outside_host_);
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
  Kokkos::View<int*, ExecSpace> contact_number_;  // particles and walls touching each particle, at recycling
  typename Kokkos::View<int*, ExecSpace>::HostMirror contact_number_host_;
  Recycler recycler_;  // the continuous flow's counters and RNG (recycling.hpp)
  scene::TermList<const typename particles_type::vector_view&> terms_;
  bool gravity_on_ = true;
  int sorts_ = 0;
  long long steps_ = 0;
};

}  // namespace mesoflow::hopper
