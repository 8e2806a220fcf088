// tradeoff_droplet — speed–accuracy trade-off of the DP droplet (capillary-droplets §2, App. B):
// the cost of one orifice passage (scenes/droplets/orifice_run.hpp, the Fig. 2 scene) per unit of
// physical time against the error of its speed profile v_g(h), for the number of vertices N_v and
// the time step Δt, in float and in double. Scene: the Fig. 2 droplet (Γ = 0.16, b0/b∞ = 0.064,
// V_t = 0.08, K_l/Γ = 10⁻³) through a w = 0.7σ orifice (passage ~70 t0; Fig. 2's w = 0.4σ takes
// ~290 t0, too long for N_v = 1024 in float and double within the report's budget; --width 0.4).
//
// Error: Δ_v of eq. 14 (App. B uses it to choose N_v and K_l), √(Σ_i ((v_ref,i − v_i)/v_i)²/N_f),
// with the converged reference's samples in −1.2σ ≤ h ≤ 0.9σ as the "measured" frames (a run stops
// at h = 1σ, so frames past 0.9σ would meet no sample of a run that stopped a sample earlier), the run's
// v_g interpolated between its samples at each h_i (analysis/droplets/profile_calibration.hpp).
// References, both in double: the finest N_v at its automatic Δt for the N_v sweep; the smallest Δt
// at --dt-vertices for the Δt sweep. "delta_v_vs_double" is the error float adds: Δ_v of the float run
// against the double run of the same N_v and Δt.
//
// Cost: wall and process CPU seconds of the whole passage (FIRE relaxation included, a few ms) per
// t0 of simulated time, one host thread unless --threads says otherwise.
//
// Output (<out> = --output without its extension): <out>.csv, one row per run and sweep;
// <out>.json, the references, how converged they are (the Δ_v between the two finest levels), and
// the float speed-up. perf/tradeoff/run_droplet runs this and perf/tradeoff/plot_tradeoff_panels.py.
#include "drivers/common/cli.hpp"
#include "drivers/common/output_paths.hpp"
#include "analysis/droplets/profile_calibration.hpp"
#include "scenes/droplets/orifice_run.hpp"
#include "perf/tradeoff/cost_clock.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace mesoflow {
namespace {

struct Parameters {
  droplets::OrificeScene scene = [] {
    droplets::OrificeScene s;  // the Fig. 2 droplet (Γ = 0.16, b0/b∞ = 0.064, V_t = 0.08) at w = 0.7σ
    s.width = 0.7;
    return s;
  }();
  double perimeter_ratio = 1e-3;  // K_l/Γ (App. B)
  int max_vertices = 1024;
  int min_vertices = 16;
  int dt_vertices = 256;
  double frames_from_h = -1.2;  // σ: reference samples from here ...
  double frames_to_h = 0.9;     // ... to here are the frames of eq. 14
  int threads = 1;
  bool quick = false;
};

struct Run {
  std::string precision;
  int vertices;
  double dt, dt_factor;
  droplets::OrificeProfile profile;
  tradeoff::Cost cost;
  std::string failure;  // the NaN watchdog's diagnosis when the run went non-finite; empty otherwise
};

std::vector<double> speed_over_vt(const droplets::OrificeProfile& p, double vt) {
  std::vector<double> v(p.vg.size());
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = p.vg[i] / vt;
  return v;
}

// The frames of eq. 14 taken from a profile: its samples from the first with h ≥ from_h to the
// last with h ≤ to_h.
droplets::MeasuredProfile frames_of(const droplets::OrificeProfile& p, double vt, double from_h, double to_h) {
  droplets::MeasuredProfile m;
  bool started = false;
  for (std::size_t i = 0; i < p.h.size(); ++i) {
    started = started || p.h[i] >= from_h;
    if (!started || p.h[i] > to_h) continue;
    m.h.push_back(p.h[i]);
    m.vg_over_vt.push_back(p.vg[i] / vt);
  }
  if (m.h.size() < 3) throw std::runtime_error("tradeoff_droplet: the reference profile has < 3 samples past h = " +
                                               std::to_string(from_h) +
                                               " and below h = " + std::to_string(to_h));
  return m;
}

template <class Real>
Run run_one(const Parameters& par, const char* precision, int vertices, double dt_factor, bool quiet) {
  droplets::OrificeScene s = par.scene;
  s.droplet.vertices = vertices;
  s.droplet.perimeter_stiffness = par.perimeter_ratio * s.droplet.line_tension;
  s.droplet.dt = 0;
  s.droplet.dt = dt_factor * droplets::resolve_time_step(s.droplet, true);
  Run r{precision, vertices, s.droplet.dt, dt_factor, {}, {}, {}};
  const tradeoff::CostClock clock;
  try {
    r.profile = droplets::run_orifice<Real>(s, [](const auto&, const auto&) {});
  } catch (const watchdog::NonFiniteState& e) {  // a result of the report (float at large N_v), not an error
    r.failure = e.what();
  }
  r.cost = clock.elapsed();
  if (!quiet) {
    std::cerr << "tradeoff_droplet: " << precision << " N_v = " << vertices << " Δt = " << r.dt << ": ";
    if (r.failure.empty())
      std::cerr << droplets::to_string(r.profile.outcome) << " at t = " << r.profile.t.back() << " t0";
    else
      std::cerr << "non-finite (" << r.failure << ")";
    std::cerr << ", " << r.cost.wall << " s wall, " << r.cost.cpu << " s CPU\n";
  }
  return r;
}

void run(const Parameters& par, const cli::DriverApp& app) {
  if (par.min_vertices > par.max_vertices)
    throw std::invalid_argument("--min-vertices " + std::to_string(par.min_vertices) + " must be <= --max-vertices " +
                                std::to_string(par.max_vertices));
  if (par.dt_vertices < par.min_vertices || par.dt_vertices > par.max_vertices)
    throw std::invalid_argument("--dt-vertices " + std::to_string(par.dt_vertices) + " must lie in [--min-vertices, "
                                "--max-vertices] = [" + std::to_string(par.min_vertices) + ", " +
                                std::to_string(par.max_vertices) + "]");
  const double vt = par.scene.droplet.terminal_speed;
  std::vector<int> vertex_levels;
  for (int n = par.min_vertices; n <= par.max_vertices; n *= 2) vertex_levels.push_back(n);
  if (vertex_levels.back() != par.max_vertices) vertex_levels.push_back(par.max_vertices);
  if (vertex_levels.size() < 3) throw std::invalid_argument("--min-vertices, --max-vertices: need >= 3 levels N_v, N_v·2, ...");

  // Δt levels at dt_vertices: ×2 where the stability limit allows it, 1, ½, ¼ of the automatic step.
  droplets::DropletParameters d = par.scene.droplet;
  d.vertices = par.dt_vertices;
  d.perimeter_stiffness = par.perimeter_ratio * d.line_tension;
  const double dt_auto = droplets::resolve_time_step(d, true);
  std::vector<double> dt_factors;
  if (2 * dt_auto <= droplets::droplet_stability(d, true).max_dt()) dt_factors.push_back(2);
  for (double f : {1.0, 0.5, 0.25}) dt_factors.push_back(f);

  // Runs: double and float back to back, so both meet the same load on a shared machine.
  std::vector<Run> runs;
  auto run_pair = [&](int n, double f) {
    runs.push_back(run_one<double>(par, "double", n, f, app.quiet()));
    runs.push_back(run_one<float>(par, "float", n, f, app.quiet()));
  };
  for (int n : vertex_levels) run_pair(n, 1.0);
  for (double f : dt_factors)
    if (f != 1.0) run_pair(par.dt_vertices, f);
  auto find = [&](const std::string& precision, int n, double f) -> const Run& {
    for (const auto& r : runs)
      if (r.precision == precision && r.vertices == n && r.dt_factor == f) return r;
    throw std::logic_error("tradeoff_droplet: missing run");
  };
  const Run& ref_n = find("double", vertex_levels.back(), 1.0);
  const Run& ref_dt = find("double", par.dt_vertices, dt_factors.back());
  for (const Run* ref : {&ref_n, &ref_dt})
    if (!ref->failure.empty())
      throw std::runtime_error("tradeoff_droplet: the reference (double, N_v = " + std::to_string(ref->vertices) +
                               ") went non-finite: " + ref->failure);
  const auto frames_n = frames_of(ref_n.profile, vt, par.frames_from_h, par.frames_to_h);
  const auto frames_dt = frames_of(ref_dt.profile, vt, par.frames_from_h, par.frames_to_h);
  auto delta_v = [&](const droplets::MeasuredProfile& frames, const Run& r) {
    return r.failure.empty() ? droplets::speed_deviation(frames, r.profile.h, speed_over_vt(r.profile, vt)) : NAN;
  };

  const driver::OutputPaths out(app.output());
  std::ofstream csv(out.csv);
  if (!csv) throw std::runtime_error("cannot write " + out.csv);
  csv << std::setprecision(8)
      << "sweep,precision,vertices,dt,dt_factor,outcome,t_end,steps,wall_s,cpu_s,wall_per_t0,cpu_per_t0,delta_v,"
         "delta_v_vs_double,max_vg_over_vt_after\n";
  // A run that went non-finite has outcome non_finite and NaN in the columns it could not measure.
  auto row = [&](const char* sweep, const Run& r, const droplets::MeasuredProfile& frames) {
    const bool ok = r.failure.empty();
    const double t = ok ? r.profile.t.back() : NAN;
    double vmax = ok ? 0.0 : NAN;
    for (std::size_t i = 0; i < r.profile.h.size(); ++i)
      if (r.profile.h[i] > 0) vmax = std::max(vmax, r.profile.vg[i] / vt);
    const Run& twin = find("double", r.vertices, r.dt_factor);
    const double vs_double =
        r.precision == "double" ? 0.0
        : twin.failure.empty()  ? delta_v(frames_of(twin.profile, vt, par.frames_from_h, par.frames_to_h), r)
                                : NAN;
    csv << sweep << ',' << r.precision << ',' << r.vertices << ',' << r.dt << ',' << r.dt_factor << ','
        << (ok ? droplets::to_string(r.profile.outcome) : "non_finite") << ',' << t << ',' << r.profile.steps << ',' << r.cost.wall << ','
        << r.cost.cpu << ',' << r.cost.wall / t << ',' << r.cost.cpu / t << ',' << delta_v(frames, r) << ','
        << vs_double << ',' << vmax << '\n';
  };
  for (int n : vertex_levels)
    for (const char* p : {"double", "float"}) row("vertices", find(p, n, 1.0), frames_n);
  for (double f : dt_factors)
    for (const char* p : {"double", "float"}) row("dt", find(p, par.dt_vertices, f), frames_dt);
  csv.close();

  // Summary: references, their convergence (Δ_v of the second-finest level), float speed-up over
  // the configurations both precisions completed (CPU per t0 summed, so the costliest dominate).
  const Run& next_n = find("double", vertex_levels[vertex_levels.size() - 2], 1.0);
  const Run& next_dt = find("double", par.dt_vertices, dt_factors[dt_factors.size() - 2]);
  double cpu_double = 0, cpu_float = 0, wall_double = 0, wall_float = 0;
  std::string failures;
  for (const auto& r : runs) {
    if (!r.failure.empty()) {
      std::string msg = r.failure;
      std::replace(msg.begin(), msg.end(), '"', '\'');
      failures += std::string(failures.empty() ? "" : ",\n    ") + "{\"precision\": \"" + r.precision +
                  "\", \"vertices\": " + std::to_string(r.vertices) + ", \"dt_factor\": " + std::to_string(r.dt_factor) +
                  ", \"diagnosis\": \"" + msg + "\"}";
      continue;
    }
    if (r.precision != "float") continue;
    const Run& twin = find("double", r.vertices, r.dt_factor);
    if (!twin.failure.empty()) continue;
    cpu_float += r.cost.cpu / r.profile.t.back();
    wall_float += r.cost.wall / r.profile.t.back();
    cpu_double += twin.cost.cpu / twin.profile.t.back();
    wall_double += twin.cost.wall / twin.profile.t.back();
  }
  std::ofstream json(out.summary);
  json << std::setprecision(8) << "{\n  \"program\": \"tradeoff_droplet\",\n  \"scene\": \"orifice, Fig. 2 droplet: w = "
       << par.scene.width << ", Gamma = " << par.scene.droplet.line_tension << ", b0/binf = "
       << par.scene.droplet.near_wall_drag << ", V_t = " << vt << ", K_l/Gamma = " << par.perimeter_ratio
       << "\",\n  \"observable\": \"Delta_v of eq. 14 over v_g(h)/v_t, frames in h = [" << par.frames_from_h << ", "
       << par.frames_to_h << "]\",\n  \"reference_vertices\": {\"vertices\": " << ref_n.vertices << ", \"dt\": " << ref_n.dt
       << ", \"frames\": " << frames_n.h.size() << ", \"delta_v_of_next_coarser\": " << delta_v(frames_n, next_n)
       << "},\n  \"reference_dt\": {\"vertices\": " << ref_dt.vertices << ", \"dt\": " << ref_dt.dt
       << ", \"frames\": " << frames_dt.h.size() << ", \"delta_v_of_next_coarser\": " << delta_v(frames_dt, next_dt)
       << "},\n  \"float_speedup_cpu\": " << cpu_double / cpu_float << ",\n  \"float_speedup_wall\": "
       << wall_double / wall_float << ",\n  \"threads\": " << par.threads << ",\n  \"quick\": "
       << (par.quick ? "true" : "false") << ",\n  \"non_finite_runs\": [" << (failures.empty() ? "" : "\n    ")
       << failures << "],\n  \"kokkos\": \"" << kokkos_configuration() << "\"\n}\n";
  if (!app.quiet()) std::cout << "tradeoff_droplet: wrote " << out.csv << " and " << out.summary << '\n';
}

}  // namespace
}  // namespace mesoflow

int main(int argc, char** argv) {
  using mesoflow::cli::Bounds;
  mesoflow::Parameters par;
  mesoflow::cli::DriverApp app(
      "Speed-accuracy trade-off of the DP droplet through the Fig. 2 orifice: cost per t0 against Delta_v of "
      "v_g(h) (eq. 14) for N_v and dt, float and double",
      "tradeoff_droplet.csv");
  app.add_int("--min-vertices", par.min_vertices, "coarsest N_v of the sweep (doubled up to --max-vertices)", 8, 4096);
  app.add_int("--max-vertices", par.max_vertices, "finest N_v: the reference of the N_v sweep", 8, 4096);
  app.add_int("--dt-vertices", par.dt_vertices, "N_v of the time-step sweep", 8, 4096);
  app.add_real("--width", par.scene.width, "orifice width w/σ", 0.0, 10.0, Bounds::left_open);
  app.add_real("--frames-from-h", par.frames_from_h, "reference samples from this h/σ on are the frames of eq. 14",
               -1000.0, 0.0);
  app.add_real("--frames-to-h", par.frames_to_h, "... up to this h/σ (below the end height 1σ)", 0.0, 1.0,
               Bounds::right_open);
  app.add_int("--threads", par.threads, "host threads (0: OMP_NUM_THREADS or all cores)", 0, 4096);
  app.add_flag("--quick", par.quick, "the ctest: N_v 16..64, time-step sweep at N_v = 16");
  return app.run(argc, argv, [&] {
    if (par.quick) {
      par.min_vertices = 16;
      par.max_vertices = 64;
      par.dt_vertices = 16;
    }
    mesoflow::KokkosScope kokkos(par.threads);
    mesoflow::run(par, app);
  });
}
