// lj_fluid — a Lennard-Jones fluid in a periodic box: the reference scene of mesoflow's common
// kernels (cell lists, Verlet lists, the generic pair loop, velocity Verlet, FIRE, Langevin,
// H5MD output, checkpoint/restart). Its defaults follow LAMMPS' bench/in.lj: ρ = 0.8442, k_BT = 1.44,
// r_c = 2.5σ, skin 0.3σ, Δt = 0.005τ.
//
// Units (LJ reduced): length σ, energy ε, mass m, time τ = σ√(m/ε), k_B = 1; density in σ^-D.
//
// Scene: N particles on a square/cubic lattice (jittered) fill a periodic box of side
// L = (N/ρ)^(1/D); FIRE relaxes it towards a nearby potential-energy minimum (at most
// --fire-iterations iterations, as the studies remove overlaps before a run), velocities are
// drawn from the Maxwell distribution at k_BT (zero total momentum, rescaled to exactly k_BT), then
// velocity Verlet runs NVE, or NVT with --gamma > 0 (Langevin thermostat).
//
// Output (<out> = --output without its extension): <out>.h5 (H5MD: positions, velocities,
// observables, parameters), <out>.xdmf (ParaView), <out>.csv (observables), <out>.json (summary),
// <out>.ckpt.h5 (checkpoint, replaced atomically; --restart continues from it).
#include "drivers/common/cli.hpp"
#include "drivers/common/json_summary.hpp"
#include "scenes/common/nan_watchdog.hpp"
#include "drivers/common/output_paths.hpp"
#include "drivers/common/particle_io.hpp"
#include "drivers/common/progress.hpp"
#include "scenes/common/time_step_limit.hpp"
#include "kernels/common/fire.hpp"
#include "kernels/common/langevin.hpp"
#include "kernels/common/lennard_jones.hpp"
#include "kernels/common/lennard_jones_stability.hpp"
#include "kernels/common/pair_force.hpp"
#include "kernels/common/random.hpp"
#include "kernels/common/reductions.hpp"
#include "kernels/common/velocity_verlet.hpp"
#include "scenes/lj_fluid/lj_fluid_scene.hpp"

#include <chrono>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>

namespace mesoflow {
namespace {

struct Parameters {
  int dimension = 3;
  int particles = 4000;
  double density = 0.8442;
  double temperature = 1.44;
  double cutoff = 2.5;
  double skin = 0.3;
  double dt = 0.005;
  bool force_dt = false;  // --force-dt
  long long steps = 2000;
  double gamma = 0.0;
  long long seed = 12345;
  int fire_iterations = 500;
  long long dump_every = 100;
  long long checkpoint_every = 500;
  long long check_every = 100;  // NaN watchdog
  std::string precision = "double";
  int threads = 0;
  bool restart = false;
};

template <int D, class Real>
void run(const Parameters& par, const cli::DriverApp& app) {
  using Exec = Kokkos::DefaultExecutionSpace;
  const driver::OutputPaths out(app.output());
  const Real L = Real(std::pow(par.particles / par.density, 1.0 / D));
  const auto box = Box<D, Real>::cube(L, true);
  const LennardJones<Real> lj(Real(1), Real(1), Real(par.cutoff));
  const LangevinThermostat<Real> langevin(Real(par.gamma), Real(par.temperature), std::uint64_t(par.seed));
  Particles<D, Real, Exec> p(par.particles, "lj");
  NeighborList<D, Real, Exec> list(Real(par.cutoff), Real(par.skin));
  PairForce<D, Real, Exec> pair;
  VelocityVerlet<D, Real, Exec> vv(Real(par.dt));
  cli::KernelTimers timers;

  auto pair_forces = [&] {
    {
      cli::ScopedTimer t(timers, "neighbor");
      if (list.update(p, box)) wrap_positions(p, box);
    }
    cli::ScopedTimer t(timers, "pair");
    p.zero_forces();
    return pair.accumulate(lj, p, list, box);
  };

  std::int64_t step = 0;
  double time = 0, potential = 0;
  std::optional<io::H5mdWriter> h5;
  if (par.restart) {
    const auto at = lj_fluid::read_checkpoint(out.checkpoint, p, list, box);
    step = at.step;
    time = at.time;
    h5.emplace(io::H5mdWriter::resume(out.trajectory, step));
    if (!app.quiet()) std::cerr << "lj_fluid: resumed from " << out.checkpoint << " at step " << step << "\n";
  } else {
    lj_fluid::place_on_lattice(p, L, std::uint64_t(par.seed));
    FireParameters fire;
    fire.dt_start = par.dt;
    fire.dt_max = 10 * par.dt;
    fire.max_iterations = par.fire_iterations;
    fire.force_tolerance = 1e-6;
    const auto quench = fire_minimize(p, pair_forces, fire);
    if (!app.quiet())
      std::cerr << "lj_fluid: FIRE quench " << quench.iterations << " iterations, U/N = "
              << quench.energy / par.particles << ", max |F| = " << quench.max_force << "\n";
    lj_fluid::thermalize(p, par.temperature, std::uint64_t(par.seed));
    potential = pair_forces();
    h5.emplace(out.trajectory, "mesoflow", MESOFLOW_VERSION, "mesoflow lj_fluid");
    for (const auto& [key, value] : app.resolved_parameters()) h5->set_parameter(key, value);
    h5->set_parameter("box_length", double(L));
    driver::add_particles_group(*h5, "fluid", p.size(), box);
  }

  auto record = [&] {
    const double ke = kinetic_energy(p);
    const double dof = double(D) * (double(p.size()) - 1.0);
    h5->append_observable("kinetic_energy", step, time, ke);
    h5->append_observable("potential_energy", step, time, potential);
    h5->append_observable("total_energy", step, time, ke + potential);
    h5->append_observable("temperature", step, time, 2.0 * ke / dof);
    const auto P = momentum(p);
    h5->append_observable("momentum", step, time, P.data(), D);
    driver::write_frame(*h5, "fluid", step, time, p);
  };
  if (!par.restart) record();

  cli::ProgressLine progress(par.steps - step, par.particles, !app.quiet());
  const std::int64_t first = step;
  const auto t0 = std::chrono::steady_clock::now();
  const int builds_before = list.num_builds();
  auto one_step = [&] {
    {
      cli::ScopedTimer t(timers, "integrate");
      vv.first_half(p);
    }
    potential = pair_forces();
    if (langevin.active()) {
      cli::ScopedTimer t(timers, "langevin");
      langevin.accumulate(p, vv.velocity_for_forces(p), Real(par.dt), step);
    }
    {
      cli::ScopedTimer t(timers, "integrate");
      vv.second_half(p);
    }
    ++step;
    time = double(step) * par.dt;
  };
  // The NaN watchdog (scenes/common/nan_watchdog.hpp): checked every check_every steps and before
  // every output and checkpoint, so neither is ever written from a non-finite state.
  watchdog::Watched watched = watchdog::watch_particles(p);
  watched.step = one_step;
  watched.steps = [&] { return (long long)step; };
  watched.set_steps = [&](long long s) {
    step = s;
    time = double(step) * par.dt;
  };
  watched.after_restore = [&] { list.build(p, box); };
  watched.terms = {{"Lennard-Jones pair forces", [&] { pair_forces(); }}};
  if (langevin.active())
    watched.terms.push_back({"Langevin thermostat γ", [&] {
                               p.zero_forces();
                               langevin.accumulate(p, p.v, Real(par.dt), step);
                             },
                             true});
  watchdog::NanWatchdog watch(std::move(watched), par.check_every);
  while (step < par.steps) {
    one_step();
    watch.after_step();
    const bool dump = step % par.dump_every == 0 || step == par.steps;
    const bool checkpoint = step % par.checkpoint_every == 0 || step == par.steps;
    if (dump || checkpoint) watch.check();
    if (dump) {
      cli::ScopedTimer t(timers, "output");
      record();
    }
    if (checkpoint) {
      cli::ScopedTimer t(timers, "checkpoint");
      h5->flush();
      lj_fluid::write_checkpoint(out.checkpoint, step, time, p, list, box);
    }
    progress.update(step - first);
  }
  progress.finish();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  h5->write_xdmf(out.xdmf);
  h5.reset();
  driver::write_observables_csv(out.trajectory, out.csv,
                                {"kinetic_energy", "potential_energy", "total_energy", "temperature"});
  const double steps_per_second = step > first && wall > 0 ? double(step - first) / wall : 0.0;
  cli::write_summary(out.summary, {{"driver", "lj_fluid"}, {"dimension", D}, {"precision", par.precision},
                                   {"particles", par.particles},
                                   {"resumed_from_step", par.restart ? first : 0}, {"steps_run", step - first}, {"wall_seconds", wall},
                                   {"steps_per_second", steps_per_second},
                                   {"particle_updates_per_second", steps_per_second * par.particles},
                                   {"neighbor_list_builds", list.num_builds() - builds_before},
                                   {"kokkos", kokkos_configuration()}});
  if (!app.quiet()) timers.print(std::cout);
}

}  // namespace
}  // namespace mesoflow

int main(int argc, char** argv) {
  using mesoflow::cli::Bounds;
  mesoflow::Parameters par;
  mesoflow::cli::DriverApp app(
      "Lennard-Jones fluid in a periodic box (LJ units): the reference scene of mesoflow's common kernels",
      "lj_fluid.h5");
  app.add_int("--dimension", par.dimension, "spatial dimension", 2, 3);
  app.add_int("--particles", par.particles, "number of particles N", 2, 100000000);
  app.add_real("--density", par.density, "number density ρσ^D", 0.0, 1.2, Bounds::left_open);
  app.add_real("--temperature", par.temperature, "initial (and thermostat) temperature k_BT/ε", 0.0, 100.0, Bounds::left_open);
  app.add_real("--cutoff", par.cutoff, "LJ cutoff r_c/σ", 1.0, 10.0);
  app.add_real("--skin", par.skin, "neighbor-list skin /σ", 0.0, 5.0, Bounds::left_open);
  app.add_real("--dt", par.dt, "time step Δt/τ (refused above the stability limit)", 0.0, 0.02, Bounds::left_open);
  app.add_flag(mesoflow::cli::force_dt_flag, par.force_dt, mesoflow::cli::force_dt_help);
  app.add_int("--steps", par.steps, "time steps to run (total, including any before a restart)", 0, 1000000000000LL);
  app.add_real("--gamma", par.gamma, "Langevin friction rate γτ (0: NVE)", 0.0, 1000.0);
  app.add_int("--seed", par.seed, "random seed (lattice jitter, velocities, Langevin noise)", 0, 4294967295LL);
  app.add_int("--fire-iterations", par.fire_iterations, "FIRE iterations of the initial quench", 0, 10000000);
  app.add_positive("--dump-every", par.dump_every, "steps between trajectory frames and observables");
  app.add_positive("--checkpoint-every", par.checkpoint_every, "steps between checkpoints");
  app.add_int("--check-every", par.check_every,
              "steps between NaN-watchdog checks (a non-finite state stops the run, naming particle, term and step)",
              1, 1000000);
  app.add_choice("--precision", par.precision, "floating-point precision of the kernels", {"double", "float"});
  app.add_int("--threads", par.threads, "host threads (0: OMP_NUM_THREADS or all cores)", 0, 4096);
  app.add_flag("--restart", par.restart, "continue from <output>.ckpt.h5 (the same parameters otherwise)");
  return app.run(argc, argv, [&] {
    // Contacts at 0.9σ and the Langevin friction (kernels/common/lennard_jones_stability.hpp).
    const auto limit = mesoflow::lennard_jones_stability(1.0, 1.0, 1.0, par.temperature, par.gamma);
    mesoflow::cli::check_time_step("lj_fluid", par.dt, {limit.max_dt(), limit.limiting_term("τ")}, par.force_dt);
    mesoflow::KokkosScope kokkos(par.threads);
    const bool single = par.precision == "float";
    if (par.dimension == 2)
      single ? mesoflow::run<2, float>(par, app) : mesoflow::run<2, double>(par, app);
    else
      single ? mesoflow::run<3, float>(par, app) : mesoflow::run<3, double>(par, app);
  });
}
