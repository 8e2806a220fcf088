// calibrate — fits the DP model's line tension Γ and near-wall drag b0/b∞ to a measured speed
// profile of a droplet passing a narrow orifice (capillary-droplets §4.1, Fig. 2–3): minimises the
// RMS relative speed deviation Δ_v of eq. 14 over simulated passages (orifice_run.hpp), with the
// simulated speed interpolated linearly between frames at each measured h. b∞ is set by the
// terminal speed V_t (eq. 15), the orifice width and droplet resolution by the user.
//
// Units (§2.2): length σ (undeformed droplet diameter), acceleration g, areal mass density ρ;
// time t0 = √(σ/g). The measured CSV gives h/σ (distance of the centre of mass past the orifice,
// negative before it) and v_g/v_t in columns `h` and `vg_over_vt` (an `orifice` profile CSV works).
//
// Method (analysis/droplets/profile_calibration.hpp, over passages of scenes/droplets/orifice_run.hpp
// with the trial Γ, b0/b∞ and K_l/Γ held): a grid of --grid-points per fitted parameter over
// [--gamma-min, --gamma-max] × [--drag-min, --drag-max] (log-spaced), then Nelder–Mead in
// (ln Γ, ln b0/b∞) to --tolerance; --max-evaluations orifice passages at most.
//
// Output (<out> = --output without its extension): <out>.csv (every evaluation: Γ, b0/b∞, Δ_v,
// outcome, seconds), <out>.best.csv (the best-fit simulated profile, as the orifice driver writes
// it), <out>.json (best Γ, b0/b∞, Δ_v, convergence), <out>.png (measured and best-fit v_g/v_t
// against h; --no-plot skips it).
#include "drivers/common/cli.hpp"
#include "drivers/common/json_summary.hpp"
#include "drivers/common/output_paths.hpp"
#include "analysis/droplets/profile_calibration.hpp"
#include "scenes/droplets/orifice_run.hpp"

#include <chrono>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <optional>

namespace mesoflow {
namespace {

struct Parameters {
  droplets::OrificeScene scene = [] {
    droplets::OrificeScene s;  // first guess and scene: the Fig. 3(d) experiment at N_v = 64
    s.droplet.vertices = 64;
    s.droplet.line_tension = 1.0;
    s.droplet.near_wall_drag = 0.1;
    s.droplet.terminal_speed = 0.032;
    s.width = 0.7;
    s.start_h = -1.5;
    return s;
  }();
  std::string measured;
  std::string fit = "both";
  droplets::CalibrationBounds bounds;
  droplets::SimplexSettings simplex;
  int grid_points = 5;
  double perimeter_ratio = 1e-3;  // K_l/Γ (App. B)
  int threads = 0;
  bool no_plot = false;
};

void run(Parameters par, const cli::DriverApp& app) {
  par.bounds.validate();
  if (par.measured.empty()) throw std::invalid_argument("--measured: the measured profile CSV (h, vg_over_vt) is required");
  const auto measured = droplets::read_measured_profile(par.measured);
  auto& d = par.scene.droplet;
  d.perimeter_stiffness = par.perimeter_ratio * d.line_tension;
  par.scene.validate();
  droplets::resolve_time_step(d, true);
  const droplets::FitParameters fit = par.fit == "both"    ? droplets::FitParameters::both
                                      : par.fit == "gamma" ? droplets::FitParameters::line_tension
                                                           : droplets::FitParameters::near_wall_drag;
  const driver::OutputPaths out(app.output());
  const std::string stem = out.csv.substr(0, out.csv.size() - 4);
  std::ofstream history(out.csv);
  if (!history) throw std::runtime_error("cannot write " + out.csv);
  history << std::setprecision(10) << "evaluation,line_tension,near_wall_drag,speed_deviation,outcome,seconds\n";
  int count = 0;
  const auto start = std::chrono::steady_clock::now();
  // One orifice passage per trial Γ and/or b0/b∞ (the other at its --gamma / --near-wall-drag).
  const auto passage = [&](std::optional<double> line_tension, std::optional<double> near_wall_drag) {
    return droplets::run_orifice(droplets::calibration_scene(par.scene, line_tension, near_wall_drag));
  };
  const auto result = droplets::calibrate(measured, passage, {d.line_tension, d.near_wall_drag}, d.terminal_speed,
                                          fit, par.bounds, par.simplex, par.grid_points,
                                          [&](const auto& e) {
                                            history << ++count << ',' << e.line_tension << ',' << e.near_wall_drag
                                                    << ',' << e.speed_deviation << ',' << to_string(e.outcome) << ','
                                                    << e.seconds << '\n'
                                                    << std::flush;
                                            if (!app.quiet())
                                              std::cerr << "calibrate: " << count << ": Γ = " << e.line_tension
                                                        << ", b0/b∞ = " << e.near_wall_drag
                                                        << ": Δ_v = " << e.speed_deviation << " ("
                                                        << to_string(e.outcome) << ", " << e.seconds << " s)\n";
                                          });
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  {
    const auto& prof = result.best_profile;
    std::ofstream best(stem + ".best.csv");
    best << std::setprecision(10) << "t,h,vg_over_vt,shape_parameter,area_over_a0,kinetic_over_terminal\n";
    for (std::size_t i = 0; i < prof.t.size(); ++i)
      best << prof.t[i] << ',' << prof.h[i] << ',' << prof.vg[i] / d.terminal_speed << ',' << prof.shape[i] << ','
           << prof.area[i] << ',' << prof.kinetic[i] << '\n';
  }
  cli::write_summary(out.summary, cli::Json{{"driver", "calibrate"},
                                             {"measured", par.measured},
                                             {"frames", measured.h.size()},
                                             {"fit", par.fit},
                                             {"line_tension", result.line_tension},
                                             {"near_wall_drag", result.near_wall_drag},
                                             {"speed_deviation", cli::summary_number(result.speed_deviation)},
                                             {"converged", result.converged},
                                             {"evaluations", result.history.size()},
                                             {"wall_seconds", wall},
                                             {"kokkos", kokkos_configuration()}});
  if (!par.no_plot)
    driver::plot_with_matplotlib("calibrate", "plot_orifice_profile.py",
                                 {stem + ".best.csv", stem + ".png", "--label", "best fit", "--compare", par.measured,
                                  "measured"},
                                 stem + ".png", app.quiet());
  if (!app.quiet())
    std::cout << "calibrate: Γ = " << result.line_tension << ", b0/b∞ = " << result.near_wall_drag
              << ", Δ_v = " << result.speed_deviation << " after " << result.history.size() << " orifice runs in "
              << wall << " s" << (result.converged ? "" : " (not converged to --tolerance)") << "\n";
}

}  // namespace
}  // namespace mesoflow

int main(int argc, char** argv) {
  using mesoflow::cli::Bounds;
  mesoflow::Parameters par;
  auto& s = par.scene;
  auto& d = s.droplet;
  mesoflow::cli::DriverApp app(
      "Fit line tension Gamma and near-wall drag b0/b_inf of the DP droplet model to a measured speed profile "
      "v_g(h) at an orifice (capillary-droplets paper, sec. 4.1, eq. 14; units sigma, g, rho)",
      "calibrate.csv");
  app.add_string("--measured", par.measured, "measured profile CSV with columns h (σ) and vg_over_vt (required)");
  app.add_choice("--fit", par.fit, "parameters to fit (the other stays at its --gamma / --near-wall-drag)",
                 {"both", "gamma", "drag"});
  app.add_real("--gamma", d.line_tension, "line tension Γ: held value (--fit drag)", 0.0, 1000.0, Bounds::left_open);
  app.add_real("--near-wall-drag", d.near_wall_drag, "near-wall drag b0/b∞: held value (--fit gamma)", 0.0, 100.0);
  app.add_real("--gamma-min", par.bounds.gamma_min, "smallest Γ searched", 0.0, 1000.0, Bounds::left_open);
  app.add_real("--gamma-max", par.bounds.gamma_max, "largest Γ searched", 0.0, 1000.0, Bounds::left_open);
  app.add_real("--drag-min", par.bounds.drag_min, "smallest b0/b∞ searched", 0.0, 100.0, Bounds::left_open);
  app.add_real("--drag-max", par.bounds.drag_max, "largest b0/b∞ searched", 0.0, 100.0, Bounds::left_open);
  app.add_int("--grid-points", par.grid_points, "grid points per fitted parameter before the simplex (1: none)", 1, 50);
  app.add_int("--max-evaluations", par.simplex.max_evaluations, "orifice passages at most (grid included)", 1, 100000);
  app.add_real("--tolerance", par.simplex.x_tolerance, "simplex stops at this relative spread of the parameters", 0.0,
               1.0, Bounds::left_open);
  app.add_real("--width", s.width, "orifice width w/σ", 0.0, 10.0, Bounds::left_open);
  app.add_real("--terminal-speed", d.terminal_speed, "dimensionless terminal speed V_t (eq. 15), sets b∞", 0.0, 100.0,
               Bounds::left_open);
  app.add_int("--vertices", d.vertices, "vertices per droplet N_v (the paper: 256)", 8, 65536);
  app.add_real("--area-stiffness", d.area_stiffness, "area compressibility K_a", 0.0, 1e9);
  app.add_real("--perimeter-ratio", par.perimeter_ratio, "perimeter elasticity over line tension K_l/Γ", 0.0, 10.0);
  app.add_real("--wall-energy", d.wall_energy, "wall repulsion E_w (eq. 3)", 0.0, 1e8);
  app.add_real("--vertex-diameter", d.vertex_diameter, "vertex diameter δ/l0 (eq. 3)", 0.0, 10.0, Bounds::left_open);
  app.add_real("--start-h", s.start_h, "initial h/σ of the centre of mass", -1000.0, -1.0);
  app.add_real("--end-h", s.end_h, "a passage ends once h/σ reaches this", 0.0, 100.0, Bounds::left_open);
  app.add_real("--max-time", s.max_time, "time limit of one passage t/t0", 0.0, 1e7, Bounds::left_open);
  app.add_real("--sample-interval", s.sample_interval, "time between simulated frames /t0", 0.0, 100.0,
               Bounds::left_open);
  app.add_int("--threads", par.threads, "host threads (0: OMP_NUM_THREADS or all cores)", 0, 4096);
  app.add_flag("--no-plot", par.no_plot, "do not write the PNG plot");
  return app.run(argc, argv, [&] {
    mesoflow::KokkosScope kokkos(par.threads);
    mesoflow::run(par, app);
  });
}
