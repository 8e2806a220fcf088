// dp_hopper_scene.hpp — continuous gravity-driven hopper flow of bidisperse deformable polygons (DP),
// 2D (hopper-flows paper §2.3, §2.4, Appendix A): the DP counterpart of hopper_scene.hpp. Composes
// the DP kernels, owns the state, steps it; physics stays in kernels/.
//
// Units (§2.2–2.3): σ_avg = g = ρ (areal) = 1, t0 = √(σ_avg/g). Half the polygons small (even body
// index, effective diameter σ_s = 1/1.2), half large (σ_l = 1.4/1.2); preferred area a_m,0 = πσ_m²/4,
// preferred edge l_m,0 = √(4 a_m,0 N_v tan(π/N_v))/N_v (the regular N_v-gon, §2.4), mass M_m = a_m,0,
// vertex mass M_m/N_v (eq. 13). The dimensionless coefficients are the model's: k_a = K_a,
// k_l = K_l (segment term k_l N_v/2 Σ(l − l0)², eq. 8), k_b = K_b, ε_c = E_c, ε_w = E_w, ζ/ζ0, μ/μ0.
// Vertex contacts (eq. 9): rough (`smooth` false) — vertex disks of diameter δ_m = l_m,0; nearly
// smooth (`smooth` true) — edges as circulo-lines of width δ_m = 0.1 l_m,0 (Appendix A). Walls act on
// vertices with the same δ_m (eq. 10).
//
// Stiffness and time step. The explicit limit is computed from the stiffest modes of a small-particle
// vertex (kernels/dp/stability.hpp for the wall, segment, area and bending modes; ω Δt ≤ 1, half the
// Verlet limit) plus the vertex contacts: z = 3 contacts of stiffness ε_c/δ_s² (a vertex pressed into
// a neighbour's face touches up to two of its vertices, and the pair's reduced mass adds one more),
// and the damping rate ν = z μ/m_s + ζ/M_s of friction (eq. 12) and drag (eq. 11), with Δt ν ≤ 2
// (the explicit limit of v' = −ν v at λ = ½). The paper's E_c = E_w = 10⁴ at Δt = 10⁻³ t0 is far
// beyond the explicit limit (with δ_s = l_s,0 ≈ 0.165σ_avg the wall mode alone has ω ≈ 6.6·10³/t0);
// the defaults E_c = E_w = 100 put the rough model's limit at 1.05·10⁻³ t0, so the paper's
// Δt = 10⁻³ t0 is accepted without dissipation. With μ/μ0 = 10√10 (the paper's λ → 0 limit) the
// friction rate alone limits Δt to 7.2·10⁻⁴ t0, and the smooth model (δ ten times smaller) to
// ≈ 1.15·10⁻⁴ t0. A Δt above the limit is refused naming the limiting term; dt = 0 chooses
// min(10⁻³ t0, 0.9 × limit). Checked on a 120-polygon hopper with μ = 10√10 (the friction term of the
// limit lifted for the check): the non-rigid vertex velocities (rms ≈ 0.45 σ_avg/t0 in steady flow)
// are the same at Δt = 10⁻⁴, 3·10⁻⁴ and 6.5·10⁻⁴ t0, and larger at 9·10⁻⁴–1.05·10⁻³ t0, approaching
// the single-pair friction limit m_s/μ = 1.08·10⁻³ t0.
//
// Step: modified velocity Verlet (λ = ½) with gravity (−y) on every vertex; shape forces (eq. 8:
// area, segment springs, bending; no line tension) and gravity in one loop over vertices; vertex
// contacts (eq. 9, rough or smooth) over a full neighbor list that excludes pairs of the same polygon;
// kinetic friction between contacting vertices of different polygons (eq. 12; smooth model: between a
// vertex and the material point of the edge it touches, kernels/dp/smooth_vertex_friction.hpp;
// skipped at μ = 0); vertex–wall repulsion (eq. 10) over each vertex's candidate walls, re-marked at every
// neighbor-list rebuild exactly as HopperScene does; uniform drag −(ζ/N_v) v per vertex (eq. 11,
// kernels/dp/vertex_drag.hpp; skipped at ζ = 0). Friction and drag use the half-step velocity.
// The vertices are never sorted in memory (kernels/common/particle_sort.hpp): dp::Polygons needs the
// vertices of a body contiguous and in order, which a cell-order permutation of vertices breaks; each
// polygon's own 16 vertices stay together, which keeps the shape loop local.
//
// Continuous flow (§2.4; scenes/hopper/recycling.hpp, shared with the SP hopper), every
// `detect_every` steps: one parallel_reduce over polygons, on the
// centroids (centres of mass) of the step's BodyState, marks polygons whose centroid first passes
// below the orifice plane (height 0), adding a_m,0 to the crossed area, and counts those whose
// centroid is more than 2σ_avg below it. Only when that count is nonzero are positions and velocities
// copied to host mirrors (made once) and each such polygon re-inserted as a rigid translate of its
// current shape: a lateral target is drawn (host RNG keyed on the seed), the highest bulk polygon
// whose centroid is within σ_avg of it laterally is the anchor (the highest bulk polygon overall if
// that column is empty), and the polygon's centroid is put at a distance R_m + R_n + δ_mn from the
// anchor's (R the circumradii about the centroids), straight up, then tilting away by 15° steps, at
// the first position where none of its vertices is within δ_mn of another polygon's vertex (relative
// tolerance 10⁻⁹, as HopperScene) or within δ_m/2 of a wall, no edge crosses another polygon's edge
// and neither centroid lies inside the other polygon (smooth model: no vertex within δ_mn of another
// polygon's edge either). Every vertex takes the mean centroid velocity of the anchor and its bulk
// neighbours within 2σ_avg (issue 27). N is conserved. A blown-up state (a non-finite vertex, or
// one a box length outside the box: a forced Δt above the limit) is not recycled but left for the
// NaN watchdog (watched(), scenes/common/nan_watchdog.hpp).
//
// relax(): the polygons start as regular N_v-gons of random orientation, placed by random sequential
// adsorption (circumcircles disjoint, large polygons first) at packing fraction 0.5 of a_m,0 in the
// hopper above the exit walls; FIRE without gravity or dissipation then removes the vertex-disk
// overlaps with each other and with the walls (§2.4).
#pragma once

#include "scenes/hopper/hopper_scene.hpp"
#include "kernels/dp/area_force.hpp"
#include "kernels/dp/bending_force.hpp"
#include "kernels/dp/gravity.hpp"
#include "kernels/dp/polygons.hpp"
#include "kernels/dp/segment_spring_force.hpp"
#include "kernels/dp/shape_forces.hpp"
#include "kernels/dp/smooth_vertex_contacts.hpp"
#include "kernels/dp/smooth_vertex_friction.hpp"
#include "scenes/common/term_list.hpp"
#include "scenes/common/time_step_limit.hpp"
#include "kernels/dp/stability.hpp"
#include "kernels/dp/vertex_contacts.hpp"
#include "kernels/dp/vertex_drag.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace mesoflow::hopper {

constexpr double dp_smooth_width = 0.1;      // δ_m/l_m,0 of the circulo-lines (§2.3, Appendix A)
constexpr int dp_contacts_per_vertex = 3;    // z of the contact and friction stability terms
constexpr double dp_paper_dt = 1e-3;         // Δt/t0 of §2.3
constexpr double dp_auto_dt_fraction = 0.9;  // dt = 0: this fraction of the limit (if below 10⁻³)
constexpr double dp_skin_fraction = 0.3;     // neighbor-list skin / l_l,0
constexpr double dp_smooth_reach = 1.5;      // smooth list cutoff: this × l_l,0 + δ_l (edges stretch)

// The explicit time-step limit of the DP hopper, term by term: kernels/dp/stability.hpp.
using DpHopperStability = dp::ContactStabilityLimit;

struct DpHopperParameters {
  int particles = 300;               // N polygons, half small, half large
  int vertices = 16;                 // N_v per polygon
  double hopper_width = 20.0;        // W/σ_avg
  double orifice = 6.0;              // w/σ_avg
  double wall_angle = 90.0;          // θ_w in degrees
  double area_stiffness = 1e4;       // K_a
  double perimeter_stiffness = 10;   // K_l
  double bending_stiffness = 0.1;    // K_b
  double contact_energy = 100;       // E_c (the paper's 10⁴ is beyond the explicit limit, see above)
  double wall_energy = 100;          // E_w (idem)
  double drag = 0;                   // ζ/ζ0, eq. 11
  double friction = 0;               // μ/μ0, eq. 12
  sp::FrictionComponent friction_component = sp::FrictionComponent::full;  // as in HopperParameters
  bool smooth = false;               // false: rough vertex disks δ = l0; true: circulo-lines δ = 0.1 l0
  double dt = dp_paper_dt;           // Δt/t0; 0: min(10⁻³, 0.9 × limit)
  unsigned long long seed = 1;
  bool force_dt = false;             // run a dt above the stability limit (a warning instead of an error)

  // σ_m, a_m,0, l_m,0 and δ_m of a particle type (0 small, 1 large).
  static double diameter(int type) { return type == 0 ? sigma_small : sigma_large; }
  static double preferred_area(int type) { return pi / 4 * diameter(type) * diameter(type); }
  double edge_length(int type) const { return dp::regular_polygon_edge(preferred_area(type), vertices); }
  double vertex_diameter(int type) const { return (smooth ? dp_smooth_width : 1.0) * edge_length(type); }

  DpHopperStability stability() const {
    const double m = preferred_area(0) / vertices, l0 = edge_length(0), delta = vertex_diameter(0);
    dp::StiffnessInputs s;
    s.vertex_mass = m;
    s.edge_length = l0;
    s.perimeter = vertices * l0;
    s.vertices = vertices;
    s.wall_energy = wall_energy;
    s.vertex_diameter = delta;
    s.line_tension = 0;
    s.perimeter_stiffness = perimeter_stiffness;
    s.area_stiffness = area_stiffness;
    s.bending_stiffness = bending_stiffness;
    s.max_drag = 0;  // drag and friction: ν Δt ≤ 2 in the contact limit
    return dp::contact_stability_limit(s, dp::ContactStiffnessInputs{dp_contacts_per_vertex, contact_energy, friction,
                                                                      drag, preferred_area(0)});
  }

  // The time step a scene runs with: dt, or min(10⁻³, 0.9 × limit) for dt = 0.
  double resolved_dt() const {
    return dt > 0 ? dt : std::min(dp_paper_dt, dp_auto_dt_fraction * stability().max_dt());
  }

  // Throws std::invalid_argument naming the first parameter outside its range.
  void validate() const {
    auto require = [](bool ok, const std::string& name, const std::string& range, double value) {
      if (!ok)
        throw std::invalid_argument("dp hopper scene: " + name + " must be " + range + ", got " +
                                    std::to_string(value));
    };
    auto finite_positive = [](double v) { return std::isfinite(v) && v > 0; };
    auto finite_nonnegative = [](double v) { return std::isfinite(v) && v >= 0; };
    require(particles >= 2, "particles N", ">= 2", particles);
    require(vertices >= 8, "vertices N_v", ">= 8", vertices);
    require(std::isfinite(hopper_width) && hopper_width >= 4 * sigma_large, "hopper width W", ">= 4 σ_l", hopper_width);
    require(std::isfinite(orifice) && orifice > 0 && orifice < hopper_width, "orifice w", "in (0, W)", orifice);
    require(std::isfinite(wall_angle) && wall_angle > 0 && wall_angle <= 90, "wall angle θ_w", "in (0, 90] degrees",
            wall_angle);
    require(finite_positive(area_stiffness), "area stiffness K_a", "finite and > 0", area_stiffness);
    require(finite_positive(perimeter_stiffness), "perimeter stiffness K_l", "finite and > 0", perimeter_stiffness);
    require(finite_nonnegative(bending_stiffness), "bending stiffness K_b", "finite and >= 0", bending_stiffness);
    require(finite_positive(contact_energy), "contact energy E_c", "finite and > 0", contact_energy);
    require(finite_nonnegative(wall_energy), "wall energy E_w", "finite and >= 0", wall_energy);
    require(finite_nonnegative(drag), "drag ζ", "finite and >= 0", drag);
    require(finite_nonnegative(friction), "friction μ", "finite and >= 0", friction);
    require(std::isfinite(dt) && dt >= 0, "time step dt", "finite and >= 0 (0: automatic)", dt);
    const auto limit = stability();
    cli::check_time_step("dp hopper scene", dt, {limit.max_dt(), limit.limiting_term()}, force_dt);
  }
};

template <class Real = double, class ExecSpace = Kokkos::DefaultExecutionSpace>
class DpHopperScene {
 public:
  using particles_type = Particles<2, Real, ExecSpace>;
  using V = Vec<2, double>;

  explicit DpHopperScene(const DpHopperParameters& par)
      : par_((par.validate(), par)),
        dt_(par.resolved_dt()),
        shapes_(hopper_walls_2d<Real>(Real(par.hopper_width), Real(par.orifice), Real(par.wall_angle))),
        walls_(shapes_),
        polygons_(make_polygons(par)),
        state_(par.particles),
        contacts_(Real(par.contact_energy), {par.vertex_diameter(0), par.vertex_diameter(1)}),
        list_(Real(par.smooth ? dp_smooth_reach * par.edge_length(1) + par.vertex_diameter(1)
                              : par.vertex_diameter(1)),
              Real(dp_skin_fraction * par.edge_length(1)), NeighborListKind::full, BodyExclusion::same_body),
        vv_(Real(dt_)),
        p_(std::size_t(par.particles) * std::size_t(par.vertices), "dp_hopper"),
        outside_("mesoflow::dp_hopper::outside", std::size_t(par.particles)),
        wall_candidates_("mesoflow::dp_hopper::wall_candidates", p_.size()),
        recycler_(par.seed) {
    dp::assign_bodies(polygons_, p_);
    x_host_ = Kokkos::create_mirror_view(p_.x);
    v_host_ = Kokkos::create_mirror_view(p_.v);
    outside_host_ = Kokkos::create_mirror_view(outside_);
    place_randomly();
    declare_terms();
  }
  // The term list's launches hold `this`: a scene stays where it was built.
  DpHopperScene(const DpHopperScene&) = delete;
  DpHopperScene& operator=(const DpHopperScene&) = delete;

  // FIRE without gravity or dissipation: removes the overlaps of the random placement (§2.4).
  FireResult relax(int max_iterations = 20000) {
    FireParameters fire;
    fire.dt_start = dt_;
    fire.dt_max = std::max(dt_, 0.5 / par_.stability().omega());
    fire.max_iterations = max_iterations;
    fire.force_tolerance = relax_tolerance * par_.contact_energy;
    const auto result = fire_minimize(p_, [&] { return conservative_forces(false); }, fire);
    if (!result.converged)
      throw std::runtime_error("dp hopper scene: FIRE did not remove the initial overlaps in " +
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

  // f ← −∇U (shape, gravity if on, contacts, walls) at the current positions; returns U.
  double conservative_forces(bool with_gravity) {
    maintain_neighbors();
    p_.zero_forces();
    dp::update_body_state(polygons_, p_, state_);
    double u = shape_forces(with_gravity);
    u += par_.smooth ? dp::accumulate_smooth_vertex_contacts(contacts_, polygons_, p_, list_, box_)
                     : dp::accumulate_vertex_contacts(contacts_, p_, list_, box_, pair_);
    u += sp::accumulate_wall_repulsion(Real(par_.wall_energy), contacts_, walls_, p_, wall_candidates_);
    return u;
  }

  // Per-polygon area, perimeter, centroid and its velocity at the current state (left on the device).
  const dp::BodyState<Real, ExecSpace>& update_body_state() {
    dp::update_body_state(polygons_, p_, state_);
    return state_;
  }

  // Gravity is on unless a test switches it off (momentum conservation of the contact forces).
  void set_gravity(bool on) { gravity_on_ = on; }

  // Vertex velocities from the host (setup and tests).
  void set_velocities(const std::vector<V>& v) {
    if (v.size() != p_.size()) throw std::invalid_argument("dp hopper scene: velocities for the wrong vertex count");
    for (std::size_t i = 0; i < v.size(); ++i)
      for (int d = 0; d < 2; ++d) v_host_(i, d) = Real(v[i][d]);
    Kokkos::deep_copy(p_.v, v_host_);
  }

  // The NaN watchdog's view of the scene (scenes/common/nan_watchdog.hpp). The state is what a step
  // reads: x, v and the forces of the last step, the vertex masses, types, the polygons' `outside`
  // flags and the vertices' candidate walls (marked at the last neighbor-list build), and on the
  // host the recycling RNG and counters. The neighbor list is restored too: its reference positions
  // are kept with the state and the list is rebuilt from them after a restore (as MdpdSystem::resume
  // does), so it has the rows it had and rebuilds at the same steps: the replay retraces the run bit
  // for bit (the vertices are never sorted in memory). Every force term of step() is evaluated
  // alone; vertices are named "vertex k of polygon b". The scene must outlive the returned value.
  watchdog::Watched watched() {
    watchdog::Watched w = watchdog::watch_particles(p_);
    w.state.insert(w.state.end(), {watchdog::Field::of("mass", p_.mass), watchdog::Field::kept("type", p_.type),
                                   watchdog::Field::kept("outside", outside_),
                                   watchdog::Field::kept("wall candidates", wall_candidates_)});
    w.step = [this] { step(); };
    w.steps = [this] { return steps_; };
    w.set_steps = [this](long long s) { steps_ = s; };
    struct HostState {
      Recycler::State recycling;
      bool listed = false;                                   // the list had been built
      typename particles_type::vector_view reference;        // its reference positions
    };
    auto saved = std::make_shared<HostState>();
    saved->reference = typename particles_type::vector_view(
        Kokkos::view_alloc(Kokkos::WithoutInitializing, "mesoflow::dp_hopper::watchdog_reference"), p_.size());
    w.save_host = [this, saved] {
      saved->recycling = recycler_.state();
      saved->listed = list_.num_builds() > 0;
      if (saved->listed) copy_field(saved->reference, list_.reference_positions(), "mesoflow::watchdog::save");
    };
    w.restore_host = [this, saved] { recycler_.restore(saved->recycling); };
    w.after_restore = [this, saved] {
      if (!saved->listed) return;  // the next step builds it, as it would have
      particles_type at_reference = p_;
      at_reference.x = saved->reference;
      list_.build(at_reference, box_);
    };
    w.terms = terms_.watchdog_terms();
    const int nv = par_.vertices;
    w.particle = [nv](long long i) {
      const long long b = i / nv;
      return "vertex " + std::to_string(i % nv) + " of polygon " + std::to_string(b) +
             (b % 2 == 0 ? " (small)" : " (large)");
    };
    return w;
  }

  // The scene's components: polygons, walls and the launches of a step with their terms.
  std::vector<std::string> components() const {
    std::vector<std::string> c{std::to_string(par_.particles) + " deformable polygons of " +
                                   std::to_string(par_.vertices) + " vertices (bidisperse)",
                               std::to_string(shapes_.size()) + " walls (candidate walls per vertex)"};
    for (auto& line : terms_.components()) c.push_back(std::move(line));
    return c;
  }
  const scene::TermList<const typename particles_type::vector_view&>& terms() const { return terms_; }

  const particles_type& particles() const { return p_; }
  const dp::Polygons<Real, ExecSpace>& polygons() const { return polygons_; }
  const DpHopperParameters& parameters() const { return par_; }
  const std::vector<Shape<2, Real>>& walls() const { return shapes_; }
  const sp::SoftSphereRepulsion<Real>& contacts() const { return contacts_; }  // ε_c and δ_mn by type
  int neighbor_builds() const { return list_.num_builds(); }
  long long steps() const { return steps_; }
  double time() const { return double(steps_) * dt_; }
  double dt() const { return dt_; }
  double crossed_measure() const { return recycler_.state().crossed; }  // area out of the orifice
  long long crossings() const { return recycler_.state().crossings; }
  double last_crossing_time() const { return recycler_.state().last_crossing_time; }
  long long insertions() const { return recycler_.state().insertions; }
  const std::vector<int>& last_inserted() const { return recycler_.state().last_inserted; }  // polygons of the latest recycling
  long long last_recycling_step() const { return recycler_.state().last_recycling_step; }
  double max_insertion_overlap() const { return recycler_.state().max_insertion_overlap; }  // over all insertions

 private:
  // FIRE stops at max |F_i| < 10⁻³ E_c: contact overlaps ξ below ~2·10⁻⁴ δ (F = ε_c ξ/δ), wall
  // overlaps half that; a tighter bound only slowly settles the soft modes of the polygons.
  static constexpr double relax_tolerance = 1e-3;

  static dp::Polygons<Real, ExecSpace> make_polygons(const DpHopperParameters& par) {
    std::vector<int> counts(std::size_t(par.particles), par.vertices);
    std::vector<Real> a0(counts.size()), l0(counts.size());
    for (std::size_t b = 0; b < counts.size(); ++b) {
      a0[b] = Real(DpHopperParameters::preferred_area(int(b % 2)));
      l0[b] = Real(par.edge_length(int(b % 2)));
    }
    return dp::Polygons<Real, ExecSpace>::from_vertex_counts(counts, a0, l0);
  }

  // The scene's terms, declared once: the step, the watchdog and the summaries read this list.
  // Launches in the step's order: the shape loop (zeroes f; area, segment springs, bending at
  // K_b > 0 and gravity, one kernel), the contacts (rough: the generic pair loop; smooth: the
  // circulo-line loop), friction and wall repulsion, drag; friction and drag at the half-step velocity.
  void declare_terms() {
    using vector_view = typename particles_type::vector_view;
    const auto alone = [this](auto add) {
      return [this, add] {
        p_.zero_forces();
        add();
      };
    };
    const auto shape_term = [this](auto term) {
      return [this, term] {
        p_.zero_forces();
        dp::update_body_state(polygons_, p_, state_);
        dp::accumulate_shape_forces(polygons_, state_, p_, term);
      };
    };
    const char* rough = "vertex contacts E_c";
    const char* smooth = "smooth vertex contacts E_c";
    terms_.term({"gravity", "eq. 4", false, true, [this, shape_term] {
                   shape_term(dp::Gravity<Real>{Vec<2, Real>{{Real(0), gravity_on_ ? Real(-1) : Real(0)}}})();
                 }});
    terms_.term({"area elasticity K_a", "eq. 8", false, true,
                 shape_term(dp::AreaElasticity<Real>{Real(par_.area_stiffness)})});
    terms_.term({"segment springs K_l", "eq. 8", false, true,
                 shape_term(dp::SegmentSprings<Real>{Real(par_.perimeter_stiffness)})});
    terms_.term({"bending K_b", "eq. 8", false, par_.bending_stiffness > 0,
                 shape_term(dp::Bending<Real>{Real(par_.bending_stiffness)})});
    terms_.term({rough, "eq. 9", false, !par_.smooth,
                 alone([this] { pair_.accumulate_forces(contacts_, p_, list_, box_); })});
    terms_.term({smooth, "eq. 9, Appendix A", false, par_.smooth,
                 alone([this] { dp::accumulate_smooth_vertex_contacts(contacts_, polygons_, p_, list_, box_); })});
    terms_.term({"vertex–wall repulsion E_w", "eq. 10", false, par_.wall_energy != 0, alone([this] {
                   sp::accumulate_wall_repulsion(Real(par_.wall_energy), contacts_, walls_, p_, wall_candidates_);
                 })});
    terms_.term({"kinetic friction μ", par_.smooth ? "eq. 12, vertex–edge (Appendix A contacts)" : "eq. 12", true,
                 par_.friction > 0, alone([this] { friction_forces(p_.v); })});
    terms_.term({"vertex drag ζ", "eq. 11", true, par_.drag > 0,
                 alone([this] { dp::accumulate_vertex_drag(Real(par_.drag), polygons_, p_, p_.v); })});
    terms_.launch("shape loop (one kernel)",
                  {"area elasticity K_a", "segment springs K_l", "bending K_b", "gravity"}, [this](const vector_view&) {
                    p_.zero_forces();
                    dp::update_body_state(polygons_, p_, state_);
                    shape_forces(gravity_on_);
                  });
    // eq. 9 through the generic pair loop's dynamically scheduled force-only pass (the step needs no
    // energy); dp::accumulate_vertex_contacts is the same loop with an energy reduction.
    terms_.launch("contact loop (full neighbor list, same polygon excluded)", {rough}, [this](const vector_view&) {
      dp::require_same_body_exclusion(list_);
      pair_.accumulate_forces(contacts_, p_, list_, box_);
    });
    terms_.launch("circulo-line contact loop (full neighbor list)", {smooth}, [this](const vector_view&) {
      dp::accumulate_smooth_vertex_contacts(contacts_, polygons_, p_, list_, box_);
    });
    terms_.launch("friction loop (full neighbor list)", {"kinetic friction μ"},
                  [this](const vector_view& u) { friction_forces(u); });
    terms_.launch("wall loop (candidate walls)", {"vertex–wall repulsion E_w"}, [this](const vector_view&) {
      sp::accumulate_wall_repulsion(Real(par_.wall_energy), contacts_, walls_, p_, wall_candidates_);
    });
    terms_.launch("drag (one kernel)", {"vertex drag ζ"},
                  [this](const vector_view& u) { dp::accumulate_vertex_drag(Real(par_.drag), polygons_, p_, u); });
  }

  int type_of(int body) const { return body % 2; }
  int nv() const { return par_.vertices; }

  // Circumradius of the regular polygon of a type (place_regular_polygon's radius).
  double regular_radius(int type) const {
    return std::sqrt(2.0 * DpHopperParameters::preferred_area(type) / (nv() * std::sin(2.0 * pi / nv())));
  }

  // Random sequential adsorption of regular polygons (circumcircles disjoint, a vertex disk's half
  // width from the side walls), large first, in a column above the exit walls tall enough for
  // packing fraction 0.5 of the preferred areas; the column grows by σ_avg/2 whenever 2000 draws in
  // a row fail. Then the box for the cell list around it.
  void place_randomly() {
    const int n = par_.particles;
    double total = 0;
    for (int b = 0; b < n; ++b) total += DpHopperParameters::preferred_area(type_of(b));
    const double half = 0.5 * par_.hopper_width;
    const double bottom = 0.5 * (par_.hopper_width - par_.orifice) / std::tan(par_.wall_angle * pi / 180) + sigma_large;
    double top = bottom + total / (initial_packing * 2 * (half - 0.5 * sigma_large));
    std::mt19937_64 gen(par_.seed);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<int> order;
    for (int b = 1; b < n; b += 2) order.push_back(b);
    for (int b = 0; b < n; b += 2) order.push_back(b);
    // A grid of cells 2 R_l wide: a new circle can only meet circles in the 3 × 3 cells around it.
    const double cell = 2 * regular_radius(1);
    const int nx = std::max(1, int(2 * half / cell));
    std::vector<std::vector<int>> grid;
    auto cell_of = [&](const V& c) {
      const int i = std::min(nx - 1, std::max(0, int((c[0] + half) / cell)));
      const int j = std::max(0, int((c[1] - bottom) / cell));
      if (std::size_t(j) >= grid.size() / std::size_t(nx)) grid.resize(std::size_t(j + 2) * std::size_t(nx));
      return std::array<int, 2>{{i, j}};
    };
    std::vector<V> centre(static_cast<std::size_t>(n));
    for (const int b : order) {
      const double r = regular_radius(type_of(b));
      const double lateral = half - r - 0.5 * par_.vertex_diameter(type_of(b));
      for (int failures = 0;; ++failures) {
        if (failures == 2000) {
          top += 0.5;
          failures = 0;
        }
        const V c{{lateral * (2 * u(gen) - 1), bottom + (top - bottom) * u(gen)}};
        const auto ij = cell_of(c);
        bool free = true;
        for (int dj = -1; dj <= 1 && free; ++dj)
          for (int di = -1; di <= 1 && free; ++di) {
            const int i = ij[0] + di, j = ij[1] + dj;
            if (i < 0 || i >= nx || j < 0 || std::size_t(j) * nx >= grid.size()) continue;
            for (const int k : grid[std::size_t(j) * nx + i]) {
              const double s = r + regular_radius(type_of(k));
              if (std::pow(c[0] - centre[k][0], 2) + std::pow(c[1] - centre[k][1], 2) < s * s) {
                free = false;
                break;
              }
            }
          }
        if (!free) continue;
        centre[b] = c;
        grid[std::size_t(ij[1]) * nx + ij[0]].push_back(b);
        dp::place_regular_polygon(polygons_, b, x_host_, c, 2 * pi * u(gen));
        break;
      }
    }
    auto type = Kokkos::create_mirror_view(p_.type);
    auto mass = Kokkos::create_mirror_view(p_.mass);
    for (int b = 0; b < n; ++b)
      for (int i = polygons_.first_vertex(b); i < polygons_.first_vertex(b) + nv(); ++i) {
        type(i) = type_of(b);
        mass(i) = Real(DpHopperParameters::preferred_area(type_of(b)) / nv());
      }
    Kokkos::deep_copy(p_.x, x_host_);
    Kokkos::deep_copy(p_.type, type);
    Kokkos::deep_copy(p_.mass, mass);
    const Real lo[2] = {Real(-half - 1), Real(-recycle_depth - 2)};
    const Real len[2] = {Real(par_.hopper_width + 2), Real(top + recycle_depth + 4)};
    const bool periodic[2] = {false, false};
    box_ = Box<2, Real>(lo, len, periodic);
  }

  // f += shape and gravity forces (eq. 8 without line tension; bending only at K_b > 0); returns
  // their energy (gravity's −M g h included). `state_` must be current.
  // Eq. 12 at velocity u: between vertex disks (rough) or vertex and edge (smooth).
  void friction_forces(const typename particles_type::vector_view& u) {
    if (par_.smooth)
      dp::accumulate_smooth_vertex_friction(Real(par_.friction), contacts_, polygons_, p_, u, list_, box_,
                                            par_.friction_component);
    else
      dp::accumulate_vertex_friction(Real(par_.friction), contacts_, p_, u, list_, box_, par_.friction_component);
  }

  double shape_forces(bool with_gravity) {
    const dp::AreaElasticity<Real> area{Real(par_.area_stiffness)};
    const dp::SegmentSprings<Real> springs{Real(par_.perimeter_stiffness)};
    const dp::Gravity<Real> gravity{Vec<2, Real>{{Real(0), with_gravity ? Real(-1) : Real(0)}}};
    if (par_.bending_stiffness > 0)
      return dp::accumulate_shape_forces(polygons_, state_, p_, area, springs,
                                         dp::Bending<Real>{Real(par_.bending_stiffness)}, gravity);
    return dp::accumulate_shape_forces(polygons_, state_, p_, area, springs, gravity);
  }

  // Rebuilds the neighbor list when the skin criterion asks for it and re-marks the candidate walls.
  void maintain_neighbors() {
    if (!list_.needs_rebuild(p_.x, box_)) return;
    list_.build(p_, box_);
    sp::find_wall_candidates(list_.skin(), contacts_, walls_, p_, wall_candidates_);
  }

 public:  // kernels below: nvcc rejects a KOKKOS_LAMBDA in a private member function
  // A polygon's centroid height (of the step's BodyState) and preferred area, for count_crossings.
  struct CrossingBody {
    typename dp::BodyState<Real, ExecSpace>::vector_view com;
    Kokkos::View<Real*, ExecSpace> a0;
    KOKKOS_INLINE_FUNCTION Real height(int b) const { return com(b, 1); }
    KOKKOS_INLINE_FUNCTION double measure(int b) const { return double(a0(b)); }
  };

  // Marks first passages of centroids below the orifice plane, sums their a_m,0, recycles when needed.
  void detect_crossings() {
    const auto sums = count_crossings<Real>("mesoflow::dp_hopper::detect_crossings", par_.particles, outside_,
                                            CrossingBody{state_.com, polygons_.a0});
    if (recycler_.record_crossings(sums, time())) recycle();
  }

  // Centroid, centroid velocity and circumradius about the centroid of a polygon, from the host copies.
  struct HostBody {
    V com, velocity;
    double radius;
  };
  HostBody host_body(int b) const {
    const int begin = polygons_.first_vertex(b);
    HostBody h{V{{0, 0}}, V{{0, 0}}, 0};
    for (int i = begin; i < begin + nv(); ++i)
      for (int d = 0; d < 2; ++d) {
        h.com[d] += double(x_host_(i, d)) / nv();
        h.velocity[d] += double(v_host_(i, d)) / nv();
      }
    for (int i = begin; i < begin + nv(); ++i)
      h.radius = std::max(h.radius, std::hypot(double(x_host_(i, 0)) - h.com[0], double(x_host_(i, 1)) - h.com[1]));
    return h;
  }

  static double cross2(const V& a, const V& b) { return a[0] * b[1] - a[1] * b[0]; }
  // Distance from q to the segment a–b.
  static double point_segment_distance(const V& q, const V& a, const V& b) {
    const V ab{{b[0] - a[0], b[1] - a[1]}}, aq{{q[0] - a[0], q[1] - a[1]}};
    const double l2 = ab[0] * ab[0] + ab[1] * ab[1];
    const double t = l2 > 0 ? std::clamp((aq[0] * ab[0] + aq[1] * ab[1]) / l2, 0.0, 1.0) : 0.0;
    return std::hypot(aq[0] - t * ab[0], aq[1] - t * ab[1]);
  }
  // Whether the segments a–b and c–d cross (proper intersection or touching).
  static bool segments_cross(const V& a, const V& b, const V& c, const V& d) {
    const V ab{{b[0] - a[0], b[1] - a[1]}}, cd{{d[0] - c[0], d[1] - c[1]}};
    const double s1 = cross2(ab, V{{c[0] - a[0], c[1] - a[1]}}), s2 = cross2(ab, V{{d[0] - a[0], d[1] - a[1]}});
    const double s3 = cross2(cd, V{{a[0] - c[0], a[1] - c[1]}}), s4 = cross2(cd, V{{b[0] - c[0], b[1] - c[1]}});
    return s1 * s2 <= 0 && s3 * s4 <= 0;
  }
  // Whether q lies inside the polygon `vertices` (even–odd rule).
  static bool inside(const V& q, const std::vector<V>& vertices) {
    bool in = false;
    for (std::size_t i = 0, j = vertices.size() - 1; i < vertices.size(); j = i++) {
      const V& a = vertices[i];
      const V& b = vertices[j];
      if ((a[1] > q[1]) != (b[1] > q[1]) && q[0] < a[0] + (b[0] - a[0]) * (q[1] - a[1]) / (b[1] - a[1])) in = !in;
    }
    return in;
  }

  // Largest relative overlap of polygon i with its vertices at `shape` (centroid `com`): 1 − r/δ_mn
  // for each vertex pair (smooth: vertex–edge distance) of i and another polygon, 1 − 2d_w/δ_m for
  // each vertex and wall, and 1 for crossing edges or a centroid inside the other polygon.
  double overlap_at(int i, const std::vector<V>& shape, const V& com, double radius,
                    const std::vector<HostBody>& bodies) const {
    double worst = 0;
    const int ti = type_of(i);
    std::vector<V> other(static_cast<std::size_t>(nv()));
    for (int k = 0; k < par_.particles; ++k) {
      if (k == i) continue;
      // Circumcircles farther apart than the widest δ_mn: nothing of k is within reach.
      const double dx = bodies[k].com[0] - com[0], dy = bodies[k].com[1] - com[1];
      if (dx * dx + dy * dy > std::pow(radius + bodies[k].radius + par_.vertex_diameter(1), 2)) continue;
      const int begin = polygons_.first_vertex(k);
      for (int j = 0; j < nv(); ++j) other[j] = V{{double(x_host_(begin + j, 0)), double(x_host_(begin + j, 1))}};
      const double s = double(contacts_.contact[ti][type_of(k)]);
      if (inside(com, other) || inside(bodies[k].com, shape)) return 1;
      for (int a = 0; a < nv(); ++a) {
        const V& pa = shape[a];
        const V& pa_next = shape[(a + 1) % nv()];
        for (int b = 0; b < nv(); ++b) {
          const V& pb = other[b];
          const V& pb_next = other[(b + 1) % nv()];
          if (segments_cross(pa, pa_next, pb, pb_next)) return 1;
          const double r = par_.smooth ? std::min(point_segment_distance(pa, pb, pb_next),
                                                  point_segment_distance(pb, pa, pa_next))
                                       : std::hypot(pa[0] - pb[0], pa[1] - pb[1]);
          if (r < s) worst = std::max(worst, 1 - r / s);
        }
      }
    }
    const double delta = par_.vertex_diameter(ti);
    for (const V& q : shape)
      for (const auto& wall : shapes_) {
        const double dist = double(wall.query(Vec<2, Real>{{Real(q[0]), Real(q[1])}}).distance);
        if (dist < 0.5 * delta) worst = std::max(worst, 1 - 2 * dist / delta);
      }
    return worst;
  }

 private:
  // Whether the host copies hold a blown-up state (a time step forced above the stability limit): a
  // non-finite vertex position or velocity, or a vertex more than a box length outside the box, which
  // walls and recycling keep every vertex of a stable run inside. Such a state is not recycled (no
  // placement could succeed): it is left for the NaN watchdog, which stops the run at its next check
  // and names the step and force term (the replay skips the same recycling, so it retraces the run).
  bool blown_up() const {
    for (std::size_t i = 0; i < x_host_.extent(0); ++i)
      for (int d = 0; d < 2; ++d) {
        const double x = double(x_host_(i, d)), v = double(v_host_(i, d));
        const double lo = double(box_.lo[d]), len = double(box_.length[d]);
        if (!std::isfinite(x) || !std::isfinite(v) || x < lo - len || x > lo + 2 * len) return true;
      }
    return false;
  }

  // Host re-insertion of every polygon whose centroid is more than recycle_depth below the orifice.
  void recycle() {
    Kokkos::deep_copy(x_host_, p_.x);
    Kokkos::deep_copy(v_host_, p_.v);
    Kokkos::deep_copy(outside_host_, outside_);
    if (blown_up()) return;  // left as it is for the NaN watchdog (scenes/common/nan_watchdog.hpp)
    const int n = par_.particles;
    std::vector<HostBody> bodies(static_cast<std::size_t>(n));
    for (int b = 0; b < n; ++b) bodies[b] = host_body(b);
    std::vector<int> below;
    for (int b = 0; b < n; ++b)
      if (bodies[b].com[1] < -recycle_depth) below.push_back(b);
    const auto anchor = [&](int k) {
      return Recycler::Anchor{outside_host_(k) == 0 && !(bodies[k].com[1] < -recycle_depth), {bodies[k].com[0], 0},
                              bodies[k].com[1]};
    };
    // Polygon i translated rigidly, its centroid at R_i + R_j + δ_ij from anchor j's; every vertex
    // takes the anchor's centroid velocity.
    std::vector<V> shape(static_cast<std::size_t>(nv()));
    const auto try_place = [&](int i, int j, const V& dir) -> std::optional<double> {
      const int begin = polygons_.first_vertex(i);
      const double s = bodies[i].radius + bodies[j].radius + double(contacts_.contact[type_of(i)][type_of(j)]);
      const V c{{bodies[j].com[0] + s * dir[0], bodies[j].com[1] + s * dir[1]}};
      for (int k = 0; k < nv(); ++k)
        for (int d = 0; d < 2; ++d) shape[k][d] = c[d] + double(x_host_(begin + k, d)) - bodies[i].com[d];
      const double overlap = overlap_at(i, shape, c, bodies[i].radius, bodies);
      if (overlap > contact_tolerance) return std::nullopt;
      // The velocity: the mean of the anchor's and its bulk neighbours' (centroids within 2σ_avg),
      // as in the SP scene (hopper_scene.hpp, issue 27): the local flow, not one polygon's agitation.
      V mean{{0, 0}};
      int count = 0;
      for (int k = 0; k < n; ++k) {
        if (k == i || outside_host_(k) != 0) continue;
        const double dx = bodies[k].com[0] - bodies[j].com[0], dy = bodies[k].com[1] - bodies[j].com[1];
        if (dx * dx + dy * dy >= 4.0) continue;
        mean[0] += bodies[k].velocity[0];
        mean[1] += bodies[k].velocity[1];
        ++count;
      }
      mean[0] /= count;
      mean[1] /= count;
      for (int k = 0; k < nv(); ++k)
        for (int d = 0; d < 2; ++d) {
          x_host_(begin + k, d) = Real(shape[k][d]);
          v_host_(begin + k, d) = Real(mean[d]);
        }
      bodies[i].com = c;
      bodies[i].velocity = mean;
      outside_host_(i) = 0;
      return overlap;
    };
    recycler_.reinsert<2>(below, 0.5 * par_.hopper_width - 0.5 * sigma_large, n, anchor, try_place,
                          "dp hopper scene: no place to re-insert polygon ", steps_);
    Kokkos::deep_copy(p_.x, x_host_);
    Kokkos::deep_copy(p_.v, v_host_);
    Kokkos::deep_copy(outside_, outside_host_);
  }

  DpHopperParameters par_;
  double dt_;
  std::vector<Shape<2, Real>> shapes_;
  Geometry<2, Real, ExecSpace> walls_;
  dp::Polygons<Real, ExecSpace> polygons_;
  dp::BodyState<Real, ExecSpace> state_;
  sp::SoftSphereRepulsion<Real> contacts_;  // ε_c and δ_mn by vertex type; its diagonal gives δ_m for the walls
  NeighborList<2, Real, ExecSpace> list_;
  PairForce<2, Real, ExecSpace> pair_;
  VelocityVerlet<2, Real, ExecSpace> vv_;
  particles_type p_;
  Box<2, Real> box_;
  Kokkos::View<int*, ExecSpace> outside_;  // per polygon: 1 once its centroid has left through the orifice
  Kokkos::View<unsigned*, ExecSpace> wall_candidates_;
  typename particles_type::vector_view::HostMirror x_host_, v_host_;
  typename Kokkos::View<int*, ExecSpace>::HostMirror outside_host_;
  Recycler recycler_;  // the continuous flow's counters and RNG (recycling.hpp)
  scene::TermList<const typename particles_type::vector_view&> terms_;
  bool gravity_on_ = true;
  long long steps_ = 0;
};

}  // namespace mesoflow::hopper
