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
// Measured over the windows that make Q: the velocity profile on the hopper axis (§4, Fig. 5) and,
// SP only, the corrected flow rate Q' of Appendix B (scenes/hopper/hopper_sweep.hpp).
//
// Output (<out> = --output without its extension): <out>.h5 (per width k: observables
// window_flow_rate_<k>, profile_number_density_<k>, profile_vg_<k>; attributes w_<k>, Q_<k>, …
// (hopper::WidthRun::attributes); parameters), <out>.csv, <out>_profile.csv, <out>.json (results,
// the fit), <out>_fit.csv (the fit, when there is one), <out>.png (--no-plot skips it).
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
#include "drivers/common/json_summary.hpp"
#include "drivers/common/output_paths.hpp"
#include "analysis/common/block_average.hpp"
#include "analysis/hopper/flow_rate_fits.hpp"
#include "scenes/hopper/hopper_runs.hpp"

#include <iostream>
#include <optional>

namespace mesoflow {
namespace {

using hopper::SweepSpec;
using hopper::WidthRun;

struct Parameters : hopper::HopperRunParameters {
  int threads = 0;
  bool no_plot = false;
};

// Rank 0: the outputs of one w sweep from its widths' runs. wall_seconds in the JSON is the sum of
// the widths' run times (the sweep's wall time on one rank), so the rate is per rank.
template <int D, class SceneParameters>
std::optional<hopper::BeverlooFit> write_sweep(const SweepSpec<SceneParameters>& sweep, const std::vector<double>& widths,
                                               const std::vector<WidthRun>& runs, const Parameters& par,
                                               const cli::DriverApp& app, const ensemble::Ranks& ranks, int bodies) {
  constexpr bool soft_particles = std::is_same_v<SceneParameters, hopper::HopperParameters>;
  const driver::OutputPaths out(sweep.output);
  const std::string base = out.csv.substr(0, out.csv.size() - 4);
  const hopper::SweepTotals t = hopper::write_sweep_files(out.trajectory, out.csv, base + "_profile.csv",
                                                          app.resolved_parameters(), widths, runs, soft_particles);
  cli::Json results = cli::Json::array();
  for (std::size_t k = 0; k < widths.size(); ++k) {
    const WidthRun::Scalars& v = runs[k].scalars;
    const auto or_minus_one = [](double y) { return std::isfinite(y) ? y : -1.0; };
    results.push_back({{"w", widths[k]}, {"Q", v.Q}, {"Q_error", or_minus_one(v.Q_error)},
                       {"Q_corrected", or_minus_one(v.Q_corrected)}, {"number_density_orifice", or_minus_one(v.rho_n)},
                       {"clogged", v.clogged}, {"steady", v.steady}, {"steady_time", v.steady_time},
                       {"end_time", v.result_end_time}});
  }
  const std::optional<hopper::BeverlooFit> fit = hopper::beverloo_fit(t.x, t.Q, t.Qe);
  cli::Json json{{"driver", "hopper"}, {"model", par.model}, {"dimension", D}, {"results", results}, {"beverloo", nullptr}};
  if (fit) {
    json["beverloo"] = {{"C", fit->C}, {"C_error", fit->C_error}, {"k", fit->k}, {"k_error", fit->k_error},
                        {"beta", fit->beta}, {"beta_error", fit->beta_error}, {"chi2_per_dof", fit->chi2_per_dof},
                        {"points", t.x.size()}};
    hopper::write_beverloo_csv(base + "_fit.csv", *fit, t.x.size());
  }
  json["ranks"] = ranks.size();
  json["steps"] = t.steps;
  json["wall_seconds"] = t.wall;
  json[std::string(soft_particles ? "particle" : "vertex") + "_steps_per_second"] =
      t.wall > 0 ? double(t.steps) * sweep.base.particles * bodies / t.wall : 0.0;
  json["kokkos"] = kokkos_configuration();
  cli::write_summary(out.summary, json);
  if (!par.no_plot) {
    std::vector<std::string> args{out.csv, base + ".png", "--profile", base + "_profile.csv"};
    if (fit) args.insert(args.end(), {"--fit", base + "_fit.csv"});
    driver::plot_with_matplotlib("hopper", "plot_hopper.py", args, base + ".png", app.quiet());
  }
  if (!app.quiet() && !sweep.label.empty()) std::cout << "hopper: " << sweep.label << "\n";
  if (!app.quiet() && fit)
    std::cout << "hopper: Beverloo fit over " << t.x.size() << " widths: C = " << fit->C << " ± " << fit->C_error
              << ", k = " << fit->k << " ± " << fit->k_error << ", β = " << fit->beta << " ± " << fit->beta_error << "\n";
  return fit;
}

// The w sweeps `sweeps` (one, or one per --vary value): the work items (sweep, width) are shared
// among the ranks; rank 0 writes every sweep's outputs and returns their fits (the other ranks: none).
// Scene: HopperScene<D> (SP) or DpHopperScene (DP, D = 2); `bodies` = updates per particle-step
// reported (1 for SP, N_v vertices per polygon for DP).
template <class Scene, int D, class SceneParameters>
std::vector<std::optional<hopper::BeverlooFit>> run(const std::vector<SweepSpec<SceneParameters>>& sweeps,
                                                    const Parameters& par, const cli::DriverApp& app,
                                                    const ensemble::Ranks& ranks, int bodies) {
  std::vector<std::vector<double>> widths;
  for (const SweepSpec<SceneParameters>& sweep : sweeps) {
    const double W = sweep.base.hopper_width;
    widths.push_back(cli::parse_number_list(
        par.widths, "--widths", [W](double w) { return w > 0 && w < W; }, "in (0, W = " + std::to_string(W) + ")"));
    hopper::validate_widths(sweep.base, widths.back(), D);  // before any output
  }
  par.flow.validate();
  const std::size_t n_widths = widths.front().size();
  // This rank's items, item = sweep × n_widths + width; every rank reports its own as they finish.
  std::vector<char> sent;
  for (const std::size_t item : ensemble::shard(sweeps.size() * n_widths, ranks.rank(), ranks.size())) {
    const SweepSpec<SceneParameters>& sweep = sweeps[item / n_widths];
    const double w = widths[item / n_widths][item % n_widths];
    const WidthRun run = hopper::run_width<Scene>(sweep.base, w, item % n_widths, par.flow, analysis::block_average,
                                                  [&](const Scene& scene, const hopper::FlowResult& r) {
      if (!app.quiet())
        std::cout << "hopper: " << (sweep.label.empty() ? "" : sweep.label + ", ") << "w = " << w << ": "
                  << (r.clogged ? std::string("clogged at t = ") + std::to_string(r.end_time)
                                : "Q = " + std::to_string(r.Q) + " ± " + std::to_string(r.Q_error) +
                                      (r.steady ? "" : " (no steady state by --max-time)"))
                  << " (" << scene.steps() << " steps, " << scene.insertions() << " re-insertions)\n";
    });
    ensemble::append_bytes(sent, item);
    run.append_bytes(sent);
  }
  // Rank 0 gathers every width's run and writes the outputs; the other ranks are done.
  const std::vector<std::vector<char>> gathered = ranks.gather(sent);
  if (!ranks.root()) return {};
  std::vector<WidthRun> runs = ensemble::read_items<WidthRun>(gathered, sweeps.size() * n_widths, "hopper");
  if constexpr (std::is_same_v<SceneParameters, hopper::HopperParameters>)  // Q' of Appendix B
    hopper::correct_flow_rates(runs, Scene::mean_particle_measure(), hopper::corrected_flow_rate);
  std::vector<std::optional<hopper::BeverlooFit>> fits;
  for (std::size_t s = 0; s < sweeps.size(); ++s)
    fits.push_back(write_sweep<D>(sweeps[s], widths[s], hopper::sweep_runs(runs, s, n_widths), par, app, ranks, bodies));
  return fits;
}

// The sweeps of the --vary values (one without --vary, outputs at --output; else outputs
// <out>_<vary><value>.*), over every rank; rank 0 writes <out>_vary.csv with the Beverloo parameters
// against the value and λ = ζ/μ, and <out>_vary.json with the sigmoid β(λ) of eq. 14 when drag or
// friction is varied and at least 3 sweeps have a fit with 0 < λ < ∞.
template <class Scene, int D, class SceneParameters, class Make>
void run_sweeps(const Parameters& par, const cli::DriverApp& app, const ensemble::Ranks& ranks, int bodies, Make&& make) {
  if (par.vary.empty()) {
    run<Scene, D>(std::vector<SweepSpec<SceneParameters>>{{make(par), app.output(), ""}}, par, app, ranks, bodies);
    return;
  }
  const bool dissipation = par.vary == "drag" || par.vary == "friction";
  const auto values = cli::parse_number_list(
      par.values, "--values", [dissipation](double v) { return dissipation ? v >= 0 : v > 0; },
      dissipation ? ">= 0" : "> 0");
  const driver::OutputPaths out(app.output());
  const std::string stem = out.csv.substr(0, out.csv.size() - 4);
  std::vector<double> lambdas;
  const auto sweeps = hopper::vary_sweeps<SceneParameters>(par, values, stem, make, lambdas);
  const auto fits = run<Scene, D>(sweeps, par, app, ranks, bodies);
  if (!ranks.root()) return;  // rank 0 has every sweep's fit
  const auto vary = hopper::vary_outputs(stem + "_vary.csv", par.vary, values, lambdas, fits, dissipation, D);
  cli::Json json{{"vary", par.vary}, {"sigmoid", nullptr}};
  if (vary) {
    const hopper::SigmoidFit& sig = vary->fit;
    json["sigmoid"] = {{"lambda_c", sig.lambda_c}, {"lambda_c_error", sig.lambda_c_error}, {"stretch", sig.stretch},
                       {"stretch_error", sig.stretch_error}, {"chi2_per_dof", sig.chi2_per_dof}, {"points", vary->points}};
    if (!app.quiet())
      std::cout << "hopper: β(λ) sigmoid (eq. 14) over " << vary->points << " sweeps: λ_c = " << sig.lambda_c << " ± "
                << sig.lambda_c_error << ", 1/b = " << sig.stretch << " ± " << sig.stretch_error << "\n";
  }
  cli::write_summary(stem + "_vary.json", json);
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
    par.check_combinations();
    s.friction_component = d.friction_component = mesoflow::sp::parse_friction_component(par.friction_component);
    ranks.start();
    mesoflow::KokkosScope kokkos(par.threads);
    using namespace mesoflow::hopper;
    if (par.model == "dp")
      mesoflow::run_sweeps<DpHopperScene<>, 2, DpHopperParameters>(par, app, ranks, par.dp.vertices, polygon_sweep_parameters);
    else if (par.dimension == "2")
      mesoflow::run_sweeps<HopperScene<2>, 2, HopperParameters>(par, app, ranks, 1, particle_sweep_parameters<2>);
    else
      mesoflow::run_sweeps<HopperScene<3>, 3, HopperParameters>(par, app, ranks, 1, particle_sweep_parameters<3>);
  }));
}
