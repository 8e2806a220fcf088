// hopper — continuous gravity-driven hopper flow of bidisperse soft particles (SP, 2D and 3D) or
// deformable polygons (DP, 2D) (hopper-flows paper §2.1–2.4, §4): sweeps the orifice width w,
// measures the steady flow rate Q(w) or clogging at each, and fits the Beverloo law
// Q = C(w/σ_avg − k)^β (eq. 1) when at least 4 widths flow. Scenes: drivers/hopper/hopper_scene.hpp
// (SP), drivers/hopper/dp_hopper_scene.hpp (DP: K_a, K_l, K_b of eq. 8, E_c of eq. 9, rough or
// smooth contacts, E_w of eq. 10, ζ of eq. 11, μ of eq. 12).
//
// Units (§2.2): length σ_avg = (σ_s + σ_l)/2, acceleration g, density ρ (areal in 2D); time
// t0 = √(σ_avg/g); E_sp, E_w as in §2.2; ζ, μ in ζ0 = μ0 = ρσ_avg^{d−1} g t0; Q in Q0 = σ_avg^d/t0
// (area per t0 in 2D, volume in 3D). λ = ζ/μ is set by --drag and --friction. --dt 0 (the
// default) takes min(10⁻³ t0, 0.9 × the scene's explicit stability limit); a larger --dt is refused.
// Each width is an independent run with its own seed (--seed + the width's index, so the Q(w) of
// different widths carry independent noise, as the Beverloo fit's χ² assumes): random placement,
// FIRE without gravity, then flow (drivers/hopper/hopper_scene.hpp; steady-state and clogging criteria in
// drivers/hopper/flow_measurement.hpp).
//
// Measured over the windows that make Q (after the steady state), at each window's end:
//   - the velocity profile on the hopper axis (§4, Fig. 5): Gaussian coarse-graining of width σ_avg
//     (kernels/common/coarse_graining.hpp) at h = 0, 0.25, … 23.75 σ_avg above the orifice; the
//     number density n(h), the paper's v_g(h) = Σ v_g,i φ (j_g), and the mean particle speed j_g/n;
//   - the number density ρ_n in the 2w × w region above the orifice (3D: the cylinder of diameter 2w,
//     height w) and the corrected flow rate Q' = Q/(ρ_n a_avg) of Appendix B (SP only: the correction
//     is for overlapping soft particles; DP polygons keep their area, and Q' is not written).
// For DP the profile is coarse-grained over vertices (every polygon has N_v of them, so the mean
// vertex speed is the mean polygon speed, smeared over the polygon's extent).
//
// Output (<out> = --output without its extension): <out>.h5 (per width k: observables
// window_flow_rate_<k>, profile_number_density_<k>, profile_vg_<k> (one frame, the window average);
// attributes w_<k>, Q_<k>, Q_error_<k>, Q_corrected_<k>, clogged_<k>, steady_<k>; parameters),
// <out>.csv (w, Q, Q_error, Q_corrected, number_density_orifice, clogged, steady), <out>_profile.csv
// (w, h, n, vg_sum, vg_mean), <out>.json (results, the fit), <out>_fit.csv (the fit, when there is
// one), <out>.png (Q(w) with the fit and the v_g(h) profiles; --no-plot skips it).
// --vary NAME --values v1,…: one such sweep per value, each with outputs <out>_<NAME><v>.*, then
// <out>_vary.csv (v, λ = ζ/μ, C, k, β with errors) and <out>_vary.json (the sigmoid β(λ) of eq. 14
// when drag or friction varies and ≥ 3 fits have 0 < λ < ∞).
#include "drivers/common/cli.hpp"
#include "drivers/common/output_paths.hpp"
#include "drivers/hopper/flow_measurement.hpp"
#include "drivers/hopper/flow_rate_fits.hpp"
#include "drivers/hopper/dp_hopper_scene.hpp"
#include "drivers/hopper/hopper_scene.hpp"
#include "kernels/common/coarse_graining.hpp"
#include "kernels/io/h5md_writer.hpp"

#include <array>
#include <chrono>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <optional>
#include <sstream>

namespace mesoflow {
namespace {

constexpr int profile_points = 96;
constexpr double profile_dh = 0.25;  // σ_avg between profile points, from h = 0

// Window averages over the measuring windows of one width.
struct WidthMeasurement {
  std::array<double, profile_points> n{}, vg_sum{};
  double orifice_count = 0;
  int samples = 0;
};

struct Parameters {
  std::string vary;    // empty, or the parameter swept in an outer loop (--vary)
  std::string values;  // its values (--values)
  hopper::HopperParameters scene;
  hopper::DpHopperParameters dp;
  hopper::FlowSettings flow;
  std::string model = "sp";
  double dt = 0;  // 0: automatic
  std::string widths = "4,5,6,7,8";
  std::string dimension = "2";
  int threads = 0;
  bool no_plot = false;
};

// --widths: each in (0, W).
std::vector<double> parse_widths(const std::string& text, double W) {
  return cli::parse_number_list(
      text, "--widths", [W](double w) { return w > 0 && w < W; }, "in (0, W = " + std::to_string(W) + ")");
}

// Scene parameters for width index k: the base with w and seed + k.
template <class SceneParameters>
SceneParameters at_width(const SceneParameters& base, double w, std::size_t k) {
  SceneParameters p = base;
  p.orifice = w;
  p.seed = base.seed + k;
  return p;
}

void validate(const hopper::HopperParameters& p, int dim) { p.validate(dim); }
void validate(const hopper::DpHopperParameters& p, int) { p.validate(); }

// Scene: HopperScene<D> (SP) or DpHopperScene (DP, D = 2); `bodies` = updates per particle-step
// reported (1 for SP, N_v vertices per polygon for DP).
template <class Scene, int D, class SceneParameters>
std::optional<hopper::BeverlooFit> run(const SceneParameters& scene_base, const Parameters& par,
                                       const cli::DriverApp& app, int bodies, const std::string& output) {
  constexpr bool soft_particles = std::is_same_v<SceneParameters, hopper::HopperParameters>;
  const driver::OutputPaths out(output);
  const auto widths = parse_widths(par.widths, scene_base.hopper_width);
  for (std::size_t k = 0; k < widths.size(); ++k) validate(at_width(scene_base, widths[k], k), D);  // before any output
  par.flow.validate();
  std::optional<io::H5mdWriter> h5;
  h5.emplace(out.trajectory, "mesoflow", MESOFLOW_VERSION, "mesoflow hopper");
  for (const auto& [key, value] : app.resolved_parameters()) h5->set_parameter(key, value);
  std::vector<hopper::FlowResult> results;
  std::vector<WidthMeasurement> measured(widths.size());
  std::vector<double> corrected, densities;
  const auto wall_start = std::chrono::steady_clock::now();
  long long steps = 0;
  for (std::size_t k = 0; k < widths.size(); ++k) {
    Scene scene(at_width(scene_base, widths[k], k));
    scene.relax();
    const std::string name = "window_flow_rate_" + std::to_string(k);
    WidthMeasurement& m = measured[k];
    const auto r = hopper::measure_flow_rate<Scene>(
        scene, par.flow, [&](const Scene& s, double q, bool measuring) {
          h5->append_observable(name, s.steps(), s.time(), q);
          if (!measuring) return;
          const auto prof = gaussian_axis_profile<profile_points>(s.particles(), 0.0, profile_dh, 1.0);
          for (int j = 0; j < profile_points; ++j) {
            m.n[j] += prof.number_density[j];
            m.vg_sum[j] += prof.velocity_sum[j];
          }
          if constexpr (soft_particles) m.orifice_count += s.orifice_region_count();
          ++m.samples;
        });
    const std::string suffix = "_" + std::to_string(k);
    if (m.samples > 0) {
      for (int j = 0; j < profile_points; ++j) {
        m.n[j] /= m.samples;
        m.vg_sum[j] /= m.samples;
      }
      m.orifice_count /= m.samples;
      h5->append_observable("profile_number_density" + suffix, scene.steps(), scene.time(), m.n.data(), m.n.size());
      h5->append_observable("profile_vg" + suffix, scene.steps(), scene.time(), m.vg_sum.data(), m.vg_sum.size());
    }
    double rho_n = NAN, Q_corrected = NAN;
    if constexpr (soft_particles) {
      rho_n = m.orifice_count / scene.orifice_region_measure();
      if (rho_n > 0) Q_corrected = hopper::corrected_flow_rate(r.Q, rho_n, Scene::mean_particle_measure());
      h5->set_parameter("Q_corrected" + suffix, Q_corrected);
    }
    corrected.push_back(Q_corrected);
    densities.push_back(rho_n);
    h5->set_parameter("w" + suffix, widths[k]);
    h5->set_parameter("Q" + suffix, r.Q);
    h5->set_parameter("Q_error" + suffix, r.Q_error);
    h5->set_parameter("clogged" + suffix, r.clogged);
    h5->set_parameter("steady" + suffix, r.steady);
    h5->set_parameter("insertions" + suffix, scene.insertions());
    h5->set_parameter("max_insertion_overlap" + suffix, scene.max_insertion_overlap());
    steps += scene.steps();
    results.push_back(r);
    if (!app.quiet())
      std::cout << "hopper: w = " << widths[k] << ": "
                << (r.clogged ? std::string("clogged at t = ") + std::to_string(r.end_time)
                              : "Q = " + std::to_string(r.Q) + " ± " + std::to_string(r.Q_error) +
                                    (r.steady ? "" : " (no steady state by --max-time)"))
                << " (" << scene.steps() << " steps, " << scene.insertions() << " re-insertions)\n";
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  h5.reset();

  std::ofstream csv(out.csv);
  csv << std::setprecision(10) << "w,Q,Q_error,Q_corrected,number_density_orifice,clogged,steady\n";
  std::vector<double> x, Q, Qe;
  for (std::size_t k = 0; k < widths.size(); ++k) {
    const auto& r = results[k];
    csv << widths[k] << ',' << r.Q << ',' << r.Q_error << ',' << corrected[k] << ',' << densities[k] << ','
        << int(r.clogged) << ',' << int(r.steady) << '\n';
    if (!r.clogged && r.steady && r.Q > 0 && r.Q_error > 0) {
      x.push_back(widths[k]);
      Q.push_back(r.Q);
      Qe.push_back(r.Q_error);
    }
  }
  csv.close();
  const std::string base = out.csv.substr(0, out.csv.size() - 4);
  std::ofstream pcsv(base + "_profile.csv");
  pcsv << std::setprecision(10) << "w,h,n,vg_sum,vg_mean\n";
  for (std::size_t k = 0; k < widths.size(); ++k) {
    const auto& m = measured[k];
    if (m.samples == 0) continue;
    for (int j = 0; j < profile_points; ++j)
      pcsv << widths[k] << ',' << j * profile_dh << ',' << m.n[j] << ',' << m.vg_sum[j] << ','
           << (m.n[j] > 1e-6 ? m.vg_sum[j] / m.n[j] : 0.0) << '\n';
  }
  pcsv.close();
  std::optional<hopper::BeverlooFit> fit;
  if (x.size() >= 4) fit = hopper::fit_beverloo(x, Q, Qe);
  std::ofstream json(out.summary);
  json << std::setprecision(10) << "{\n  \"driver\": \"hopper\",\n  \"model\": \"" << par.model
       << "\",\n  \"dimension\": " << D << ",\n  \"results\": [";
  for (std::size_t k = 0; k < widths.size(); ++k) {
    const auto& r = results[k];
    json << (k ? "," : "") << "\n    {\"w\": " << widths[k] << ", \"Q\": " << r.Q << ", \"Q_error\": "
         << (std::isfinite(r.Q_error) ? r.Q_error : -1.0)
         << ", \"Q_corrected\": " << (std::isfinite(corrected[k]) ? corrected[k] : -1.0)
         << ", \"number_density_orifice\": " << (std::isfinite(densities[k]) ? densities[k] : -1.0)
         << ", \"clogged\": " << (r.clogged ? "true" : "false")
         << ", \"steady\": " << (r.steady ? "true" : "false") << ", \"steady_time\": " << r.steady_time
         << ", \"end_time\": " << r.end_time << "}";
  }
  json << "\n  ],\n";
  if (fit) {
    json << "  \"beverloo\": {\"C\": " << fit->C << ", \"C_error\": " << fit->C_error << ", \"k\": " << fit->k
         << ", \"k_error\": " << fit->k_error << ", \"beta\": " << fit->beta << ", \"beta_error\": " << fit->beta_error
         << ", \"chi2_per_dof\": " << fit->chi2_per_dof << ", \"points\": " << x.size() << "},\n";
    std::ofstream fcsv(base + "_fit.csv");
    fcsv << std::setprecision(10) << "C,C_error,k,k_error,beta,beta_error,chi2_per_dof,points\n"
         << fit->C << ',' << fit->C_error << ',' << fit->k << ',' << fit->k_error << ',' << fit->beta << ','
         << fit->beta_error << ',' << fit->chi2_per_dof << ',' << x.size() << '\n';
  } else {
    json << "  \"beverloo\": null,\n";
  }
  json << "  \"steps\": " << steps << ",\n  \"wall_seconds\": " << wall << ",\n  \"" << (soft_particles ? "particle" : "vertex") << "_steps_per_second\": "
       << (wall > 0 ? double(steps) * scene_base.particles * bodies / wall : 0.0) << ",\n  \"kokkos\": \""
       << kokkos_configuration() << "\"\n}\n";
  json.close();
  if (!par.no_plot) {
    const std::string png = base + ".png";
    std::vector<std::string> args{out.csv, png, "--profile", base + "_profile.csv"};
    if (fit) args.insert(args.end(), {"--fit", base + "_fit.csv"});
    driver::plot_with_matplotlib("hopper", "plot_hopper.py", args, png, app.quiet());
  }
  if (!app.quiet() && fit)
    std::cout << "hopper: Beverloo fit over " << x.size() << " widths: C = " << fit->C << " ± " << fit->C_error
              << ", k = " << fit->k << " ± " << fit->k_error << ", β = " << fit->beta << " ± " << fit->beta_error << "\n";
  return fit;
}

// --values: each > 0 (drag and friction may be 0).
std::vector<double> parse_values(const std::string& text, bool zero_allowed) {
  return cli::parse_number_list(
      text, "--values", [zero_allowed](double v) { return zero_allowed ? v >= 0 : v > 0; },
      zero_allowed ? ">= 0" : "> 0");
}

// Sets the --vary parameter of the scene parameters to v.
void set_varied(Parameters& par, double v) {
  const std::string& name = par.vary;
  if (name == "drag") par.scene.drag = par.dp.drag = v;
  else if (name == "friction") par.scene.friction = par.dp.friction = v;
  else if (name == "pair-energy") par.scene.pair_energy = v;
  else if (name == "perimeter-stiffness") par.dp.perimeter_stiffness = v;
  else if (name == "bending") par.dp.bending_stiffness = v;
}

// One w sweep per --values entry (outputs <out>_<vary><value>.*), then <out>_vary.csv with the
// Beverloo parameters against the value and λ = ζ/μ, and, when drag or friction is varied and at
// least 3 sweeps have a fit with 0 < λ < ∞, the sigmoid β(λ) of eq. 14 (<out>_vary.json).
template <class Sweep>
void run_varied(Parameters par, const cli::DriverApp& app, int dimension, const Sweep& sweep) {
  const bool dissipation = par.vary == "drag" || par.vary == "friction";
  const auto values = parse_values(par.values, dissipation);
  const driver::OutputPaths out(app.output());
  const std::string stem = out.csv.substr(0, out.csv.size() - 4);
  std::vector<std::optional<hopper::BeverlooFit>> fits;
  std::vector<double> lambdas;
  for (const double v : values) {
    set_varied(par, v);
    std::ostringstream name;
    name << stem << '_' << par.vary << v << ".h5";
    if (!app.quiet()) std::cout << "hopper: --" << par.vary << " " << v << "\n";
    fits.push_back(sweep(par, name.str()));
    lambdas.push_back(par.scene.friction > 0 ? par.scene.drag / par.scene.friction : HUGE_VAL);
  }
  std::ofstream csv(stem + "_vary.csv");
  csv << std::setprecision(10) << par.vary << ",lambda,C,C_error,k,k_error,beta,beta_error,chi2_per_dof\n";
  std::vector<double> x, beta, beta_error;
  for (std::size_t j = 0; j < values.size(); ++j) {
    csv << values[j] << ',' << lambdas[j];
    if (const auto& f = fits[j]) {
      csv << ',' << f->C << ',' << f->C_error << ',' << f->k << ',' << f->k_error << ',' << f->beta << ','
          << f->beta_error << ',' << f->chi2_per_dof << '\n';
      if (lambdas[j] > 0 && std::isfinite(lambdas[j])) {
        x.push_back(lambdas[j]);
        beta.push_back(f->beta);
        beta_error.push_back(f->beta_error);
      }
    } else {
      csv << ",,,,,,,\n";
    }
  }
  csv.close();
  std::ofstream json(stem + "_vary.json");
  json << std::setprecision(10) << "{\n  \"vary\": \"" << par.vary << "\",\n  \"sigmoid\": ";
  if (dissipation && x.size() >= 3) {
    const auto sig = hopper::fit_beta_sigmoid(x, beta, beta_error, dimension);
    json << "{\"lambda_c\": " << sig.lambda_c << ", \"lambda_c_error\": " << sig.lambda_c_error
         << ", \"stretch\": " << sig.stretch << ", \"stretch_error\": " << sig.stretch_error
         << ", \"chi2_per_dof\": " << sig.chi2_per_dof << ", \"points\": " << x.size() << "}\n}\n";
    if (!app.quiet())
      std::cout << "hopper: β(λ) sigmoid (eq. 14) over " << x.size() << " sweeps: λ_c = " << sig.lambda_c << " ± "
                << sig.lambda_c_error << ", 1/b = " << sig.stretch << " ± " << sig.stretch_error << "\n";
  } else {
    json << "null\n}\n";
  }
}

}  // namespace
}  // namespace mesoflow

int main(int argc, char** argv) {
  using mesoflow::cli::Bounds;
  mesoflow::Parameters par;
  auto& s = par.scene;
  auto& d = par.dp;
  auto& f = par.flow;
  mesoflow::cli::DriverApp app(
      "Hopper flow of bidisperse soft particles (2D, 3D) or deformable polygons (2D): Q(w) sweep, clogging and "
      "the Beverloo fit (hopper-flows paper; units sigma_avg, g, rho, t0 = sqrt(sigma_avg/g))",
      "hopper.h5");
  app.add_string("--widths", par.widths, "orifice widths w/σ_avg, a comma list, each in (0, W)");
  app.add_choice("--model", par.model, "sp (soft particles, eqs. 2-7) or dp (deformable polygons, eqs. 8-13; 2D)",
                 {"sp", "dp"});
  app.add_choice("--dimension", par.dimension, "2 (disks) or 3 (spheres in a cylinder; sp only)", {"2", "3"});
  app.add_int("--particles", s.particles, "particles N (half small, half large)", 2, 10000000);
  app.add_real("--hopper-width", s.hopper_width, "hopper width W/σ_avg (3D: diameter)", 4.7, 1e4);
  app.add_real("--wall-angle", s.wall_angle, "exit-wall angle θ_w in degrees", 0.0, 90.0, Bounds::left_open);
  app.add_real("--drag", s.drag, "drag ζ/ζ0 (eq. 5; dp: eq. 11)", 0.0, 1e4);
  app.add_real("--friction", s.friction, "kinetic friction μ/μ0 (eq. 6; dp: eq. 12, rough contacts only)", 0.0, 1e4);
  app.add_real("--dt", par.dt, "time step Δt/t0; 0: min(1e-3, 0.9 × stability limit); larger than the limit is refused",
               0.0, 0.01);
  app.add_int("--seed", s.seed, "random seed of width 0 (width k uses seed + k)", 0, 1LL << 62);
  app.add_real("--pair-energy", s.pair_energy, "sp: pair repulsion E_sp (eq. 2)", 0.0, 1e8, Bounds::left_open);
  app.add_real("--wall-energy", s.wall_energy, "sp: wall repulsion E_w (eq. 3)", 0.0, 1e8, Bounds::left_open);
  app.add_int("--vertices", d.vertices, "dp: vertices N_v per polygon", 8, 4096);
  app.add_real("--area-stiffness", d.area_stiffness, "dp: area stiffness K_a (eq. 8)", 0.0, 1e10, Bounds::left_open);
  app.add_real("--perimeter-stiffness", d.perimeter_stiffness, "dp: segment stiffness K_l (eq. 8)", 0.0, 1e10,
               Bounds::left_open);
  app.add_real("--bending", d.bending_stiffness, "dp: bending stiffness K_b (eq. 8)", 0.0, 1e10);
  app.add_real("--contact-energy", d.contact_energy, "dp: vertex contact energy E_c (eq. 9)", 0.0, 1e8, Bounds::left_open);
  app.add_real("--vertex-wall-energy", d.wall_energy, "dp: vertex-wall energy E_w (eq. 10)", 0.0, 1e8, Bounds::left_open);
  app.add_flag("--smooth", d.smooth, "dp: nearly smooth circulo-line contacts (Appendix A) instead of vertex disks");
  app.add_choice("--vary", par.vary,
                 "optional outer sweep over drag, friction (λ = ζ/μ, with the sigmoid β(λ) fit of eq. 14), pair-energy "
                 "(sp), perimeter-stiffness or bending (dp); one w sweep per --values entry",
                 {"", "drag", "friction", "pair-energy", "perimeter-stiffness", "bending"});
  app.add_string("--values", par.values, "the values of the --vary parameter, a comma list");
  app.add_real("--window", f.window, "rate window /t0", 0.0, 1e4, Bounds::left_open);
  app.add_int("--steady-windows", f.steady_windows, "windows M compared for the steady-state test", 2, 1000);
  app.add_int("--measure-windows", f.measure_windows, "windows averaged once steady", 4, 100000);
  app.add_real("--clog-time", f.clog_time, "clogged after this long without a crossing /t0", 0.0, 1e7, Bounds::left_open);
  app.add_real("--max-time", f.max_time, "time limit per width /t0", 0.0, 1e8, Bounds::left_open);
  app.add_int("--threads", par.threads, "host threads (0: OMP_NUM_THREADS or all cores)", 0, 4096);
  app.add_flag("--no-plot", par.no_plot, "do not write the PNG plot");
  return app.run(argc, argv, [&] {
    mesoflow::KokkosScope kokkos(par.threads);
    if (par.model == "dp" && par.dimension != "2")
      throw std::invalid_argument("--dimension: the dp model is 2D only, got " + par.dimension);
    if (par.vary == "pair-energy" && par.model != "sp")
      throw std::invalid_argument("--vary pair-energy: needs --model sp");
    if ((par.vary == "perimeter-stiffness" || par.vary == "bending") && par.model != "dp")
      throw std::invalid_argument("--vary " + par.vary + ": needs --model dp");
    if (par.vary.empty() && !par.values.empty()) throw std::invalid_argument("--values: needs --vary");
    const int dim = par.dimension == "2" ? 2 : 3;
    // One w sweep with the parameters as they are in p.
    const auto sweep = [&](const mesoflow::Parameters& p, const std::string& output) {
      if (p.model == "dp") {
        mesoflow::hopper::DpHopperParameters d = p.dp;
        d.particles = p.scene.particles;
        d.hopper_width = p.scene.hopper_width;
        d.wall_angle = p.scene.wall_angle;
        d.drag = p.scene.drag;
        d.friction = p.scene.friction;
        d.seed = p.scene.seed;
        d.dt = p.dt;
        return mesoflow::run<mesoflow::hopper::DpHopperScene<>, 2>(d, p, app, d.vertices, output);
      }
      mesoflow::hopper::HopperParameters sp = p.scene;
      sp.dt = p.dt > 0 ? p.dt : std::min(1e-3, 0.9 * sp.max_stable_dt(dim));
      return dim == 2 ? mesoflow::run<mesoflow::hopper::HopperScene<2>, 2>(sp, p, app, 1, output)
                      : mesoflow::run<mesoflow::hopper::HopperScene<3>, 3>(sp, p, app, 1, output);
    };
    if (par.vary.empty())
      sweep(par, app.output());
    else
      mesoflow::run_varied(par, app, dim, sweep);
  });
}
