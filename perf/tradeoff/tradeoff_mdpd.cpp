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
//
// --observable permeability: the Darcy permeability κ of a 2D square pillar array (the `pillars`
// driver's scene, scenes/pillars/pillar_scene.hpp: fluid equilibrated at rest, pillars carved from
// it as tethered solid particles, k_S = 12.5, cores deeper than 1.2σ repelling the fluid by WCA), at
// porosity ε = --porosity (0.8), over the time step and the resolution of the geometry in
// interaction ranges: the pillar diameter d/r_A (r_A = r_c = 1) at fixed ε, so the lattice spacing
// s = d √(π/(4(1 − ε))) and every length of the geometry scale with d — the finer, the more r_c
// across a pillar and a gap. The box is one unit cell s × s (one pillar at its centre; κ of a square
// array is a property of the unit cell), periodic. The whole fluid is driven by f_b along x (the
// paper's driving region with L_d = L_x), so Darcy with the paper's Δp = f_b ρ L_d gives
// κ = μ ε ⟨u_x⟩ / (f_b ρ), ⟨u_x⟩ the mean fluid-particle velocity, μ = 26.1 (the paper's 2D value),
// ε the geometric porosity; κ/d² is compared with Sangani & Acrivos's exact Stokes value where ε is
// in their Table 1 (0.07621 at ε = 0.8). f_b = f0 · 5/d (f0 = --driving-force, 0.2) keeps the
// shear rates the same at every d (⟨u⟩ ∝ κ f_b ∝ d² f_b, gaps ∝ d), as the viscosity sweep keeps its
// shear rate; at d = 5 ⟨u_x⟩ ≈ 0.1.
//   dt ∈ {0.015, 0.01, 0.005, 0.0025} at d = 5          (reference dt = 0.0025)
//   d ∈ {2.5, 3.5, 5, 7, 10} at dt = 0.01               (reference d = 10)
// Each run: fluid at rest for 10τ, carve, force on, a warm-up of max(20τ, 5 s²ρ/(π²μ)), then
// `--sample-time` τ sampled every 0.1τ; κ's standard error from 10 block means. A run whose fluid
// temperature leaves k_BT ± 0.5 is stopped and marked unstable.
#include "drivers/common/cli.hpp"
#include "analysis/pillars/permeability_theory.hpp"
#include "scenes/pillars/pillar_layouts.hpp"
#include "scenes/pillars/pillar_scene.hpp"
#include "kernels/common/box.hpp"
#include "kernels/common/kokkos_compat.hpp"
#include "kernels/common/reductions.hpp"
#include "scenes/pillars/mdpd_system.hpp"
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
  double porosity = 0.8;       // permeability: ε of the square array
  double driving_force = 0.2;  // permeability: f_b at d = 5 (f_b = f0 · 5/d)
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


// ---- permeability (--observable permeability) ----

constexpr double kMu2D = 26.1, kD0 = 5.0;

// Sangani & Acrivos's exact κ/d² of a square array at ε, where ε is in their Table 1; NaN elsewhere.
double sangani_acrivos_exact(double porosity) {
  for (const auto& row : pillars::sangani_acrivos_square_table())
    if (std::abs(row[0] - porosity) < 1e-9) return row[1];
  return std::numeric_limits<double>::quiet_NaN();
}

struct KappaRow {
  std::string sweep, precision;
  double dt = 0, diameter = 0, spacing = 0, porosity = 0, fb = 0;
  long long particles = 0, solids = 0, steps = 0;
  double warmup_time = 0, sample_time = 0, mean_u = 0, mean_u_stderr = 0, kappa = 0, kappa_stderr = 0;
  double temperature = 0;  // fluid kinetic temperature (mean flow removed), over the samples
  double wall_per_tau = 0, cpu_per_tau = 0;
  bool finite = true;
};

template <class Real>
KappaRow run_kappa(const std::string& sweep, double dt, double diameter, const Settings& s) {
  using Exec = Kokkos::DefaultExecutionSpace;
  const pillars::PillarLayout layout =
      pillars::regular_lattice(pillars::Lattice::square, s.porosity, diameter, 1, 1);
  pillars::SceneGeometry g;
  g.dim = D;
  g.Lx = layout.length_x;
  g.Ly = layout.length_y;
  g.diameter = layout.diameter;
  g.centres = layout.centres;
  const double fb = s.driving_force * kD0 / diameter;
  mdpd::MdpdParameters mp;
  mp.B = 30;
  mp.dt = dt;
  mp.validate();
  mdpd::MdpdOptions opt;  // k_S = 12.5, WCA cores ε = σ = 1: the pillars driver's
  bool periodic[D] = {true, true};
  Real lor[D] = {0, 0}, lenr[D] = {Real(g.Lx), Real(g.Ly)};
  const Box<D, Real> box(lor, lenr, periodic);
  mdpd::MdpdSystem<D, Real, Exec> sys(mp, box, std::uint64_t(s.seed), opt);
  pillars::fill_fluid(sys, g, kRho, std::uint64_t(s.seed));
  Kokkos::View<double*, Exec> pillar_x("mesoflow::tradeoff::mdpd::pillar_x", 1);
  Kokkos::deep_copy(pillar_x, g.centres[0][0]);

  const double relax = g.Lx * g.Lx * kRho / (M_PI * M_PI * kMu2D);
  const long long rest = std::llround(10.0 / dt);
  const long long warmup = std::llround(std::max(20.0, 5 * relax) / dt);
  const long long every = std::max(1LL, std::llround(0.1 / dt));
  const long long samples = std::max<long long>(kBlocks, std::llround(s.sample_time / dt) / every);
  const long long steps = rest + warmup + samples * every;
  std::vector<double> block_u(kBlocks, 0.0), block_n(kBlocks, 0.0);

  Kokkos::fence();
  const tradeoff::CostClock clock;
  sys.begin();
  long long done = 0;
  for (; done < rest; ++done) sys.step();
  const int solids = pillars::carve_solids(sys, g);
  sys.begin(sys.current_step());
  mdpd::DrivingRegion<Real> region;
  region.force = Real(fb);
  region.x0 = 0;
  region.length = Real(g.Lx);
  sys.set_driving_region(region);
  double t_sum = 0;
  long long sample = 0;
  bool unstable = false;
  for (; done < steps; ++done) {
    sys.step();
    if (done + 1 > rest + warmup && (done + 1 - rest - warmup) % every == 0) {
      const auto fs = pillars::sample_flow(sys, g, pillar_x, 0.0, g.Lx, 1);
      const int k = int(std::min<long long>(kBlocks - 1, sample * kBlocks / samples));
      block_u[k] += fs.velocity[0];
      block_n[k] += fs.count[0];
      ++sample;
      const double t = mdpd::kinetic_temperature(sys.particles, int(mdpd::particle_type::fluid));
      t_sum += t;
      if (!(std::abs(t - mp.kT) < 0.5) || !std::isfinite(fs.velocity[0])) {  // unstable at this dt
        unstable = true;
        ++done;
        break;
      }
    }
  }
  Kokkos::fence();
  const tradeoff::Cost cost = clock.elapsed();

  KappaRow r;
  r.sweep = sweep;
  r.precision = sizeof(Real) == 4 ? "float" : "double";
  r.dt = dt;
  r.diameter = diameter;
  r.spacing = g.Lx;
  r.porosity = layout.porosity();
  r.fb = fb;
  r.particles = (long long)sys.particles.size();
  r.solids = solids;
  r.steps = done;
  r.warmup_time = double(rest + warmup) * dt;
  r.sample_time = double(sample * every) * dt;
  r.temperature = t_sum / double(std::max(1LL, sample));
  r.wall_per_tau = cost.wall / (double(done) * dt);
  r.cpu_per_tau = cost.cpu / (double(done) * dt);
  r.finite = !unstable;
  if (r.finite) {
    double su = 0, sn = 0, m = 0, m2 = 0;
    for (int k = 0; k < kBlocks; ++k) {
      su += block_u[k];
      sn += block_n[k];
      const double uk = block_u[k] / block_n[k];
      m += uk / kBlocks;
      m2 += uk * uk / kBlocks;
    }
    r.mean_u = su / sn;
    r.mean_u_stderr = std::sqrt(std::max(0.0, m2 - m * m) / (kBlocks - 1));
    const double scale = kMu2D * r.porosity / (fb * kRho);
    r.kappa = scale * r.mean_u;
    r.kappa_stderr = scale * r.mean_u_stderr;
  } else {
    r.mean_u = r.mean_u_stderr = r.kappa = r.kappa_stderr = std::numeric_limits<double>::quiet_NaN();
  }
  return r;
}

void run_permeability(bool quick, const Settings& s, const std::string& json_path, bool quiet) {
  struct Case {
    const char* sweep;
    double dt, diameter;
  };
  const std::vector<Case> cases =
      quick ? std::vector<Case>{{"dt", 0.02, 2.5},      {"dt", 0.01, 2.5},         {"dt", 0.005, 2.5},
                                {"resolution", 0.01, 2.5}, {"resolution", 0.01, 3.5}, {"resolution", 0.01, 5}}
            : std::vector<Case>{{"dt", 0.015, 5},         {"dt", 0.01, 5},          {"dt", 0.005, 5},
                                {"dt", 0.0025, 5},        {"resolution", 0.01, 2.5}, {"resolution", 0.01, 3.5},
                                {"resolution", 0.01, 5},  {"resolution", 0.01, 7},   {"resolution", 0.01, 10}};
  const double exact = sangani_acrivos_exact(s.porosity);
  std::vector<KappaRow> rows;
  for (const char* precision : {"double", "float"}) {
    for (const Case& c : cases) {
      // The same (dt, d) in both sweeps is one run.
      const KappaRow* same = nullptr;
      for (const KappaRow& r : rows)
        if (r.precision == precision && r.dt == c.dt && r.diameter == c.diameter) same = &r;
      if (same) {
        KappaRow copy = *same;
        copy.sweep = c.sweep;
        rows.push_back(copy);
        continue;
      }
      rows.push_back(std::string(precision) == "double" ? run_kappa<double>(c.sweep, c.dt, c.diameter, s)
                                                        : run_kappa<float>(c.sweep, c.dt, c.diameter, s));
      const KappaRow& r = rows.back();
      if (!quiet)
        std::cerr << std::setprecision(4) << "tradeoff_mdpd: " << r.precision << " " << r.sweep << " dt = " << r.dt
                  << " d = " << r.diameter << " (" << r.particles << " particles, " << r.solids
                  << " solid): kappa/d^2 " << r.kappa / (r.diameter * r.diameter) << " ± "
                  << r.kappa_stderr / (r.diameter * r.diameter) << ", <u> " << r.mean_u << ", T " << r.temperature
                  << ", " << r.cpu_per_tau << " cpu s/tau, " << r.wall_per_tau << " wall s/tau\n";
    }
  }
  auto reference = [&](const std::string& sweep) -> const KappaRow& {
    const KappaRow* ref = nullptr;
    for (const KappaRow& r : rows)
      if (r.precision == "double" && r.sweep == sweep) ref = &r;
    return *ref;
  };
  auto over_d2 = [](const KappaRow& r) { return r.kappa / (r.diameter * r.diameter); };
  const std::string stem = json_path.size() > 5 && json_path.substr(json_path.size() - 5) == ".json"
                               ? json_path.substr(0, json_path.size() - 5)
                               : json_path;
  std::ofstream csv(stem + ".csv");
  csv << "sweep,precision,dt,diameter,spacing,porosity,particles,solids,steps,warmup_tau,sample_tau,fb,mean_u,"
         "mean_u_stderr,kappa,kappa_stderr,kappa_over_d2,kappa_over_d2_stderr,temperature,rel_err_ref,"
         "rel_err_ref_stderr,rel_err_exact,rel_err_exact_stderr,wall_s_per_tau,cpu_s_per_tau,stable\n"
      << std::setprecision(9);
  for (const KappaRow& r : rows) {
    const KappaRow& ref = reference(r.sweep);
    const bool is_ref = r.precision == "double" && r.dt == ref.dt && r.diameter == ref.diameter;
    const double k2 = over_d2(r), k2_err = r.kappa_stderr / (r.diameter * r.diameter), k2_ref = over_d2(ref);
    csv << r.sweep << "," << r.precision << "," << r.dt << "," << r.diameter << "," << r.spacing << "," << r.porosity
        << "," << r.particles << "," << r.solids << "," << r.steps << "," << r.warmup_time << "," << r.sample_time
        << "," << r.fb << "," << r.mean_u << "," << r.mean_u_stderr << "," << r.kappa << "," << r.kappa_stderr << ","
        << k2 << "," << k2_err << "," << r.temperature << "," << k2 / k2_ref - 1 << ","
        << (is_ref ? 0.0 : std::hypot(k2_err, k2 * ref.kappa_stderr / ref.kappa) / k2_ref) << ","
        << k2 / exact - 1 << "," << k2_err / exact << "," << r.wall_per_tau << "," << r.cpu_per_tau << ","
        << (r.finite ? 1 : 0) << "\n";
  }
  std::ofstream json(json_path);
  json << std::setprecision(9) << "{\n  \"program\": \"tradeoff_mdpd\",\n  \"observable\": \"Darcy permeability "
       << "kappa/d^2 of a 2D square pillar array (one unit cell, uniform driving, paper fluid)\",\n  \"porosity\": "
       << s.porosity << ",\n  \"driving_force_at_d5\": " << s.driving_force << ",\n  \"viscosity_used\": " << kMu2D
       << ",\n  \"sangani_acrivos_exact_over_d2\": " << json_number(exact) << ",\n  \"quick\": "
       << (quick ? "true" : "false") << ",\n  \"threads\": " << concurrency<Kokkos::DefaultExecutionSpace>()
       << ",\n  \"references\": [";
  bool first = true;
  for (const char* sweep : {"dt", "resolution"}) {
    const KappaRow& ref = reference(sweep);
    const KappaRow* next = nullptr;
    for (const KappaRow& r : rows)
      if (r.precision == "double" && r.sweep == sweep && &r != &ref) next = &r;
    json << (first ? "\n" : ",\n") << "    {\"sweep\": \"" << sweep << "\", \"dt\": " << ref.dt
         << ", \"diameter\": " << ref.diameter << ", \"kappa_over_d2\": " << json_number(over_d2(ref))
         << ", \"stderr\": " << json_number(ref.kappa_stderr / (ref.diameter * ref.diameter))
         << ", \"second_finest_kappa_over_d2\": " << json_number(over_d2(*next)) << ", \"second_finest_stderr\": "
         << json_number(next->kappa_stderr / (next->diameter * next->diameter)) << "}";
    first = false;
  }
  json << "\n  ],\n  \"float_vs_double\": [";
  first = true;
  for (const KappaRow& f : rows) {
    if (f.precision != "float") continue;
    for (const KappaRow& d : rows) {
      if (d.precision != "double" || d.sweep != f.sweep || d.dt != f.dt || d.diameter != f.diameter) continue;
      json << (first ? "\n" : ",\n") << "    {\"sweep\": \"" << f.sweep << "\", \"dt\": " << f.dt
           << ", \"diameter\": " << f.diameter << ", \"cpu_speedup\": " << d.cpu_per_tau / f.cpu_per_tau
           << ", \"wall_speedup\": " << d.wall_per_tau / f.wall_per_tau
           << ", \"kappa_float_over_double_minus_1\": " << json_number(f.kappa / d.kappa - 1)
           << ", \"combined_stderr\": " << json_number(std::hypot(f.kappa_stderr / d.kappa, d.kappa_stderr / d.kappa))
           << "}";
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
  std::string observable = "viscosity";
  mesoflow::cli::DriverApp app(
      "MDPD speed–accuracy trade-off: cost per τ against the error of the viscosity (periodic Poiseuille) or of the "
      "permeability of a square pillar array",
      "tradeoff_mdpd.json");
  app.add_choice("--observable", observable, "viscosity (periodic Poiseuille) or permeability (square pillar array)",
                 {"viscosity", "permeability"});
  app.add_flag("--quick", quick,
               "small grid for the ctest (viscosity: dt = 0.02, 0.01, 0.005 at L/2 = 5; permeability: dt = 0.02, "
               "0.01, 0.005 at d = 2.5 and d = 2.5, 3.5, 5 at dt = 0.01)");
  app.add_real("--porosity", s.porosity, "permeability: porosity ε of the square array", 0.3, 0.99);
  app.add_real("--driving-force", s.driving_force, "permeability: f_b at d = 5 (f_b = f0 · 5/d)", 0.0, 10.0,
               mesoflow::cli::Bounds::left_open);
  app.add_real("--sample-time", s.sample_time, "sampled physical time per setting (τ)", 1.0, 1e6);
  app.add_int("--seed", s.seed, "random seed", 0, 4294967295LL);
  app.add_int("--threads", threads, "host threads (0: OMP_NUM_THREADS or all cores)", 0, 4096);
  return app.run(argc, argv, [&] {
    mesoflow::KokkosScope kokkos(threads);
    if (observable == "permeability")
      mesoflow::run_permeability(quick, s, app.output(), app.quiet());
    else
      mesoflow::run(quick, s, app.output(), app.quiet());
  });
}
