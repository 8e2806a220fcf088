// capsule — a microcapsule (SPH fluid + mass-spring membrane, the Discrete Multi-Physics model)
// through a constriction, and in simple shear: Rahmat et al., sph-microcapsules-constriction.
//
// Units, the membrane's k_b from Ca, c0 of eq. (6), the flow control and the step that follows the
// state: scenes/capsule/capsule_runs.hpp; the scene: scenes/capsule/capsule_scene.hpp.
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
#include "io/h5md_writer.hpp"
#include "kernels/common/kokkos_compat.hpp"
#include "scenes/capsule/capsule_runs.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
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

// A comma list of values in (lo, hi].
std::vector<double> parse_list(const std::string& text, const std::string& flag, double lo, double hi) {
  std::ostringstream range;
  range << "in (" << lo << ", " << hi << "]";
  return cli::parse_number_list(text, flag, [=](double v) { return v > lo && v <= hi; }, range.str());
}

std::string tag(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// Writes `text` to `path` atomically: a temporary beside it, then a rename.
void write_atomically(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp);
    f << text;
    if (!f) throw std::runtime_error("cannot write " + tmp);
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) throw std::runtime_error("cannot rename " + tmp + " to " + path);
}

std::string scene_signature(const Parameters& par, double ca, double eta) {
  std::ostringstream s;
  s << std::setprecision(10) << par.mode << ";Pi=" << par.resolution << ";Ca=" << ca << ";eta=" << eta
    << ";Re=" << par.reynolds << ";ht=" << par.thickness << ";level=" << par.level << ";diag=" << par.diagonals
    << ";h=" << par.support << ";walls=" << par.walls << ";lambda=" << par.viscosity_ratio << ";c0=" << par.c0
    << ";strain=" << par.membrane_strain << ";delta=" << par.density_variation << ";tmax=" << par.t_max << ";sample=" << par.sample_every
    << ";stall=" << par.stall_window;
  if (par.dt > 0) s << ";dt=" << par.dt;
  return s.str();
}

capsule::RunResult run_constriction(const Parameters& par, const cli::DriverApp& app, const std::string& stem,
                                    double ca, double eta) {
  const bool quiet = app.quiet();
  capsule::ConstrictionRun<> run(par, ca, eta, quiet);
  const auto& scene = run.scene();
  const auto& g = run.channel();
  const auto& phys = run.physical();
  const double d = par.resolution, dt = run.start_dt();
  const std::string name = stem + "_ca" + tag(ca) + "_eta" + tag(eta);
  capsule::RunResult r;
  r.ca = ca;
  r.eta = eta;
  r.eta_effective = g.constriction_width / d;
  r.dt = dt / d;
  r.c0 = phys.c0;
  r.k_b = phys.k_b;
  r.particles = scene.num_particles();
  r.series_csv = name + "_series.csv";
  r.sections_csv = name + "_sections.csv";
  r.signature = scene_signature(par, ca, eta);

  io::H5mdWriter h5(name + ".h5");
  for (const auto& [key, value] : app.resolved_parameters()) h5.set_parameter(key, value);
  const std::pair<const char*, double> parameters[] = {
      {"ca_run", ca}, {"eta_run", eta}, {"eta_effective", r.eta_effective}, {"diameter_lattice", d},
      {"viscosity", phys.mu}, {"surface_shear_modulus", phys.G_s}, {"k_b", phys.k_b}, {"c0", phys.c0}, {"dt", dt}};
  for (const auto& [key, value] : parameters) h5.set_parameter(key, value);
  h5.set_parameter("particles", scene.num_particles());
  h5.set_parameter("membrane_particles", scene.num_membrane());
  h5.set_parameter("wall_particles", scene.num_walls());
  const auto& box = scene.system().box();
  h5.add_particles_group("membrane", 3, std::size_t(scene.num_membrane()), {box.lo[0], box.lo[1], box.lo[2]},
                         {box.length[0], box.length[1], box.length[2]},
                         {box.periodic[0], box.periodic[1], box.periodic[2]});

  struct Output {  // the measures of each sample (analysis/capsule/capsule_shape.hpp), written here
    const capsule::ConstrictionRun<>& run;
    io::H5mdWriter& h5;
    cli::ProgressLine progress_line;
    std::ofstream series, sections;
    const std::vector<double> section_targets = {2.0, 3.0, 3.5, 4.0, 4.5, 5.0, 5.5};
    std::size_t next_section = 0;
    std::vector<double> xs, dx_s, dy_s, dz_s, cf_s, cr_s;
    void progress(long step) { progress_line.update(step); }
    void sample(const capsule::ConstrictionSample& s) {
      const double d = run.physical().d, a = run.physical().a;
      const auto D = capsule::deformation_indices(s.y, d);
      const auto section = capsule::midplane_section(s.y, run.scene().mesh().triangle, d);
      const double cf = capsule::tip_curvature(section, s.x_c, d, +1, a);
      const double cr = capsule::tip_curvature(section, s.x_c, d, -1, a);
      const auto& l = s.limits;
      series << s.time << "," << s.x_c / d << "," << s.x_front / d << "," << s.x_rear / d << "," << D[0] << ","
             << D[1] << "," << D[2] << "," << cf << "," << cr << "," << s.body_force << "," << s.flux_ratio << ","
             << s.density_deviation << "," << s.dt / d << "," << l.sph.viscous / d << "," << l.sph.acoustic / d
             << "," << l.sph.force / d << "," << l.sph.acoustic_viscous / d << "," << l.bond / d
             << std::endl;  // flushed: the run can be watched
      const std::int64_t s64 = s.step;
      h5.append_observable("x_c", s64, s.time, s.x_c / d);
      h5.append_observable("deformation_index", s64, s.time, D.data(), 3);
      const double curv[2] = {cf, cr};
      h5.append_observable("tip_curvature_front_rear", s64, s.time, curv, 2);
      h5.append_observable("body_force", s64, s.time, s.body_force);
      h5.append_observable("flux_ratio", s64, s.time, s.flux_ratio);
      h5.append_observable("max_density_deviation", s64, s.time, s.density_deviation);
      if (s.index % run.frame_samples() == 0) {
        const auto pos = capsule::membrane_positions(run.scene());
        h5.append("membrane", "position", s64, s.time, pos.data(), std::size_t(run.scene().num_membrane()), 3);
      }
      for (; next_section < section_targets.size() && s.x_c / d >= section_targets[next_section]; ++next_section)
        for (const auto& q : section)
          sections << section_targets[next_section] << "," << q[0] / d << "," << q[1] / d << "\n";
      xs.push_back(s.x_c / d);
      dx_s.push_back(D[0]);
      dy_s.push_back(D[1]);
      dz_s.push_back(D[2]);
      cf_s.push_back(cf);
      cr_s.push_back(cr);
    }
  } out{run, h5, cli::ProgressLine(run.max_steps(), scene.num_particles(), !quiet), std::ofstream(r.series_csv),
        std::ofstream(r.sections_csv)};
  out.series << "time,x_c,x_front,x_rear,Dx,Dy,Dz,Cf,Cr,body_force,flux_ratio,max_density_deviation,dt,"
                "limit_viscous,limit_acoustic,limit_force,limit_acoustic_viscous,limit_bond\n"
             << std::setprecision(8);
  out.sections << "x_c_target,x,y\n" << std::setprecision(8);
  const auto t0 = std::chrono::steady_clock::now();
  r.status = run.run(out);
  out.progress_line.finish();
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.steps = double(run.steps());
  run.governor().report(dt);
  r.max_density_deviation = run.max_density_deviation();
  r.particle_steps_per_second = r.steps * scene.num_particles() / r.wall_seconds;
  if (!std::isnan(run.exit_time())) {
    r.passage_time = run.exit_time() - run.entry_time();
    r.inverse_passage_time = 1 / r.passage_time;
    r.status = "passed";
  }
  r.Dx4 = capsule::value_at(out.xs, out.dx_s, 4.0);
  r.Dy4 = capsule::value_at(out.xs, out.dy_s, 4.0);
  r.Dz4 = capsule::value_at(out.xs, out.dz_s, 4.0);
  const double at[3] = {3.5, 4.0, 4.5};
  for (int k = 0; k < 3; ++k) {
    r.Cf[k] = capsule::value_at(out.xs, out.cf_s, at[k]);
    r.Cr[k] = capsule::value_at(out.xs, out.cr_s, at[k]);
  }
  h5.write_xdmf(name + ".xdmf");
  write_atomically(name + "_result.csv", std::string(capsule::sweep_header) + "\n" + capsule::csv_row(r) + "\n");
  if (!quiet)
    std::cerr << "capsule: Ca " << ca << ", eta " << eta << " (effective " << r.eta_effective << "): " << r.status
              << ", passage time " << r.passage_time << " d/U, Dx(4) " << r.Dx4 << ", max |drho|/rho0 "
              << r.max_density_deviation << ", " << r.particle_steps_per_second << " particle-steps/s\n";
  return r;
}

void constriction_sweep(const Parameters& par, const cli::DriverApp& app) {
  const driver::OutputPaths out(app.output());
  const std::string stem = out.trajectory.substr(0, out.trajectory.size() - 3);
  const auto cas = parse_list(par.ca, "--ca", 0.0, 100.0);
  const auto etas = parse_list(par.eta, "--eta", 0.0, 2.0);
  std::vector<capsule::RunResult> results;
  for (double eta : etas)
    for (double ca : cas) {
      const std::string run = stem + "_ca" + tag(ca) + "_eta" + tag(eta);
      const auto done = par.restart ? capsule::read_result(run + "_result.csv") : std::nullopt;
      if (done && done->signature == scene_signature(par, ca, eta)) {
        if (!app.quiet()) std::cerr << "capsule: reusing the finished run " << run << "\n";
        results.push_back(*done);
        continue;
      }
      results.push_back(run_constriction(par, app, stem, ca, eta));
    }
  std::ostringstream table;
  table << capsule::sweep_header << "\n";
  for (const auto& r : results) table << capsule::csv_row(r) << "\n";
  write_atomically(stem + "_sweep.csv", table.str());

  // Pearson's r against Ca per η (eq. 17, Table 1).
  cli::Json j{{"driver", "capsule"}, {"mode", "constriction"}, {"resolution", par.resolution},
              {"reynolds", par.reynolds}, {"runs", results.size()}, {"kokkos", kokkos_configuration()}};
  j["pearson_r"] = cli::Json::array();
  for (double eta : etas) {
    const auto column = [&](auto get) {
      std::vector<double> x, c;
      for (const auto& r : results)
        if (r.eta == eta) {
          x.push_back(get(r));
          c.push_back(r.ca);
        }
      return cli::summary_number(capsule::pearson_r(x, c));
    };
    using R = capsule::RunResult;
    cli::Json row{{"eta", eta},
                  {"inverse_passage_time", column([](const R& r) { return r.inverse_passage_time; })},
                  {"Dx_at_4", column([](const R& r) { return r.Dx4; })},
                  {"Dy_at_4", column([](const R& r) { return r.Dy4; })},
                  {"Dz_at_4", column([](const R& r) { return r.Dz4; })}};
    const char* at[3] = {"3.5", "4", "4.5"};
    for (int k = 0; k < 3; ++k) {
      row[std::string("Cf_at_") + at[k]] = column([k](const R& r) { return r.Cf[k]; });
      row[std::string("Cr_at_") + at[k]] = column([k](const R& r) { return r.Cr[k]; });
    }
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
  const auto cas = parse_list(par.ca, "--ca", 0.0, 100.0);
  std::ostringstream table;
  const std::string header =
      "ca,taylor_deformation,taylor_deformation_std,inclination_over_pi,inclination_over_pi_std,dt_gamma,"
      "shear_time,particles,max_density_deviation,wall_seconds,series_csv,signature";
  table << header << "\n";
  for (double ca : cas) {
    const std::string name = stem + "_shear_ca" + tag(ca);
    const std::string signature = scene_signature(par, ca, 0) + ";box=" + tag(par.shear_box_x) + "x" +
                                  tag(par.shear_box_y) + "x" + tag(par.shear_box_z);
    if (par.restart) {  // reuse a finished run of the same scene
      std::ifstream done(name + "_result.csv");
      std::string h, row;
      if (done && std::getline(done, h) && std::getline(done, row) && h == header &&
          row.size() > signature.size() && row.compare(row.size() - signature.size(), signature.size(), signature) == 0) {
        if (!app.quiet()) std::cerr << "capsule: reusing the finished run " << name << "\n";
        table << row << "\n";
        continue;
      }
    }
    capsule::ShearRun<> run(par, ca, app.quiet());
    struct Output {
      cli::ProgressLine progress_line;
      std::ofstream series;
      std::vector<double> t_s, D_s, th_s;
      void progress(long step) { progress_line.update(step); }
      void sample(double t, const std::vector<Eigen::Vector3d>& y, double dens, double dt_gamma) {
        const auto s = capsule::shear_plane_shape(y);
        series << t << "," << s.taylor << "," << s.inclination / capsule::pi << "," << dens << "," << dt_gamma
               << std::endl;
        t_s.push_back(t);
        D_s.push_back(s.taylor);
        th_s.push_back(s.inclination / capsule::pi);
      }
    } o{cli::ProgressLine(run.max_steps(), run.scene().num_particles(), !app.quiet()),
        std::ofstream(name + "_series.csv")};
    o.series << "shear_time,taylor_deformation,inclination_over_pi,max_density_deviation,dt_gamma\n"
             << std::setprecision(8);
    const auto t0 = std::chrono::steady_clock::now();
    run.run(o);
    o.progress_line.finish();
    run.governor().report(run.start_dt());
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const auto D = capsule::steady_value(o.t_s, o.D_s, 0.7 * par.t_max);  // the last 30% of the run
    const auto T = capsule::steady_value(o.t_s, o.th_s, 0.7 * par.t_max);
    std::ostringstream row;
    row << std::setprecision(8) << ca << "," << D.mean << "," << D.std << "," << T.mean << "," << T.std << ","
        << run.start_dt() * run.physical().shear_rate << "," << par.t_max << "," << run.scene().num_particles() << ","
        << run.max_density_deviation() << "," << wall << "," << name + "_series.csv" << "," << signature;
    write_atomically(name + "_result.csv", header + "\n" + row.str() + "\n");
    table << row.str() << "\n";
    if (!app.quiet())
      std::cerr << "capsule shear: Ca " << ca << ": D_xy = " << D.mean << ", theta/pi = " << T.mean << " (" << wall
                << " s)\n";
  }
  write_atomically(stem + "_shear.csv", table.str());
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
  app.add_choice("--mode", par.mode, "constriction (§3-§5) or shear (§4.1 validation)", {"constriction", "shear"});
  app.add_int("--resolution", par.resolution, "lattice spacings per capsule diameter d (paper: 56)", 6, 128);
  auto list_check = [](const std::string& flag, double lo, double hi) {
    return CLI::Validator(
        [=](std::string& text) {
          try {
            mesoflow::parse_list(text, flag, lo, hi);
            return std::string();
          } catch (const std::exception& e) {
            return std::string(e.what());
          }
        },
        "LIST");
  };
  app.add_string("--ca", par.ca, "capillary number(s) Ca = mu U a/G_s, comma-separated, each in (0, 100]")
      ->check(list_check("--ca", 0.0, 100.0));
  app.add_string("--eta", par.eta, "constriction mode: width(s) eta = t_c/d, comma-separated, each in (0, 2]")
      ->check(list_check("--eta", 0.0, 2.0));
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
    mesoflow::KokkosScope kokkos(par.threads);
    if (par.mode == "shear")
      mesoflow::shear_runs(par, app);
    else
      mesoflow::constriction_sweep(par, app);
  });
}
