// tradeoff_dp_hopper — speed–accuracy trade-off of the 2D DP hopper (hopper-flows §2.3, §2.4, §4): the
// cost of continuous hopper flow of deformable polygons (scenes/hopper/dp_hopper_scene.hpp) per unit
// of physical time against the error of its flow rate Q (scenes/hopper/flow_measurement.hpp), for
// the time step Δt and a shape stiffness of eq. 8 (the bending stiffness K_b, or the perimeter
// stiffness K_l with --stiffness perimeter), in float and in double. The SP counterpart is
// tradeoff_hopper.cpp.
//
// Scene (defaults): N = 150 bidisperse polygons of N_v = 16 vertices, rough contacts (vertex disks
// δ = l0), W = 15σ_avg, θ_w = 90°, w = 5σ_avg, K_a = 10⁴, K_l = 10, K_b = 0.1, E_c = E_w = 100 (the
// scene's defaults: the paper's 10⁴ is beyond the explicit limit, docs/hopper.md), drag only
// (ζ/ζ0 = 1/√10, μ = 0: the paper's λ → ∞ limit, as the SP report).
// Sweeps:
//   - stiffness (K_b, or K_l) over --stiffnesses, each at the largest step it allows, 0.9 × the
//     scene's explicit stability limit (DpHopperParameters::stability(): the contact and wall modes
//     set it until the bending or spring mode overtakes them). Reference: the largest value, the
//     stiffest (most nearly rigid) polygon.
//   - Δt ∈ {0.9 × limit} ∪ --dts at the stiffness --dt-stiffness. Reference: the smallest.
// Error: |Q − Q_ref|/Q_ref, with its statistical error √(σ_Q² + σ_ref²)/Q_ref beside it (σ: the
// block-averaging error of analysis/common/block_average.hpp, combined over --seeds independent
// runs). Q of one configuration is the mean over --seeds runs (seeds 1…n: random placement, FIRE,
// then flow).
// "error_vs_double" is the error float adds: |Q_float − Q_double|/Q_double at the same stiffness and Δt.
// Cost: wall and process CPU seconds of the flow (FIRE excluded) per t0, one host thread.
//
// Output (<out> = --output without its extension): <out>.csv, one row per configuration and sweep;
// <out>.json, the references, how converged they are, the float speed-up.
// perf/tradeoff/run_dp_hopper runs this and perf/tradeoff/plot_tradeoff_panels.py.
#include "drivers/common/cli.hpp"
#include "drivers/common/output_paths.hpp"
#include "scenes/hopper/dp_hopper_scene.hpp"
#include "scenes/hopper/flow_measurement.hpp"
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
  hopper::DpHopperParameters scene = [] {
    hopper::DpHopperParameters p;  // N_v = 16, rough, K_a = 10⁴, K_l = 10, K_b = 0.1, E_c = E_w = 100
    p.particles = 150;
    p.hopper_width = 15;
    p.orifice = 5;
    p.drag = 1 / std::sqrt(10.0);
    p.friction = 0;
    return p;
  }();
  hopper::FlowSettings flow = [] {
    hopper::FlowSettings f;
    f.measure_windows = 30;  // 60 t0 of measurement after the steady state
    f.max_time = 1000;
    return f;
  }();
  std::string stiffness = "bending";  // which stiffness the sweep varies: bending (K_b) or perimeter (K_l)
  std::string stiffnesses = "0.01,0.1,1,10,100";
  double dt_stiffness = 0.1;
  std::string dts = "5e-4,2.5e-4";
  int seeds = 3;
  int threads = 1;
  bool quick = false;
};

// The CSV column and sweep name of the stiffness, and its symbol.
std::string stiffness_column(const Parameters& par) {
  return par.stiffness == "bending" ? "bending_stiffness" : "perimeter_stiffness";
}
std::string stiffness_symbol(const Parameters& par) { return par.stiffness == "bending" ? "K_b" : "K_l"; }

hopper::DpHopperParameters with_stiffness(const Parameters& par, double k) {
  hopper::DpHopperParameters p = par.scene;
  (par.stiffness == "bending" ? p.bending_stiffness : p.perimeter_stiffness) = k;
  return p;
}

// The explicit limit at a stiffness, and the largest step used: 0.9 × it.
double limit_dt(const Parameters& par, double k) { return with_stiffness(par, k).stability().max_dt(); }
double stable_dt(const Parameters& par, double k) { return 0.9 * limit_dt(par, k); }

struct Config : tradeoff::FlowRateRuns {
  std::string precision;
  double stiffness = 0, dt = 0;
};

template <class Real>
Config run_config(const Parameters& par, const char* precision, double k, double dt, bool quiet) {
  Config c;
  static_cast<tradeoff::FlowRateRuns&>(c) = tradeoff::seed_averaged_flow_rate(
      par.seeds, par.scene.seed, par.flow,
      [&](std::uint64_t seed) {
        hopper::DpHopperParameters p = with_stiffness(par, k);
        p.dt = dt;
        p.seed = seed;
        return hopper::DpHopperScene<Real>(p);
      },
      std::string("tradeoff_dp_hopper: ") + precision + " " + stiffness_symbol(par) + " = " + std::to_string(k) +
          " Δt = " + std::to_string(dt),
      quiet);
  c.precision = precision;
  c.stiffness = k;
  c.dt = dt;
  return c;
}

void run(const Parameters& par, const cli::DriverApp& app) {
  const std::string column = stiffness_column(par), symbol = stiffness_symbol(par);
  const bool bending = par.stiffness == "bending";
  const auto ks = cli::parse_number_list(
      par.stiffnesses, "--stiffnesses",
      [bending](double k) { return std::isfinite(k) && (bending ? k >= 0 : k > 0); },
      bending ? "finite and >= 0" : "finite and > 0");
  if (ks.size() < 3) throw std::invalid_argument("--stiffnesses: need >= 3 values, got " + par.stiffnesses);
  std::vector<double> sorted = ks;
  std::sort(sorted.begin(), sorted.end());
  if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
    throw std::invalid_argument("--stiffnesses: values must differ, got " + par.stiffnesses);
  if (std::find(sorted.begin(), sorted.end(), par.dt_stiffness) == sorted.end()) {
    std::ostringstream s;
    s << "--dt-stiffness " << par.dt_stiffness << " must be one of --stiffnesses " << par.stiffnesses;
    throw std::invalid_argument(s.str());
  }
  par.flow.validate();
  for (double k : sorted) {
    hopper::DpHopperParameters p = with_stiffness(par, k);
    p.dt = stable_dt(par, k);
    p.validate();
  }
  // Δt levels at dt_stiffness: 0.9 × limit (the stiffness sweep's step), then --dts below it.
  const double dt_max = stable_dt(par, par.dt_stiffness);
  const auto extra = cli::parse_number_list(
      par.dts, "--dts", [](double dt) { return std::isfinite(dt) && dt > 0; }, "finite and > 0");
  std::vector<double> dts{dt_max};
  std::vector<double> below;
  for (double dt : extra)
    if (dt < dt_max) below.push_back(dt);
  std::sort(below.begin(), below.end(), std::greater<double>());
  below.erase(std::unique(below.begin(), below.end()), below.end());
  dts.insert(dts.end(), below.begin(), below.end());
  if (dts.size() < 3) {
    std::ostringstream s;
    s << "--dts: need >= 2 steps below 0.9 × the stability limit " << dt_max << " at " << symbol << " = "
      << par.dt_stiffness << ", got " << par.dts;
    throw std::invalid_argument(s.str());
  }

  std::vector<Config> runs;
  auto run_pair = [&](double k, double dt) {
    runs.push_back(run_config<double>(par, "double", k, dt, app.quiet()));
    runs.push_back(run_config<float>(par, "float", k, dt, app.quiet()));
  };
  for (double k : sorted) run_pair(k, stable_dt(par, k));
  for (double dt : dts)
    if (dt != dt_max) run_pair(par.dt_stiffness, dt);
  auto find = [&](const std::string& precision, double k, double dt) -> const Config& {
    for (const auto& c : runs)
      if (c.precision == precision && c.stiffness == k && c.dt == dt) return c;
    throw std::logic_error("tradeoff_dp_hopper: missing run");
  };
  const Config& ref_k = find("double", sorted.back(), stable_dt(par, sorted.back()));
  const Config& ref_dt = find("double", par.dt_stiffness, dts.back());
  for (const Config* ref : {&ref_k, &ref_dt})
    if (!(ref->Q > 0))
      throw std::runtime_error("tradeoff_dp_hopper: the reference (" + symbol + " = " + std::to_string(ref->stiffness) +
                               ", Δt = " + std::to_string(ref->dt) + ") did not flow: Q = " + std::to_string(ref->Q));

  const driver::OutputPaths out(app.output());
  std::ofstream csv(out.csv);
  if (!csv) throw std::runtime_error("cannot write " + out.csv);
  csv << std::setprecision(8) << "sweep,precision,bending_stiffness,perimeter_stiffness,dt,dt_over_limit,Q,Q_error,"
                                 "clogged_runs,unsteady_runs,flow_time,wall_s,cpu_s,wall_per_t0,cpu_per_t0,error,"
                                 "error_sigma,error_vs_double\n";
  auto row = [&](const std::string& sweep, const Config& c, const Config& ref) {
    const bool is_ref = &c == &ref;
    const Config& twin = find("double", c.stiffness, c.dt);
    const hopper::DpHopperParameters p = with_stiffness(par, c.stiffness);
    csv << sweep << ',' << c.precision << ',' << p.bending_stiffness << ',' << p.perimeter_stiffness << ',' << c.dt
        << ',' << c.dt / limit_dt(par, c.stiffness) << ',' << c.Q << ',' << c.Q_error << ',' << c.clogged << ','
        << c.unsteady << ',' << c.flow_time << ',' << c.cost.wall << ',' << c.cost.cpu << ','
        << c.cost.wall / c.flow_time << ',' << c.cost.cpu / c.flow_time << ','
        << (is_ref ? 0.0 : std::abs(c.Q - ref.Q) / ref.Q) << ','
        << (is_ref ? c.Q_error / ref.Q : std::hypot(c.Q_error, ref.Q_error) / ref.Q) << ','
        << (c.precision == "double" ? 0.0 : std::abs(c.Q - twin.Q) / twin.Q) << '\n';
  };
  for (double k : sorted)
    for (const char* p : {"double", "float"}) row(column, find(p, k, stable_dt(par, k)), ref_k);
  for (double dt : dts)
    for (const char* p : {"double", "float"}) row("dt", find(p, par.dt_stiffness, dt), ref_dt);
  csv.close();

  const Config& next_k = find("double", sorted[sorted.size() - 2], stable_dt(par, sorted[sorted.size() - 2]));
  const Config& next_dt = find("double", par.dt_stiffness, dts[dts.size() - 2]);
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
  const auto& sp = par.scene;
  std::ofstream json(out.summary);
  json << std::setprecision(8) << "{\n  \"program\": \"tradeoff_dp_hopper\",\n  \"scene\": \"2D DP hopper: N = "
       << sp.particles << " x N_v = " << sp.vertices << ", " << (sp.smooth ? "smooth" : "rough")
       << " contacts, W = " << sp.hopper_width << ", w = " << sp.orifice << ", theta_w = " << sp.wall_angle
       << ", K_a = " << sp.area_stiffness << ", K_l = " << sp.perimeter_stiffness << ", K_b = " << sp.bending_stiffness
       << ", E_c = " << sp.contact_energy << ", E_w = " << sp.wall_energy << ", zeta = " << sp.drag
       << ", mu = " << sp.friction << " (the swept stiffness replaces its value)\",\n  \"stiffness\": \"" << column
       << "\",\n  \"observable\": \"flow rate Q (Q0 = sigma_avg^2/t0), mean of " << par.seeds << " seeds, "
       << par.flow.measure_windows << " windows of " << par.flow.window
       << " t0 after the steady state\",\n  \"reference_stiffness\": {\"" << column << "\": " << ref_k.stiffness
       << ", \"dt\": " << ref_k.dt << ", \"Q\": " << ref_k.Q << ", \"Q_error\": " << ref_k.Q_error << ", "
       << converged(ref_k, next_k) << "},\n  \"reference_dt\": {\"" << column << "\": " << ref_dt.stiffness
       << ", \"dt\": " << ref_dt.dt << ", \"Q\": " << ref_dt.Q << ", \"Q_error\": " << ref_dt.Q_error << ", "
       << converged(ref_dt, next_dt) << "},\n  \"stability_limit\": [";
  for (std::size_t i = 0; i < sorted.size(); ++i)
    json << (i ? ", " : "") << "{\"" << column << "\": " << sorted[i] << ", \"dt_limit\": " << limit_dt(par, sorted[i])
         << ", \"limiting_term\": \"" << with_stiffness(par, sorted[i]).stability().limiting_term() << "\"}";
  json << "],\n  \"float_speedup_cpu\": " << cpu_double / cpu_float << ",\n  \"float_speedup_wall\": "
       << wall_double / wall_float << ",\n  \"seeds\": " << par.seeds << ",\n  \"threads\": " << par.threads
       << ",\n  \"quick\": " << (par.quick ? "true" : "false") << ",\n  \"kokkos\": \"" << kokkos_configuration()
       << "\"\n}\n";
  if (!app.quiet()) std::cout << "tradeoff_dp_hopper: wrote " << out.csv << " and " << out.summary << '\n';
}

}  // namespace
}  // namespace mesoflow

int main(int argc, char** argv) {
  mesoflow::Parameters par;
  mesoflow::cli::DriverApp app(
      "Speed-accuracy trade-off of the 2D DP hopper: cost per t0 against the error of the flow rate Q for a shape "
      "stiffness (K_b or K_l) and the time step, float and double",
      "tradeoff_dp_hopper.csv");
  app.add_choice("--stiffness", par.stiffness, "the swept stiffness: bending (K_b) or perimeter (K_l)",
                 {"bending", "perimeter"});
  app.add_string("--stiffnesses", par.stiffnesses, "stiffness levels (>= 3; the largest is the reference)");
  app.add_real("--dt-stiffness", par.dt_stiffness, "stiffness of the time-step sweep (one of --stiffnesses)", 0.0,
               1e9);
  app.add_string("--dts", par.dts, "time steps of the Δt sweep besides 0.9 × the limit (those below it are run)");
  app.add_real("--orifice", par.scene.orifice, "orifice width w/σ_avg", 0.0, 20.0, mesoflow::cli::Bounds::open);
  app.add_real("--hopper-width", par.scene.hopper_width, "hopper width W/σ_avg", 0.0, 200.0,
               mesoflow::cli::Bounds::open);
  app.add_int("--particles", par.scene.particles, "polygons N", 2, 100000);
  app.add_int("--vertices", par.scene.vertices, "vertices per polygon N_v", 8, 1024);
  app.add_int("--seeds", par.seeds, "independent runs per configuration", 1, 1000);
  app.add_int("--measure-windows", par.flow.measure_windows, "windows of 2 t0 averaged into Q after the steady state",
              4, 100000);
  app.add_int("--threads", par.threads, "host threads (0: OMP_NUM_THREADS or all cores)", 0, 4096);
  app.add_flag("--quick", par.quick, "the ctest: K_b 0.01, 0.1, 10; Δt 0.9 × limit, 7·10⁻⁴, 5·10⁻⁴; 2 seeds, "
                                     "N = 60, W = 10, 8 windows of 1 t0");
  return app.run(argc, argv, [&] {
    if (par.quick) {
      par.stiffness = "bending";
      par.stiffnesses = "0.01,0.1,10";
      par.dt_stiffness = 0.1;
      par.dts = "7e-4,5e-4";
      par.seeds = 2;  // one seed resolved K_b by 4.0σ, then 2.5σ after a change of trajectories (issue 27)
      par.flow.window = 1;
      par.flow.measure_windows = 8;
      par.scene.particles = 60;
      par.scene.hopper_width = 10;
    }
    mesoflow::KokkosScope kokkos(par.threads);
    mesoflow::run(par, app);
  });
}
