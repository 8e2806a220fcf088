// crystal — a one-dimensional microfluidic crystal of flattened droplets (rigid discs) carried by
// an MPC-AT+a solvent through a 2D channel, and its phonons (mpc-microfluidic-crystal-phonons
// paper, §4 and Appendix B). Every run also measures the velocity ratio K = u_d/u_oil, so the
// single-droplet calibration run of Appendix B is `crystal --discs 1`; with one disc K is also given
// against the oil speed far from it, across the width and on the axis (docs/mpc.md, "K of a single disc").
//
// Units (Appendix B): cell size Δx, solvent particle mass m, k_BT; time τ = Δx √(m/k_BT). The
// defaults are the paper's scene: R = 5Δx, h = 0.005τ, n = 40 particles per cell (ρ = 40 m/Δx²),
// g = 0.1 (body acceleration of the solvent, Δx/τ²), γ = 2·10⁴ m/τ (plate friction −γ u_d),
// channel L × W = 1000Δx × 15Δx with walls at y = 0 and y = W, 90 discs (spacing a = L/N), WCA
// ε = k_BT, r0 = Δx (eq. B.4), disc mass M = ρπR², zigzag (triangle wave) of six discs per
// wavelength. η of eq. (B.3) for these values: 321.77 m/τ. Walls: bounce-back, and virtual
// particles in the cut wall cells, by default the mirror images of the fluid next to the wall
// (no slip; kernels/mpc/wall_mirror_particles.hpp), or with --wall-virtual maxwell Appendix B's
// Maxwell–Boltzmann particles at the wall velocity (a slip length ≈ 0.1Δx; docs/mpc.md).
//
// Output (<out> = --output without its extension): <out>.h5 (H5MD: disc positions, unwrapped
// along x, and velocities every --frame-interval; observables u_oil (mean solvent velocity), u_d
// (mean disc velocity); parameters as attributes), <out>.xdmf, <out>.csv (the observables),
// <out>.json (K, u_d, u_oil, Re, Pe, B, β, v_p, speed; for one disc also "far_field": the oil speed
// far from the disc, mean and on the axis, and K against each, with the profile in
// <out>_far_profile.csv and the two speeds per frame as observables u_far_mean, u_far_axis), and
// for two or more discs
// <out>_phonons.h5 (power spectra of eqs. 1-2, theory curves of eqs. 3, 4, 8, 11-14, correlation
// eq. 5; analysis/crystal/phonon_spectra.hpp), <out>_theory.csv and <out>_phonons.png
// (scripts/plot_crystal.py). Frames before --warmup are written but left out of K and the spectra.
// <out>.ckpt.h5 is replaced atomically every --checkpoint-interval; --restart continues from it.
// The scene: scenes/crystal/channel_flow.hpp (its terms, watchdog view and checkpoint fields),
// scenes/crystal/crystal_record.hpp (disc placement, frames, far field) and
// scenes/crystal/crystal_run.hpp (the run, its frames and checkpoints); η of eq. (B.3):
// kernels/mpc/mpc_viscosity.hpp; K and the phonon analysis: analysis/crystal/run_analysis.hpp.
#include "analysis/crystal/run_analysis.hpp"
#include "drivers/common/cli.hpp"
#include "drivers/common/json_summary.hpp"
#include "drivers/common/output_paths.hpp"
#include "drivers/common/progress.hpp"
#include "drivers/common/restart.hpp"
#include "scenes/common/time_step_limit.hpp"
#include "scenes/crystal/crystal_run.hpp"

#include <chrono>
#include <iostream>

namespace mesoflow {
namespace {

struct Parameters : crystal::CrystalRunParameters {
  int threads = 0;
  bool restart = false;
  bool no_plot = false;
};

template <class Real>
void run(const Parameters& par, const cli::DriverApp& app) {
  const driver::OutputPaths out(app.output());
  const std::string base = out.csv.substr(0, out.csv.size() - 4);
  const auto& f = par.flow;
  crystal::CrystalRun<Real> run(par, out.checkpoint, crystal::scene_signature(par));
  const auto& flow = run.flow();
  const auto& rec = run.record();
  const std::size_t nd = run.discs();
  const bool far = run.far_field();
  if (par.restart) {
    const io::CheckpointReader ck(out.checkpoint);
    driver::check_restart_scene(ck, out.checkpoint, crystal::scene_signature(par),
                                "--time, --checkpoint-interval, --check-every, --threads and --no-plot");
    run.resume(ck, out.trajectory);
    if (!app.quiet()) std::cerr << "crystal: resumed from " << out.checkpoint << " at step " << flow.steps_done() << "\n";
  } else {
    run.start(out.trajectory, app.resolved_parameters());
  }

  const std::int64_t first = std::int64_t(flow.steps_done()), total_steps = run.total_steps();
  cli::ProgressLine progress(total_steps - first, std::int64_t(flow.num_solvent()), !app.quiet());
  const auto wall_start = std::chrono::steady_clock::now();
  run.run([&](std::int64_t step) { progress.update(step - first); });
  progress.finish();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  run.close(out.xdmf);
  if (far)
    driver::write_observables_csv(out.trajectory, out.csv, {"u_oil", "u_d", "u_far_mean", "u_far_axis"});
  else
    driver::write_observables_csv(out.trajectory, out.csv, {"u_oil", "u_d"});

  const auto m = crystal::measured_frames(rec.steps, rec.u_d, rec.u_oil, run.warmup_steps());
  const std::size_t frames = m.count;
  const double ud = m.u_d, uoil = m.u_oil;
  const double eta = crystal::viscosity_b3(f);
  const auto numbers = crystal::run_numbers(m, eta, f.density * f.mass / (f.cell_size * f.cell_size), f.disc_radius,
                                            f.friction, f.kT);
  const double K = numbers.K, reynolds = numbers.reynolds, peclet = numbers.peclet;

  cli::Json j{{"driver", "crystal"}, {"discs", nd}, {"solvent_particles", flow.num_solvent()},
              {"measured_frames", frames}, {"u_d", ud}, {"u_oil", uoil}, {"K", K}, {"wall_virtual", par.wall_virtual},
              {"viscosity_b3", eta}, {"reynolds", reynolds}, {"peclet", peclet}};
  if (far) {
    // The far-field profile over the measured frames, its mean and its centre line.
    const auto& ff = rec.far_field();
    rec.write_far_profile(base + "_far_profile.csv");
    const auto [u_far, u_axis] = rec.far_speeds();
    j["far_field"] = {{"from_disc", ff.from_disc}, {"u_mean", u_far}, {"u_axis", u_axis},
                      {"K_mean", u_far != 0 ? ud / u_far : 0.0}, {"K_axis", u_axis != 0 ? ud / u_axis : 0.0}};
    if (!app.quiet())
      std::cout << "crystal: far from the disc (≥ " << ff.from_disc << " Δx): mean oil speed " << u_far
                << ", on the axis " << u_axis << "; u_d/u_axis = " << (u_axis != 0 ? ud / u_axis : 0.0) << "\n";
  }
  if (nd >= 2) {
    const double dt_frame = double(run.frame_steps()) * f.h;
    const auto ph = crystal::phonon_analysis(rec.x, rec.y, m, nd, f.length, f.width, f.disc_radius,
                                             par.calibrated_ratio, dt_frame, base + "_phonons.h5", base + "_theory.csv");
    j["theory_K"] = ud / ph.theory_uoil;
    j["spacing"] = ph.spacing;
    j["B"] = ph.B;
    j["beta"] = ph.beta;
    j["phase_velocity"] = ph.phase_velocity;
    j["frame_interval"] = dt_frame;
    if (!par.no_plot) {
      const std::string png = base + "_phonons.png";
      driver::plot_with_matplotlib("crystal", "plot_crystal.py", {base + "_phonons.h5", png}, png, app.quiet());
    }
  }
  j["components"] = flow.components();
  j["resumed_from_step"] = par.restart ? first : 0;
  j["steps_run"] = total_steps - first;
  j["wall_seconds"] = wall;
  j["steps_per_second"] = wall > 0 ? double(total_steps - first) / wall : 0.0;
  j["kokkos"] = kokkos_configuration();
  cli::write_summary(out.summary, j);
  if (!app.quiet())
    std::cout << "crystal: " << nd << " discs, " << flow.num_solvent() << " solvent particles, " << frames
              << " measured frames; u_d = " << ud << ", u_oil = " << uoil << " Δx/τ, K = " << K << ", Re = " << reynolds
              << "; " << total_steps - first << " steps in " << wall << " s\n";
}

}  // namespace
}  // namespace mesoflow

int main(int argc, char** argv) {
  using mesoflow::cli::Bounds;
  mesoflow::Parameters par;
  auto& f = par.flow;
  mesoflow::cli::DriverApp app(
      "A 1D microfluidic crystal of rigid discs in an MPC-AT+a channel flow, its phonon spectra and K = u_d/u_oil "
      "(mpc-microfluidic-crystal-phonons paper, Appendix B; units: cell size Δx, particle mass m, k_BT, "
      "tau = Δx sqrt(m/k_BT))",
      "crystal.h5");
  app.add_real("--length", f.length, "channel length L/Δx (periodic, a multiple of Δx)", 0.0, 1e6, Bounds::left_open);
  app.add_real("--width", f.width, "channel width W/Δx (walls at y = 0 and W)", 0.0, 1e5, Bounds::left_open);
  app.add_real("--radius", f.disc_radius, "disc radius R/Δx", 0.0, 1e4, Bounds::left_open);
  app.add_real("--density", f.density, "solvent particles per cell n", 0.0, 1e4, Bounds::left_open);
  app.add_real("--dt", f.h, "MPC time step h/τ (refused above the discs' stability limit)", 0.0, 10.0, Bounds::left_open);
  app.add_flag(mesoflow::cli::force_dt_flag, par.force_dt, mesoflow::cli::force_dt_help);
  app.add_real("--body-force", f.body_acceleration, "body acceleration g of the solvent along x, Δx/τ²", -1e3, 1e3);
  app.add_real("--friction", f.friction, "plate friction γ of F = -γ u_d, m/τ", 0.0, 1e9);
  app.add_real("--wca-epsilon", f.wca_epsilon, "WCA energy ε/k_BT (eq. B.4)", 0.0, 1e6);
  app.add_real("--wca-range", f.wca_r0, "WCA length r0/Δx (eq. B.4)", 0.0, 100.0, Bounds::left_open);
  app.add_choice("--collision", par.rule, "MPC collision rule", {"at+a", "at-a", "srd"});
  app.add_choice("--wall-virtual", par.wall_virtual,
                 "virtual particles in the walls' cut cells: mirror (images of the fluid next to the wall: no slip) "
                 "or maxwell (Appendix B: Maxwell-Boltzmann at the wall velocity, a slip of ~0.1 cell)",
                 {"mirror", "maxwell"});
  app.add_int("--discs", par.discs, "number of discs N (spacing a = L/N)", 0, 1000000);
  app.add_int("--wavelength", par.wavelength, "discs per period of the initial zigzag", 1, 1000000);
  app.add_real("--amplitude", par.amplitude, "zigzag amplitude /Δx (-1: largest without wall contact)", -1.0, 1e4);
  app.add_real("--warmup", par.warmup, "time before the measured frames, τ", 0.0, 1e9);
  app.add_real("--time", par.time, "measured time, τ", 0.0, 1e9, Bounds::left_open);
  app.add_real("--frame-interval", par.frame_interval, "time between frames, τ", 0.0, 1e9, Bounds::left_open);
  app.add_int("--check-every", par.check_every,
              "steps between NaN-watchdog checks (a non-finite state stops the run, naming particle, term and step)",
              1, 1000000);
  app.add_real("--checkpoint-interval", par.checkpoint_interval, "time between checkpoints, τ", 0.0, 1e9,
               Bounds::left_open);
  app.add_real("--calibrated-k", par.calibrated_ratio,
               "K = u_d/u_oil of a single-disc run for the theory curves (0: this run's own ratio)", 0.0, 1.0);
  app.add_int("--seed", par.seed, "random seed (solvent, collisions)", 0, 4294967295LL);
  app.add_choice("--precision", par.precision, "floating-point precision of the kernels", {"double", "float"});
  app.add_flag("--deterministic", f.deterministic,
               "deterministic sums: MPC cell sums and disc impulses over index-ordered segments, bitwise the same on "
               "every backend and thread count (docs/design.md; costs a sort per step)");
  app.add_int("--threads", par.threads, "host threads (0: OMP_NUM_THREADS or all cores)", 0, 4096);
  app.add_flag("--restart", par.restart, "continue from <out>.ckpt.h5");
  app.add_flag("--no-plot", par.no_plot, "do not write the PNG plot");
  return app.run(argc, argv, [&] {
    par.validate();  // the run's ranges and the step against the stability limit
    mesoflow::KokkosScope kokkos(par.threads);
    if (par.precision == "float")
      mesoflow::run<float>(par, app);
    else
      mesoflow::run<double>(par, app);
  });
}
