// mdpd_system.hpp — an MDPD particle system and its time step: the composition of the MDPD terms
// that the pillar driver, the viscosity tool, the tests and the benchmarks share.
//
// Integrator: the paper integrates with Verlet leap-frog (§2.5.1). We use its velocity-Verlet form
// (velocity_verlet.hpp, λ = ½), which generates the same positions and half-step velocities,
//   v(t+½dt) = v(t−½dt) + dt F(t)/m,   x(t+dt) = x(t) + dt v(t+½dt),
// with the dissipative force F(t+dt) evaluated at the half-step velocity v(t+½dt), the latest one
// a leap-frog has at hand. Observables (temperature, flux) use the full-step velocity
// v(t+dt) = v(t+½dt) + ½dt F(t+dt)/m.
//
// A step: half kick + drift; neighbor-list upkeep (rebuild when a particle moved more than half
// the skin; every `sort_every` rebuilds the particles are reordered in memory by cell, LAMMPS'
// atom sort, so neighbors stay close in memory as the flow mixes the fluid); many-body densities;
// pair forces (gathered from packed rows, packed_state.hpp); tethers (only if the scene has solids); driving force (only if f_b ≠ 0); half kick.
//
// Terms, declared once (declare_terms(), scenes/common/term_list.hpp): the conservative pair force
// A, B (eq. 9a), the dissipative and random pair forces (eqs. 9b–c), the WCA repulsion of solid
// cores, the tethers k_S, the driving force f_b and the split Poiseuille force of the viscosity
// mode, each active where its coefficient (or the scene) makes it act. The step's force evaluation
// runs the list's launches in order (one fused pair loop for the three pair terms, then one kernel
// per body term), the NaN watchdog takes each term alone (a pair term alone is its own
// MdpdPairForce with the other coefficients zero: the run's kernels, so the same arithmetic), and
// components() names the launches that run.
#pragma once

#include "kernels/common/kernel_launch.hpp"
#include "kernels/common/neighbor_list.hpp"
#include "kernels/common/particle_sort.hpp"
#include "kernels/common/reductions.hpp"
#include "kernels/common/velocity_verlet.hpp"
#include "kernels/mdpd/local_density.hpp"
#include "kernels/mdpd/mdpd_pair_force.hpp"
#include "kernels/mdpd/region_body_force.hpp"
#include "kernels/mdpd/tether_springs.hpp"
#include "scenes/common/term_list.hpp"

#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

namespace mesoflow::mdpd {

struct MdpdOptions {
  NeighborListKind list_kind = NeighborListKind::half;
  double skin = 0.2;         // bench_mdpd: 0.2σ beats 0.3σ and 0.4σ at ρ = 6
  int cells_per_reach = 2;   // neighbor-list binning (neighbor_list.hpp)
  int sort_every = 20;    // rebuilds between memory reorderings; 0: never
  double k_S = 12.5;      // tether stiffness of solid particles (ε/σ²)
  double wca_epsilon = 1.0, wca_sigma = 1.0;
};

template <int D, class Real, class ExecSpace>
struct MdpdTermsAlone;

template <int D, class Real, class ExecSpace = Kokkos::DefaultExecutionSpace>
class MdpdSystem {
 public:
  using vector_view = typename Particles<D, Real, ExecSpace>::vector_view;
  using scalar_view = Kokkos::View<Real*, ExecSpace>;
  using tag_view = Kokkos::View<std::uint32_t*, ExecSpace>;
  using rows_view = PackedRows<Real, ExecSpace>;

  MdpdSystem(const MdpdParameters& par, const Box<D, Real>& box, std::uint64_t seed, const MdpdOptions& opt = {})
      : par_((par.validate(), par)),
        box_(box),
        opt_(opt),
        density_(DensityWeight<D, Real>(par.density_kernel, Real(par.r_B), par.density_self_term)),
        pair_(par, seed, Real(opt.wca_epsilon), Real(opt.wca_sigma)),
        tether_(Real(opt.k_S)),
        integrator_(Real(par.dt)),
        seed_(seed) {
    if (!(opt.skin >= 0 && opt.skin <= 2))
      throw std::invalid_argument("mdpd: neighbor skin must be in [0, 2] σ, got " + std::to_string(opt.skin));
    if (opt.sort_every < 0)
      throw std::invalid_argument("mdpd: sort_every must be >= 0, got " + std::to_string(opt.sort_every));
    declare_terms();
  }

  // Fresh storage for n particles (fluid, unit mass, tags 0…n−1, sites at the origin).
  void allocate(int n) {
    particles.allocate(std::size_t(n), "mdpd");
    tag = tag_view("mesoflow::mdpd::tag", n);
    rho = scalar_view("mesoflow::mdpd::rho", n);
    site = vector_view("mesoflow::mdpd::site", n);
    solid_drag = vector_view("mesoflow::mdpd::solid_drag", n);
    xr_ = rows_view("mesoflow::mdpd::packed_x", n);
    vr_ = rows_view("mesoflow::mdpd::packed_v", n);
    fr_ = rows_view("mesoflow::mdpd::packed_f", n);
    const auto t = tag;
    mesoflow::launch::parallel_for(
        "mesoflow::mdpd::tags", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) { t(i) = std::uint32_t(i); });
  }

  void set_driving_region(const DrivingRegion<Real>& region) {
    region_ = region;
    declare_terms();
  }
  void set_split_force(const SplitBodyForce<Real>& split) {
    split_ = split;
    declare_terms();
  }
  const DrivingRegion<Real>& driving_region() const { return region_; }

  // Call once the particles are placed (and after any change of types): finds which terms the
  // scene needs, builds the list and computes the forces at the current step.
  void begin(std::uint64_t step = 0) {
    step_ = step;
    prepare_terms();
    builds_since_sort_ = 0;
    compute_forces(false, particles.v);
  }

  // Counters that, with the particle arrays (x, v, f, mass, type, body), tag, site and the list's
  // reference positions, make up the state a bit-identical restart needs.
  struct Counters {
    std::uint64_t step;
    int builds_since_sort, num_sorts;
  };
  Counters counters() const { return {step_, builds_since_sort_, num_sorts_}; }
  vector_view neighbor_reference_positions() const { return list_->reference_positions(); }

  // Continues a saved run: the particle arrays, tag and site hold the saved values (f the forces
  // of the saved step, which are not recomputed); the list is rebuilt from its saved reference
  // positions, so it has the same rows as when the state was saved.
  void resume(const Counters& c, const vector_view& reference) {
    prepare_terms();
    Particles<D, Real, ExecSpace> at_reference = particles;
    at_reference.x = reference;
    list_->build(at_reference, box_);
    step_ = c.step;
    builds_since_sort_ = c.builds_since_sort;
    num_sorts_ = c.num_sorts;
  }

  // One time step; with `record_drag`, solid_drag(i) holds the force of the fluid on solid i
  // at the end of the step.
  void step(bool record_drag = false) {
    integrator_.first_half(particles);
    ++step_;
    compute_forces(record_drag, integrator_.velocity_for_forces(particles));
    integrator_.second_half(particles);
  }

  std::uint64_t current_step() const { return step_; }
  double time() const { return double(step_) * par_.dt; }
  const MdpdParameters& parameters() const { return par_; }
  const MdpdOptions& options() const { return opt_; }
  const Box<D, Real>& box() const { return box_; }
  const NeighborList<D, Real, ExecSpace>& neighbor_list() const { return *list_; }
  bool has_solids() const { return has_solids_; }
  bool has_core() const { return has_core_; }
  int num_sorts() const { return num_sorts_; }
  std::uint64_t seed() const { return seed_; }

  using Terms = scene::TermList<bool, const vector_view&>;
  // The system's terms (see the file comment): the force evaluation, the watchdog and summaries.
  const Terms& terms() const { return own_terms().list; }
  std::vector<std::string> components() const { return terms().components(); }

  // The state a bit-identical restart needs (scenes/common/checkpoint_fields.hpp), declared once
  // for writing and reading: the particle arrays (x, v, the forces of the last step, mass, type,
  // pillar index), tags, tether sites, the list's reference positions and the counters. Loading
  // wants the storage allocated at the stored size and resumes the system (the list rebuilt from
  // the reference positions).
  template <class Archive>
  void checkpoint_fields(Archive& a) {
    a("position", particles.x);
    a("velocity", particles.v);
    a("force", particles.f);
    a("mass", particles.mass);
    a("site", site);
    a("type", particles.type);
    a("body", particles.body);
    a("tag", tag);
    const vector_view reference = Archive::loading ? vector_view("mesoflow::pillars::x_ref", particles.size())
                                                   : neighbor_reference_positions();
    a("neighbor_reference_position", reference);
    Counters c = counters();
    a("step", c.step);
    a("builds_since_sort", c.builds_since_sort);
    a("num_sorts", c.num_sorts);
    if (Archive::loading) resume(c, reference);
  }

  Particles<D, Real, ExecSpace> particles;
  tag_view tag;              // identities keying the pair noise; follow particles through sorts
  scalar_view rho;           // many-body densities ρ̄_i of the last force evaluation
  vector_view site;          // tether sites of solid particles
  vector_view solid_drag;    // force of the fluid on each solid particle (when recorded)

  // prepare_terms and compute_forces are implementation details, public only because nvcc rejects a
  // KOKKOS_LAMBDA in a private or protected member function.

  // Which terms the scene needs (solids with tethers, solid cores with WCA), and a fresh list.
  void prepare_terms() {
    const auto type = particles.type;
    int solids = 0, cores = 0;
    mesoflow::launch::parallel_reduce(
        "mesoflow::mdpd::count_solids", Kokkos::RangePolicy<ExecSpace>(0, particles.size()),
        KOKKOS_LAMBDA(int i, int& s, int& c) {
          s += is_solid(type(i));
          c += type(i) == particle_type::solid_core;
        },
        solids, cores);
    has_solids_ = solids > 0 && tether_.stiffness() != Real(0);
    has_core_ = cores > 0;
    list_.emplace(pair_.reach(has_core_), Real(opt_.skin), opt_.list_kind, BodyExclusion::none, opt_.cells_per_reach);
    list_->set_inner_cutoff(density_.weight().h);  // rows list the density's pairs first
    declare_terms();
  }

  // `v`: the velocities the dissipative force sees (the integrator's prediction during a step).
  // List upkeep, then the term list's launches (declare_terms()); without an active pair term the
  // pair loop, which assigns f, is skipped and f starts from zero.
  void compute_forces(bool record_drag, const vector_view& v_forces) {
    update_list();
    const Terms& terms = own_terms().list;
    if (!terms.serves_active_term(terms.launches().front())) particles.zero_forces();
    terms.evaluate(record_drag, v_forces);
  }

  // Neighbor-list upkeep: rebuild past half the skin, and every sort_every rebuilds a memory sort.
  void update_list() {
    const bool rebuilt = list_->update(particles, box_);
    if (rebuilt) {
      wrap_positions(particles, box_);
      if (opt_.sort_every > 0 && ++builds_since_sort_ >= opt_.sort_every) {
        sort_particles_by_cell(particles, list_->cells(), tag, rho, site, solid_drag);
        list_->build(particles, box_);
        builds_since_sort_ = 0;
        ++num_sorts_;
      }
    }
  }

  // f ← the pair forces of eqs. (9a–c) and the core WCA: many-body densities, then one pair loop
  // over packed rows (packed_state.hpp).
  void pair_forces(bool record_drag, const vector_view& v_forces) {
    pack_vectors<D, Real, ExecSpace>(particles.x, xr_);
    // The density pass reads only the front of each row: (r_B + skin)³/(r_A + skin)³ = 0.54 of it
    // in 3D, 0.77 in 2D (the list's inner cutoff is r_B).
    density_.compute(xr_, *list_, box_, rho);
    {
      const auto xr = xr_, vr = vr_;
      const auto v = v_forces;
      const auto density = rho;
      mesoflow::launch::parallel_for(
          "mesoflow::mdpd::pack_density_velocity", Kokkos::RangePolicy<ExecSpace>(0, particles.size()),
          KOKKOS_LAMBDA(int i) {
            xr(i, rho_column) = density(i);
            for (int d = 0; d < D; ++d) vr(i, d) = v(i, d);
          });
    }
    pair_.compute(xr_, vr_, particles.type, tag, *list_, box_, step_, has_core_, fr_,
                  record_drag ? solid_drag : vector_view());
    {
      const auto f = particles.f;
      const auto fr = fr_;
      mesoflow::launch::parallel_for(
          "mesoflow::mdpd::unpack_forces", Kokkos::RangePolicy<ExecSpace>(0, particles.size()), KOKKOS_LAMBDA(int i) {
            for (int d = 0; d < D; ++d) f(i, d) = fr(i, d);
          });
    }
  }

 private:
  // The terms, once (see the file comment); re-declared when the scene changes which act (the
  // solids and cores found by prepare_terms, the driving region, the split force).
  void declare_terms() {
    Terms& terms_ = own_terms_.list;
    terms_ = Terms{};
    const auto pair_alone = [this](int which) {
      return [this, which] {
        auto& a = alone();
        a.evaluate(*this, which == 0 ? a.conservative : (which == 1 ? a.thermostat : a.core), which == 0, which == 2);
      };
    };
    terms_.term({"MDPD conservative force A, B", "eq. 9a", false, par_.A != 0 || par_.B != 0, pair_alone(0)});
    terms_.term({"MDPD dissipative and random forces D, R", "eqs. 9b-c", true, par_.R != 0, pair_alone(1)});
    terms_.term({"WCA repulsion of solid cores", "", false, has_core_, pair_alone(2)});
    terms_.term({"tether springs k_S", "", false, has_solids_, [this] {
                   particles.zero_forces();
                   tether_.accumulate(particles, site, box_);
                 }});
    terms_.term({"driving force f_b", "", false, region_.active(), [this] {
                   particles.zero_forces();
                   add_region_body_force(particles, region_, box_);
                 }});
    terms_.term({"split Poiseuille force", "", false, split_.active(), [this] {
                   particles.zero_forces();
                   add_split_body_force(particles, split_, box_);
                 }});
    terms_.launch("pair loop (density pass + one pair kernel)",
                  {"MDPD conservative force A, B", "MDPD dissipative and random forces D, R",
                   "WCA repulsion of solid cores"},
                  [this](bool record_drag, const vector_view& v) { pair_forces(record_drag, v); });
    terms_.launch("tethers (one kernel)", {"tether springs k_S"},
                  [this](bool, const vector_view&) { tether_.accumulate(particles, site, box_); });
    terms_.launch("driving region (one kernel)", {"driving force f_b"},
                  [this](bool, const vector_view&) { add_region_body_force(particles, region_, box_); });
    terms_.launch("split body force (one kernel)", {"split Poiseuille force"},
                  [this](bool, const vector_view&) { add_split_body_force(particles, split_, box_); });
  }

  // Scratch of the terms alone, made at first use (and again if the particles were reallocated).
  MdpdTermsAlone<D, Real, ExecSpace>& alone() {
    if (!alone_ || alone_->xr.extent(0) != particles.size())
      alone_ = std::make_shared<MdpdTermsAlone<D, Real, ExecSpace>>(*this);
    return *alone_;
  }

  MdpdParameters par_;
  Box<D, Real> box_;
  MdpdOptions opt_;
  LocalDensity<D, Real, ExecSpace> density_;
  MdpdPairForce<D, Real, ExecSpace> pair_;
  TetherSprings<D, Real, ExecSpace> tether_;
  VelocityVerlet<D, Real, ExecSpace> integrator_;
  std::optional<NeighborList<D, Real, ExecSpace>> list_;
  rows_view xr_, vr_, fr_;  // packed positions + ρ̄, velocities, pair forces (packed_state.hpp)
  DrivingRegion<Real> region_{};
  SplitBodyForce<Real> split_{};
  std::uint64_t step_ = 0;
  std::uint64_t seed_;        // the pair noise's (the terms alone use it too)
  bool has_solids_ = false, has_core_ = false;
  int builds_since_sort_ = 0, num_sorts_ = 0;
  // The term list, left empty by a copy or move of the system (its launches and terms alone hold
  // `this`): a copy declares its own at first use (own_terms()).
  struct OwnTerms {
    Terms list;
    OwnTerms() = default;
    OwnTerms(const OwnTerms&) {}
    OwnTerms& operator=(const OwnTerms&) {
      list = Terms{};
      return *this;
    }
  };
  const OwnTerms& own_terms() const {
    if (own_terms_.list.launches().empty()) const_cast<MdpdSystem*>(this)->declare_terms();
    return own_terms_;
  }
  OwnTerms own_terms_;
  std::shared_ptr<MdpdTermsAlone<D, Real, ExecSpace>> alone_;
};

// xr(i, ρ̄ column) ← rho(i), or 0 where rho is empty.
template <class Real, class Exec>
void set_density_column(const PackedRows<Real, Exec>& xr, const Kokkos::View<Real*, Exec>& rho) {
  const bool zero = rho.extent(0) == 0;
  mesoflow::launch::parallel_for(
      "mesoflow::pillars::watchdog_density_column", Kokkos::RangePolicy<Exec>(0, xr.extent(0)),
      KOKKOS_LAMBDA(int i) { xr(i, rho_column) = zero ? Real(0) : rho(i); });
}

// f(i) += fr(i) (the pair forces of packed rows).
template <int D, class Real, class Exec>
void add_packed_forces(const PackedRows<Real, Exec>& fr, const typename Particles<D, Real, Exec>::vector_view& f) {
  mesoflow::launch::parallel_for(
      "mesoflow::pillars::watchdog_add_pair_forces", Kokkos::RangePolicy<Exec>(0, f.extent(0)), KOKKOS_LAMBDA(int i) {
        for (int d = 0; d < D; ++d) f(i, d) += fr(i, d);
      });
}

// The pair terms of an MDPD system evaluated alone, for the NaN watchdog's attribution: each its
// own MdpdPairForce with the other coefficients zero, on scratch rows.
template <int D, class Real, class Exec>
struct MdpdTermsAlone {
  using System = MdpdSystem<D, Real, Exec>;
  using Rows = PackedRows<Real, Exec>;

  static MdpdParameters only(MdpdParameters p, bool conservative, bool thermostat) {
    if (!conservative) p.A = p.B = 0;
    if (!thermostat) p.R = 0;
    return p;
  }

  explicit MdpdTermsAlone(const System& sys)
      : conservative(only(sys.parameters(), true, false), sys.seed(), Real(sys.options().wca_epsilon),
                     Real(sys.options().wca_sigma)),
        thermostat(only(sys.parameters(), false, true), sys.seed(), Real(sys.options().wca_epsilon),
                   Real(sys.options().wca_sigma)),
        core(only(sys.parameters(), false, false), sys.seed(), Real(sys.options().wca_epsilon),
             Real(sys.options().wca_sigma)),
        density(DensityWeight<D, Real>(sys.parameters().density_kernel, Real(sys.parameters().r_B),
                                      sys.parameters().density_self_term)),
        xr("mesoflow::pillars::watchdog_xr", sys.particles.size()),
        vr("mesoflow::pillars::watchdog_vr", sys.particles.size()),
        fr("mesoflow::pillars::watchdog_fr", sys.particles.size()),
        rho("mesoflow::pillars::watchdog_rho", sys.particles.size()) {}

  // f ← the pair force of `term` alone at the current state.
  void evaluate(System& sys, MdpdPairForce<D, Real, Exec>& term, bool with_density, bool with_core) {
    const auto& p = sys.particles;
    pack_vectors<D, Real, Exec>(p.x, xr);
    pack_vectors<D, Real, Exec>(p.v, vr);
    if (with_density) density.compute(xr, sys.neighbor_list(), sys.box(), rho);
    set_density_column(xr, with_density ? rho : Kokkos::View<Real*, Exec>());
    term.compute(xr, vr, p.type, sys.tag, sys.neighbor_list(), sys.box(), sys.current_step(), with_core, fr);
    p.zero_forces();
    add_packed_forces<D, Real, Exec>(fr, p.f);
  }

  MdpdPairForce<D, Real, Exec> conservative, thermostat, core;
  LocalDensity<D, Real, Exec> density;
  Rows xr, vr, fr;
  Kokkos::View<Real*, Exec> rho;
};

// Kinetic temperature of the particles of one type (−1: all), k_BT = Σ m v² / (D N_dof) with the
// mean velocity of those particles removed (N_dof = N − 1).
template <int D, class Real, class ExecSpace>
double kinetic_temperature(const Particles<D, Real, ExecSpace>& p, int only_type = -1) {
  const auto v = p.v;
  const auto m = p.mass;
  const auto type = p.type;
  const auto s = parallel_sum<2 * D + 2, ExecSpace>(
      "mesoflow::mdpd::kinetic_temperature", int(p.size()), KOKKOS_LAMBDA(int i, double(&acc)[2 * D + 2]) {
        if (only_type >= 0 && type(i) != only_type) return;
        for (int d = 0; d < D; ++d) {
          acc[d] += double(m(i)) * double(v(i, d));
          acc[D + d] += double(m(i)) * double(v(i, d)) * double(v(i, d));
        }
        acc[2 * D] += double(m(i));
        acc[2 * D + 1] += 1.0;
      });
  if (s[2 * D + 1] < 2) return 0.0;
  double twice_ke = 0;
  for (int d = 0; d < D; ++d) twice_ke += s[D + d] - s[d] * s[d] / s[2 * D];
  return twice_ke / (double(D) * (s[2 * D + 1] - 1.0));
}

}  // namespace mesoflow::mdpd
