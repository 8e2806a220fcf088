// sph_system.hpp — a weakly compressible SPH particle system and its time step (paper §2.2, §2.5):
// the composition of the SPH terms that tests, benchmarks and scenes share.
//
// A step (sph_integrator.hpp, eqs. 11–16): half kick, half density update, extrapolated velocity ū
// and drift; neighbor-list upkeep (a full list of reach support + skin, rebuilt when a particle has
// moved more than half the skin; at the first build and then every `sort_every` rebuilds the
// particles are reordered in memory by cell, as MdpdSystem does); the packed rows with the
// pressures of eq. (6); the fused pair loop, ρ̇ of eq. (4) and f of eq. (5) with the body force
// (sph_pair_interactions.hpp; walls as chosen in SphOptions::wall_velocity, no_slip_walls.hpp);
// second half kick and density update.
//
// Per particle: Particles' x, v, f, mass, type (particle_types.hpp: fluid, inner fluid, fixed wall
// or membrane), and here rho, drho (ρ̇ of the last force evaluation), pressure, mu (dynamic
// viscosity), u_bar (ū), and wall_geometry for Morris walls.
// allocate() sets ρ = ρ0, μ = 0, unit mass, type fluid; set them for the scene before begin().
//
// Forces beyond the SPH terms (the membrane bonds of eq. 7, kernels/msm): begin(extra) and
// step(extra) call the host-side functor extra(particles) right after the pair loop has assigned
// f^{n+1} and before the second half kick of eq. (15), so whatever it adds to particles.f enters
// eqs. (15) and, at the next step, (11) and (13): f_i = (eq. 5)_i + extra_i. begin() and step()
// are begin(extra) and step(extra) with nothing extra. time_step_limits() sees the extra forces
// in the accelerations only; a stiff extra term brings its own limit (bonds:
// HarmonicBonds::time_step_limit), which the scene combines with these.
//
// Memory sorting moves particles to other indices. Whatever names particles by index (bond ends)
// must follow: after each sort (the first in begin(), before its extra functor runs),
// last_sort_new_index()(i) is the new index of the particle that was at index i, and num_sorts()
// counts the sorts; a scene compares num_sorts() with the count it has seen, from its extra
// functor (which runs after any sort of that step), and renumbers with
// renumber_particle_indices() (kernels/common/particle_sort.hpp).
#pragma once

#include "kernels/common/kernel_launch.hpp"
#include "kernels/common/neighbor_list.hpp"
#include "kernels/common/particle_sort.hpp"
#include "kernels/common/velocity_verlet.hpp"
#include "kernels/sph/no_slip_walls.hpp"
#include "kernels/sph/smoothing_kernels.hpp"
#include "kernels/sph/sph_integrator.hpp"
#include "kernels/sph/sph_pair_interactions.hpp"
#include "kernels/sph/sph_time_step.hpp"

#include <optional>
#include <stdexcept>
#include <string>

namespace mesoflow::sph {

// The extra functor of begin() and step(): adds nothing.
struct NoExtraForces {
  template <class P>
  void operator()(const P&) const {}
};

struct SphOptions {
  // half: each pair once, forces scattered (reproducible at a fixed thread count); full: each row
  // sums its own particle (the same bits on every backend and thread count).
  NeighborListKind list_kind = NeighborListKind::half;
  double skin_fraction = 0.1;  // neighbor skin in units of the kernel support
  int cells_per_reach = 1;     // neighbor-list binning (neighbor_list.hpp)
  int sort_every = 20;         // rebuilds between memory reorderings, the first at begin(); 0: never
  WallVelocity wall_velocity = WallVelocity::prescribed;  // the paper's walls (no_slip_walls.hpp)
  double beta_max = 8.0;       // cap of Morris' wall factor β (no_slip_walls.hpp)
};

template <int D, class Real, class ExecSpace = Kokkos::DefaultExecutionSpace, class Kernel = LucyKernel<D, Real>>
class SphSystem {
 public:
  using vector_view = typename Particles<D, Real, ExecSpace>::vector_view;
  using scalar_view = Kokkos::View<Real*, ExecSpace>;
  using int_view = Kokkos::View<int*, ExecSpace>;

  SphSystem(const Kernel& kernel, const TaitEquationOfState<Real>& eos, const Box<D, Real>& box, Real dt,
            const SphOptions& opt = {})
      : kernel_(kernel),
        eos_(eos),
        box_(box),
        opt_(opt),
        pair_(kernel, BodyForce<D, Real>{}),
        integrator_(dt),
        morris_(opt.beta_max) {
    if (!(opt.skin_fraction >= 0 && opt.skin_fraction <= 1))
      throw std::invalid_argument("sph: skin_fraction must be in [0, 1], got " + std::to_string(opt.skin_fraction));
    if (opt.sort_every < 0)
      throw std::invalid_argument("sph: sort_every must be >= 0, got " + std::to_string(opt.sort_every));
  }

  // Fresh storage for n fluid particles of unit mass at ρ = ρ0, μ = 0.
  void allocate(int n) {
    particles.allocate(std::size_t(n), "sph");
    rho = scalar_view(Kokkos::ViewAllocateWithoutInitializing("mesoflow::sph::rho"), n);
    drho = scalar_view("mesoflow::sph::drho", n);
    pressure = scalar_view("mesoflow::sph::pressure", n);
    mu = scalar_view("mesoflow::sph::mu", n);
    u_bar = vector_view("mesoflow::sph::u_bar", n);
    rows_ = SphRows<D, Real, ExecSpace>("mesoflow::sph::rows", n);
    Kokkos::deep_copy(rho, eos_.rho0);
    if (opt_.wall_velocity == WallVelocity::morris)
      wall_geometry = WallGeometry<D, Real, ExecSpace>("mesoflow::sph::wall_geometry", n);
    if (opt_.sort_every > 0) sort_new_index_ = int_view("mesoflow::sph::sort_new_index", n);
  }

  void set_body_force(const BodyForce<D, Real>& body) { pair_.set_body_force(body); }
  void set_dt(Real dt) { integrator_.set_dt(dt); }

  // Call once the particles are placed and their types, masses, densities and viscosities set:
  // builds the list and evaluates ρ̇ and f at the current state, with ū = v; then extra(particles)
  // adds its forces to f.
  void begin() { begin(NoExtraForces{}); }

  template <class ExtraForces>
  void begin(ExtraForces&& extra) {
    set_u_bar_to_velocity();
    list_.emplace(kernel_.support, Real(opt_.skin_fraction * double(kernel_.support)), opt_.list_kind,
                  BodyExclusion::none, opt_.cells_per_reach);
    // The first build sorts: a scene's initial order (a lattice, layer by layer) is rarely the cell
    // order, and the pair loop ran 8% slower in it until the sort after `sort_every` rebuilds.
    builds_since_sort_ = opt_.sort_every > 0 ? opt_.sort_every - 1 : 0;
    compute_rates();
    extra(particles);
  }

  // ū ← v. Not inside begin(): nvcc rejects a KOKKOS_LAMBDA in a function template instantiated
  // with a host lambda's type (the extra-forces callback).
  void set_u_bar_to_velocity() {
    const auto v = particles.v, ub = u_bar;
    mesoflow::launch::parallel_for(
        "mesoflow::sph::initial_u_bar", Kokkos::RangePolicy<ExecSpace>(0, particles.size()), KOKKOS_LAMBDA(int i) {
          for (int d = 0; d < D; ++d) ub(i, d) = v(i, d);
        });
  }

  void step() { step(NoExtraForces{}); }

  // Eqs. (11)–(16), with extra(particles) adding its forces to f^{n+1} between the pair loop and
  // the second half kick (eq. 15).
  template <class ExtraForces>
  void step(ExtraForces&& extra) {
    integrator_.first_half(particles, rho, drho, u_bar);
    compute_rates();
    extra(particles);
    integrator_.second_half(particles, rho, drho);
    ++step_;
  }

  // A step whose force evaluation the caller composes (a scene's term list, capsule_scene.hpp):
  // forces() runs between the first and the second half kick, calls compute_rates() (the SPH pair
  // loop, which assigns ρ̇ and f) and adds whatever it adds after it: step(extra) is
  // step_composed([&] { compute_rates(); extra(particles); }).
  template <class Forces>
  void step_composed(Forces&& forces) {
    integrator_.first_half(particles, rho, drho, u_bar);
    forces();
    integrator_.second_half(particles, rho, drho);
    ++step_;
  }

  // The stability limits at the current state (a host reduction: not every step).
  SphTimeStepLimits time_step_limits(const SphTimeStepCoefficients& c = {}) const {
    const auto mu_ = mu, rho_ = rho;
    const auto type = particles.type;
    double nu_max = 0, nu_min = 0, c_max = 0;
    const auto eos = eos_;
    mesoflow::launch::parallel_reduce(
        "mesoflow::sph::max_viscosity", Kokkos::RangePolicy<ExecSpace>(0, particles.size()),
        KOKKOS_LAMBDA(int i, double& nu) {
          const double nu_i = double(mu_(i)) / double(rho_(i));
          if (nu_i > nu) nu = nu_i;
        },
        Kokkos::Max<double>(nu_max));
    mesoflow::launch::parallel_reduce(
        "mesoflow::sph::min_viscosity", Kokkos::RangePolicy<ExecSpace>(0, particles.size()),
        KOKKOS_LAMBDA(int i, double& nu) {
          if (is_fixed(type(i))) return;
          const double nu_i = double(mu_(i)) / double(rho_(i));
          if (nu_i < nu) nu = nu_i;
        },
        Kokkos::Min<double>(nu_min));
    nu_min = std::min(nu_min, nu_max);
    mesoflow::launch::parallel_reduce(
        "mesoflow::sph::max_sound_speed", Kokkos::RangePolicy<ExecSpace>(0, particles.size()),
        KOKKOS_LAMBDA(int i, double& c) {
          const double c_i = is_fixed(type(i)) ? 0.0 : double(eos.sound_speed(rho_(i)));
          if (c_i > c) c = c_i;
        },
        Kokkos::Max<double>(c_max));
    if (!(c_max > 0)) c_max = double(eos_.c0);
    return sph_time_step_limits(time_step_length(kernel_), nu_max, c_max, max_fluid_acceleration(particles), c, nu_min);
  }

  const Kernel& kernel() const { return kernel_; }
  const TaitEquationOfState<Real>& equation_of_state() const { return eos_; }
  const Box<D, Real>& box() const { return box_; }
  const NeighborList<D, Real, ExecSpace>& neighbor_list() const { return *list_; }

  // Counters that, with the per-particle arrays (x, v, f, ρ, ρ̇, mass, μ, ū, type, body, wall
  // geometry) and the list's reference positions, make up the state a bit-identical continuation
  // needs (the NaN watchdog's replay; MdpdSystem has the same pair).
  struct Counters {
    long long step;
    int builds_since_sort, num_sorts;
  };
  Counters counters() const { return {step_, builds_since_sort_, num_sorts_}; }
  vector_view neighbor_reference_positions() const { return list_->reference_positions(); }

  // Continues from a saved state: the arrays hold the saved values (ρ̇, f and ū those of the saved
  // step, not recomputed); the list is rebuilt from its saved reference positions, so it has the
  // same rows, and the next rebuild and sort come at the same steps, as when the state was saved.
  void resume(const Counters& c, const vector_view& reference) {
    Particles<D, Real, ExecSpace> at_reference = particles;
    at_reference.x = reference;
    list_->build(at_reference, box_);
    step_ = c.step;
    builds_since_sort_ = c.builds_since_sort;
    num_sorts_ = c.num_sorts;
  }

  Real dt() const { return integrator_.dt(); }
  long long current_step() const { return step_; }
  int num_sorts() const { return num_sorts_; }
  // After a sort: new_index(i) = the index of the particle that was at i before it (empty with
  // sort_every = 0; stale until the first sort).
  const int_view& last_sort_new_index() const { return sort_new_index_; }

  Particles<D, Real, ExecSpace> particles;
  scalar_view rho;       // ρ (integrated by eqs. 12, 16)
  scalar_view drho;      // ρ̇ of the last evaluation of eq. (4)
  scalar_view pressure;  // p(ρ) of eq. (6) at the last evaluation
  scalar_view mu;        // dynamic viscosity
  vector_view u_bar;     // ū of eq. (13)
  // With WallVelocity::morris: per wall particle the unit normal into the fluid and the depth below
  // the wall surface (no_slip_walls.hpp); empty otherwise.
  WallGeometry<D, Real, ExecSpace> wall_geometry;

  // Neighbor-list upkeep (with the memory sorts), the packed rows with the pressures of eq. (6),
  // and the fused pair loop: ρ̇ of eq. (4) and f of eq. (5) with the body force.
  void compute_rates() {
    if (list_->update(particles, box_)) {
      wrap_positions(particles, box_);
      if (opt_.sort_every > 0 && ++builds_since_sort_ >= opt_.sort_every) {
        sort_particles_by_cell(particles, list_->cells(), rho, drho, pressure, mu, u_bar, wall_geometry);
        invert_permutation(list_->cells().cell_particles(), sort_new_index_);
        list_->build(particles, box_);
        builds_since_sort_ = 0;
        ++num_sorts_;
      }
    }
    pack_sph_rows(particles, u_bar, rho, mu, eos_, rows_, pressure);
    pair_.compute(rows_, particles.type, *list_, box_, particles.f, drho, wall_geometry, morris_);
  }

 private:
  Kernel kernel_;
  TaitEquationOfState<Real> eos_;
  Box<D, Real> box_;
  SphOptions opt_;
  SphPairInteractions<D, Real, ExecSpace, Kernel> pair_;
  SphIntegrator<D, Real, ExecSpace> integrator_;
  std::optional<NeighborList<D, Real, ExecSpace>> list_;
  SphRows<D, Real, ExecSpace> rows_;
  int_view sort_new_index_;
  MorrisWallFactor<Real> morris_;
  long long step_ = 0;
  int builds_since_sort_ = 0, num_sorts_ = 0;
};

}  // namespace mesoflow::sph
