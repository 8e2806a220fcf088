// pillars — MDPD flow through pillar arrays (Hulikal Chakrapani, Bazyar, Lammertink, Luding &
// den Otter, Soft Matter 19, 436 (2023)), and the viscosity of any MDPD fluid.
//
// Units (paper §2.5.1): length σ = r_A, mass m, energy ε = k_BT, time τ = σ√(m/ε). Defaults are
// the paper's: ρ = 6, A = −40, B = 25 (3D) / 30 (2D), r_B = 0.75, R = 12 (D = 72), dt = 0.01,
// tethers k_S = 12.5, pillar diameter d = 5, L_d = 5, bins of 0.5σ in elevation.
//
// --mode flow (Fig. 2; scenes/pillars/pillar_flow.hpp): pillars (and, in 3D with --height H > 0,
//   walls) carved from an equilibrated fluid, a body force f_b driving it in x ∈ [0, L_d); after
//   --warmup-steps, samples every --sample-every steps; the Darcy, drag and Brinkman estimates of
//   analysis/pillars/permeability_estimates.hpp (eqs. 1-3, 5, 7); --kappa-p (from the matching 2D
//   run) adds μ_eff/μ, eq. (7)'s κ_eff and B's theory value. --layout none checks κ_w = H²/12.
// --mode theory: the square- and hexagonal-array permeability curves over ε (<out>_theory.csv) and
//   Sangani & Acrivos' exact square-array values (<out>_sangani_acrivos_table.csv).
// --mode viscosity: periodic Poiseuille in a periodic box; the two parabolas of u_x(z) give η.
// --mode bulk: the fluid at rest in a periodic box (--box, --lz): per sample the mean many-body
//   density ⟨ρ̄⟩, k_BT and the pressure (kinetic + conservative and dissipative virials), g(r) (scenes/pillars/
//   bulk_run.hpp); <out>.json (means, block errors), <out>_samples.csv, <out>_rdf.csv. The LAMMPS
//   comparison of docs/mdpd.md (scripts/compare_lammps_mdpd).
// Checkpoints (flow): every --checkpoint-every steps after carving, <out>.ckpt.h5 is replaced
// atomically by the state of PillarFlow::checkpoint_fields; --restart continues bit-identically at the
// same thread count (only --steps, --checkpoint-every, --check-every and --threads may change).
// NaN watchdog (pillars::watched): every --check-every steps and before every sample, the final frame
// and every checkpoint; a non-finite value stops the run (exit status 1) naming particle, term and
// step, before anything is written from the bad state.
// Output (<out> = --output without extension): <out>.h5 (H5MD: final frame with particle types,
// observables per sample, parameters), <out>.xdmf, <out>_profile.csv (per bin: z, fluid count,
// ⟨u_x⟩, u_s, pillar force density, Brinkman fit), <out>_layout.csv (pillar centres), <out>.json
// (summary with the theory values), <out>.png (profile and fit). The runs as the options give them,
// and the record of a flow run: scenes/pillars/pillar_runs.hpp.
#include "analysis/pillars/permeability_estimates.hpp"
#include "drivers/common/cli.hpp"
#include "drivers/common/json_summary.hpp"
#include "drivers/common/output_paths.hpp"
#include "drivers/common/progress.hpp"
#include "drivers/common/restart.hpp"
#include "scenes/common/time_step_limit.hpp"
#include "analysis/common/block_average.hpp"
#include "scenes/pillars/bulk_run.hpp"
#include "scenes/pillars/pillar_runs.hpp"

#include <chrono>
#include <fstream>
#include <iomanip>
#include <iostream>

namespace mesoflow {
namespace {

struct Parameters : pillars::PillarRunParameters {
  std::string mode = "flow";
  int threads = 0;
  bool restart = false;
  bool force_dt = false;  // --force-dt
  double rdf_max = 3.0, rdf_bin = 0.02;  // bulk mode: g(r) range and bin width
  long long rdf_every = 10;              // bulk mode: samples between g(r) histograms
};

template <int D>
void run_flow(const Parameters& par, const cli::DriverApp& app) {
  const driver::OutputPaths out(app.output());
  const std::string stem = out.trajectory.substr(0, out.trajectory.size() - 3);
  const bool quiet = app.quiet();
  const pillars::PillarLayout layout = pillars::make_layout(par);
  const pillars::PillarFlowSettings s = pillars::flow_settings(par, layout, D);
  const double mu = par.viscosity_for_kappa(D);
  const auto& g = s.geometry;
  if (par.layout != "none") pillars::write_csv(layout, stem + "_layout.csv");
  pillars::PillarFlow<D> flow(s);
  auto& sys = flow.system();
  // The parameters a restart must share with the run it continues, as a string kept in the
  // checkpoint: all but the run length, the checkpoint interval, the threads and the output options.
  const std::string signature = driver::scene_signature(
      app, {"steps", "checkpoint-every", "check-every", "threads", "restart", "quiet", "output"});

  std::int64_t resumed_from_step = 0;  // the checkpoint's step after --restart
  pillars::FlowRecording<D> recording(flow, out.checkpoint, signature);
  const auto t0 = std::chrono::steady_clock::now();
  if (par.restart) {
    driver::require_checkpoint(out.checkpoint);
    const io::CheckpointReader ck(out.checkpoint);
    driver::check_restart_scene(ck, out.checkpoint, signature, "--steps, --checkpoint-every, --check-every and --threads");
    resumed_from_step = recording.resume(ck, out.trajectory);
    if (!quiet) std::cerr << "pillars: resumed from " << out.checkpoint << " at step " << sys.current_step() << "\n";
  } else {
    recording.start(par.equilibrate_steps, par.check_every, out.trajectory, app.resolved_parameters());
  }
  if (!quiet)
    std::cerr << "pillars: " << D << "D, " << sys.particles.size() << " particles (" << flow.solid_particles()
              << " solid), box " << g.Lx << " x " << g.Ly << (D == 3 ? " x " + std::to_string(g.Lz) : std::string())
              << ", porosity " << s.porosity << ", f_b = " << s.driving_force << "\n";

  const long long total = par.warmup_steps + par.steps, first = flow.steps_after_carving();
  cli::ProgressLine progress(total - first, int(sys.particles.size()), !quiet);
  recording.run(par.warmup_steps, par.steps, par.sample_every, par.checkpoint_every, par.check_every,
                [&](long long done) { progress.update(done - first); });
  progress.finish();
  const double wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const auto& rec = flow.record();
  if (rec.samples == 0) throw std::invalid_argument("--steps must cover at least one --sample-every interval");

  pillars::FlowMeasurement m{D, g.Lx, g.Ly, g.Lz, g.H, g.diameter, s.porosity, g.centres, flow.x_lo(), flow.x_hi(),
                             mu, s.driving_force, par.density, par.driving_length, rec.count, rec.velocity,
                             rec.pillar_force, rec.tether, rec.driven, rec.sum_u, rec.sum_u2, rec.sample_u,
                             rec.sample_tether, rec.samples, rec.count_all, rec.velocity_all, rec.tether_all,
                             rec.sample_u_box, rec.sample_count_profile, rec.sample_velocity_profile};
  const auto e = pillars::estimate_permeability(m);
  pillars::write_flow_profile(stem + "_profile.csv", e, rec.count);
  recording.write_xdmf(out.xdmf);

  const double d2 = g.diameter * g.diameter;
  const double samples = double(std::max<long long>(rec.samples, 1));
  cli::Json j{{"driver", "pillars"}, {"mode", "flow"}, {"dimension", D}, {"layout", par.layout},
              {"porosity", s.porosity}, {"diameter", g.diameter}, {"box", {g.Lx, g.Ly, g.Lz}}, {"walls_height", g.H},
              {"particles", sys.particles.size()}, {"solid_particles", flow.solid_particles()},
              {"driving_force", s.driving_force}, {"pressure_difference", e.pressure_difference},
              {"pressure_difference_force_balance", e.pressure_difference_force_balance},
              {"kappa_darcy_force_balance", e.kappa_darcy_force_balance}, {"viscosity_used", mu},
              {"samples", rec.samples}, {"mean_ux", e.mean_u}, {"mean_ux_naive_error", e.mean_u_naive_error},
              {"mean_ux_block_error", e.mean_u_block_error},
              {"kappa_darcy_relative_error", e.kappa_darcy_relative_error},
              {"kappa_drag_tether_relative_error", e.kappa_drag_tether_relative_error},
              {"superficial_velocity", e.superficial_velocity}, {"kappa_darcy", e.kappa_darcy},
              {"kappa_darcy_over_d2", e.kappa_darcy / d2}, {"kappa_drag_pair", e.kappa_drag_pair},
              {"kappa_drag_tether", e.kappa_drag_tether}, {"measured_pillars", e.measured_pillars},
              {"region", {flow.x_lo(), flow.x_hi()}}, {"region_fluid_fraction", e.region_fluid_fraction},
              {"superficial_velocity_region", e.superficial_velocity_region},
              {"superficial_velocity_box", e.superficial_velocity_box}, {"kappa_darcy_box", e.kappa_darcy_box},
              {"kappa_darcy_box_relative_error", e.kappa_darcy_box_relative_error},
              {"kappa_drag_tether_region", e.kappa_drag_tether_region},
              {"tether_force_all_pillars", -rec.tether_all / samples},
              {"driving_force_total", s.driving_force * rec.driven / samples},
              {"wall_force_bottom", rec.wall_bottom / samples},
              {"wall_force_top", rec.wall_top / samples}};
  if (!g.centres.empty() && s.porosity < 1)
    for (const auto& [name, value] : pillars::square_array_theory(s.porosity)) j["theory_over_d2"][name] = value;
  if (g.walls()) j["kappa_walls_theory"] = pillars::kappa_walls(g.H);
  if (e.fit) {
    const auto& f = *e.fit;
    cli::Json b{{"B", f.B}, {"alpha", f.alpha}, {"rms_residual", f.rms_residual},
                {"alpha_at_bound", f.alpha_at_lower_bound || f.alpha_at_upper_bound},
                {"jackknife_blocks", e.jackknife_blocks}, {"alpha_error", e.alpha_jackknife_error},
                {"B_error", e.B_jackknife_error}};
    if (par.kappa_p > 0)
      for (const auto& [name, value] : pillars::brinkman_theory(par.kappa_p, f.alpha, e.alpha_jackknife_error, g.H,
                                                                e.pressure_difference, mu, g.Lx))
        b[name] = value;
    j["brinkman"] = b;
  }
  j["components"] = flow.components();
  j["resumed_from_step"] = resumed_from_step;
  j["steps_run"] = std::int64_t(sys.current_step()) - resumed_from_step;  // equilibration included
  j["wall_seconds"] = wall_seconds;
  j["particle_steps_per_second"] =
      double(sys.particles.size()) * double((par.restart ? 0 : par.equilibrate_steps) + total - first) / wall_seconds;
  j["kokkos"] = kokkos_configuration();
  cli::write_summary(out.summary, j);
  if (!quiet)
    std::cerr << "pillars: U_s = " << e.superficial_velocity << " ± " << s.porosity * e.mean_u_block_error
              << ", kappa_darcy/d^2 = " << e.kappa_darcy / d2 << ", kappa_drag (pair, tether)/d^2 = "
              << e.kappa_drag_pair / d2 << ", " << e.kappa_drag_tether / d2 << "\n";
  if (g.walls())
    driver::plot_with_matplotlib("pillars", "plot_pillars.py", {stem + "_profile.csv", out.summary, stem + ".png"},
                                 stem + ".png", quiet);
}

// Periodic Poiseuille viscosity (Backer et al. 2005) in a fully periodic box.
template <int D>
void run_viscosity(const Parameters& par, const cli::DriverApp& app) {
  const driver::OutputPaths out(app.output());
  const std::string stem = out.trajectory.substr(0, out.trajectory.size() - 3);
  pillars::ViscosityRun<D> run(par);
  const auto& sys = run.system();
  const auto& mp = run.fluid();
  cli::ProgressLine progress(par.warmup_steps + par.steps, int(sys.particles.size()), !app.quiet());
  const auto samples = run.run(par.equilibrate_steps, par.warmup_steps, par.steps, par.sample_every, par.check_every,
                               [&](long long done) { progress.update(done); });
  progress.finish();
  if (samples.samples == 0) throw std::invalid_argument("--steps must cover at least one --sample-every interval");
  const double rho = run.number_density();
  const auto fit = pillars::fit_poiseuille_viscosity(samples.count, samples.velocity, run.gradient_length(), rho,
                                                     run.force(), samples.temperature_sum / samples.samples, D);
  pillars::write_viscosity_profile(stem + "_profile.csv", fit);
  cli::Json j{{"driver", "pillars"}, {"mode", "viscosity"}, {"dimension", D}, {"A", mp.A}, {"B", mp.B},
              {"r_B", mp.r_B}, {"R", mp.R}, {"dt", mp.dt}, {"density", rho}, {"force", run.force()},
              {"density_kernel", par.density_kernel}, {"density_self_term", par.density_self_term},
              {"viscosity", fit.viscosity}, {"viscosity_error", fit.viscosity_error},
              {"max_velocity", fit.max_velocity}, {"temperature", fit.thermal_temperature},
              {"samples", samples.samples}};
  j["components"] = sys.components();
  cli::write_summary(out.summary, j);
  if (!app.quiet())
    std::cerr << "pillars: viscosity " << fit.viscosity << " ± " << fit.viscosity_error << " (ρ = " << rho
              << ", k_BT = " << fit.thermal_temperature << ")\n";
}

// The fluid at rest in a periodic box: ⟨ρ̄⟩, k_BT, pressure and g(r) (scenes/pillars/bulk_run.hpp).
template <int D>
void run_bulk(const Parameters& par, const cli::DriverApp& app) {
  const driver::OutputPaths out(app.output());
  const std::string stem = out.trajectory.substr(0, out.trajectory.size() - 3);
  pillars::BulkRun<D> run(par, par.rdf_max, par.rdf_bin);
  const auto& sys = run.system();
  const auto& mp = run.fluid();
  cli::ProgressLine progress(par.equilibrate_steps + par.steps, int(sys.particles.size()), !app.quiet());
  const auto t0 = std::chrono::steady_clock::now();
  const auto s = run.run(par.equilibrate_steps, par.steps, par.sample_every, par.rdf_every, par.check_every,
                         [&](long long done) { progress.update(done); });
  progress.finish();
  const double wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (s.step.size() < 4) throw std::invalid_argument("--steps must cover at least 4 --sample-every intervals");
  {
    std::ofstream csv(stem + "_samples.csv");
    csv << "step,mean_density,temperature,pressure,pressure_virial,pressure_dissipative\n" << std::setprecision(10);
    for (std::size_t k = 0; k < s.step.size(); ++k)
      csv << std::int64_t(s.step[k]) << "," << s.mean_density[k] << "," << s.temperature[k] << "," << s.pressure[k]
          << "," << s.pressure_virial[k] << "," << s.pressure_dissipative[k] << "\n";
  }
  {
    std::ofstream csv(stem + "_rdf.csv");
    csv << "r,g\n" << std::setprecision(10);
    for (std::size_t b = 0; b < s.rdf.size(); ++b) csv << s.rdf_r[b] << "," << s.rdf[b] << "\n";
  }
  cli::Json j{{"driver", "pillars"}, {"mode", "bulk"}, {"dimension", D}, {"A", mp.A}, {"B", mp.B},
              {"r_B", mp.r_B}, {"R", mp.R}, {"dissipation", mp.dissipation()}, {"dt", mp.dt},
              {"density_kernel", par.density_kernel}, {"density_self_term", par.density_self_term},
              {"particles", sys.particles.size()}, {"number_density", run.number_density()},
              {"volume", run.volume()}, {"samples", s.step.size()}, {"sample_every", par.sample_every},
              {"seed", par.seed}};
  const auto add = [&](const std::string& name, const std::vector<double>& q) {
    double mean = 0, error = 0;
    analysis::block_average(q, mean, error);
    j[name] = mean;
    j[name + "_error"] = error;
  };
  add("mean_density", s.mean_density);
  add("temperature", s.temperature);
  add("pressure", s.pressure);
  add("pressure_virial", s.pressure_virial);
  add("pressure_dissipative", s.pressure_dissipative);
  j["rdf_max"] = run.rdf_max();
  j["components"] = sys.components();
  j["wall_seconds"] = wall_seconds;
  j["kokkos"] = kokkos_configuration();
  cli::write_summary(out.summary, j);
  if (!app.quiet())
    std::cerr << "pillars: <rho_bar> = " << j["mean_density"].get<double>() << " ± " << j["mean_density_error"].get<double>()
              << ", P = " << j["pressure"].get<double>() << " ± " << j["pressure_error"].get<double>()
              << ", k_BT = " << j["temperature"].get<double>() << "\n";
}

}  // namespace
}  // namespace mesoflow

int main(int argc, char** argv) {
  using mesoflow::cli::Bounds;
  mesoflow::Parameters par;
  mesoflow::cli::DriverApp app("MDPD flow through pillar arrays: permeability, Brinkman fits, viscosity (Soft Matter 19, 436)",
                               "pillars.h5");
  app.add_choice("--mode", par.mode,
                 "flow through pillars, the fluid's viscosity (periodic Poiseuille), the theory curves (CSV), or the fluid at rest (bulk: density, pressure, g(r))",
                 {"flow", "viscosity", "theory", "bulk"});
  app.add_int("--dimension", par.dimension, "2 (pillars only) or 3", 2, 3);
  app.add_choice("--layout", par.layout, "pillar arrangement",
                 {"square", "rotated-square", "hexagonal", "irregular", "file", "none"});
  app.add_string("--layout-file", par.layout_file, "pillar centres (CSV of pillar_layouts.hpp) for --layout file");
  app.add_real("--porosity", par.porosity, "porosity ε (regular and irregular layouts)", 0.0, 1.0, Bounds::open);
  app.add_real("--diameter", par.diameter, "pillar diameter d/σ", 1.0, 100.0);
  app.add_int("--cells-x", par.cells_x, "unit cells of a regular layout along the flow", 1, 1000);
  app.add_int("--cells-y", par.cells_y, "unit cells of a regular layout across the flow", 1, 1000);
  app.add_int("--pillars", par.pillars, "pillars of an irregular layout", 1, 100000);
  app.add_real("--aspect", par.aspect, "L_y/L_x of an irregular layout", 0.1, 10.0);
  app.add_real("--exclusion", par.exclusion, "Monte Carlo disc diameter / d (paper: 1.2)", 1.0, 2.0);
  app.add_int("--mc-sweeps", par.mc_sweeps, "hard-disc Monte Carlo sweeps of an irregular layout", 0, 1000000000LL);
  app.add_real("--height", par.height, "3D: wall separation H/σ (0: periodic in z)", 0.0, 100.0);
  app.add_real("--lz", par.lz, "3D box height without walls; viscosity mode: box edge along the gradient", 2.4, 1000.0);
  app.add_real("--box", par.box, "viscosity mode and --layout none: box edge L_x = L_y", 2.4, 1000.0);
  app.add_real("--fb", par.fb, "driving body force f_b (−1: 0.2 in 2D, 0.3 in 3D; viscosity mode: 0.5)", -1.0, 10.0);
  app.add_real("--driving-length", par.driving_length, "length L_d of the driving region", 0.0, 1000.0, Bounds::left_open);
  app.add_real("--viscosity", par.viscosity, "μ used for κ (−1: paper's 17.5 in 3D, 26.1 in 2D)", -1.0, 1000.0);
  app.add_real("--kappa-p", par.kappa_p, "pillar permeability κ_p (σ²) for Brinkman's μ_eff (0: none)", 0.0, 1e6);
  app.add_real("--bin-width", par.bin_width, "elevation bin width", 0.05, 10.0);
  app.add_int("--equilibrate-steps", par.equilibrate_steps, "steps of the quiescent fluid before carving", 0, 100000000LL);
  app.add_int("--warmup-steps", par.warmup_steps, "steps of driven flow before sampling", 0, 1000000000LL);
  app.add_int("--steps", par.steps, "production steps", 1, 1000000000LL);
  app.add_positive("--sample-every", par.sample_every, "steps between samples");
  app.add_real("--density", par.density, "number density ρ", 0.5, 20.0);
  app.add_real("--A", par.A, "attraction A (ε/σ)", -1000.0, 1000.0);
  app.add_real("--B", par.B, "repulsion B (−1: 25 in 3D, 30 in 2D)", -1.0, 1000.0);
  app.add_real("--r-B", par.r_B, "density cut-off r_B/σ", 0.1, 1.0);
  app.add_real("--R", par.R, "random-force strength R", 0.0, 1000.0);
  app.add_real("--dt", par.dt, "time step dt/τ (refused above the stability limit)", 0.0, 0.05, Bounds::left_open);
  app.add_flag(mesoflow::cli::force_dt_flag, par.force_dt, mesoflow::cli::force_dt_help);
  app.add_real("--k-S", par.k_S, "tether stiffness of solid particles", 0.0, 1e4);
  app.add_choice("--density-kernel", par.density_kernel, "many-body density weight (lucy: LAMMPS' mdpd/rhosum)",
                 {"normalized", "lucy"});
  app.add_choice("--density-self-term", par.density_self_term,
                 "add the self weight w(0) to every density (off: LAMMPS' mdpd/rhosum, which has none)",
                 {"off", "on"});
  app.add_real("--rdf-max", par.rdf_max, "bulk mode: g(r) range (at most half the shortest box edge)", 0.1, 100.0);
  app.add_real("--rdf-bin", par.rdf_bin, "bulk mode: g(r) bin width", 0.001, 1.0);
  app.add_int("--rdf-every", par.rdf_every, "bulk mode: samples between g(r) histograms (0: no g(r))", 0,
              1000000000LL);
  app.add_choice("--list", par.list, "neighbor list", {"half", "full"});
  app.add_int("--seed", par.seed, "random seed", 0, 4294967295LL);
  app.add_int("--threads", par.threads, "host threads (0: OMP_NUM_THREADS or all cores)", 0, 4096);
  app.add_int("--checkpoint-every", par.checkpoint_every, "flow mode: steps between checkpoints (<out>.ckpt.h5)", 1,
              1000000000LL);
  app.add_flag("--restart", par.restart, "flow mode: continue the interrupted run from <out>.ckpt.h5");
  app.add_int("--check-every", par.check_every,
              "steps between NaN-watchdog checks (a non-finite state stops the run, naming particle, term and step)",
              1, 1000000);
  return app.run(argc, argv, [&] {
    if (par.mode != "theory") {  // flow: tethered solids and WCA cores; viscosity: fluid only
      const auto limit = mesoflow::pillars::pillar_stability(par, par.dimension, par.mode == "flow");
      mesoflow::cli::check_time_step("pillars", par.dt, {limit.max_dt(), limit.limiting_term("τ")}, par.force_dt);
    }
    mesoflow::KokkosScope kokkos(par.threads);
    if (par.mode == "theory") {
      const std::string t = mesoflow::driver::OutputPaths(app.output()).trajectory;
      const std::string stem = t.substr(0, t.size() - 3);
      mesoflow::pillars::write_theory_tables(stem + "_theory.csv", stem + "_sangani_acrivos_table.csv");
      if (!app.quiet()) std::cerr << "pillars: wrote " << stem << "_theory.csv\n";
    }
    else if (par.mode == "bulk")
      par.dimension == 2 ? mesoflow::run_bulk<2>(par, app) : mesoflow::run_bulk<3>(par, app);
    else if (par.mode == "viscosity")
      par.dimension == 2 ? mesoflow::run_viscosity<2>(par, app) : mesoflow::run_viscosity<3>(par, app);
    else
      par.dimension == 2 ? mesoflow::run_flow<2>(par, app) : mesoflow::run_flow<3>(par, app);
  });
}
