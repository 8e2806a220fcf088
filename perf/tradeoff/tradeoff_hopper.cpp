// tradeoff_hopper — speed–accuracy trade-off of the 2D SP hopper (hopper-flows §2.1–2.4, §4): the
// cost of continuous hopper flow (scenes/hopper/hopper_scene.hpp) per unit of physical time against
// the error of its flow rate Q (scenes/hopper/flow_measurement.hpp), for the time step Δt and the
// particle stiffness E_sp (eq. 2), in float and in double.
//
// Scene: N = 300 bidisperse particles, W = 20σ_avg, θ_w = 90°, w = 6σ_avg, E_w = 10⁴, drag only
// (ζ/ζ0 = 1/√10, μ = 0: the paper's λ → ∞ limit, Fig. 2c).
// Sweeps:
//   - E_sp ∈ {20, 50, 100, 10³, 10⁴, 10⁵}, each at the largest step it allows, 0.9 × its explicit
//     stability limit (HopperParameters::stability_limit: the wall E_w sets it up to E_sp ≈ 10⁴,
//     the pairs above): softer particles are cheaper and flow differently. Reference: E_sp = 10⁵,
//     the paper's rigid-particle limit (App. B, Fig. 10).
//   - Δt ∈ {0.9 × limit, 10⁻³ (the paper's), ½, ¼ of 10⁻³} at E_sp = 10² (--dt-pair-energy).
//     Reference: the smallest.
// Error: |Q − Q_ref|/Q_ref, with its statistical error √(σ_Q² + σ_ref²)/Q_ref beside it (σ: the
// block-averaging error of analysis/common/block_average.hpp, combined over --seeds independent
// runs). Q of one configuration is the mean over --seeds runs (seeds 1…n: random placement, FIRE,
// then flow).
// "error_vs_double" is the error float adds: |Q_float − Q_double|/Q_double at the same E_sp and Δt.
// Cost: wall and process CPU seconds of the flow (FIRE excluded) per t0, one host thread.
//
// Output (<out> = --output without its extension): <out>.csv, one row per configuration and sweep;
// <out>.json, the references, how converged they are, the float speed-up.
// perf/tradeoff/run_hopper runs this and perf/tradeoff/plot_tradeoff_panels.py.
#include "drivers/common/cli.hpp"
#include "drivers/common/output_paths.hpp"
#include "scenes/hopper/flow_measurement.hpp"
#include "scenes/hopper/hopper_scene.hpp"
#include "perf/tradeoff/cost_clock.hpp"
#include "perf/tradeoff/seed_averaged_flow_rate.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace mesoflow {
namespace {

struct Parameters {
  hopper::HopperParameters scene = [] {
    hopper::HopperParameters p;  // N = 300, W = 20, w = 6, θ_w = 90°, E_w = 10⁴ (defaults)
    p.drag = 1 / std::sqrt(10.0);
    p.friction = 0;
    return p;
  }();
  hopper::FlowSettings flow = [] {
    hopper::FlowSettings f;
    f.measure_windows = 80;  // 160 t0 of measurement after the steady state
    f.max_time = 1000;
    return f;
  }();
  std::string pair_energies = "20,50,100,1000,10000,100000";
  double dt_pair_energy = 100;
  int seeds = 4;
  int threads = 1;
  bool quick = false;
};

// The largest step an E_sp allows here: 0.9 × the explicit stability limit.
double stable_dt(hopper::HopperParameters p, double pair_energy) {
  p.pair_energy = pair_energy;
  return 0.9 * p.max_stable_dt(2);
}

struct Config : tradeoff::FlowRateRuns {
  std::string precision;
  double pair_energy = 0, dt = 0;
};

template <class Real>
Config run_config(const Parameters& par, const char* precision, double pair_energy, double dt, bool quiet) {
  Config c;
  static_cast<tradeoff::FlowRateRuns&>(c) = tradeoff::seed_averaged_flow_rate(
      par.seeds, par.scene.seed, par.flow,
      [&](std::uint64_t seed) {
        hopper::HopperParameters p = par.scene;
        p.pair_energy = pair_energy;
        p.dt = dt;
        p.seed = seed;
        return hopper::HopperScene<2, Real>(p);
      },
      std::string("tradeoff_hopper: ") + precision + " E_sp = " + std::to_string(pair_energy) + " Δt = " +
          std::to_string(dt),
      quiet);
  c.precision = precision;
  c.pair_energy = pair_energy;
  c.dt = dt;
  return c;
}

void run(const Parameters& par, const cli::DriverApp& app) {
  const auto energies = cli::parse_number_list(
      par.pair_energies, "--pair-energies", [](double e) { return std::isfinite(e) && e > 0; }, "finite and > 0");
  if (energies.size() < 3) throw std::invalid_argument("--pair-energies: need >= 3 values, got " + par.pair_energies);
  std::vector<double> sorted = energies;
  std::sort(sorted.begin(), sorted.end());
  if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
    throw std::invalid_argument("--pair-energies: values must differ, got " + par.pair_energies);
  if (std::find(sorted.begin(), sorted.end(), par.dt_pair_energy) == sorted.end())
    throw std::invalid_argument("--dt-pair-energy " + std::to_string(par.dt_pair_energy) +
                                " must be one of --pair-energies " + par.pair_energies);
  par.flow.validate();
  par.scene.validate(2);
  // Δt levels at dt_pair_energy: 0.9 × limit (the E_sp sweep's step), the paper's 10⁻³, ½, ¼ of it.
  const double dt_max = stable_dt(par.scene, par.dt_pair_energy);
  std::vector<double> dts{dt_max};
  for (double dt : {1e-3, 5e-4, 2.5e-4})
    if (dt < dt_max) dts.push_back(dt);
  if (dts.size() < 3) throw std::invalid_argument("--dt-pair-energy: its stability limit leaves < 3 time steps");

  std::vector<Config> runs;
  auto run_pair = [&](double e, double dt) {
    runs.push_back(run_config<double>(par, "double", e, dt, app.quiet()));
    runs.push_back(run_config<float>(par, "float", e, dt, app.quiet()));
  };
  for (double e : sorted) run_pair(e, stable_dt(par.scene, e));
  for (double dt : dts)
    if (dt != dt_max) run_pair(par.dt_pair_energy, dt);
  auto find = [&](const std::string& precision, double e, double dt) -> const Config& {
    for (const auto& c : runs)
      if (c.precision == precision && c.pair_energy == e && c.dt == dt) return c;
    throw std::logic_error("tradeoff_hopper: missing run");
  };
  const Config& ref_e = find("double", sorted.back(), stable_dt(par.scene, sorted.back()));
  const Config& ref_dt = find("double", par.dt_pair_energy, dts.back());
  for (const Config* ref : {&ref_e, &ref_dt})
    if (!(ref->Q > 0))
      throw std::runtime_error("tradeoff_hopper: the reference (E_sp = " + std::to_string(ref->pair_energy) +
                               ", Δt = " + std::to_string(ref->dt) + ") did not flow: Q = " + std::to_string(ref->Q));

  const driver::OutputPaths out(app.output());
  std::ofstream csv(out.csv);
  if (!csv) throw std::runtime_error("cannot write " + out.csv);
  csv << std::setprecision(8)
      << "sweep,precision,pair_energy,dt,dt_over_limit,Q,Q_error,clogged_runs,unsteady_runs,flow_time,wall_s,cpu_s,"
         "wall_per_t0,cpu_per_t0,error,error_sigma,error_vs_double\n";
  auto row = [&](const char* sweep, const Config& c, const Config& ref) {
    const bool is_ref = &c == &ref;
    const Config& twin = find("double", c.pair_energy, c.dt);
    csv << sweep << ',' << c.precision << ',' << c.pair_energy << ',' << c.dt << ','
        << c.dt / (stable_dt(par.scene, c.pair_energy) / 0.9) << ',' << c.Q << ',' << c.Q_error << ',' << c.clogged
        << ',' << c.unsteady << ',' << c.flow_time << ',' << c.cost.wall << ',' << c.cost.cpu << ','
        << c.cost.wall / c.flow_time << ',' << c.cost.cpu / c.flow_time << ','
        << (is_ref ? 0.0 : std::abs(c.Q - ref.Q) / ref.Q) << ','
        << (is_ref ? c.Q_error / ref.Q : std::hypot(c.Q_error, ref.Q_error) / ref.Q) << ','
        << (c.precision == "double" ? 0.0 : std::abs(c.Q - twin.Q) / twin.Q) << '\n';
  };
  for (double e : sorted)
    for (const char* p : {"double", "float"}) row("pair_energy", find(p, e, stable_dt(par.scene, e)), ref_e);
  for (double dt : dts)
    for (const char* p : {"double", "float"}) row("dt", find(p, par.dt_pair_energy, dt), ref_dt);
  csv.close();

  const Config& next_e = find("double", sorted[sorted.size() - 2], stable_dt(par.scene, sorted[sorted.size() - 2]));
  const Config& next_dt = find("double", par.dt_pair_energy, dts[dts.size() - 2]);
  double cpu_double = 0, cpu_float = 0, wall_double = 0, wall_float = 0;
  for (const auto& c : runs) {
    (c.precision == "double" ? cpu_double : cpu_float) += c.cost.cpu / c.flow_time;
    (c.precision == "double" ? wall_double : wall_float) += c.cost.wall / c.flow_time;
  }
  auto converged = [](const Config& ref, const Config& next) {
    std::ostringstream s;
    s << std::setprecision(6) << "\"error_of_next_coarser\": " << std::abs(next.Q - ref.Q) / ref.Q
      << ", \"error_sigma\": " << std::hypot(next.Q_error, ref.Q_error) / ref.Q;
    return s.str();
  };
  std::ofstream json(out.summary);
  json << std::setprecision(8) << "{\n  \"program\": \"tradeoff_hopper\",\n  \"scene\": \"2D SP hopper: N = "
       << par.scene.particles << ", W = " << par.scene.hopper_width << ", w = " << par.scene.orifice
       << ", theta_w = " << par.scene.wall_angle << ", E_w = " << par.scene.wall_energy << ", zeta = " << par.scene.drag
       << ", mu = " << par.scene.friction << "\",\n  \"observable\": \"flow rate Q (Q0 = sigma_avg^2/t0), mean of "
       << par.seeds << " seeds, " << par.flow.measure_windows << " windows of " << par.flow.window
       << " t0 after the steady state\",\n  \"reference_pair_energy\": {\"pair_energy\": " << ref_e.pair_energy
       << ", \"dt\": " << ref_e.dt << ", \"Q\": " << ref_e.Q << ", \"Q_error\": " << ref_e.Q_error << ", "
       << converged(ref_e, next_e) << "},\n  \"reference_dt\": {\"pair_energy\": " << ref_dt.pair_energy
       << ", \"dt\": " << ref_dt.dt << ", \"Q\": " << ref_dt.Q << ", \"Q_error\": " << ref_dt.Q_error << ", "
       << converged(ref_dt, next_dt) << "},\n  \"float_speedup_cpu\": " << cpu_double / cpu_float
       << ",\n  \"float_speedup_wall\": " << wall_double / wall_float << ",\n  \"seeds\": " << par.seeds
       << ",\n  \"threads\": " << par.threads << ",\n  \"quick\": " << (par.quick ? "true" : "false")
       << ",\n  \"kokkos\": \"" << kokkos_configuration() << "\"\n}\n";
  if (!app.quiet()) std::cout << "tradeoff_hopper: wrote " << out.csv << " and " << out.summary << '\n';
}

}  // namespace
}  // namespace mesoflow

int main(int argc, char** argv) {
  mesoflow::Parameters par;
  mesoflow::cli::DriverApp app(
      "Speed-accuracy trade-off of the 2D SP hopper: cost per t0 against the error of the flow rate Q for the "
      "particle stiffness E_sp and the time step, float and double",
      "tradeoff_hopper.csv");
  app.add_string("--pair-energies", par.pair_energies, "E_sp levels (>= 3; the largest is the reference)");
  app.add_real("--dt-pair-energy", par.dt_pair_energy, "E_sp of the time-step sweep (one of --pair-energies)", 0.0,
               1e9, mesoflow::cli::Bounds::left_open);
  app.add_real("--orifice", par.scene.orifice, "orifice width w/σ_avg", 0.0, 20.0, mesoflow::cli::Bounds::open);
  app.add_int("--particles", par.scene.particles, "particles N", 2, 100000);
  app.add_int("--seeds", par.seeds, "independent runs per configuration", 1, 1000);
  app.add_int("--measure-windows", par.flow.measure_windows, "windows of 2 t0 averaged into Q after the steady state",
              4, 100000);
  app.add_int("--threads", par.threads, "host threads (0: OMP_NUM_THREADS or all cores)", 0, 4096);
  app.add_flag("--quick", par.quick, "the ctest: E_sp 20, 100, 10⁴, 1 seed, 12 windows; N = 200");
  return app.run(argc, argv, [&] {
    if (par.quick) {
      par.pair_energies = "20,100,10000";
      par.seeds = 1;
      par.flow.measure_windows = 12;
      par.scene.particles = 200;
    }
    mesoflow::KokkosScope kokkos(par.threads);
    mesoflow::run(par, app);
  });
}
