// capsule — a microcapsule (SPH fluid + mass-spring membrane, the Discrete Multi-Physics model)
// through a constriction, and in simple shear: Rahmat et al., sph-microcapsules-constriction.
//
// Units (§4: "normalized using characteristic length d, time d/U, and velocity U"): the simulation
// runs in lattice units — spacing Δx = 1, reference density ρ0 = 1, the target speed U = 1 — with
// the capsule diameter d = Π Δx (--resolution Π, particles per diameter: the paper's ξ-3 is 56) and
// the viscosity set by the Reynolds number (§4: "the inertial force is much smaller than the
// viscous force"; the paper gives ρ, μ and d but not U, so Re is a parameter, default 1):
//   constriction: Re = ρ0 U d/μ;   shear: Re = ρ0 γ̇ a²/μ, U = V (the walls' speed), γ̇ = 2V/L_y.
// The membrane's k_b follows from the capillary number Ca = μ U a/G_s (§4; shear: μ γ̇ a/G_s) with
// G_s = E h_t/(2(1 + ν)), E = 5 k_b/(√3 δ_ave), ν = 1/4 (§4, as quoted; capsule_mesh.hpp shows the
// paper's bond counts give 0.84 E and ν = 1/3 — --diagonals both gives the quoted network exactly).
// Everything written is in the paper's units: lengths over d, times over d/U (shear: γ̇ t), x_c
// measured from the domain's inlet end.
//
// --mode constriction (§3, Fig. 1; §4.2–§5): the 7d × 2d × 2d channel of channel_geometry.hpp
//   (periodic in x; walls in y and z; constriction x ∈ [3d, 5d) of width t_c = η d in y), the capsule
//   centred in the inlet at x = 1.5d. The body force on the fluids is adjusted to hold U, "the
//   maximum axial velocity in the constriction" (§4): the controller holds the fluid's total x
//   momentum at ρ0 ū_c A_c L_x — the flux through the constriction (A_c = t_c × 2d) at the mean
//   velocity ū_c = U/(u_max/ū) of fully developed flow in that rectangular duct — by
//   g ← g exp(κ(1 − P_x/P*)) every T_c = 0.02 d/U, κ = T_c/τ with τ = 2d²/(π² ν) the decay time of
//   the 2d × 2d duct's slowest viscous mode (an integral loop with damping ratio ½ on that mode);
//   g starts from the ducts' resistances and is capped at 20 times that start.
//   Measured every --sample-every: x_c, D_∞,x, D_∞,y, D_∞,z, C_f, C_r (capsule_shape.hpp), g, P_x/P*,
//   max |ρ − ρ0|/ρ0. Passage time: from the front reaching the constriction (x = 3d) to the rear
//   leaving it (x = 5d). The run ends when x_c reaches 6d, at --t-max, or when the capsule stalls
//   (blockage: its centroid moves less than 0.01d in --stall-window after its front entered).
//   A sweep (--ca and --eta lists) runs every pair and tabulates, per run, 1/t_pass, D_∞,Λ at
//   x_c = 4 and C_f, C_r at x_c = 3.5, 4, 4.5, and per η Pearson's r of each against Ca (eq. 17,
//   Table 1).
// --mode shear (§4.1): the capsule in a 5d × 4d × 4d box (--shear-box), walls bounding y sliding at
//   ∓V; D_xy and the inclination θ/π, steady values averaged over the last 30% of --t-max.
//
// Time step: the smallest of the SPH limits and the bonds' (capsule_scene.hpp) at the start; at low
// Re with a raised c0 the acoustic-viscous limit 2ν/c0² binds (sph_time_step.hpp), at finer Π the
// acoustic one C_c h/c. The step then follows the state: at every sample the running limits
// (CapsuleScene::running_time_step_limits: viscous, acoustic and force at the current state) are
// evaluated again and an automatic step above them is lowered to them, never raised. Where the
// capsule squeezes the fluid the Tait sound speed grows as (ρ/ρ0)³, and a step kept at its starting
// value diverged (Π = 16 at the slot's entrance, docs/sph-capsules.md, "Resolution study"). A step
// given with --dt is kept, with one warning when the running limit falls below it. Sample times
// stay --sample-every apart to within a step; the series records the step and the limits.
// c0 of eq. (6), for density variations δ = --density-variation (default 1%, the paper's;
// tait_equation_of_state.hpp): the largest of U/√δ, Morris et al.'s viscous criterion √(ν U/(L δ))
// with L = t_c/2 (shear: L_y/2), their body-force criterion √(2 g₀ L_x/δ) — the pressure drop along
// the channel at twice the starting body force g₀ (the controller raises g by up to 1.6 times while
// the capsule plugs the constriction, measured at Π = 12, Ca = 0.25), which at low Re is the
// largest — and the membrane's √(Δp/(ρ0 δ)) for the pressure jump Δp = 2 G_s ε/a at a membrane
// strain ε = --membrane-strain (default 5%); or --c0.
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
// NaN watchdog (scenes/common/nan_watchdog.hpp, CapsuleScene::watched()): every --check-every steps
// and before every sample (series row, observables, membrane frame) the state is checked; a
// non-finite value stops the run with exit status 1 and a message naming the particle (membrane
// vertex, fluid or wall particle by its build-order index), the force term and the step. Nothing is
// written from the bad state: the series and trajectory end at the last good sample, and the run's
// _result.csv, the sweep table and the summary are not written. In the constriction the watched step
// includes the flow controller, whose body force is kept with the state, so the replay applies the
// same forces.
//
// Divergence guard: an explicit step that blows up can stay finite for a while (the Π = 16
// constriction run of docs/sph-capsules.md reached |ρ − ρ0|/ρ0 = 485 within one sample, and its
// centroid jumped back by 1.3d, which the stall test would have called a blockage). Every sample
// therefore also checks the largest |ρ − ρ0|/ρ0: beyond 1 (the Tait equation of state, eq. 6, is
// set up for a few percent) the run stops with exit status 1 and a message naming the step, the
// time and the deviation; as with a non-finite value, nothing is written from that state.
#include "scenes/capsule/capsule_scene.hpp"
#include "analysis/capsule/capsule_shape.hpp"
#include "scenes/capsule/channel_geometry.hpp"
#include "drivers/common/cli.hpp"
#include "drivers/common/output_paths.hpp"
#include "drivers/common/particle_io.hpp"
#include "drivers/common/progress.hpp"

#include "kernels/common/kokkos_compat.hpp"
#include "io/h5md_writer.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>

namespace mesoflow {
namespace {

// The divergence guard of the file comment.
constexpr double kDivergedDensityDeviation = 1.0;
void check_not_diverged(double density_deviation, long step, double time, const char* time_unit) {
  if (density_deviation <= kDivergedDensityDeviation) return;
  std::ostringstream m;
  m << "capsule: the run diverged at step " << step << " (t = " << time << " " << time_unit
    << "): the largest |rho - rho0|/rho0 is " << density_deviation << ", beyond " << kDivergedDensityDeviation
    << " (eq. 6 is set up for a few percent); nothing was written from this state. A smaller --dt, a larger "
       "--c0 or a coarser --resolution may hold it";
  throw std::runtime_error(m.str());
}

// The step follows the state (file comment, "Time step"). At every sample the scene's running
// limits (CapsuleScene::running_time_step_limits) are evaluated again: an automatic step above
// them is lowered to them, never raised; a step given with --dt is kept, with one warning naming
// the term and the limit the first time the running limit falls below it. Steps are in lattice
// units; messages give them in the run's time unit (`unit` lattice time units, named `unit_name`).
class StepGovernor {
 public:
  StepGovernor(double dt, bool automatic, bool quiet, double unit, const char* unit_name)
      : dt_(dt), automatic_(automatic), quiet_(quiet), unit_(unit), unit_name_(unit_name) {}
  double dt() const { return dt_; }
  long lowered() const { return lowered_; }

  // At a sample at time t (run units), with the scene's running limits there. Returns true when
  // the step was lowered (the caller then re-derives its step counts).
  template <class Scene>
  bool revise(Scene& scene, const capsule::CapsuleTimeStepLimits& limits, double t) {
    const double limit = limits.dt();
    if (!(dt_ > limit)) return false;
    if (!automatic_) {
      if (!warned_)
        std::cerr << "warning: capsule: at t = " << t << " " << unit_name_ << " the stability limit fell to "
                  << limit / unit_ << " " << unit_name_ << " (" << limits.term() << "), below the given --dt "
                  << dt_ / unit_ << "; the run goes on with it\n";
      warned_ = true;
      return false;
    }
    if (!quiet_ && lowered_ == 0)
      std::cerr << "capsule: at t = " << t << " " << unit_name_ << " the step follows the stability limit, "
                << limits.term() << ", down from " << dt_ / unit_ << " to " << limit / unit_ << " " << unit_name_
                << "\n";
    dt_ = limit;
    scene.set_dt(dt_);
    ++lowered_;
    return true;
  }
  // One line for the end of a run whose step was lowered.
  void report(double dt0) const {
    if (lowered_ > 0 && !quiet_)
      std::cerr << "capsule: the step was lowered " << lowered_ << " times, from " << dt0 / unit_ << " to "
                << dt_ / unit_ << " " << unit_name_ << "\n";
  }

 private:
  double dt_;
  bool automatic_, quiet_;
  double unit_;
  const char* unit_name_;
  bool warned_ = false;
  long lowered_ = 0;
};

constexpr double pi = 3.14159265358979323846;

struct Parameters {
  std::string mode = "constriction";
  int resolution = 12;  // Π: lattice spacings per capsule diameter
  std::string ca = "0.25";
  std::string eta = "0.5";
  double reynolds = 1.0;
  double thickness = 1.0;  // h_t/Δx
  int level = 3;
  std::string diagonals = "one";
  double support = 2.5;  // Lucy support h/Δx
  std::string walls = "morris";
  double viscosity_ratio = 1.0;
  double c0 = 0;  // 0: the rule in the file comment
  double membrane_strain = 0.05;
  double density_variation = 0.01;
  double t_max = 25.0;
  double sample_every = 0.05;
  double frame_every = 0.5;
  double stall_window = 4.0;
  double shear_box_x = 5, shear_box_y = 4, shear_box_z = 4;
  int threads = 0;
  bool restart = false;
  double dt = 0;          // d/U (shear: 1/γ̇); 0: the scene's stability limit
  bool force_dt = false;  // --force-dt
  long long check_every = 100;  // steps between NaN-watchdog checks
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

// One run's results (a row of the sweep table).
struct RunResult {
  double ca = 0, eta = 0, eta_effective = 0;
  std::string status;  // passed, blocked (stalled), blocked (t-max)
  double passage_time = NAN, inverse_passage_time = 0;
  double Dx4 = NAN, Dy4 = NAN, Dz4 = NAN;
  double Cf[3] = {NAN, NAN, NAN}, Cr[3] = {NAN, NAN, NAN};  // at x_c = 3.5, 4, 4.5
  double max_density_deviation = 0;
  double dt = 0, c0 = 0, k_b = 0, steps = 0, wall_seconds = 0, particle_steps_per_second = 0;
  int particles = 0;
  std::string series_csv, sections_csv, signature;
};

const char* sweep_header =
    "ca,eta,eta_effective,status,passage_time,inverse_passage_time,Dx_at_4,Dy_at_4,Dz_at_4,Cf_at_3.5,Cf_at_4,"
    "Cf_at_4.5,Cr_at_3.5,Cr_at_4,Cr_at_4.5,max_density_deviation,dt,c0,k_b,steps,particles,wall_seconds,"
    "particle_steps_per_second,series_csv,sections_csv,signature";

std::string csv_row(const RunResult& r) {
  std::ostringstream s;
  s << std::setprecision(8) << r.ca << "," << r.eta << "," << r.eta_effective << "," << r.status << ","
    << r.passage_time << "," << r.inverse_passage_time << "," << r.Dx4 << "," << r.Dy4 << "," << r.Dz4;
  for (double c : r.Cf) s << "," << c;
  for (double c : r.Cr) s << "," << c;
  s << "," << r.max_density_deviation << "," << r.dt << "," << r.c0 << "," << r.k_b << "," << r.steps << ","
    << r.particles << "," << r.wall_seconds << "," << r.particle_steps_per_second << "," << r.series_csv << ","
    << r.sections_csv << "," << r.signature;
  return s.str();
}

std::optional<RunResult> read_result(const std::string& path) {
  std::ifstream f(path);
  std::string header, row;
  if (!f || !std::getline(f, header) || !std::getline(f, row) || header != sweep_header) return std::nullopt;
  std::vector<std::string> c;
  std::stringstream ss(row);
  std::string item;
  while (std::getline(ss, item, ',')) c.push_back(item);
  if (c.size() != 26) return std::nullopt;
  auto num = [&](int k) { return std::strtod(c[std::size_t(k)].c_str(), nullptr); };
  RunResult r;
  r.ca = num(0);
  r.eta = num(1);
  r.eta_effective = num(2);
  r.status = c[3];
  r.passage_time = num(4);
  r.inverse_passage_time = num(5);
  r.Dx4 = num(6);
  r.Dy4 = num(7);
  r.Dz4 = num(8);
  for (int k = 0; k < 3; ++k) {
    r.Cf[k] = num(9 + k);
    r.Cr[k] = num(12 + k);
  }
  r.max_density_deviation = num(15);
  r.dt = num(16);
  r.c0 = num(17);
  r.k_b = num(18);
  r.steps = num(19);
  r.particles = int(num(20));
  r.wall_seconds = num(21);
  r.particle_steps_per_second = num(22);
  r.series_csv = c[23];
  r.sections_csv = c[24];
  r.signature = c[25];
  return r;
}

// The scene's physical parameters from the dimensionless ones (lattice units Δx = ρ0 = U = 1).
struct Physical {
  double d, a, mu, G_s, k_b, c0, shear_rate = 0;
};

capsule::CapsuleSceneParameters scene_parameters(const Parameters& par, const capsule::ChannelGeometry& g,
                                                 double ca, double velocity_scale_length, double pressure_drop,
                                                 Physical& phys) {
  capsule::CapsuleSceneParameters sp;
  const double d = par.resolution;
  phys.d = d;
  phys.a = 0.5 * d;
  sp.channel = g;
  sp.spacing = 1;
  sp.support = par.support;
  sp.rho0 = 1;
  sp.radius = phys.a;
  sp.thickness = par.thickness;
  sp.level = par.level;
  sp.diagonals = par.diagonals == "both" ? msm::DiagonalBonds::both_per_quad : msm::DiagonalBonds::one_per_quad;
  sp.sph.wall_velocity = sph::parse_wall_velocity(par.walls);
  // μ from Re; G_s from Ca; k_b from G_s = E h_t/(2(1 + ν)), E = 5 k_b/(√3 δ), ν = 1/4.
  double strain_rate_length;  // μ U a/G_s (constriction) or μ γ̇ a/G_s (shear)
  if (par.mode == "shear") {
    phys.shear_rate = 2.0 / g.length[1];
    phys.mu = phys.shear_rate * phys.a * phys.a / par.reynolds;
    strain_rate_length = phys.shear_rate * phys.a;
  } else {
    phys.mu = d / par.reynolds;
    strain_rate_length = 1.0 * phys.a;
  }
  phys.G_s = phys.mu * strain_rate_length / ca;
  // δ_ave of the mesh: build it once to measure (cheap next to the run).
  msm::CapsuleMembraneParameters mp;
  mp.radius = phys.a;
  mp.thickness = par.thickness;
  mp.level = par.level;
  mp.bonds.k_b = 1;
  mp.bonds.diagonals = sp.diagonals;
  const double bond_length = msm::capsule_membrane(mp).mean_in_layer_bond_length();
  phys.k_b = phys.G_s * 2 * (1 + 0.25) * std::sqrt(3.0) * bond_length / (5 * par.thickness);
  sp.k_b = phys.k_b;
  sp.mu_outer = phys.mu;
  sp.mu_inner = phys.mu * par.viscosity_ratio;
  const double nu = phys.mu;  // ρ0 = 1
  const double delta = par.density_variation;
  const double morris = sph::morris_speed_of_sound(1.0, nu, velocity_scale_length, 0.0, delta);
  const double delta_p = 2 * phys.G_s * par.membrane_strain / phys.a;
  phys.c0 = par.c0 > 0 ? par.c0 : std::max({morris, std::sqrt(delta_p / delta), std::sqrt(pressure_drop / delta)});
  sp.u_max = 1;
  sp.c0 = phys.c0;
  // --dt in the run's time unit: d/U with U = 1 (constriction), 1/γ̇ (shear); the scene refuses it
  // above its limit (capsule_scene.hpp) unless --force-dt.
  if (par.dt > 0) sp.dt = par.dt * (par.mode == "shear" ? 1.0 / phys.shear_rate : d);
  sp.force_dt = par.force_dt;
  return sp;
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

template <class Scene>
double fluid_momentum_x(const Scene& scene) {
  using Exec = Kokkos::DefaultExecutionSpace;
  const auto& p = scene.system().particles;
  const auto v = p.v;
  const auto m = p.mass;
  const auto type = p.type;
  double px = 0;
  Kokkos::parallel_reduce(
      "mesoflow::capsule::fluid_momentum_x", Kokkos::RangePolicy<Exec>(0, int(p.size())),
      KOKKOS_LAMBDA(int i, double& acc) {
        if (!sph::is_fixed(type(i))) acc += double(m(i)) * double(v(i, 0));
      },
      px);
  return px;
}

// Membrane positions in vertex order (outer layer then inner), row-major, for the trajectory.
template <class Scene>
std::vector<double> membrane_positions(const Scene& scene) {
  const auto x = driver::to_row_major(scene.system().particles.x);
  auto slot = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), scene.membrane_slot());
  std::vector<double> out(std::size_t(3 * scene.num_membrane()));
  for (int k = 0; k < scene.num_membrane(); ++k)
    for (int d = 0; d < 3; ++d) out[std::size_t(3 * k + d)] = x[std::size_t(3 * slot(k) + d)];
  return out;
}

RunResult run_constriction(const Parameters& par, const cli::DriverApp& app, const std::string& stem, double ca,
                           double eta) {
  using Real = double;
  using Exec = Kokkos::DefaultExecutionSpace;
  const bool quiet = app.quiet();
  const auto g = capsule::constriction_channel(par.resolution, eta, 1.0);
  const double d = par.resolution;
  // The body force: start from the ducts' resistances (inlet/outlet 2d × 2d, constriction t_c × 2d).
  const auto duct_c = capsule::rectangular_duct(g.constriction_width, 2 * d);
  const auto duct_w = capsule::rectangular_duct(2 * d, 2 * d);
  const double u_mean_c = 1.0 / duct_c.peak_to_mean();
  const double u_mean_w = u_mean_c * g.constriction_width / (2 * d);
  const double l_c = g.constriction_end - g.constriction_begin;
  const double mu = d / par.reynolds;
  const double g0 = mu * (u_mean_c * l_c / duct_c.mean_coefficient +
                          u_mean_w * (g.length[0] - l_c) / duct_w.mean_coefficient) / g.length[0];
  Physical phys{};
  auto sp = scene_parameters(par, g, ca, 0.5 * g.constriction_width, 2 * g0 * g.length[0], phys);
  sp.centre = std::array<double, 3>{1.5 * d, d, d};
  sp.body_force = {g0, 0, 0};
  capsule::CapsuleScene<Real, Exec> scene(sp);
  const double dt = double(scene.system().dt());
  StepGovernor governor(dt, par.dt == 0, quiet, d, "d/U");
  const double target_px = u_mean_c * g.constriction_width * 2 * d * g.length[0];  // ρ0 = 1
  const double tau = 2 * d * d / (pi * pi * phys.mu);  // slowest viscous mode of the 2d × 2d duct
  // Step counts of the control and sampling intervals at the current step (re-derived when the
  // governor lowers it; samples stay par.sample_every apart to within a step).
  long control_every = 0, sample_every = 0;
  double kappa = 0;
  const auto derive_step_counts = [&] {
    const double h = governor.dt();
    control_every = std::max(1L, long(std::lround(0.02 * d / h)));
    kappa = std::min(0.5, control_every * h / tau);
    sample_every = std::max(1L, long(std::lround(par.sample_every * d / h)));
  };
  derive_step_counts();
  const long frame_samples = std::max(1L, long(std::lround(par.frame_every / par.sample_every)));
  const double t_end = par.t_max * d;
  const long max_steps = long(std::ceil(t_end / dt));  // at the starting step: the progress line's estimate
  const long stall_samples = std::max(2L, long(std::lround(par.stall_window / par.sample_every)));

  const std::string run = stem + "_ca" + tag(ca) + "_eta" + tag(eta);
  RunResult r;
  r.ca = ca;
  r.eta = eta;
  r.eta_effective = g.constriction_width / d;
  r.dt = dt / d;
  r.c0 = phys.c0;
  r.k_b = phys.k_b;
  r.particles = scene.num_particles();
  r.series_csv = run + "_series.csv";
  r.sections_csv = run + "_sections.csv";
  r.signature = scene_signature(par, ca, eta);

  io::H5mdWriter h5(run + ".h5");
  for (const auto& [key, value] : app.resolved_parameters()) h5.set_parameter(key, value);
  h5.set_parameter("ca_run", ca);
  h5.set_parameter("eta_run", eta);
  h5.set_parameter("eta_effective", r.eta_effective);
  h5.set_parameter("diameter_lattice", d);
  h5.set_parameter("viscosity", phys.mu);
  h5.set_parameter("surface_shear_modulus", phys.G_s);
  h5.set_parameter("k_b", phys.k_b);
  h5.set_parameter("c0", phys.c0);
  h5.set_parameter("dt", dt);
  h5.set_parameter("particles", scene.num_particles());
  h5.set_parameter("membrane_particles", scene.num_membrane());
  h5.set_parameter("wall_particles", scene.num_walls());
  const auto& box = scene.system().box();
  std::vector<double> lo(3), edges(3);
  std::vector<bool> periodic(3);
  for (int k = 0; k < 3; ++k) {
    lo[std::size_t(k)] = box.lo[k];
    edges[std::size_t(k)] = box.length[k];
    periodic[std::size_t(k)] = box.periodic[k];
  }
  h5.add_particles_group("membrane", 3, std::size_t(scene.num_membrane()), lo, edges, periodic);

  std::ofstream series(r.series_csv);
  series << "time,x_c,x_front,x_rear,Dx,Dy,Dz,Cf,Cr,body_force,flux_ratio,max_density_deviation,dt,"
            "limit_viscous,limit_acoustic,limit_force,limit_acoustic_viscous,limit_bond\n"
         << std::setprecision(8);
  std::ofstream sections(r.sections_csv);
  sections << "x_c_target,x,y\n" << std::setprecision(8);
  const std::vector<double> section_targets = {2.0, 3.0, 3.5, 4.0, 4.5, 5.0, 5.5};
  std::size_t next_section = 0;

  std::vector<double> xs, dx_s, dy_s, dz_s, cf_s, cr_s;
  double x_c_prev = NAN, x_c_unwrapped = 0, t_in = NAN, t_out = NAN, body = g0;
  const auto t0 = std::chrono::steady_clock::now();
  cli::ProgressLine progress(max_steps, scene.num_particles(), !quiet);
  // The flow controller, after every step; part of the watched step, with `body` kept.
  const auto control = [&] {
    if (scene.steps() % control_every != 0) return;
    const double ratio = fluid_momentum_x(scene) / target_px;
    body *= std::exp(std::clamp(kappa * (1 - ratio), -0.5, 0.5));
    body = std::min(body, 20 * g0);
    sph::BodyForce<3, Real> bf;
    bf.g[0] = body;
    scene.set_body_force(bf);
  };
  watchdog::Watched watched = scene.watched();
  watched.step = [&] {
    scene.step();
    control();
  };
  {
    auto kept = std::make_shared<double>(body);
    auto save = watched.save_host, restore = watched.restore_host;
    watched.save_host = [&body, kept, save] {
      save();
      *kept = body;
    };
    watched.restore_host = [&body, kept, restore] {
      restore();
      body = *kept;
    };
  }
  watchdog::NanWatchdog watch(std::move(watched), par.check_every);
  long step = 0, next_sample = 0, samples = 0;
  double t_lattice = 0;  // simulated time, lattice units (the step may change)
  r.status = "blocked (t-max)";
  for (;; ++step) {
    if (step > 0) {
      const double h = governor.dt();
      scene.step();
      control();
      t_lattice += h;
      watch.after_step();
      progress.update(step);
    }
    const bool last = t_lattice >= t_end * (1 - 1e-12);
    if (step < next_sample) {
      if (last) break;
      continue;
    }
    watch.check();  // nothing is sampled or written from a non-finite state
    const auto y = scene.outer_layer_positions();
    const auto shape = scene.membrane_shape(y);
    double xc = shape.centroid[0];
    if (std::isnan(x_c_prev)) {
      x_c_unwrapped = xc;
    } else {
      double dxc = xc - x_c_prev;
      dxc -= g.length[0] * std::floor(dxc / g.length[0] + 0.5);
      x_c_unwrapped += dxc;
    }
    x_c_prev = xc;
    const double shift = x_c_unwrapped - xc;  // unwrap the vertices with the centroid
    std::vector<Eigen::Vector3d> yu = y;
    for (auto& p : yu) p[0] += shift;
    double x_front = -1e300, x_rear = 1e300;
    for (const auto& p : yu) {
      x_front = std::max(x_front, p[0]);
      x_rear = std::min(x_rear, p[0]);
    }
    const auto D = capsule::deformation_indices(yu, d);
    const auto section = capsule::midplane_section(yu, scene.mesh().triangle, d);
    const double cf = capsule::tip_curvature(section, x_c_unwrapped, d, +1, phys.a);
    const double cr = capsule::tip_curvature(section, x_c_unwrapped, d, -1, phys.a);
    const double time = t_lattice / d;
    const double dens = scene.max_density_deviation();
    check_not_diverged(dens, step, time, "d/U");
    r.max_density_deviation = std::max(r.max_density_deviation, dens);
    const double flux_ratio = fluid_momentum_x(scene) / target_px;
    const auto limits = scene.running_time_step_limits();
    series << time << "," << x_c_unwrapped / d << "," << x_front / d << "," << x_rear / d << "," << D[0] << ","
           << D[1] << "," << D[2] << "," << cf << "," << cr << "," << body << "," << flux_ratio << "," << dens << ","
           << governor.dt() / d << "," << limits.sph.viscous / d << "," << limits.sph.acoustic / d << ","
           << limits.sph.force / d << "," << limits.sph.acoustic_viscous / d << "," << limits.bond / d
           << std::endl;  // flushed: the run can be watched
    const std::int64_t s64 = step;
    h5.append_observable("x_c", s64, time, x_c_unwrapped / d);
    h5.append_observable("deformation_index", s64, time, D.data(), 3);
    const double curv[2] = {cf, cr};
    h5.append_observable("tip_curvature_front_rear", s64, time, curv, 2);
    h5.append_observable("body_force", s64, time, body);
    h5.append_observable("flux_ratio", s64, time, flux_ratio);
    h5.append_observable("max_density_deviation", s64, time, dens);
    if (samples % frame_samples == 0) {
      const auto pos = membrane_positions(scene);
      h5.append("membrane", "position", s64, time, pos.data(), std::size_t(scene.num_membrane()), 3);
    }
    while (next_section < section_targets.size() && x_c_unwrapped / d >= section_targets[next_section]) {
      for (const auto& q : section)
        sections << section_targets[next_section] << "," << q[0] / d << "," << q[1] / d << "\n";
      ++next_section;
    }
    xs.push_back(x_c_unwrapped / d);
    dx_s.push_back(D[0]);
    dy_s.push_back(D[1]);
    dz_s.push_back(D[2]);
    cf_s.push_back(cf);
    cr_s.push_back(cr);
    if (std::isnan(t_in) && x_front >= g.constriction_begin) t_in = time;
    if (std::isnan(t_out) && x_rear >= g.constriction_end) t_out = time;
    if (x_c_unwrapped >= 6 * d) {
      r.status = "passed";
      break;
    }
    if (!std::isnan(t_in) && xs.size() > std::size_t(stall_samples) &&
        xs.back() - xs[xs.size() - 1 - std::size_t(stall_samples)] < 0.01) {
      r.status = "blocked (stalled)";
      break;
    }
    if (last) break;
    ++samples;
    if (governor.revise(scene, limits, time)) derive_step_counts();
    next_sample = step + sample_every;
  }
  progress.finish();
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.steps = double(step);
  governor.report(dt);
  r.particle_steps_per_second = r.steps * scene.num_particles() / r.wall_seconds;
  if (!std::isnan(t_out)) {
    r.passage_time = t_out - t_in;
    r.inverse_passage_time = 1 / r.passage_time;
    if (r.status != "passed") r.status = "passed";
  }
  r.Dx4 = capsule::value_at(xs, dx_s, 4.0);
  r.Dy4 = capsule::value_at(xs, dy_s, 4.0);
  r.Dz4 = capsule::value_at(xs, dz_s, 4.0);
  const double at[3] = {3.5, 4.0, 4.5};
  for (int k = 0; k < 3; ++k) {
    r.Cf[k] = capsule::value_at(xs, cf_s, at[k]);
    r.Cr[k] = capsule::value_at(xs, cr_s, at[k]);
  }
  h5.write_xdmf(run + ".xdmf");
  write_atomically(run + "_result.csv", std::string(sweep_header) + "\n" + csv_row(r) + "\n");
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
  std::vector<RunResult> results;
  for (double eta : etas)
    for (double ca : cas) {
      const std::string run = stem + "_ca" + tag(ca) + "_eta" + tag(eta);
      if (par.restart) {
        const auto done = read_result(run + "_result.csv");
        if (done && done->signature == scene_signature(par, ca, eta)) {
          if (!app.quiet()) std::cerr << "capsule: reusing the finished run " << run << "\n";
          results.push_back(*done);
          continue;
        }
      }
      results.push_back(run_constriction(par, app, stem, ca, eta));
    }
  std::ostringstream table;
  table << sweep_header << "\n";
  for (const auto& r : results) table << csv_row(r) << "\n";
  write_atomically(stem + "_sweep.csv", table.str());

  // Pearson's r against Ca per η (eq. 17, Table 1).
  std::ostringstream json;
  json << std::setprecision(8) << "{\n  \"driver\": \"capsule\",\n  \"mode\": \"constriction\",\n  \"resolution\": "
       << par.resolution << ",\n  \"reynolds\": " << par.reynolds << ",\n  \"runs\": " << results.size()
       << ",\n  \"kokkos\": \"" << kokkos_configuration() << "\",\n  \"pearson_r\": [";
  bool first = true;
  for (double eta : etas) {
    std::vector<const RunResult*> rows;
    for (const auto& r : results)
      if (r.eta == eta) rows.push_back(&r);
    auto column = [&](auto get) {
      std::vector<double> x, c;
      for (const auto* r : rows) {
        x.push_back(get(*r));
        c.push_back(r->ca);
      }
      return capsule::pearson_r(x, c);
    };
    auto out_r = [&](const char* name, double v) {
      json << "\"" << name << "\": ";
      if (std::isfinite(v))
        json << v;
      else
        json << "null";
    };
    json << (first ? "" : ",") << "\n    {\"eta\": " << eta << ", ";
    first = false;
    out_r("inverse_passage_time", column([](const RunResult& r) { return r.inverse_passage_time; }));
    json << ", ";
    out_r("Dx_at_4", column([](const RunResult& r) { return r.Dx4; }));
    json << ", ";
    out_r("Dy_at_4", column([](const RunResult& r) { return r.Dy4; }));
    json << ", ";
    out_r("Dz_at_4", column([](const RunResult& r) { return r.Dz4; }));
    const char* cf_names[3] = {"Cf_at_3.5", "Cf_at_4", "Cf_at_4.5"};
    const char* cr_names[3] = {"Cr_at_3.5", "Cr_at_4", "Cr_at_4.5"};
    for (int k = 0; k < 3; ++k) {
      json << ", ";
      out_r(cf_names[k], column([k](const RunResult& r) { return r.Cf[k]; }));
      json << ", ";
      out_r(cr_names[k], column([k](const RunResult& r) { return r.Cr[k]; }));
    }
    json << "}";
  }
  json << "\n  ]\n}\n";
  write_atomically(out.summary, json.str());
  driver::plot_with_matplotlib("capsule", "plot_capsule.py", {"constriction", stem + "_sweep.csv", stem + ".png",
                                                               stem + "_snapshot.png"},
                               stem + ".png", app.quiet());
}

void shear_runs(const Parameters& par, const cli::DriverApp& app) {
  using Real = double;
  using Exec = Kokkos::DefaultExecutionSpace;
  const driver::OutputPaths out(app.output());
  const std::string stem = out.trajectory.substr(0, out.trajectory.size() - 3);
  const auto cas = parse_list(par.ca, "--ca", 0.0, 100.0);
  const double d = par.resolution;
  std::ostringstream table;
  const std::string header =
      "ca,taylor_deformation,taylor_deformation_std,inclination_over_pi,inclination_over_pi_std,dt_gamma,"
      "shear_time,particles,max_density_deviation,wall_seconds,series_csv,signature";
  table << header << "\n";
  for (double ca : cas) {
    const std::string run = stem + "_shear_ca" + tag(ca);
    const std::string signature = scene_signature(par, ca, 0) + ";box=" + tag(par.shear_box_x) + "x" +
                                  tag(par.shear_box_y) + "x" + tag(par.shear_box_z);
    if (par.restart) {  // reuse a finished run of the same scene
      std::ifstream done(run + "_result.csv");
      std::string h, row;
      if (done && std::getline(done, h) && std::getline(done, row) && h == header &&
          row.size() > signature.size() && row.compare(row.size() - signature.size(), signature.size(), signature) == 0) {
        if (!app.quiet()) std::cerr << "capsule: reusing the finished run " << run << "\n";
        table << row << "\n";
        continue;
      }
    }
    const auto g = capsule::shear_channel({par.shear_box_x * d, par.shear_box_y * d, par.shear_box_z * d}, 1.0);
    Physical phys{};
    auto sp = scene_parameters(par, g, ca, 0.5 * g.length[1], 0.0, phys);
    capsule::CapsuleScene<Real, Exec> scene(sp);
    const double dt = double(scene.system().dt());
    const double gamma = phys.shear_rate;
    StepGovernor governor(dt, par.dt == 0, app.quiet(), 1 / gamma, "1/shear rate");
    const long max_steps = long(std::ceil(par.t_max / (gamma * dt)));  // at the starting step: an estimate
    long sample_every = std::max(1L, long(std::lround(par.sample_every / (gamma * dt))));
    std::ofstream series(run + "_series.csv");
    series << "shear_time,taylor_deformation,inclination_over_pi,max_density_deviation,dt_gamma\n"
           << std::setprecision(8);
    std::vector<double> t_s, D_s, th_s;
    double dens_max = 0;
    const auto t0 = std::chrono::steady_clock::now();
    cli::ProgressLine progress(max_steps, scene.num_particles(), !app.quiet());
    watchdog::NanWatchdog watch(scene.watched(), par.check_every);
    double t_lattice = 0;  // simulated time, lattice units (the step may change)
    for (long step = 0, next_sample = 0;; ++step) {
      if (step > 0) {
        const double h = governor.dt();
        scene.step();
        t_lattice += h;
        watch.after_step();
        progress.update(step);
      }
      const bool last = t_lattice * gamma >= par.t_max * (1 - 1e-12);
      if (step < next_sample) {
        if (last) break;
        continue;
      }
      watch.check();  // nothing is sampled or written from a non-finite state
      const auto s = capsule::shear_plane_shape(scene.outer_layer_positions());
      const double dens = scene.max_density_deviation();
      const double t = t_lattice * gamma;
      check_not_diverged(dens, step, t, "1/shear rate");
      dens_max = std::max(dens_max, dens);
      series << t << "," << s.taylor << "," << s.inclination / pi << "," << dens << "," << governor.dt() * gamma
             << std::endl;
      t_s.push_back(t);
      D_s.push_back(s.taylor);
      th_s.push_back(s.inclination / pi);
      if (last) break;
      if (governor.revise(scene, scene.running_time_step_limits(), t))
        sample_every = std::max(1L, long(std::lround(par.sample_every / (gamma * governor.dt()))));
      next_sample = step + sample_every;
    }
    progress.finish();
    governor.report(dt);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    // Steady values: the last 30% of the run.
    double sD = 0, sD2 = 0, sT = 0, sT2 = 0;
    int n = 0;
    for (std::size_t k = 0; k < t_s.size(); ++k)
      if (t_s[k] >= 0.7 * par.t_max) {
        sD += D_s[k];
        sD2 += D_s[k] * D_s[k];
        sT += th_s[k];
        sT2 += th_s[k] * th_s[k];
        ++n;
      }
    const double mD = n ? sD / n : NAN, mT = n ? sT / n : NAN;
    std::ostringstream row;
    row << std::setprecision(8) << ca << "," << mD << "," << std::sqrt(std::max(0.0, sD2 / n - mD * mD)) << ","
        << mT << "," << std::sqrt(std::max(0.0, sT2 / n - mT * mT)) << "," << dt * gamma << "," << par.t_max << ","
        << scene.num_particles() << "," << dens_max << "," << wall << "," << run + "_series.csv" << "," << signature;
    write_atomically(run + "_result.csv", header + "\n" + row.str() + "\n");
    table << row.str() << "\n";
    if (!app.quiet())
      std::cerr << "capsule shear: Ca " << ca << ": D_xy = " << mD << ", theta/pi = " << mT << " (" << wall
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
