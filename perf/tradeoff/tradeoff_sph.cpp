// tradeoff_sph — speed–accuracy trade-off of the SPH capsule (sph-microcapsules-constriction §4.1):
// the cost of the simple-shear cell (scenes/capsule/capsule_scene.hpp, as `capsule --mode shear`
// builds it) per unit of shear time γ̇t against the error of the capsule's Taylor deformation D_xy,
// over the resolution Π and the speed of sound c0, in float and in double.
//
// Scene: the capsule (outer radius a = d/2, thickness h_t = --thickness-ratio × a, level-3 two-layer
// membrane, one diagonal per quad, the paper's G_s of §4) centred in a box of --box d per side,
// periodic in x and z, between Morris walls at y = 0 and L_y sliding at ∓V (γ̇ = 2V/L_y), Lucy
// support 2.5Δx, Re = ρ0 γ̇ a²/μ, Ca = μ γ̇ a/G_s, inner and outer fluid alike. Lattice units Δx = ρ0 =
// V = 1, d = Π Δx. The parameters are derived as in capsule.cpp's scene_parameters (shear mode),
// except h_t, which here scales with d so that every Π models the same capsule (the driver holds
// h_t = --thickness Δx; at Π = 8 and the default 0.25 the two agree). c0 of eq. (6) is --c0-factor
// times the driver's rule (capsule.cpp: the largest of V/√δ, √(νV/(δ L_y/2)) and the membrane's
// √(2 G_s ε/(a ρ0 δ)), δ = 1%, ε = 5%). The time step is the scene's stability limit.
// Observable: D_xy of the outer layer in the shear plane (capsule_shape.hpp), sampled every
// --sample-every γ̇t and averaged over γ̇t ∈ [--window-start, --shear-time]. Beside it: the
// inclination θ/π over the same window, the largest |ρ − ρ0|/ρ0 over the run (all particles, and the
// fluid alone) and the mean over the fluid in the window.
// Sweeps (each with its reference, the finest level in double; defaults: Ca = 0.3, Re = 0.5, a 3d box,
// γ̇t = 5, window [3, 5]):
//   resolution: Π ∈ --resolutions (6, 8, 10) at c0 = 1 × the rule  (reference: the largest Π)
//   c0:         --c0-factors (0.5, 1, 2) × the rule at Π = --c0-resolution (8)  (reference: the largest)
// --precisions double runs double alone (a finer reference checked on its own, e.g. Π = 12); --dt-gamma
// sets γ̇Δt for every run (to separate c0 from the time step it sets).
// A setting that both sweeps contain is run once and listed in both. Error: |D_xy − D_xy,ref| and
// its ratio to D_xy,ref; "float adds" is |D_float − D_double| at the same setting (JSON).
// Cost: wall and process CPU seconds of the time stepping and sampling (the scene's construction
// excluded) per unit γ̇t, one host thread.
//
// Output (<out> = --output without its extension): <out>.csv, one row per run and sweep; <out>.json,
// the references and how converged they are, float against double; <out>_series.csv, every sample
// of every run (to check that the window sits on the plateau). perf/tradeoff/run_sph runs this and
// perf/tradeoff/plot_tradeoff_panels.py.
#include "scenes/capsule/capsule_scene.hpp"
#include "analysis/capsule/capsule_shape.hpp"
#include "scenes/capsule/channel_geometry.hpp"
#include "drivers/common/cli.hpp"
#include "kernels/common/kokkos_compat.hpp"
#include "kernels/sph/tait_equation_of_state.hpp"
#include "perf/tradeoff/cost_clock.hpp"

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

constexpr double pi = 3.14159265358979323846;
constexpr double kResolutionLo = 6, kResolutionHi = 64, kFactorLo = 0, kFactorHi = 16;

struct Parameters {
  std::string resolutions = "6,8,10";
  std::string c0_factors = "0.5,1,2";
  int c0_resolution = 8;
  double ca = 0.3;
  double reynolds = 0.5;
  double box = 3;              // box edge in d (cube)
  double thickness_ratio = 0.25;  // h_t/a
  int level = 3;
  double density_variation = 0.01;
  double membrane_strain = 0.05;
  double shear_time = 5;
  double window_start = 3;
  std::string precisions = "double,float";
  double dt_gamma = 0;  // γ̇Δt; 0: the scene's stability limit
  double sample_every = 0.1;
  int threads = 1;
  bool quick = false;
};

std::vector<double> parse_resolutions(const std::string& text) {
  return cli::parse_number_list(
      text, "--resolutions", [](double v) { return v >= kResolutionLo && v <= kResolutionHi && v == std::floor(v); },
      "in [6, 64] (whole lattice spacings per diameter)");
}

std::vector<double> parse_factors(const std::string& text) {
  return cli::parse_number_list(
      text, "--c0-factors", [](double v) { return v > kFactorLo && v <= kFactorHi; }, "in (0, 16]");
}

// A JSON number, or null where it is not finite.
std::string json_number(double x) {
  if (!std::isfinite(x)) return "null";
  std::ostringstream s;
  s << std::setprecision(9) << x;
  return s.str();
}

struct Setting {
  int resolution = 8;
  double c0_factor = 1;
};

struct Row {
  std::string precision;
  Setting setting;
  double c0 = 0, dt_gamma = 0, k_b = 0;
  long long particles = 0, steps = 0;
  double shear_time = 0;
  double D = NAN, D_std = NAN, theta = NAN;
  double max_dev_all = 0, max_dev_fluid = 0, mean_dev_fluid = 0;
  double wall = 0, cpu = 0;
  bool finite = true;
};

// The fluid's (outer and inner) largest and summed |ρ − ρ0|/ρ0, and its particle count.
template <class Scene>
void fluid_density_deviation(const Scene& scene, double& max_dev, double& mean_dev) {
  using Exec = Kokkos::DefaultExecutionSpace;
  const auto rho = scene.system().rho;
  const auto type = scene.system().particles.type;
  const double rho0 = scene.parameters().rho0;
  const int n = int(scene.system().particles.size());
  double largest = 0, sum = 0;
  Kokkos::parallel_reduce(
      "mesoflow::tradeoff::sph::fluid_density_max", Kokkos::RangePolicy<Exec>(0, n),
      KOKKOS_LAMBDA(int i, double& acc) {
        const int t = type(i);
        const bool fluid = t == sph::particle_type::fluid || t == sph::particle_type::inner_fluid;
        const double e = fluid ? kmath::fabs(double(rho(i)) / rho0 - 1.0) : 0.0;
        if (e > acc) acc = e;
      },
      Kokkos::Max<double>(largest));
  Kokkos::parallel_reduce(
      "mesoflow::tradeoff::sph::fluid_density_sum", Kokkos::RangePolicy<Exec>(0, n),
      KOKKOS_LAMBDA(int i, double& acc) {
        const int t = type(i);
        const bool fluid = t == sph::particle_type::fluid || t == sph::particle_type::inner_fluid;
        acc += fluid ? kmath::fabs(double(rho(i)) / rho0 - 1.0) : 0.0;
      },
      sum);
  max_dev = largest;
  mean_dev = sum / double(scene.num_fluid());
}

template <class Real>
Row run_case(const Parameters& par, const Setting& s, std::ostream& series, bool quiet) {
  using Exec = Kokkos::DefaultExecutionSpace;
  const double d = s.resolution, a = 0.5 * d, h_t = par.thickness_ratio * a;
  const double L = par.box * d;
  const auto g = capsule::shear_channel({L, L, L}, 1.0);
  // As capsule.cpp's scene_parameters (shear): μ from Re, G_s from Ca, k_b from G_s = E h_t/(2(1 + ν)),
  // E = 5 k_b/(√3 δ), ν = 1/4; c0 from the rule (times the factor).
  const double shear_rate = 2.0 / g.length[1];
  const double mu = shear_rate * a * a / par.reynolds;
  const double G_s = mu * shear_rate * a / par.ca;
  msm::CapsuleMembraneParameters mp;
  mp.radius = a;
  mp.thickness = h_t;
  mp.level = par.level;
  mp.bonds.k_b = 1;
  mp.bonds.diagonals = msm::DiagonalBonds::one_per_quad;
  const double bond_length = msm::capsule_membrane(mp).mean_in_layer_bond_length();
  const double k_b = G_s * 2 * (1 + 0.25) * std::sqrt(3.0) * bond_length / (5 * h_t);
  const double delta = par.density_variation;
  const double morris = sph::morris_speed_of_sound(1.0, mu, 0.5 * g.length[1], 0.0, delta);
  const double delta_p = 2 * G_s * par.membrane_strain / a;
  const double c0 = s.c0_factor * std::max(morris, std::sqrt(delta_p / delta));

  capsule::CapsuleSceneParameters sp;
  sp.channel = g;
  sp.spacing = 1;
  sp.support = 2.5;
  sp.rho0 = 1;
  sp.radius = a;
  sp.thickness = h_t;
  sp.level = par.level;
  sp.diagonals = msm::DiagonalBonds::one_per_quad;
  sp.sph.wall_velocity = sph::parse_wall_velocity("morris");
  sp.k_b = k_b;
  sp.mu_outer = mu;
  sp.mu_inner = mu;
  sp.u_max = 1;
  sp.c0 = c0;
  if (par.dt_gamma > 0) sp.dt = par.dt_gamma / shear_rate;  // refused by the scene above its limit
  capsule::CapsuleScene<Real, Exec> scene(sp);

  const double dt = double(scene.system().dt());
  // (1 − 10⁻⁶: a float dt, rounded below the nominal, must not add a step or move a sample out of the window.)
  const long long steps = (long long)(std::ceil(par.shear_time / (shear_rate * dt) * (1 - 1e-6)));
  const long long every = std::max(1LL, (long long)(std::llround(par.sample_every / (shear_rate * dt))));
  Row r;
  r.precision = sizeof(Real) == 4 ? "float" : "double";
  r.setting = s;
  r.c0 = c0;
  r.dt_gamma = dt * shear_rate;
  r.k_b = k_b;
  r.particles = scene.num_particles();
  double sD = 0, sD2 = 0, sT = 0, dev_sum = 0;
  int n = 0;
  long long done = 0;
  Kokkos::fence();
  const tradeoff::CostClock clock;
  for (long long step = 0; step <= steps; ++step) {
    if (step > 0) {
      scene.step();
      ++done;
    }
    if (step % every != 0 && step != steps) continue;
    const auto shape = capsule::shear_plane_shape(scene.outer_layer_positions());
    const double all = scene.max_density_deviation();
    double fluid_max = 0, fluid_mean = 0;
    fluid_density_deviation(scene, fluid_max, fluid_mean);
    const double t = double(step) * dt * shear_rate;
    series << r.precision << "," << s.resolution << "," << s.c0_factor << "," << t << "," << shape.taylor << ","
           << shape.inclination / pi << "," << all << "," << fluid_max << "," << fluid_mean << "\n";
    r.max_dev_all = std::max(r.max_dev_all, all);
    r.max_dev_fluid = std::max(r.max_dev_fluid, fluid_max);
    if (!scene.all_finite()) {  // the row is marked; its cost is that of the steps it ran
      r.finite = false;
      if (!quiet)
        std::cerr << "tradeoff_sph: " << r.precision << " Pi = " << s.resolution << ", c0 x " << s.c0_factor
                  << ": non-finite state at shear time " << t << "\n";
      break;
    }
    if (t >= par.window_start * (1 - 1e-6)) {
      sD += shape.taylor;
      sD2 += shape.taylor * shape.taylor;
      sT += shape.inclination / pi;
      dev_sum += fluid_mean;
      ++n;
    }
  }
  Kokkos::fence();
  const tradeoff::Cost cost = clock.elapsed();
  r.steps = done;
  r.shear_time = double(done) * dt * shear_rate;
  r.wall = cost.wall;
  r.cpu = cost.cpu;
  if (r.finite && n > 0) {
    r.D = sD / n;
    r.D_std = std::sqrt(std::max(0.0, sD2 / n - r.D * r.D));
    r.theta = sT / n;
    r.mean_dev_fluid = dev_sum / n;
  }
  return r;
}

void run(const Parameters& par, const std::string& json_path, bool quiet) {
  const auto resolutions = parse_resolutions(par.resolutions);
  const auto factors = parse_factors(par.c0_factors);
  if (!(par.window_start < par.shear_time))
    throw std::invalid_argument("--window-start " + json_number(par.window_start) + " must be below --shear-time " +
                                json_number(par.shear_time));
  if (!(par.sample_every <= par.shear_time - par.window_start))
    throw std::invalid_argument("--sample-every " + json_number(par.sample_every) +
                                " leaves no sample in the window [--window-start, --shear-time] = [" +
                                json_number(par.window_start) + ", " + json_number(par.shear_time) + "]");
  std::vector<std::string> precision_list;
  if (par.precisions == "double,float" || par.precisions == "float,double")
    precision_list = {"double", "float"};
  else if (par.precisions == "double")
    precision_list = {"double"};
  else
    throw std::invalid_argument("--precisions must be double,float or double (the references are in double), got '" +
                                par.precisions + "'");
  const bool with_float = precision_list.size() == 2;
  std::vector<double> all = resolutions;
  all.push_back(par.c0_resolution);
  for (double p : all) {
    const double edge = par.box * p;
    if (std::abs(edge - std::round(edge)) > 1e-9)
      throw std::invalid_argument("--box " + json_number(par.box) + " times Pi = " + json_number(p) + " is " +
                                  json_number(edge) + " lattice spacings: the box edge must be whole (--resolutions, "
                                  "--c0-resolution)");
  }
  // The distinct settings, resolution sweep first.
  struct Member {
    std::string sweep;
    Setting setting;
  };
  std::vector<Member> members;
  for (double p : resolutions) members.push_back({"resolution", {int(p), 1.0}});
  for (double f : factors) members.push_back({"c0", {par.c0_resolution, f}});
  std::vector<Setting> settings;
  for (const auto& m : members) {
    bool seen = false;
    for (const auto& s : settings) seen = seen || (s.resolution == m.setting.resolution && s.c0_factor == m.setting.c0_factor);
    if (!seen) settings.push_back(m.setting);
  }

  const std::string stem = json_path.size() > 5 && json_path.substr(json_path.size() - 5) == ".json"
                               ? json_path.substr(0, json_path.size() - 5)
                               : json_path;
  std::ofstream series(stem + "_series.csv");
  if (!series) throw std::runtime_error("cannot write " + stem + "_series.csv");
  series << "precision,resolution,c0_factor,shear_time,taylor_deformation,inclination_over_pi,"
            "max_density_deviation,max_density_deviation_fluid,mean_density_deviation_fluid\n"
         << std::setprecision(8);
  std::vector<Row> rows;
  for (const std::string& precision : precision_list) {
    for (const Setting& s : settings) {
      rows.push_back(precision == "double" ? run_case<double>(par, s, series, quiet)
                                                        : run_case<float>(par, s, series, quiet));
      series.flush();
      const Row& r = rows.back();
      if (!quiet)
        std::cerr << std::setprecision(4) << "tradeoff_sph: " << r.precision << " Pi = " << s.resolution << ", c0 = "
                  << s.c0_factor << " x rule = " << r.c0 << " V (" << r.particles << " particles, dt gamma "
                  << r.dt_gamma << "): D_xy " << r.D << " ± " << r.D_std << ", max |drho|/rho0 " << r.max_dev_all
                  << " (fluid " << r.max_dev_fluid << "), " << r.cpu / r.shear_time << " cpu s, "
                  << r.wall / r.shear_time << " wall s per gamma t\n";
    }
  }
  auto find = [&](const std::string& precision, const Setting& s) -> const Row& {
    for (const Row& r : rows)
      if (r.precision == precision && r.setting.resolution == s.resolution && r.setting.c0_factor == s.c0_factor)
        return r;
    throw std::logic_error("tradeoff_sph: missing run");
  };
  // The reference of each sweep: its finest level (largest Π; largest c0) in double.
  auto finest = [&](const std::string& sweep) {
    Setting best{};
    bool first = true;
    for (const auto& m : members) {
      if (m.sweep != sweep) continue;
      const double key = sweep == "resolution" ? m.setting.resolution : m.setting.c0_factor;
      const double best_key = sweep == "resolution" ? best.resolution : best.c0_factor;
      if (first || key > best_key) best = m.setting;
      first = false;
    }
    return best;
  };
  for (const char* sweep : {"resolution", "c0"}) {
    const Row& ref = find("double", finest(sweep));
    if (!ref.finite || !std::isfinite(ref.D))
      throw std::runtime_error(std::string("tradeoff_sph: the reference of the ") + sweep + " sweep (Pi = " +
                               std::to_string(ref.setting.resolution) + ", c0 x " + json_number(ref.setting.c0_factor) +
                               ") did not finish finite");
  }

  std::ofstream csv(stem + ".csv");
  if (!csv) throw std::runtime_error("cannot write " + stem + ".csv");
  csv << "sweep,precision,resolution,c0_factor,c0,dt_gamma,k_b,particles,steps,shear_time,window_start,"
         "taylor_deformation,taylor_deformation_std,inclination_over_pi,error,rel_error,error_vs_double,"
         "max_density_deviation,max_density_deviation_fluid,mean_density_deviation_fluid,wall_s,cpu_s,"
         "wall_per_shear_time,cpu_per_shear_time,finite\n"
      << std::setprecision(9);
  for (const auto& m : members)
    for (const std::string& precision : precision_list) {
      const Row& r = find(precision, m.setting);
      const Row& ref = find("double", finest(m.sweep));
      const Row& dbl = find("double", m.setting);
      csv << m.sweep << "," << r.precision << "," << r.setting.resolution << "," << r.setting.c0_factor << "," << r.c0
          << "," << r.dt_gamma << "," << r.k_b << "," << r.particles << "," << r.steps << "," << r.shear_time << ","
          << par.window_start << "," << r.D << "," << r.D_std << "," << r.theta << "," << std::abs(r.D - ref.D) << ","
          << std::abs(r.D - ref.D) / ref.D << "," << std::abs(r.D - dbl.D) << "," << r.max_dev_all << ","
          << r.max_dev_fluid << "," << r.mean_dev_fluid << "," << r.wall << "," << r.cpu << ","
          << r.wall / r.shear_time << "," << r.cpu / r.shear_time << "," << (r.finite ? 1 : 0) << "\n";
    }

  std::ofstream json(json_path);
  if (!json) throw std::runtime_error("cannot write " + json_path);
  json << std::setprecision(9) << "{\n  \"program\": \"tradeoff_sph\",\n  \"observable\": \"Taylor deformation D_xy "
       << "of the capsule in simple shear, mean over the window\",\n  \"quick\": " << (par.quick ? "true" : "false")
       << ",\n  \"threads\": " << concurrency<Kokkos::DefaultExecutionSpace>() << ",\n  \"scene\": {\"ca\": " << par.ca
       << ", \"reynolds\": " << par.reynolds << ", \"box_d\": " << par.box << ", \"thickness_over_a\": "
       << par.thickness_ratio << ", \"level\": " << par.level << ", \"shear_time\": " << par.shear_time
       << ", \"window\": [" << par.window_start << ", " << par.shear_time << "], \"sample_every\": " << par.sample_every
       << "},\n  \"references\": [";
  bool first = true;
  for (const char* sweep : {"resolution", "c0"}) {
    const Setting best = finest(sweep);
    const Row& ref = find("double", best);
    // The reference's own convergence: the next-finest level of the sweep, in double.
    const Row* next = nullptr;
    for (const auto& m : members) {
      if (m.sweep != sweep) continue;
      const Row& r = find("double", m.setting);
      if (&r == &ref) continue;
      const double key = std::string(sweep) == "resolution" ? r.setting.resolution : r.setting.c0_factor;
      const double next_key = next ? (std::string(sweep) == "resolution" ? next->setting.resolution
                                                                         : next->setting.c0_factor)
                                   : -1;
      if (key > next_key) next = &r;
    }
    json << (first ? "\n" : ",\n") << "    {\"sweep\": \"" << sweep << "\", \"resolution\": " << ref.setting.resolution
         << ", \"c0_factor\": " << ref.setting.c0_factor << ", \"c0\": " << ref.c0
         << ", \"taylor_deformation\": " << json_number(ref.D) << ", \"taylor_deformation_std\": "
         << json_number(ref.D_std) << ", \"second_finest_taylor_deformation\": " << json_number(next ? next->D : NAN)
         << ", \"second_finest_error\": " << json_number(next ? std::abs(next->D - ref.D) : NAN) << "}";
    first = false;
  }
  json << "\n  ],\n  \"float_vs_double\": [";
  first = true;
  for (const Setting& s : with_float ? settings : std::vector<Setting>{}) {
    const Row& f = find("float", s);
    const Row& dbl = find("double", s);
    json << (first ? "\n" : ",\n") << "    {\"resolution\": " << s.resolution << ", \"c0_factor\": " << s.c0_factor
         << ", \"cpu_speedup\": " << json_number(dbl.cpu / dbl.shear_time / (f.cpu / f.shear_time))
         << ", \"wall_speedup\": " << json_number(dbl.wall / dbl.shear_time / (f.wall / f.shear_time))
         << ", \"taylor_deformation_float_minus_double\": " << json_number(f.D - dbl.D) << "}";
    first = false;
  }
  json << "\n  ]\n}\n";
  if (!json) throw std::runtime_error("cannot write " + json_path);
  if (!quiet) std::cerr << "tradeoff_sph: wrote " << stem << ".csv, " << stem << "_series.csv and " << json_path << "\n";
}

}  // namespace
}  // namespace mesoflow

int main(int argc, char** argv) {
  using mesoflow::cli::Bounds;
  mesoflow::Parameters par;
  mesoflow::cli::DriverApp app(
      "SPH capsule speed–accuracy trade-off: cost per unit shear time against the error of D_xy in simple shear",
      "tradeoff_sph.json");
  // The option's name leads the message already (DriverApp): the list parser's own prefix is dropped.
  auto list_check = [](const std::string& flag, auto parse) {
    return CLI::Validator(
        [=](std::string& text) {
          try {
            parse(text);
            return std::string();
          } catch (const std::exception& e) {
            const std::string what = e.what(), prefix = flag + ": ";
            return what.compare(0, prefix.size(), prefix) == 0 ? what.substr(prefix.size()) : what;
          }
        },
        "LIST");
  };
  app.add_string("--resolutions", par.resolutions,
                 "resolution sweep: Pi = lattice spacings per diameter, comma-separated, each in [6, 64] (the "
                 "largest is the reference)")
      ->check(list_check("--resolutions", mesoflow::parse_resolutions));
  app.add_string("--c0-factors", par.c0_factors,
                 "c0 sweep: multiples of the driver's c0 rule, comma-separated, each in (0, 16] (the largest is the "
                 "reference)")
      ->check(list_check("--c0-factors", mesoflow::parse_factors));
  app.add_int("--c0-resolution", par.c0_resolution, "Pi of the c0 sweep", 6, 64);
  app.add_real("--ca", par.ca, "capillary number Ca = mu gamma a/G_s", 0.0, 100.0, Bounds::left_open);
  app.add_real("--reynolds", par.reynolds, "Re = rho gamma a^2/mu", 1e-3, 100.0);
  app.add_real("--box", par.box, "edge of the cubic shear box, in d", 1.5, 20.0);
  app.add_real("--thickness-ratio", par.thickness_ratio, "membrane thickness h_t/a", 0.05, 0.5);
  app.add_int("--level", par.level, "icosphere subdivisions of the membrane", 1, 5);
  app.add_real("--shear-time", par.shear_time, "run length, gamma t", 0.0, 1e3, Bounds::left_open);
  app.add_real("--window-start", par.window_start, "D_xy is averaged over gamma t in [this, --shear-time]", 0.0, 1e3);
  app.add_real("--sample-every", par.sample_every, "sampling interval, gamma t", 0.0, 10.0, Bounds::left_open);
  app.add_real("--dt-gamma", par.dt_gamma,
               "time step as gamma dt for every run (0: each scene's stability limit; larger is refused)", 0.0, 0.1);
  app.add_string("--precisions", par.precisions, "double,float (the report) or double (a reference check alone)");
  app.add_int("--threads", par.threads, "host threads (0: OMP_NUM_THREADS or all cores)", 0, 4096);
  app.add_flag("--quick", par.quick,
               "the ctest: a 2.5d box, Pi = 6 and 8, c0 x 0.5, 1, 2 at Pi = 6, gamma t = 0.8 (window from 0.5)");
  return app.run(argc, argv, [&] {
    if (par.quick) {
      par.resolutions = "6,8";
      par.c0_factors = "0.5,1,2";
      par.c0_resolution = 6;
      par.box = 2.5;
      par.shear_time = 0.8;
      par.window_start = 0.5;
    }
    mesoflow::KokkosScope kokkos(par.threads);
    mesoflow::run(par, app.output(), app.quiet());
  });
}
