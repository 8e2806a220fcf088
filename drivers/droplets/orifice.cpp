// orifice — one capillary droplet (deformable polygon) falling through a narrow orifice
// (capillary-droplets §2.1, §4.1, Fig. 1a): the speed v_g(h) and shape parameter 𝒜(h) of the
// droplet against its distance h from the orifice. The default scene is the paper's Fig. 2:
// w = 0.4σ, Γ = 0.16, b0/b∞ = 0.064, V_t = 0.08, N_v = 256, K_a = 10⁴, K_l/Γ = 10⁻³.
//
// Units (§2.2): length σ (undeformed droplet diameter), acceleration g, areal mass density ρ;
// time t0 = √(σ/g); so a0 = πσ²/4, M = π/4, speeds in σ/t0 and the terminal speed v_t = V_t
// (eq. 15). The dimensionless Γ, K_a, K_l, E_w, b0/b∞, V_t are the paper's.
// Deviations from the paper, measured in docs/droplets.md: E_w = 0.05 instead of 10⁴ (the paper's
// value with vertex diameter δ = l0 is beyond the explicit stability limit at Δt = 10⁻³ t0);
// Δt = min(10⁻³ t0, stability limit) unless --dt is given (refused above the limit).
//
// Output (<out> = --output without its extension): <out>.h5 (H5MD: droplet vertex positions and
// velocities every --frame-every samples; observables h, v_g, 𝒜, a/a0, E_k/E_t; parameters as
// attributes), <out>.xdmf (ParaView), <out>.csv (the profile: t, h, v_g/v_t, 𝒜, a/a0, E_k/E_t),
// <out>.json (outcome and summary), <out>.png (v_g/v_t and 𝒜 against h; --no-plot skips it).
#include "drivers/common/cli.hpp"
#include "drivers/common/json_summary.hpp"
#include "drivers/common/output_paths.hpp"
#include "drivers/common/particle_io.hpp"
#include "drivers/common/progress.hpp"
#include "scenes/droplets/orifice_run.hpp"

#include <algorithm>
#include <chrono>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <optional>

namespace mesoflow {
namespace {

struct Parameters {
  droplets::OrificeScene scene;
  double perimeter_ratio = 1e-3;  // K_l/Γ (App. B)
  long long frame_every = 20;     // samples between trajectory frames
  int threads = 0;
  bool no_plot = false;
};

// The profile CSV: one row per sample.
void write_profile_csv(const std::string& path, const droplets::OrificeProfile& prof, double vt) {
  std::ofstream csv(path);
  if (!csv) throw std::runtime_error("cannot write " + path);
  csv << std::setprecision(10) << "t,h,vg_over_vt,shape_parameter,area_over_a0,kinetic_over_terminal\n";
  for (std::size_t i = 0; i < prof.t.size(); ++i)
    csv << prof.t[i] << ',' << prof.h[i] << ',' << prof.vg[i] / vt << ',' << prof.shape[i] << ',' << prof.area[i]
        << ',' << prof.kinetic[i] << '\n';
}

void run(const Parameters& par, const cli::DriverApp& app) {
  const driver::OutputPaths out(app.output());
  droplets::OrificeScene scene = par.scene;
  scene.droplet.perimeter_stiffness = par.perimeter_ratio * scene.droplet.line_tension;
  const double vt = scene.droplet.terminal_speed;
  scene.validate();
  droplets::resolve_time_step(scene.droplet, true);  // refuses a --dt above the stability limit before any output

  std::optional<io::H5mdWriter> h5;
  h5.emplace(out.trajectory, "mesoflow", MESOFLOW_VERSION, "mesoflow orifice");
  for (const auto& [key, value] : app.resolved_parameters()) h5->set_parameter(key, value);
  h5->set_parameter("perimeter_stiffness", scene.droplet.perimeter_stiffness);
  const double half = 2.0 + std::abs(scene.start_h) + scene.end_h;
  const double lo[2] = {-half, -scene.end_h - 1.0}, len[2] = {2 * half, half + scene.end_h + 1.0};
  const bool periodic[2] = {false, false};
  driver::add_particles_group(*h5, "droplet", std::size_t(scene.droplet.vertices), Box<2, double>(lo, len, periodic));

  const long long total_samples = std::llround(scene.max_time / scene.sample_interval) + 1;
  cli::ProgressLine progress(total_samples, scene.droplet.vertices, !app.quiet());
  long long samples = 0;
  const auto wall_start = std::chrono::steady_clock::now();
  const auto prof = droplets::run_orifice(scene, [&](const auto& s, const droplets::OrificeProfile& p) {
    const std::int64_t step = s.steps();
    const double t = s.time();
    h5->append_observable("h", step, t, p.h.back());
    h5->append_observable("vg", step, t, p.vg.back());
    h5->append_observable("shape_parameter", step, t, p.shape.back());
    h5->append_observable("area_over_a0", step, t, p.area.back());
    h5->append_observable("kinetic_over_terminal", step, t, p.kinetic.back());
    if (samples % par.frame_every == 0) driver::write_frame(*h5, "droplet", step, t, s.particles());
    progress.update(++samples);
  });
  progress.finish();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  h5->set_parameter("dt_used", prof.dt);
  h5->set_parameter("outcome", droplets::to_string(prof.outcome));
  h5->write_xdmf(out.xdmf);
  h5.reset();
  write_profile_csv(out.csv, prof, vt);

  // Summary: outcome, extreme speeds before and after the orifice, largest deformation.
  double vmin_before = HUGE_VAL, vmax_after = 0, shape_max = 0;
  for (std::size_t i = 0; i < prof.t.size(); ++i) {
    if (prof.h[i] > -0.5 && prof.h[i] < 0) vmin_before = std::min(vmin_before, prof.vg[i] / vt);
    if (prof.h[i] > 0) vmax_after = std::max(vmax_after, prof.vg[i] / vt);
    shape_max = std::max(shape_max, prof.shape[i]);
  }
  cli::write_summary(out.summary, cli::Json{{"driver", "orifice"},
                                             {"outcome", droplets::to_string(prof.outcome)},
                                             {"time", prof.t.back()},
                                             {"final_h", prof.h.back()},
                                             {"dt", prof.dt},
                                             {"steps", prof.steps},
                                             {"min_vg_over_vt_before_orifice", std::isfinite(vmin_before) ? vmin_before : 0.0},
                                             {"max_vg_over_vt_after_orifice", vmax_after},
                                             {"max_shape_parameter", shape_max},
                                             {"free_area_over_a0", prof.free_area},
                                             {"max_area_error", prof.max_area_error},
                                             {"wall_seconds", wall},
                                             {"steps_per_second", wall > 0 ? prof.steps / wall : 0.0},
                                             {"components", prof.components},
                                             {"kokkos", kokkos_configuration()}});
  if (!par.no_plot) {
    const std::string png = out.csv.substr(0, out.csv.size() - 4) + ".png";
    driver::plot_with_matplotlib("orifice", "plot_orifice_profile.py", {out.csv, png}, png, app.quiet());
  }
  if (!app.quiet())
    std::cout << "orifice: " << droplets::to_string(prof.outcome) << " at t = " << prof.t.back() << " t0, h = "
              << prof.h.back() << "σ; max 𝒜 = " << shape_max << ", max v_g/v_t after the orifice = " << vmax_after
              << "; " << prof.steps << " steps of Δt = " << prof.dt << " in " << wall << " s\n";
}

}  // namespace
}  // namespace mesoflow

int main(int argc, char** argv) {
  using mesoflow::cli::Bounds;
  mesoflow::Parameters par;
  auto& d = par.scene.droplet;
  mesoflow::cli::DriverApp app(
      "A capillary droplet (deformable polygon) through a narrow orifice: v_g(h) and shape parameter(h) "
      "(capillary-droplets paper, Fig. 2-4; units sigma, g, rho, t0 = sqrt(sigma/g))",
      "orifice.h5");
  app.add_real("--width", par.scene.width, "orifice width w/σ", 0.0, 10.0, Bounds::left_open);
  app.add_real("--gamma", d.line_tension, "dimensionless line tension Γ", 0.0, 1000.0, Bounds::left_open);
  app.add_real("--near-wall-drag", d.near_wall_drag, "near-wall drag ratio b0/b∞ (eq. 6)", 0.0, 100.0);
  app.add_real("--terminal-speed", d.terminal_speed, "dimensionless terminal speed V_t (eq. 15)", 0.0, 100.0,
               Bounds::left_open);
  app.add_int("--vertices", d.vertices, "vertices per droplet N_v", 8, 65536);
  app.add_real("--area-stiffness", d.area_stiffness, "area compressibility K_a", 0.0, 1e9);
  app.add_real("--bending", d.bending_stiffness, "bending stiffness K_b (hopper-flows eq. 8; 0: no bending term)", 0.0,
               1e9);
  app.add_real("--perimeter-ratio", par.perimeter_ratio, "perimeter elasticity over line tension K_l/Γ", 0.0, 10.0);
  app.add_real("--wall-energy", d.wall_energy, "wall repulsion E_w (eq. 3)", 0.0, 1e8);
  app.add_real("--vertex-diameter", d.vertex_diameter, "vertex diameter δ/l0 (eq. 3)", 0.0, 10.0, Bounds::left_open);
  app.add_real("--drag-exponent", d.drag_exponent, "near-wall drag exponent α (eq. 6)", 0.0, 10.0, Bounds::left_open);
  app.add_real("--drag-floor", d.drag_floor, "floor d_min/σ on the wall distance of eq. 6", 0.0, 1.0, Bounds::left_open);
  app.add_real("--dt", d.dt, "time step Δt/t0 (0: min(1e-3, stability limit))", 0.0, 0.01);
  app.add_flag(mesoflow::cli::force_dt_flag, d.force_dt, mesoflow::cli::force_dt_help);
  app.add_real("--start-h", par.scene.start_h, "initial distance of the centre of mass from the orifice h/σ", -1000.0,
               -1.0);
  app.add_real("--end-h", par.scene.end_h, "the droplet has passed once h/σ reaches this", 0.0, 100.0, Bounds::left_open);
  app.add_real("--max-time", par.scene.max_time, "time limit t/t0", 0.0, 1e7, Bounds::left_open);
  app.add_real("--sample-interval", par.scene.sample_interval, "time between profile samples /t0", 0.0, 100.0,
               Bounds::left_open);
  app.add_real("--clog-threshold", par.scene.clog_threshold, "clogged once E_k/E_t falls below this (App. C)", 0.0, 1.0,
               Bounds::open);
  app.add_positive("--frame-every", par.frame_every, "profile samples between trajectory frames");
  app.add_int("--check-every", par.scene.check_interval,
              "steps between NaN-watchdog checks (a non-finite state stops the run, naming particle, term and step)",
              1, 1000000);
  app.add_int("--threads", par.threads, "host threads (0: OMP_NUM_THREADS or all cores)", 0, 4096);
  app.add_flag("--no-plot", par.no_plot, "do not write the PNG plot");
  return app.run(argc, argv, [&] {
    mesoflow::KokkosScope kokkos(par.threads);
    mesoflow::run(par, app);
  });
}
