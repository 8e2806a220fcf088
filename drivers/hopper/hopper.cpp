// hopper — continuous gravity-driven hopper flow of bidisperse soft particles (SP, 2D and 3D) or
// deformable polygons (DP, 2D) (hopper-flows paper §2.1–2.4, §4): sweeps the orifice width w,
// measures the steady flow rate Q(w) or clogging at each, and fits the Beverloo law
// Q = C(w/σ_avg − k)^β (eq. 1) when at least 4 widths flow. Scenes: scenes/hopper/hopper_scene.hpp
// (SP), scenes/hopper/dp_hopper_scene.hpp (DP: K_a, K_l, K_b of eq. 8, E_c of eq. 9, rough or
// smooth contacts, E_w of eq. 10, ζ of eq. 11, μ of eq. 12).
//
// Units (§2.2): length σ_avg = (σ_s + σ_l)/2, acceleration g, density ρ (areal in 2D); time
// t0 = √(σ_avg/g); E_sp, E_w as in §2.2; ζ, μ in ζ0 = μ0 = ρσ_avg^{d−1} g t0; Q in Q0 = σ_avg^d/t0
// (area per t0 in 2D, volume in 3D). λ = ζ/μ is set by --drag and --friction. --dt 0 (the
// default) takes min(10⁻³ t0, 0.9 × the scene's explicit stability limit); a larger --dt is refused.
// Each width is an independent run with its own seed (--seed + the width's index, so the Q(w) of
// different widths carry independent noise, as the Beverloo fit's χ² assumes): random placement,
// FIRE without gravity, then flow (scenes/hopper/hopper_scene.hpp; steady-state and clogging criteria in
// scenes/hopper/flow_measurement.hpp).
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
//
// Under mpirun/srun (docs/scale-out.md) the work items, (--vary value, width) pairs, are dealt round
// robin to the ranks (drivers/common/ensemble_mpi.hpp); a width's run depends only on its parameters
// and index (seed + k), not on the rank that runs it. Rank 0 gathers the runs and writes every
// output above, the same files as one process writes; the other ranks write nothing. A killed
// hopper sweep is run again from the start.
#include "drivers/common/cli.hpp"
#include "drivers/common/ensemble_mpi.hpp"
#include "drivers/common/output_paths.hpp"
#include "scenes/hopper/flow_measurement.hpp"
#include "analysis/hopper/flow_rate_fits.hpp"
#include "scenes/hopper/dp_hopper_scene.hpp"
#include "scenes/hopper/hopper_scene.hpp"
#include "kernels/common/coarse_graining.hpp"
#include "io/h5md_writer.hpp"

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

// One width's run, as rank 0 writes it: the flow result, the rate of every window (the
// window_flow_rate observable), the window-averaged profiles and the scene's counters at the end.
struct WidthRun {
  struct Scalars {  // the fixed-size part, sent as bytes
    double Q = 0, Q_error = 0;
    bool clogged = false, steady = false;
    double steady_time = 0, result_end_time = 0;
    long long steps = 0;  // at the end of the run (the profile frames' step)
    double time = 0;      // t/t0 at the end
    double rho_n = NAN, Q_corrected = NAN;
    long long insertions = 0;
    double max_insertion_overlap = 0;
    double seconds = 0;  // wall time of this width's run
    std::size_t windows = 0;
  } scalars;
  WidthMeasurement measured;
  struct Window {
    std::int64_t step;
    double time, q;
  };
  std::vector<Window> windows;

  // The result without its window rates (they are in `windows`).
  hopper::FlowResult result() const {
    hopper::FlowResult r;
    r.Q = scalars.Q;
    r.Q_error = scalars.Q_error;
    r.clogged = scalars.clogged;
    r.steady = scalars.steady;
    r.steady_time = scalars.steady_time;
    r.end_time = scalars.result_end_time;
    return r;
  }
};

void append_bytes(std::vector<char>& out, std::size_t item, const WidthRun& run) {
  ensemble::append_bytes(out, item);
  WidthRun::Scalars s = run.scalars;
  s.windows = run.windows.size();
  ensemble::append_bytes(out, s);
  ensemble::append_bytes(out, run.measured);
  for (const WidthRun::Window& w : run.windows) ensemble::append_bytes(out, w);
}

// Reads the width runs of one rank's bytes into runs[item].
void read_runs(const std::vector<char>& bytes, std::vector<WidthRun>& runs) {
  for (std::size_t offset = 0; offset < bytes.size();) {
    const auto k = ensemble::read_bytes<std::size_t>(bytes, offset);
    if (k >= runs.size()) throw std::runtime_error("hopper: a rank sent work item " + std::to_string(k));
    WidthRun& run = runs[k];
    run.scalars = ensemble::read_bytes<WidthRun::Scalars>(bytes, offset);
    run.measured = ensemble::read_bytes<WidthMeasurement>(bytes, offset);
    run.windows.resize(run.scalars.windows);
    for (WidthRun::Window& w : run.windows) w = ensemble::read_bytes<WidthRun::Window>(bytes, offset);
  }
}

struct Parameters {
  std::string vary;    // empty, or the parameter swept in an outer loop (--vary)
  std::string values;  // its values (--values)
  hopper::HopperParameters scene;
  hopper::DpHopperParameters dp;
  hopper::FlowSettings flow;
  std::string model = "sp";
  std::string friction_component = "full";  // --friction-component
  double dt = 0;  // 0: automatic
  std::string widths = "4,5,6,7,8";
  std::string dimension = "2";
  int threads = 0;
  bool no_plot = false;
};

// One w sweep: its parameters (with the --vary value set), output path and console label ("--drag
// 0.3" with --vary, else empty); SweepSpec the same with the scene's parameters.
struct SweepRequest {
  Parameters parameters;
  std::string output, label;
};
template <class SceneParameters>
struct SweepSpec {
  SceneParameters base;
  std::string output, label;
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
std::optional<hopper::BeverlooFit> write_sweep(const SweepSpec<SceneParameters>& sweep, const std::vector<double>& widths,
                                               const std::vector<WidthRun>& runs, const Parameters& par,
                                               const cli::DriverApp& app, const ensemble::Ranks& ranks, int bodies);

// The w sweeps `sweeps` (one, or one per --vary value): the work items (sweep, width) are shared
// among the ranks; rank 0 writes every sweep's outputs and returns their fits (the other ranks: none).
template <class Scene, int D, class SceneParameters>
std::vector<std::optional<hopper::BeverlooFit>> run(const std::vector<SweepSpec<SceneParameters>>& sweeps,
                                                    const Parameters& par, const cli::DriverApp& app,
                                                    const ensemble::Ranks& ranks, int bodies) {
  constexpr bool soft_particles = std::is_same_v<SceneParameters, hopper::HopperParameters>;
  std::vector<std::vector<double>> widths;
  for (const SweepSpec<SceneParameters>& sweep : sweeps) {
    widths.push_back(parse_widths(par.widths, sweep.base.hopper_width));
    for (std::size_t k = 0; k < widths.back().size(); ++k)
      validate(at_width(sweep.base, widths.back()[k], k), D);  // before any output
  }
  par.flow.validate();
  const std::size_t n_widths = widths.front().size();
  // This rank's items, item = sweep × n_widths + width; every rank reports its own as they finish.
  std::vector<char> sent;
  for (const std::size_t item : ensemble::shard(sweeps.size() * n_widths, ranks.rank(), ranks.size())) {
    const std::size_t k = item % n_widths;
    const SweepSpec<SceneParameters>& sweep = sweeps[item / n_widths];
    const auto width_start = std::chrono::steady_clock::now();
    Scene scene(at_width(sweep.base, widths[item / n_widths][k], k));
    scene.relax();
    WidthRun run;
    WidthMeasurement& m = run.measured;
    const auto r = hopper::measure_flow_rate<Scene>(
        scene, par.flow, [&](const Scene& s, double q, bool measuring) {
          run.windows.push_back({std::int64_t(s.steps()), s.time(), q});
          if (!measuring) return;
          const auto prof = gaussian_axis_profile<profile_points>(s.particles(), 0.0, profile_dh, 1.0);
          for (int j = 0; j < profile_points; ++j) {
            m.n[j] += prof.number_density[j];
            m.vg_sum[j] += prof.velocity_sum[j];
          }
          if constexpr (soft_particles) m.orifice_count += s.orifice_region_count();
          ++m.samples;
        });
    if (m.samples > 0) {
      for (int j = 0; j < profile_points; ++j) {
        m.n[j] /= m.samples;
        m.vg_sum[j] /= m.samples;
      }
      m.orifice_count /= m.samples;
    }
    WidthRun::Scalars& v = run.scalars;
    if constexpr (soft_particles) {
      v.rho_n = m.orifice_count / scene.orifice_region_measure();
      if (v.rho_n > 0) v.Q_corrected = hopper::corrected_flow_rate(r.Q, v.rho_n, Scene::mean_particle_measure());
    }
    v.Q = r.Q;
    v.Q_error = r.Q_error;
    v.clogged = r.clogged;
    v.steady = r.steady;
    v.steady_time = r.steady_time;
    v.result_end_time = r.end_time;
    v.steps = scene.steps();
    v.time = scene.time();
    v.insertions = scene.insertions();
    v.max_insertion_overlap = scene.max_insertion_overlap();
    v.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - width_start).count();
    append_bytes(sent, item, run);
    if (!app.quiet())
      std::cout << "hopper: " << (sweep.label.empty() ? "" : sweep.label + ", ") << "w = " << widths[item / n_widths][k]
                << ": "
                << (r.clogged ? std::string("clogged at t = ") + std::to_string(r.end_time)
                              : "Q = " + std::to_string(r.Q) + " ± " + std::to_string(r.Q_error) +
                                    (r.steady ? "" : " (no steady state by --max-time)"))
                << " (" << scene.steps() << " steps, " << scene.insertions() << " re-insertions)\n";
  }
  // Rank 0 gathers every width's run and writes the outputs; the other ranks are done.
  const std::vector<std::vector<char>> gathered = ranks.gather(sent);
  if (!ranks.root()) return {};
  std::vector<WidthRun> runs(sweeps.size() * n_widths);
  for (const std::vector<char>& bytes : gathered) read_runs(bytes, runs);
  std::vector<std::optional<hopper::BeverlooFit>> fits;
  for (std::size_t s = 0; s < sweeps.size(); ++s)
    fits.push_back(write_sweep<Scene, D>(
        sweeps[s], widths[s],
        std::vector<WidthRun>(runs.begin() + std::ptrdiff_t(s * n_widths), runs.begin() + std::ptrdiff_t((s + 1) * n_widths)),
        par, app, ranks, bodies));
  return fits;
}

// Rank 0: the outputs of one w sweep from its widths' runs. wall_seconds in the JSON is the sum of
// the widths' run times (the sweep's wall time on one rank), so the rate is per rank.
template <class Scene, int D, class SceneParameters>
std::optional<hopper::BeverlooFit> write_sweep(const SweepSpec<SceneParameters>& sweep, const std::vector<double>& widths,
                                               const std::vector<WidthRun>& runs, const Parameters& par,
                                               const cli::DriverApp& app, const ensemble::Ranks& ranks, int bodies) {
  constexpr bool soft_particles = std::is_same_v<SceneParameters, hopper::HopperParameters>;
  const driver::OutputPaths out(sweep.output);
  double wall = 0;
  for (const WidthRun& run : runs) wall += run.scalars.seconds;
  std::optional<io::H5mdWriter> h5;
  h5.emplace(out.trajectory, "mesoflow", MESOFLOW_VERSION, "mesoflow hopper");
  for (const auto& [key, value] : app.resolved_parameters()) h5->set_parameter(key, value);
  std::vector<hopper::FlowResult> results;
  std::vector<WidthMeasurement> measured(widths.size());
  std::vector<double> corrected, densities;
  long long steps = 0;
  for (std::size_t k = 0; k < widths.size(); ++k) {
    const WidthRun& run = runs[k];
    const WidthRun::Scalars& v = run.scalars;
    const std::string name = "window_flow_rate_" + std::to_string(k);
    for (const WidthRun::Window& w : run.windows) h5->append_observable(name, w.step, w.time, w.q);
    const std::string suffix = "_" + std::to_string(k);
    const WidthMeasurement& m = measured[k] = run.measured;
    if (m.samples > 0) {
      h5->append_observable("profile_number_density" + suffix, v.steps, v.time, m.n.data(), m.n.size());
      h5->append_observable("profile_vg" + suffix, v.steps, v.time, m.vg_sum.data(), m.vg_sum.size());
    }
    if constexpr (soft_particles) h5->set_parameter("Q_corrected" + suffix, v.Q_corrected);
    corrected.push_back(v.Q_corrected);
    densities.push_back(v.rho_n);
    h5->set_parameter("w" + suffix, widths[k]);
    h5->set_parameter("Q" + suffix, v.Q);
    h5->set_parameter("Q_error" + suffix, v.Q_error);
    h5->set_parameter("clogged" + suffix, v.clogged);
    h5->set_parameter("steady" + suffix, v.steady);
    h5->set_parameter("insertions" + suffix, v.insertions);
    h5->set_parameter("max_insertion_overlap" + suffix, v.max_insertion_overlap);
    steps += v.steps;
    results.push_back(run.result());
  }
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
  json << "  \"ranks\": " << ranks.size() << ",\n  \"steps\": " << steps << ",\n  \"wall_seconds\": " << wall << ",\n  \"" << (soft_particles ? "particle" : "vertex") << "_steps_per_second\": "
       << (wall > 0 ? double(steps) * sweep.base.particles * bodies / wall : 0.0) << ",\n  \"kokkos\": \""
       << kokkos_configuration() << "\"\n}\n";
  json.close();
  if (!par.no_plot) {
    const std::string png = base + ".png";
    std::vector<std::string> args{out.csv, png, "--profile", base + "_profile.csv"};
    if (fit) args.insert(args.end(), {"--fit", base + "_fit.csv"});
    driver::plot_with_matplotlib("hopper", "plot_hopper.py", args, png, app.quiet());
  }
  if (!app.quiet() && !sweep.label.empty()) std::cout << "hopper: " << sweep.label << "\n";
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
void run_varied(Parameters par, const cli::DriverApp& app, const ensemble::Ranks& ranks, int dimension,
                const Sweep& sweep) {
  const bool dissipation = par.vary == "drag" || par.vary == "friction";
  const auto values = parse_values(par.values, dissipation);
  const driver::OutputPaths out(app.output());
  const std::string stem = out.csv.substr(0, out.csv.size() - 4);
  std::vector<SweepRequest> sweeps;
  std::vector<double> lambdas;
  for (const double v : values) {
    set_varied(par, v);
    std::ostringstream name, label;
    name << stem << '_' << par.vary << v << ".h5";
    label << "--" << par.vary << " " << v;
    sweeps.push_back({par, name.str(), label.str()});
    lambdas.push_back(par.scene.friction > 0 ? par.scene.drag / par.scene.friction : HUGE_VAL);
  }
  const std::vector<std::optional<hopper::BeverlooFit>> fits = sweep(sweeps);
  if (!ranks.root()) return;  // rank 0 has every sweep's fit
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
  mesoflow::ensemble::Ranks ranks;  // MPI, when launched by mpirun/srun: before Kokkos, ended after it
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
  app.add_choice("--friction-component", par.friction_component,
                 "the part of the contact's relative velocity that friction damps: full (eqs. 6, 12 as printed) or "
                 "tangential (perpendicular to the centre-to-centre vector, as the authors' public code)",
                 {"full", "tangential"});
  app.add_real("--dt", par.dt, "time step Δt/t0; 0: min(1e-3, 0.9 × stability limit); larger than the limit is refused",
               0.0, 0.01);
  app.add_flag(mesoflow::cli::force_dt_flag, s.force_dt, mesoflow::cli::force_dt_help);
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
  app.add_int("--check-every", f.check_interval,
              "steps between NaN-watchdog checks (a non-finite state stops the run, naming particle, term and step)",
              1, 1000000);
  app.add_real("--clog-time", f.clog_time, "clogged after this long without a crossing /t0", 0.0, 1e7, Bounds::left_open);
  app.add_real("--max-time", f.max_time, "time limit per width /t0", 0.0, 1e8, Bounds::left_open);
  app.add_int("--threads", par.threads, "host threads (0: OMP_NUM_THREADS or all cores)", 0, 4096);
  app.add_flag("--no-plot", par.no_plot, "do not write the PNG plot");
  return ranks.finish(app.run(argc, argv, [&] {
    if (par.model == "dp" && par.dimension != "2")
      throw std::invalid_argument("--dimension: the dp model is 2D only, got " + par.dimension);
    if (par.vary == "pair-energy" && par.model != "sp")
      throw std::invalid_argument("--vary pair-energy: needs --model sp");
    if ((par.vary == "perimeter-stiffness" || par.vary == "bending") && par.model != "dp")
      throw std::invalid_argument("--vary " + par.vary + ": needs --model dp");
    if (par.vary.empty() && !par.values.empty()) throw std::invalid_argument("--values: needs --vary");
    s.friction_component = d.friction_component = mesoflow::sp::parse_friction_component(par.friction_component);
    ranks.start();
    mesoflow::KokkosScope kokkos(par.threads);
    const int dim = par.dimension == "2" ? 2 : 3;
    // The w sweeps of `requests`, each with the parameters as they are in its request, over all ranks.
    const auto sweep = [&](const std::vector<mesoflow::SweepRequest>& requests) {
      if (par.model == "dp") {
        std::vector<mesoflow::SweepSpec<mesoflow::hopper::DpHopperParameters>> sweeps;
        for (const mesoflow::SweepRequest& request : requests) {
          const mesoflow::Parameters& p = request.parameters;
          mesoflow::hopper::DpHopperParameters d = p.dp;
          d.particles = p.scene.particles;
          d.hopper_width = p.scene.hopper_width;
          d.wall_angle = p.scene.wall_angle;
          d.drag = p.scene.drag;
          d.friction = p.scene.friction;
          d.friction_component = p.scene.friction_component;
          d.seed = p.scene.seed;
          d.dt = p.dt;
          d.force_dt = p.scene.force_dt;
          sweeps.push_back({d, request.output, request.label});
        }
        return mesoflow::run<mesoflow::hopper::DpHopperScene<>, 2>(sweeps, par, app, ranks, par.dp.vertices);
      }
      std::vector<mesoflow::SweepSpec<mesoflow::hopper::HopperParameters>> sweeps;
      for (const mesoflow::SweepRequest& request : requests) {
        const mesoflow::Parameters& p = request.parameters;
        mesoflow::hopper::HopperParameters sp = p.scene;
        sp.dt = p.dt > 0 ? p.dt : std::min(1e-3, 0.9 * sp.max_stable_dt(dim));
        sweeps.push_back({sp, request.output, request.label});
      }
      return dim == 2 ? mesoflow::run<mesoflow::hopper::HopperScene<2>, 2>(sweeps, par, app, ranks, 1)
                      : mesoflow::run<mesoflow::hopper::HopperScene<3>, 3>(sweeps, par, app, ranks, 1);
    };
    if (par.vary.empty())
      sweep({{par, app.output(), ""}});
    else
      mesoflow::run_varied(par, app, ranks, dim, sweep);
  }));
}
