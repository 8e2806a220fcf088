// capsule — a microcapsule (SPH fluid + mass-spring membrane, the Discrete Multi-Physics model)
// through a constriction, and in simple shear: Rahmat et al., sph-microcapsules-constriction.
//
// Units, the membrane's k_b from Ca, c0 of eq. (6), the flow control and the step that follows the
// state: scenes/capsule/capsule_runs.hpp; the scene: scenes/capsule/capsule_scene.hpp; the record
// of a constriction run: scenes/capsule/capsule_record.hpp.
//
// --mode constriction (§3, Fig. 1; §4.2–§5): the 7d × 2d × 2d channel (periodic in x; walls in y and
//   z; constriction x ∈ [3d, 5d) of width t_c = η d in y), the capsule centred in the inlet at
//   x = 1.5d, the flow held at U in the constriction. Measured every --sample-every: x_c, D_∞,x,
//   D_∞,y, D_∞,z, C_f, C_r (analysis/capsule/capsule_shape.hpp), g, P_x/P*, max |ρ − ρ0|/ρ0. Passage
//   time: from the front reaching the constriction (x = 3d) to the rear leaving it (x = 5d). The run
//   ends when x_c reaches 6d, at --t-max, or when the capsule stalls (its centroid moves less than
//   0.01d in --stall-window after its front entered). A sweep (--ca and --eta lists) runs every pair
//   and tabulates, per run, 1/t_pass, D_∞,Λ at x_c = 4 and C_f, C_r at x_c = 3.5, 4, 4.5, and per η
//   Pearson's r of each against Ca (eq. 17, Table 1).
// --mode shear (§4.1): the capsule in a 5d × 4d × 4d box (--shear-box), walls bounding y sliding at
//   ∓V; D_xy and the inclination θ/π, steady values averaged over the last 30% of --t-max.
// --mode moduli: no run; <out>.json holds the membrane's moduli per k_b (the network's G_s and K_A,
//   measured on a patch at the mesh's h_t/δ_ave, and §4's formula) and how Ca converts between the two
//   definitions (--shear-modulus; issue 29 item 1). Every run's summary carries the same block.
//
// Output, for --output <out>.h5: per run <out>_ca<Ca>_eta<η>.h5 (H5MD: the membrane's positions
// every --frame-every, the measures as observables, the parameters) with its .xdmf, _series.csv
// and _sections.csv (the xy mid-plane outline at x_c = 2, 3, 3.5, 4, 4.5, 5, 5.5); <out>_sweep.csv
// (one row per run), <out>.json (summary, Pearson table), <out>.png (measures against x_c) and
// <out>_snapshot.png (outlines in the channel). Shear: per Ca <out>_shear_ca<Ca>_series.csv, and
// <out>_shear.csv and <out>_shear.png. A run's row is also kept in <out>_ca<Ca>_eta<η>_result.csv
// (shear: <out>_shear_ca<Ca>_result.csv), written then renamed; with --restart a sweep reuses the
// finished runs whose scene matches and runs only the rest (an interrupted run starts over).
//
// NaN watchdog (CapsuleScene::watched(); the constriction's controller and its body force are part
// of the watched step) every --check-every steps and before every sample; a non-finite value, or the
// divergence guard (|ρ − ρ0|/ρ0 > 1 at a sample), stops the run with exit status 1, naming what it
// found, before anything is written from that state: the run's _result.csv, the sweep table and the
// summary are not written.
#include "analysis/capsule/capsule_shape.hpp"
#include "analysis/capsule/sweep_results.hpp"
#include "drivers/common/cli.hpp"
#include "drivers/common/json_summary.hpp"
#include "drivers/common/output_paths.hpp"
#include "drivers/common/progress.hpp"
#include "kernels/common/kokkos_compat.hpp"
#include "scenes/capsule/capsule_record.hpp"
#include "scenes/capsule/capsule_runs.hpp"

#include <chrono>
#include <iostream>
#include <sstream>

namespace mesoflow {
namespace {

struct Parameters : capsule::CapsuleRunParameters {
  std::string ca = "0.25";
  std::string eta = "0.5";
  int threads = 0;
  bool restart = false;
};

capsule::RunResult run_constriction(const Parameters& par, const cli::DriverApp& app, const std::string& stem,
                                    double ca, double eta) {
  const bool quiet = app.quiet();
  capsule::ConstrictionRun<> run(par, ca, eta, quiet);
  const auto& scene = run.scene();
  const auto& phys = run.physical();
  const double d = par.resolution, dt = run.start_dt();
  const std::string name = stem + "_ca" + driver::tag(ca) + "_eta" + driver::tag(eta);
  capsule::RunResult r;
  r.ca = ca;
  r.eta = eta;
  r.eta_effective = run.channel().constriction_width / d;
  r.dt = dt / d;
  r.c0 = phys.c0;
  r.k_b = phys.k_b;
  r.particles = scene.num_particles();
  r.series_csv = name + "_series.csv";
  r.sections_csv = name + "_sections.csv";
  r.signature = capsule::scene_signature(par, ca, eta);

  capsule::ConstrictionRecord<> record(run, name, ca, eta, app.resolved_parameters());
  struct Output {  // the measures of each sample (analysis/capsule/capsule_shape.hpp), recorded
    const capsule::ConstrictionRun<>& run;
    capsule::ConstrictionRecord<>& record;
    cli::ProgressLine progress_line;
    void progress(long step) { progress_line.update(step); }
    void sample(const capsule::ConstrictionSample& s) {
      const double d = run.physical().d, a = run.physical().a;
      const auto m = capsule::sample_shape(s.y, run.scene().mesh().triangle, s.x_c, d, a);
      record.add(s, m.D, m.cf, m.cr, m.section);
    }
  } out{run, record, cli::ProgressLine(run.max_steps(), scene.num_particles(), !quiet)};
  const auto t0 = std::chrono::steady_clock::now();
  r.status = run.run(out);
  out.progress_line.finish();
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.steps = double(run.steps());
  run.governor().report(dt);
  r.max_density_deviation = run.max_density_deviation();
  r.particle_steps_per_second = r.steps * scene.num_particles() / r.wall_seconds;
  capsule::set_passage(r, run.entry_time(), run.exit_time());
  capsule::set_values_at(r, record.xs, record.dx_s, record.dy_s, record.dz_s, record.cf_s, record.cr_s);
  record.write_xdmf(name + ".xdmf");
  driver::write_atomically(name + "_result.csv", std::string(capsule::sweep_header) + "\n" + capsule::csv_row(r) + "\n");
  if (!quiet)
    std::cerr << "capsule: Ca " << ca << ", eta " << eta << " (effective " << r.eta_effective << "): " << r.status
              << ", passage time " << r.passage_time << " d/U, Dx(4) " << r.Dx4 << ", max |drho|/rho0 "
              << r.max_density_deviation << ", " << r.particle_steps_per_second << " particle-steps/s\n";
  return r;
}

// The membrane's moduli per unit k_b and how the two definitions of Ca convert (issue 29 item 1):
// Ca_paper = Ca_network · G_s,network/G_s,paper at the same k_b.
cli::Json membrane_summary(const Parameters& par) {
  const auto m = capsule::membrane_moduli_per_bond(par);
  return cli::Json{{"shear_modulus_definition", par.shear_modulus},
                   {"thickness_over_spacing", m.thickness_over_spacing},
                   {"shear_modulus_network_over_k_b", m.shear_network},
                   {"area_modulus_network_over_k_b", m.area_network},
                   {"shear_modulus_paper_formula_over_k_b", m.shear_paper},
                   {"ca_paper_formula_over_ca_network", m.shear_network / m.shear_paper}};
}

// --mode moduli: the membrane block alone, with the formula's inputs, for docs and scripts.
void moduli_summary(const Parameters& par, const cli::DriverApp& app) {
  const driver::OutputPaths out(app.output());
  const auto m = capsule::membrane_moduli_per_bond(par);
  cli::Json j{{"driver", "capsule"}, {"mode", "moduli"}, {"resolution", par.resolution}, {"thickness", par.thickness},
              {"level", par.level}, {"diagonals", par.diagonals}, {"membrane", membrane_summary(par)},
              {"kokkos", kokkos_configuration()}};
  cli::write_summary(out.summary, j);
  if (!app.quiet())
    std::cerr << "capsule moduli: h_t/delta_ave " << m.thickness_over_spacing << ", network G_s " << m.shear_network
              << " k_b, K_A " << m.area_network << " k_b; paper formula G_s " << m.shear_paper
              << " k_b; Ca(formula) = " << m.shear_network / m.shear_paper << " Ca(network)\n";
}

void constriction_sweep(const Parameters& par, const cli::DriverApp& app) {
  const driver::OutputPaths out(app.output());
  const std::string stem = out.trajectory.substr(0, out.trajectory.size() - 3);
  const auto cas = cli::parse_number_list_in(par.ca, "--ca", 0.0, 100.0);
  const auto etas = cli::parse_number_list_in(par.eta, "--eta", 0.0, 2.0);
  std::vector<capsule::RunResult> results;
  for (double eta : etas)
    for (double ca : cas) {
      const std::string run = stem + "_ca" + driver::tag(ca) + "_eta" + driver::tag(eta);
      const auto done = par.restart ? capsule::read_result(run + "_result.csv") : std::nullopt;
      if (done && done->signature == capsule::scene_signature(par, ca, eta)) {
        if (!app.quiet()) std::cerr << "capsule: reusing the finished run " << run << "\n";
        results.push_back(*done);
        continue;
      }
      run_constriction(par, app, stem, ca, eta);
      // The row as written (8 significant digits), as a reused run reads it: a sweep's table and
      // Pearson r come out the same whether its runs were made now or reused with --restart.
      const auto written = capsule::read_result(run + "_result.csv");
      if (!written) throw std::runtime_error("capsule: cannot read back " + run + "_result.csv");
      results.push_back(*written);
    }
  driver::write_atomically(stem + "_sweep.csv", capsule::sweep_table(results));

  // Pearson's r against Ca per η (eq. 17, Table 1).
  cli::Json j{{"driver", "capsule"}, {"mode", "constriction"}, {"resolution", par.resolution},
              {"reynolds", par.reynolds}, {"runs", results.size()}, {"kokkos", kokkos_configuration()}};
  j["membrane"] = membrane_summary(par);
  j["pearson_r"] = cli::Json::array();
  for (const auto& [eta, columns] : capsule::pearson_table(results, etas)) {
    cli::Json row{{"eta", eta}};
    for (const auto& [name, r] : columns) row[name] = cli::summary_number(r);
    j["pearson_r"].push_back(row);
  }
  cli::write_summary(out.summary, j);
  driver::plot_with_matplotlib("capsule", "plot_capsule.py", {"constriction", stem + "_sweep.csv", stem + ".png",
                                                               stem + "_snapshot.png"},
                               stem + ".png", app.quiet());
}

void shear_runs(const Parameters& par, const cli::DriverApp& app) {
  const driver::OutputPaths out(app.output());
  const std::string stem = out.trajectory.substr(0, out.trajectory.size() - 3);
  const auto cas = cli::parse_number_list_in(par.ca, "--ca", 0.0, 100.0);
  std::ostringstream table;
  table << capsule::shear_header << "\n";
  for (double ca : cas) {
    const std::string name = stem + "_shear_ca" + driver::tag(ca);
    const std::string signature = capsule::shear_signature(par, ca);
    // --restart: reuse a finished run of the same scene
    const auto done = par.restart ? capsule::read_shear_result(name + "_result.csv", signature) : std::nullopt;
    if (done) {
      if (!app.quiet()) std::cerr << "capsule: reusing the finished run " << name << "\n";
      table << *done << "\n";
      continue;
    }
    capsule::ShearRun<> run(par, ca, app.quiet());
    struct Output {  // the shape of each sample (analysis/capsule/sweep_results.hpp), in the series
      cli::ProgressLine progress_line;
      capsule::ShearSeries series;
      void progress(long step) { progress_line.update(step); }
      void sample(double t, const std::vector<Eigen::Vector3d>& y, double dens, double dt_gamma) {
        series.add(t, y, dens, dt_gamma);
      }
    } o{cli::ProgressLine(run.max_steps(), run.scene().num_particles(), !app.quiet()),
        capsule::ShearSeries(name + "_series.csv")};
    const auto t0 = std::chrono::steady_clock::now();
    run.run(o);
    o.progress_line.finish();
    run.governor().report(run.start_dt());
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const auto [D, T] = o.series.steady_values(0.7 * par.t_max);  // the last 30% of the run
    const std::string row =
        capsule::shear_row(ca, D, T, run.start_dt() * run.physical().shear_rate, par.t_max, run.scene().num_particles(),
                           run.max_density_deviation(), wall, name + "_series.csv", signature);
    driver::write_atomically(name + "_result.csv", std::string(capsule::shear_header) + "\n" + row + "\n");
    table << row << "\n";
    if (!app.quiet())
      std::cerr << "capsule shear: Ca " << ca << ": D_xy = " << D.mean << ", theta/pi = " << T.mean << " (" << wall
                << " s)\n";
  }
  driver::write_atomically(stem + "_shear.csv", table.str());
  cli::write_summary(out.summary, cli::Json{{"driver", "capsule"}, {"mode", "shear"}, {"resolution", par.resolution},
                                            {"reynolds", par.reynolds}, {"runs", cas.size()},
                                            {"membrane", membrane_summary(par)}, {"kokkos", kokkos_configuration()}});
  driver::plot_with_matplotlib("capsule", "plot_capsule.py", {"shear", stem + "_shear.csv", stem + "_shear.png"},
                               stem + "_shear.png", app.quiet());
}

}  // namespace
}  // namespace mesoflow

int main(int argc, char** argv) {
  using mesoflow::cli::Bounds;
  mesoflow::Parameters par;
  mesoflow::cli::DriverApp app("SPH microcapsule through a constriction, or in simple shear (DMP: SPH + mass-spring membrane)",
                               "capsule.h5");
  app.add_choice("--shear-modulus", par.shear_modulus,
                 "G_s in Ca: network (measured on a patch of this membrane network) or paper (E h_t/(2(1+nu)), "
                 "E = 5 k_b/(sqrt(3) delta), nu = 1/4)",
                 {"network", "paper"});
  app.add_choice("--mode", par.mode,
                 "constriction (§3-§5), shear (§4.1 validation) or moduli (the membrane's G_s and K_A only, no run)",
                 {"constriction", "shear", "moduli"});
  app.add_int("--resolution", par.resolution, "lattice spacings per capsule diameter d (paper: 56)", 6, 128);
  app.add_string("--ca", par.ca, "capillary number(s) Ca = mu U a/G_s, comma-separated, each in (0, 100]")
      ->check(mesoflow::cli::number_list_check("--ca", 0.0, 100.0));
  app.add_string("--eta", par.eta, "constriction mode: width(s) eta = t_c/d, comma-separated, each in (0, 2]")
      ->check(mesoflow::cli::number_list_check("--eta", 0.0, 2.0));
  app.add_real("--reynolds", par.reynolds, "Re = rho U d/mu (shear: rho gamma a^2/mu)", 1e-3, 100.0);
  app.add_real("--thickness", par.thickness, "membrane thickness h_t / lattice spacing", 0.25, 4.0);
  app.add_int("--level", par.level, "icosphere subdivisions of the membrane (paper: 4)", 1, 5);
  app.add_choice("--diagonals", par.diagonals,
                 "inter-layer diagonals: one per quad (the paper's counts) or both (its E and nu exactly)",
                 {"one", "both"});
  app.add_real("--support", par.support, "Lucy kernel support h / lattice spacing", 1.5, 4.0);
  app.add_choice("--walls", par.walls, "wall velocity seen by the fluid: morris (no slip) or prescribed (the paper's)",
                 {"morris", "prescribed"});
  app.add_real("--viscosity-ratio", par.viscosity_ratio, "inner/outer viscosity", 0.01, 100.0);
  app.add_flag("--deterministic", par.deterministic,
               "deterministic sums: full neighbor lists (each particle sums its own forces), bitwise the same on "
               "every backend and thread count (docs/design.md; about twice the pair work)");
  app.add_real("--c0", par.c0, "sound speed of eq. (6) in units of U (0: the rule of the file comment)", 0.0, 1e4);
  app.add_real("--density-variation", par.density_variation,
               "target density variation delta of c0's rule (paper: below 1%)", 1e-4, 0.1);
  app.add_real("--membrane-strain", par.membrane_strain, "membrane strain for c0's pressure-jump criterion", 0.0, 1.0,
               Bounds::left_open);
  app.add_real("--t-max", par.t_max, "run length limit, d/U (shear: gamma t)", 0.0, 1e4, Bounds::left_open);
  app.add_real("--sample-every", par.sample_every, "sampling interval, d/U (shear: gamma t)", 0.0, 10.0,
               Bounds::left_open);
  app.add_real("--frame-every", par.frame_every, "constriction mode: membrane trajectory frame interval, d/U", 0.0, 100.0,
               Bounds::left_open);
  app.add_real("--stall-window", par.stall_window, "constriction mode: blocked when the centroid moves < 0.01 d over this time, d/U", 0.0, 1e3,
               Bounds::left_open);
  app.add_real("--shear-box-x", par.shear_box_x, "shear mode: box along the flow, in d", 2.0, 20.0);
  app.add_real("--shear-box-y", par.shear_box_y, "shear mode: box across (wall to wall), in d", 1.5, 20.0);
  app.add_real("--shear-box-z", par.shear_box_z, "shear mode: box along the vorticity, in d", 1.5, 20.0);
  app.add_real("--dt", par.dt, "time step, d/U (shear: 1/gamma); 0: the stability limit, larger is refused", 0.0, 1.0);
  app.add_flag(mesoflow::cli::force_dt_flag, par.force_dt, mesoflow::cli::force_dt_help);
  app.add_int("--threads", par.threads, "host threads (0: OMP_NUM_THREADS or all cores)", 0, 4096);
  app.add_flag("--restart", par.restart, "reuse the finished runs (Ca, eta) of the same scene");
  app.add_int("--check-every", par.check_every,
              "steps between NaN-watchdog checks (a non-finite state stops the run, naming particle, term and step)",
              1, 1000000);
  return app.run(argc, argv, [&] {
    par.validate();  // the options' ranges again, as the Python module checks them (one rule)
    mesoflow::KokkosScope kokkos(par.threads);
    if (par.mode == "moduli")
      mesoflow::moduli_summary(par, app);
    else if (par.mode == "shear")
      mesoflow::shear_runs(par, app);
    else
      mesoflow::constriction_sweep(par, app);
  });
}
