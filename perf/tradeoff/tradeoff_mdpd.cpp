// tradeoff_mdpd.cpp — speed–accuracy trade-off of the MDPD liquid (issue 8): cost per unit physical
// time against the error of its shear viscosity, over the time step dt and the resolution of the
// flow in interaction ranges r_A (= r_c, the unit of length), in float and double.
//
// Fluid: the paper's 2D liquid (docs/mdpd.md: ρ = 6, A = −40, B = 30, r_B = 0.75, R = 12, normalized
// density weight, half neighbor list). Observable: η from periodic Poiseuille flow in a periodic box
// L_x × L_y = 10 × L (region_body_force.hpp's split force along x, reversing at y = 0 and L/2), from
// the fitted curvature (periodic_poiseuille.hpp, bins of 0.5 r_A, those within 1 r_A of the
// reversals left out) — the method of `pillars --mode viscosity`. Resolution: the half-width L/2 of
// each Poiseuille half in units of r_A. The force is g = 2.0/L so that the largest shear rate,
// ρ g L/(4η) ≈ 0.115/τ with η ≈ 26, is the same at every L (the documented 20 × 20 run's g = 0.1);
// the fluid thins under shear, so a fixed g would mix shear thinning into the resolution sweep.
//
// Two sweeps (each with its own reference, the finest level in double):
//   dt ∈ {0.02, 0.015, 0.01, 0.005, 0.0025} at L/2 = 10    (reference dt = 0.0025; a run whose
//   kinetic temperature leaves k_BT ± 0.5 is stopped and marked unstable)
//   L/2 ∈ {5, 7.5, 10, 15} at dt = 0.01              (reference L/2 = 15)
// Each run: particles uniform, 5τ at rest, then the force on, a warm-up of max(10τ, 5 relaxation
// times (L/2)²ρ/(π²η)), then `--sample-time` τ sampled every 0.1τ in 10 blocks. Cost: wall and
// process-CPU seconds of the whole run per τ.
#include "drivers/common/cli.hpp"
#include "drivers/pillars/pillar_scene.hpp"
#include "kernels/common/box.hpp"
#include "kernels/common/kokkos_compat.hpp"
#include "kernels/common/reductions.hpp"
#include "kernels/mdpd/mdpd_system.hpp"
#include "perf/tradeoff/cost_clock.hpp"
#include "perf/tradeoff/periodic_poiseuille.hpp"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace mesoflow {
namespace {

constexpr int D = 2;
constexpr double kLx = 10, kRho = 6, kEtaNominal = 26.1, kShearRate = 0.115, kBinWidth = 0.5, kExclude = 1.0;
constexpr double kRest = 5;
constexpr int kBlocks = 10;
constexpr int NB = pillars::max_profile_bins;

// A JSON number, or null where it is not finite (an unstable run).
std::string json_number(double x) {
  if (!std::isfinite(x)) return "null";
  std::ostringstream s;
  s << std::setprecision(9) << x;
  return s.str();
}

struct Settings {
  double sample_time = 300;
  long long seed = 7;
};

struct Row {
  std::string sweep, precision;
  double dt = 0, half_width = 0, g = 0;
  long long particles = 0, steps = 0;
  double warmup_time = 0, sample_time = 0, eta = 0, eta_stderr = 0, temperature = 0;
  double wall_per_tau = 0, cpu_per_tau = 0;
  bool finite = true;
};

template <class Real>
Row run_case(const std::string& sweep, double dt, double half_width, const Settings& s) {
  using Exec = Kokkos::DefaultExecutionSpace;
  const double Ly = 2 * half_width;
  const double g = kShearRate * 4 * kEtaNominal / (kRho * Ly);
  mdpd::MdpdParameters mp;
  mp.B = 30;
  mp.dt = dt;
  mp.validate();
  pillars::SceneGeometry geometry;
  geometry.dim = D;
  geometry.Lx = kLx;
  geometry.Ly = Ly;
  bool periodic[D] = {true, true};
  Real lor[D] = {0, 0}, lenr[D] = {Real(kLx), Real(Ly)};
  const Box<D, Real> box(lor, lenr, periodic);
  mdpd::MdpdSystem<D, Real, Exec> sys(mp, box, std::uint64_t(s.seed));
  pillars::fill_fluid(sys, geometry, kRho, std::uint64_t(s.seed));
  const int bins = int(std::lround(Ly / kBinWidth));
  if (bins > NB) throw std::invalid_argument("tradeoff_mdpd: too many profile bins");
  const double relax = half_width * half_width * kRho / (M_PI * M_PI * kEtaNominal);
  const long long rest = std::llround(kRest / dt);
  const long long warmup = std::llround(std::max(10.0, 5 * relax) / dt);
  const long long every = std::max(1LL, std::llround(0.1 / dt));
  const long long samples = std::max<long long>(kBlocks, std::llround(s.sample_time / dt) / every);
  const long long steps = rest + warmup + samples * every;
  tradeoff::BlockedProfile profile(bins, kBlocks, samples);

  Kokkos::fence();
  const tradeoff::CostClock clock;
  sys.begin();
  const auto x = sys.particles.x;
  const auto v = sys.particles.v;
  const int N = int(sys.particles.size());
  double t_sum = 0;
  long long sample = 0;
  bool unstable = false;
  long long done = 0;
  for (long long step = 0; step < steps; ++step) {
    if (step == rest) sys.set_split_force({Real(g)});
    sys.step();
    ++done;
    if (step >= rest + warmup && (step - rest - warmup + 1) % every == 0) {
      const double bw = Ly / bins;
      const auto sums = parallel_sum<2 * NB, Exec>(
          "mesoflow::tradeoff::mdpd::profile", N, KOKKOS_LAMBDA(int i, double(&acc)[2 * NB]) {
            double y = double(x(i, D - 1));
            y -= Ly * kmath::floor(y / Ly);
            int b = int(y / bw);
            b = b < 0 ? 0 : (b >= bins ? bins - 1 : b);  // (a non-finite y of a blown-up run lands in bin 0)
            acc[b] += 1.0;
            acc[NB + b] += double(v(i, 0));
          });
      profile.add(sample++, sums, NB);
      const double t = mdpd::kinetic_temperature(sys.particles);
      t_sum += t;
      if (!(std::abs(t - mp.kT) < 0.5)) {  // unstable at this dt: stop, the row is marked
        unstable = true;
        break;
      }
    }
  }
  Kokkos::fence();
  const tradeoff::Cost cost = clock.elapsed();

  Row r;
  r.sweep = sweep;
  r.precision = sizeof(Real) == 4 ? "float" : "double";
  r.dt = dt;
  r.half_width = half_width;
  r.g = g;
  r.particles = N;
  r.steps = done;
  r.warmup_time = double(rest + warmup) * dt;
  r.sample_time = double(samples * every) * dt;
  // Thermal temperature: the kinetic temperature less the streaming profile's share (as the pillars
  // driver's viscosity mode reports it).
  r.temperature = t_sum / double(std::max(1LL, sample)) - (unstable ? 0.0 : profile.mean_square_stream_velocity() / D);
  r.wall_per_tau = cost.wall / (double(done) * dt);
  r.cpu_per_tau = cost.cpu / (double(done) * dt);
  r.finite = !unstable;
  if (r.finite) {
    const auto fit = profile.fit(Ly, kExclude);
    r.eta = kRho * g / (2 * fit.curvature);
    r.eta_stderr = std::abs(r.eta * fit.curvature_stderr / fit.curvature);
  } else {
    r.eta = r.eta_stderr = std::numeric_limits<double>::quiet_NaN();
  }
  return r;
}

void run(bool quick, const Settings& s, const std::string& json_path, bool quiet) {
  // (sweep, dt, L/2); the last entry of each sweep is its reference.
  struct Case {
    const char* sweep;
    double dt, half_width;
  };
  const std::vector<Case> cases =
      quick ? std::vector<Case>{{"dt", 0.02, 5}, {"dt", 0.01, 5}, {"dt", 0.005, 5}}
            : std::vector<Case>{{"dt", 0.02, 10},          {"dt", 0.015, 10},        {"dt", 0.01, 10},
                                {"dt", 0.005, 10},         {"dt", 0.0025, 10},       {"resolution", 0.01, 5},
                                {"resolution", 0.01, 7.5}, {"resolution", 0.01, 10}, {"resolution", 0.01, 15}};
  std::vector<Row> rows;
  for (const char* precision : {"double", "float"}) {
    for (const Case& c : cases) {
      rows.push_back(std::string(precision) == "double" ? run_case<double>(c.sweep, c.dt, c.half_width, s)
                                                        : run_case<float>(c.sweep, c.dt, c.half_width, s));
      const Row& r = rows.back();
      if (!quiet)
        std::cerr << std::setprecision(4) << "tradeoff_mdpd: " << r.precision << " " << r.sweep << " dt = " << r.dt
                  << " L/2 = " << r.half_width << ": eta " << r.eta << " ± " << r.eta_stderr << ", T " << r.temperature
                  << ", " << r.cpu_per_tau << " cpu s/tau, " << r.wall_per_tau << " wall s/tau\n";
    }
  }
  // The reference of each sweep: its last case in double.
  auto reference = [&](const std::string& sweep) -> const Row& {
    const Row* ref = nullptr;
    for (const Row& r : rows)
      if (r.precision == "double" && r.sweep == sweep) ref = &r;
    return *ref;
  };
  const std::string stem = json_path.size() > 5 && json_path.substr(json_path.size() - 5) == ".json"
                               ? json_path.substr(0, json_path.size() - 5)
                               : json_path;
  std::ofstream csv(stem + ".csv");
  csv << "sweep,precision,dt,half_width,particles,steps,warmup_tau,sample_tau,g,eta,eta_stderr,temperature,"
         "rel_err_ref,rel_err_ref_stderr,wall_s_per_tau,cpu_s_per_tau,stable\n"
      << std::setprecision(9);
  for (const Row& r : rows) {
    const Row& ref = reference(r.sweep);
    const bool is_ref = &ref == &r;
    csv << r.sweep << "," << r.precision << "," << r.dt << "," << r.half_width << "," << r.particles << "," << r.steps
        << "," << r.warmup_time << "," << r.sample_time << "," << r.g << "," << r.eta << "," << r.eta_stderr << ","
        << r.temperature << "," << r.eta / ref.eta - 1 << ","
        << (is_ref ? 0.0 : std::hypot(r.eta_stderr, r.eta * ref.eta_stderr / ref.eta) / ref.eta) << ","
        << r.wall_per_tau << "," << r.cpu_per_tau << "," << (r.finite ? 1 : 0) << "\n";
  }
  std::ofstream json(json_path);
  json << std::setprecision(9) << "{\n  \"program\": \"tradeoff_mdpd\",\n  \"observable\": \"shear viscosity (periodic "
       << "Poiseuille, 2D paper fluid)\",\n  \"quick\": " << (quick ? "true" : "false")
       << ",\n  \"threads\": " << concurrency<Kokkos::DefaultExecutionSpace>() << ",\n  \"references\": [";
  bool first = true;
  for (const char* sweep : {"dt", "resolution"}) {
    bool present = false;
    for (const Row& r : rows) present = present || r.sweep == sweep;
    if (!present) continue;
    const Row& ref = reference(sweep);
    // The reference's own convergence: the second-finest level of the sweep.
    const Row* next = nullptr;
    for (const Row& r : rows)
      if (r.precision == "double" && r.sweep == sweep && &r != &ref) next = &r;
    json << (first ? "\n" : ",\n") << "    {\"sweep\": \"" << sweep << "\", \"dt\": " << ref.dt
         << ", \"half_width\": " << ref.half_width << ", \"eta\": " << ref.eta << ", \"stderr\": " << ref.eta_stderr
         << ", \"second_finest_eta\": " << next->eta << ", \"second_finest_stderr\": " << next->eta_stderr << "}";
    first = false;
  }
  json << "\n  ],\n  \"float_vs_double\": [";
  first = true;
  for (const Row& f : rows) {
    if (f.precision != "float") continue;
    for (const Row& d : rows) {
      if (d.precision != "double" || d.sweep != f.sweep || d.dt != f.dt || d.half_width != f.half_width) continue;
      json << (first ? "\n" : ",\n") << "    {\"sweep\": \"" << f.sweep << "\", \"dt\": " << f.dt
           << ", \"half_width\": " << f.half_width << ", \"cpu_speedup\": " << d.cpu_per_tau / f.cpu_per_tau
           << ", \"wall_speedup\": " << d.wall_per_tau / f.wall_per_tau
           << ", \"eta_float_over_double_minus_1\": " << json_number(f.eta / d.eta - 1)
           << ", \"combined_stderr\": " << json_number(std::hypot(f.eta_stderr / d.eta, d.eta_stderr / d.eta)) << "}";
      first = false;
    }
  }
  json << "\n  ]\n}\n";
  if (!quiet) std::cerr << "tradeoff_mdpd: wrote " << stem << ".csv and " << json_path << "\n";
}

}  // namespace
}  // namespace mesoflow

int main(int argc, char** argv) {
  mesoflow::Settings s;
  bool quick = false;
  int threads = 1;
  mesoflow::cli::DriverApp app("MDPD speed–accuracy trade-off: cost per τ against the error of the viscosity",
                               "tradeoff_mdpd.json");
  app.add_flag("--quick", quick, "small grid (dt = 0.02, 0.01, 0.005 at L/2 = 5) for the ctest");
  app.add_real("--sample-time", s.sample_time, "sampled physical time per setting (τ)", 1.0, 1e6);
  app.add_int("--seed", s.seed, "random seed", 0, 4294967295LL);
  app.add_int("--threads", threads, "host threads (0: OMP_NUM_THREADS or all cores)", 0, 4096);
  return app.run(argc, argv, [&] {
    mesoflow::KokkosScope kokkos(threads);
    mesoflow::run(quick, s, app.output(), app.quiet());
  });
}
