// capsule_runs.hpp — the runs of the capsule study (sph-microcapsules-constriction §3–§5): the
// capsule through the constriction of Fig. 1 and in simple shear (§4.1), composed from CapsuleScene
// (capsule_scene.hpp). Setup and loops only; the measures of a sample (deformation indices, tip
// curvatures, the shear-plane shape) are analysis/capsule/capsule_shape.hpp, applied by the driver.
//
// Units (§4): lattice units Δx = ρ0 = U = 1, capsule diameter d = Π Δx, the viscosity from Re,
//   constriction: Re = ρ0 U d/μ;   shear: Re = ρ0 γ̇ a²/μ, γ̇ = 2V/L_y with V = 1 the walls' speed;
// the membrane's k_b from Ca = μ U a/G_s (shear: μ γ̇ a/G_s). G_s is the shear modulus of *our*
// network (shear_modulus = "network", the default; issue 29 item 1): measured on a flat periodic
// patch of the same network at the run's h_t/δ_ave (membrane_elasticity.hpp), so k_b = G_s/(G_s/k_b).
// shear_modulus = "paper" keeps §4's formula G_s = E h_t/(2(1 + ν)), E = 5 k_b/(√3 δ_ave), ν = 1/4
// (kernels/msm/membrane_moduli.hpp), which the runs before issue 29 used; both capillary numbers are
// recorded with every run (Physical::ca_network, ca_paper), so either converts into the other.
// c0 of eq. (6) for density variations δ: the largest of Morris et al.'s viscous criterion
// √(ν U/(L δ)) (with U/√δ), their body-force criterion √(2 g₀ L_x/δ) for the pressure drop at twice
// the starting body force, and the membrane's √(Δp/(ρ0 δ)), Δp = 2 G_s ε/a at strain ε.
//
// Constriction flow control: the body force holds the fluid's x momentum at ρ0 ū_c A_c L_x (the flux
// through the constriction at the mean velocity ū_c = U/(u_max/ū) of developed flow in that duct) by
// g ← g exp(κ(1 − P_x/P*)) every T_c = 0.02 d/U, κ = T_c/τ, τ = 2d²/(π² ν) the slowest viscous mode
// of the 2d × 2d duct; g starts from the ducts' resistances and is capped at 20 times that start.
//
// Time step (StepGovernor): at every sample the scene's running limits are evaluated again; an
// automatic step above them is lowered to them, never raised; a given --dt is kept, with one
// warning. Divergence guard: beyond |ρ − ρ0|/ρ0 = 1 at a sample the run stops (eq. 6 is set up for
// a few percent), before anything is written from that state.
#pragma once

#include "kernels/common/kernel_launch.hpp"
#include "kernels/msm/membrane_moduli.hpp"
#include "scenes/capsule/membrane_elasticity.hpp"
#include "kernels/sph/tait_equation_of_state.hpp"
#include "scenes/capsule/capsule_scene.hpp"
#include "scenes/capsule/channel_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <initializer_list>
#include <iostream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace mesoflow::capsule {

constexpr double pi = 3.14159265358979323846;

// The study's dimensionless parameters (defaults: the driver's).
struct CapsuleRunParameters {
  std::string mode = "constriction";  // or "shear"
  int resolution = 12;                // Π: lattice spacings per capsule diameter
  double reynolds = 1.0;
  double thickness = 1.0;             // h_t/Δx
  int level = 3;
  std::string diagonals = "one";
  std::string shear_modulus = "network";  // G_s of Ca: "network" (measured) or "paper" (§4's formula)
  double support = 2.5;               // Lucy support h/Δx
  std::string walls = "morris";
  double viscosity_ratio = 1.0;
  double c0 = 0;                      // 0: the rule of the file comment
  double membrane_strain = 0.05;
  double density_variation = 0.01;
  double t_max = 25.0;
  double sample_every = 0.05;
  double frame_every = 0.5;
  double stall_window = 4.0;
  double shear_box_x = 5, shear_box_y = 4, shear_box_z = 4;
  double dt = 0;                      // d/U (shear: 1/γ̇); 0: the scene's stability limit
  bool force_dt = false;
  long long check_every = 100;        // steps between NaN-watchdog checks
  // The deterministic-sum mode (issue 26 item 4, docs/design.md): full neighbor lists, each row
  // summing its own particle's forces, instead of a half list whose reactions are scattered
  // (duplicated per thread on the host, float atomics on GPUs): the same bits on every backend and
  // thread count, for twice the pair evaluations.
  bool deterministic = false;

  // The ranges of the `capsule` driver's options, for callers that fill the struct themselves (the
  // Python module): std::invalid_argument naming the parameter, its range and the value.
  void validate() const {
    auto in = [](const char* name, double v, double lo, double hi, bool lo_open = false) {
      const bool ok = std::isfinite(v) && (lo_open ? v > lo : v >= lo) && v <= hi;
      if (!ok) {
        std::ostringstream s;
        s << "capsule run: " << name << " must be in " << (lo_open ? "(" : "[") << lo << ", " << hi << "], got " << v;
        throw std::invalid_argument(s.str());
      }
    };
    auto one_of = [](const char* name, const std::string& v, std::initializer_list<const char*> choices) {
      for (const char* c : choices)
        if (v == c) return;
      std::string list;
      for (const char* c : choices) list += std::string(list.empty() ? "" : ", ") + c;
      throw std::invalid_argument(std::string("capsule run: ") + name + " must be one of " + list + ", got '" + v +
                                  "'");
    };
    one_of("mode", mode, {"constriction", "shear", "moduli"});
    in("resolution", resolution, 6, 128);
    in("reynolds", reynolds, 1e-3, 100);
    in("thickness", thickness, 0.25, 4);
    in("level", level, 1, 5);
    one_of("diagonals", diagonals, {"one", "both"});
    one_of("shear_modulus", shear_modulus, {"network", "paper"});
    in("support", support, 1.5, 4);
    one_of("walls", walls, {"morris", "prescribed"});
    in("viscosity_ratio", viscosity_ratio, 0.01, 100);
    in("c0", c0, 0, 1e4);
    in("membrane_strain", membrane_strain, 0, 1, true);
    in("density_variation", density_variation, 1e-4, 0.1);
    in("t_max", t_max, 0, 1e4, true);
    in("sample_every", sample_every, 0, 10, true);
    in("frame_every", frame_every, 0, 100, true);
    in("stall_window", stall_window, 0, 1e3, true);
    in("shear_box_x", shear_box_x, 2, 20);
    in("shear_box_y", shear_box_y, 1.5, 20);
    in("shear_box_z", shear_box_z, 1.5, 20);
    in("dt", dt, 0, 1);
    in("check_every", double(check_every), 1, 1e6);
  }
};

// The scene of a run at (Ca, η) as a string, kept in its result file: a sweep's --restart reuses
// only the finished runs whose string matches (the shear runs add their box).
inline std::string scene_signature(const CapsuleRunParameters& par, double ca, double eta) {
  std::ostringstream s;
  s << std::setprecision(10) << par.mode << ";Pi=" << par.resolution << ";Ca=" << ca << ";eta=" << eta
    << ";Re=" << par.reynolds << ";ht=" << par.thickness << ";level=" << par.level << ";diag=" << par.diagonals
    << ";h=" << par.support << ";walls=" << par.walls << ";lambda=" << par.viscosity_ratio << ";c0=" << par.c0
    << ";strain=" << par.membrane_strain << ";delta=" << par.density_variation << ";tmax=" << par.t_max << ";sample=" << par.sample_every
    << ";stall=" << par.stall_window;
  if (par.dt > 0) s << ";dt=" << par.dt;
  if (par.deterministic) s << ";lists=full";
  // The runs before issue 29 used the paper's G_s and wrote no tag: their files stay reusable with
  // --shear-modulus paper.
  if (par.shear_modulus != "paper") s << ";Gs=" << par.shear_modulus;
  return s.str();
}

// The scene of a shear run at Ca: scene_signature with η = 0 and the box (in d).
inline std::string shear_signature(const CapsuleRunParameters& par, double ca) {
  std::ostringstream s;
  s << scene_signature(par, ca, 0) << ";box=" << par.shear_box_x << "x" << par.shear_box_y << "x" << par.shear_box_z;
  return s.str();
}

// The scene's physical parameters (lattice units).
struct Physical {
  double d, a, mu, G_s, k_b, c0, shear_rate = 0;
  // The membrane's moduli at this k_b: G_s and K_A of the network (measured), G_s of §4's formula,
  // and the capillary number under each definition (the run's Ca is the one par.shear_modulus names).
  double G_s_network = 0, K_A_network = 0, G_s_paper = 0, ca_network = 0, ca_paper = 0, thickness_over_spacing = 0;
};

// The membrane's moduli per unit k_b for the run's mesh (radius Π/2, h_t, level, diagonals): G_s and
// K_A of the network, measured on a patch at the mesh's h_t/δ_ave (membrane_elasticity.hpp), and
// G_s of §4's formula, E h_t/(2(1 + ν)) with E = 5 k_b/(√3 δ_ave), ν = 1/4. All three scale with k_b.
struct MembraneModuliPerBond {
  double thickness_over_spacing = 0;  // h_t/δ_ave
  double shear_network = 0, area_network = 0, shear_paper = 0;
};

inline MembraneModuliPerBond membrane_moduli_per_bond(const CapsuleRunParameters& par) {
  if (par.shear_modulus != "network" && par.shear_modulus != "paper")
    throw std::invalid_argument("capsule: --shear-modulus must be network or paper, got '" + par.shear_modulus + "'");
  // δ_ave of the mesh: build it once to measure (cheap next to the run).
  msm::CapsuleMembraneParameters mp;
  mp.radius = 0.5 * par.resolution;
  mp.thickness = par.thickness;
  mp.level = par.level;
  mp.bonds.k_b = 1;
  mp.bonds.diagonals = par.diagonals == "both" ? msm::DiagonalBonds::both_per_quad : msm::DiagonalBonds::one_per_quad;
  const double bond_length = msm::capsule_membrane(mp).mean_in_layer_bond_length();
  MembraneModuliPerBond m;
  m.thickness_over_spacing = par.thickness / bond_length;
  const auto network = measure_membrane_moduli(m.thickness_over_spacing, mp.bonds.diagonals);
  m.shear_network = network.shear;
  m.area_network = network.area;
  m.shear_paper = msm::surface_shear_modulus(1.0, bond_length, par.thickness);
  return m;
}

inline CapsuleSceneParameters scene_parameters(const CapsuleRunParameters& par, const ChannelGeometry& g, double ca,
                                               double velocity_scale_length, double pressure_drop, Physical& phys) {
  CapsuleSceneParameters sp;
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
  sp.sph.list_kind = par.deterministic ? NeighborListKind::full : NeighborListKind::half;
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
  const auto moduli = membrane_moduli_per_bond(par);
  phys.thickness_over_spacing = moduli.thickness_over_spacing;
  phys.k_b = phys.G_s / (par.shear_modulus == "paper" ? moduli.shear_paper : moduli.shear_network);
  phys.G_s_network = moduli.shear_network * phys.k_b;
  phys.K_A_network = moduli.area_network * phys.k_b;
  phys.G_s_paper = moduli.shear_paper * phys.k_b;
  phys.ca_network = phys.mu * strain_rate_length / phys.G_s_network;
  phys.ca_paper = phys.mu * strain_rate_length / phys.G_s_paper;
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
  // dt in the run's time unit: d/U with U = 1 (constriction), 1/γ̇ (shear); the scene refuses it
  // above its limit unless force_dt.
  if (par.dt > 0) sp.dt = par.dt * (par.mode == "shear" ? 1.0 / phys.shear_rate : d);
  sp.force_dt = par.force_dt;
  return sp;
}

// The divergence guard of the file comment.
constexpr double diverged_density_deviation = 1.0;
inline void check_not_diverged(double density_deviation, long step, double time, const char* time_unit) {
  if (density_deviation <= diverged_density_deviation) return;
  std::ostringstream m;
  m << "capsule: the run diverged at step " << step << " (t = " << time << " " << time_unit
    << "): the largest |rho - rho0|/rho0 is " << density_deviation << ", beyond " << diverged_density_deviation
    << " (eq. 6 is set up for a few percent); nothing was written from this state. A smaller --dt, a larger "
       "--c0 or a coarser --resolution may hold it";
  throw std::runtime_error(m.str());
}

// The step follows the state (file comment). Steps are in lattice units; messages give them in the
// run's time unit (`unit` lattice time units, named `unit_name`).
class StepGovernor {
 public:
  StepGovernor(double dt, bool automatic, bool quiet, double unit, const char* unit_name)
      : dt_(dt), automatic_(automatic), quiet_(quiet), unit_(unit), unit_name_(unit_name) {}
  double dt() const { return dt_; }
  long lowered() const { return lowered_; }

  // At a sample at time t (run units), with the scene's running limits there. Returns true when
  // the step was lowered (the caller then re-derives its step counts).
  template <class Scene>
  bool revise(Scene& scene, const CapsuleTimeStepLimits& limits, double t) {
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

// Σ m v_x over the fluids (inner and outer: what the body force drives).
template <class Scene>
double fluid_momentum_x(const Scene& scene) {
  const auto& p = scene.system().particles;
  using Exec = typename std::decay_t<decltype(p.v)>::execution_space;
  const auto v = p.v;
  const auto m = p.mass;
  const auto type = p.type;
  double px = 0;
  mesoflow::launch::parallel_reduce(
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
  const auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), scene.system().particles.x);
  auto slot = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), scene.membrane_slot());
  std::vector<double> out(std::size_t(3 * scene.num_membrane()));
  for (int k = 0; k < scene.num_membrane(); ++k)
    for (int d = 0; d < 3; ++d) out[std::size_t(3 * k + d)] = double(x(slot(k), d));
  return out;
}

// What a constriction sample hands out (lengths in lattice units, time in d/U).
struct ConstrictionSample {
  long step = 0, index = 0;  // step, and samples before this one
  double time = 0;
  std::vector<Eigen::Vector3d> y;  // outer layer, unwrapped along x with the centroid
  double x_c = 0, x_front = 0, x_rear = 0;
  double body_force = 0, flux_ratio = 0, density_deviation = 0, dt = 0;
  CapsuleTimeStepLimits limits;
};

// The capsule through the constriction (file comment): the scene, its flow control and its step.
template <class Real = double, class Exec = Kokkos::DefaultExecutionSpace>
class ConstrictionRun {
 public:
  using Scene = CapsuleScene<Real, Exec>;

  ConstrictionRun(const CapsuleRunParameters& par, double ca, double eta, bool quiet)
      : par_(par), g_(constriction_channel(par.resolution, eta, 1.0)), d_(par.resolution) {
    // The body force: start from the ducts' resistances (inlet/outlet 2d × 2d, constriction t_c × 2d).
    const double d = d_;
    const auto duct_c = rectangular_duct(g_.constriction_width, 2 * d);
    const auto duct_w = rectangular_duct(2 * d, 2 * d);
    const double u_mean_c = 1.0 / duct_c.peak_to_mean();
    const double u_mean_w = u_mean_c * g_.constriction_width / (2 * d);
    const double l_c = g_.constriction_end - g_.constriction_begin;
    const double mu = d / par.reynolds;
    g0_ = mu * (u_mean_c * l_c / duct_c.mean_coefficient + u_mean_w * (g_.length[0] - l_c) / duct_w.mean_coefficient) /
          g_.length[0];
    auto sp = scene_parameters(par, g_, ca, 0.5 * g_.constriction_width, 2 * g0_ * g_.length[0], phys_);
    sp.centre = std::array<double, 3>{1.5 * d, d, d};
    sp.body_force = {g0_, 0, 0};
    scene_ = std::make_unique<Scene>(sp);
    dt0_ = double(scene_->system().dt());
    governor_ = std::make_unique<StepGovernor>(dt0_, par.dt == 0, quiet, d, "d/U");
    target_px_ = u_mean_c * g_.constriction_width * 2 * d * g_.length[0];  // ρ0 = 1
    tau_ = 2 * d * d / (pi * pi * phys_.mu);  // slowest viscous mode of the 2d × 2d duct
    body_ = g0_;
    derive_step_counts();
  }

  // Runs until the capsule has passed (x_c ≥ 6d), stalls (its centroid moves less than 0.01d over
  // the stall window after its front entered) or t_max. out.sample(ConstrictionSample) at every
  // sample, out.progress(step) after every step. Returns the status.
  template <class Output>
  std::string run(Output& out) {
    watchdog::Watched watched = scene_->watched();
    watched.step = [this] {
      scene_->step();
      control();
    };
    {  // the controller's body force is state: kept and put back with the rest
      auto kept = std::make_shared<double>(body_);
      auto save = watched.save_host, restore = watched.restore_host;
      watched.save_host = [this, kept, save] {
        save();
        *kept = body_;
      };
      watched.restore_host = [this, kept, restore] {
        restore();
        body_ = *kept;
      };
    }
    watchdog::NanWatchdog watch(std::move(watched), par_.check_every);
    const double d = d_, t_end = par_.t_max * d;
    const long stall_samples = std::max(2L, long(std::lround(par_.stall_window / par_.sample_every)));
    double x_c_prev = NAN, x_c_unwrapped = 0, t_lattice = 0;
    long next_sample = 0, samples = 0;
    std::vector<double> xs;
    for (step_ = 0;; ++step_) {
      if (step_ > 0) {
        const double h = governor_->dt();
        scene_->step();
        control();
        t_lattice += h;
        watch.after_step();
        out.progress(step_);
      }
      const bool last = t_lattice >= t_end * (1 - 1e-12);
      if (step_ < next_sample) {
        if (last) break;
        continue;
      }
      watch.check();  // nothing is sampled or written from a non-finite state
      ConstrictionSample s;
      s.step = step_;
      s.index = samples;
      s.y = scene_->outer_layer_positions();
      const double xc = scene_->membrane_shape(s.y).centroid[0];
      if (std::isnan(x_c_prev)) {
        x_c_unwrapped = xc;
      } else {
        double dxc = xc - x_c_prev;
        dxc -= g_.length[0] * std::floor(dxc / g_.length[0] + 0.5);
        x_c_unwrapped += dxc;
      }
      x_c_prev = xc;
      const double shift = x_c_unwrapped - xc;  // unwrap the vertices with the centroid
      for (auto& p : s.y) p[0] += shift;
      s.x_front = -1e300;
      s.x_rear = 1e300;
      for (const auto& p : s.y) {
        s.x_front = std::max(s.x_front, p[0]);
        s.x_rear = std::min(s.x_rear, p[0]);
      }
      s.x_c = x_c_unwrapped;
      s.time = t_lattice / d;
      s.density_deviation = scene_->max_density_deviation();
      check_not_diverged(s.density_deviation, step_, s.time, "d/U");
      max_density_deviation_ = std::max(max_density_deviation_, s.density_deviation);
      s.flux_ratio = fluid_momentum_x(*scene_) / target_px_;
      s.limits = scene_->running_time_step_limits();
      s.body_force = body_;
      s.dt = governor_->dt();
      out.sample(s);
      xs.push_back(x_c_unwrapped / d);
      if (std::isnan(t_in_) && s.x_front >= g_.constriction_begin) t_in_ = s.time;
      if (std::isnan(t_out_) && s.x_rear >= g_.constriction_end) t_out_ = s.time;
      if (x_c_unwrapped >= 6 * d) return "passed";
      if (!std::isnan(t_in_) && xs.size() > std::size_t(stall_samples) &&
          xs.back() - xs[xs.size() - 1 - std::size_t(stall_samples)] < 0.01)
        return "blocked (stalled)";
      if (last) break;
      ++samples;
      if (governor_->revise(*scene_, s.limits, s.time)) derive_step_counts();
      next_sample = step_ + sample_every_;
    }
    return "blocked (t-max)";
  }

  const Scene& scene() const { return *scene_; }
  const ChannelGeometry& channel() const { return g_; }
  const Physical& physical() const { return phys_; }
  const StepGovernor& governor() const { return *governor_; }
  double start_dt() const { return dt0_; }
  long steps() const { return step_; }
  long frame_samples() const { return std::max(1L, long(std::lround(par_.frame_every / par_.sample_every))); }
  long max_steps() const { return long(std::ceil(par_.t_max * d_ / dt0_)); }  // at the starting step
  double max_density_deviation() const { return max_density_deviation_; }
  double entry_time() const { return t_in_; }  // front reaching the constriction (NaN: never)
  double exit_time() const { return t_out_; }  // rear leaving it (NaN: never)

 private:
  // Step counts of the control and sampling intervals at the current step (re-derived when the
  // governor lowers it; samples stay sample_every apart to within a step).
  void derive_step_counts() {
    const double h = governor_->dt();
    control_every_ = std::max(1L, long(std::lround(0.02 * d_ / h)));
    kappa_ = std::min(0.5, control_every_ * h / tau_);
    sample_every_ = std::max(1L, long(std::lround(par_.sample_every * d_ / h)));
  }

  // The flow controller, after every step (part of the watched step).
  void control() {
    if (scene_->steps() % control_every_ != 0) return;
    const double ratio = fluid_momentum_x(*scene_) / target_px_;
    body_ *= std::exp(std::clamp(kappa_ * (1 - ratio), -0.5, 0.5));
    body_ = std::min(body_, 20 * g0_);
    sph::BodyForce<3, Real> bf;
    bf.g[0] = body_;
    scene_->set_body_force(bf);
  }

  CapsuleRunParameters par_;
  ChannelGeometry g_;
  double d_;
  Physical phys_{};
  double g0_ = 0, dt0_ = 0, target_px_ = 0, tau_ = 0, body_ = 0, kappa_ = 0;
  std::unique_ptr<Scene> scene_;
  std::unique_ptr<StepGovernor> governor_;
  long control_every_ = 0, sample_every_ = 0, step_ = 0;
  double max_density_deviation_ = 0, t_in_ = NAN, t_out_ = NAN;
};

// The capsule in simple shear (§4.1): walls bounding y slide at ∓V. out.sample(t, outer layer,
// density deviation, dt·γ̇) at every sample (t = γ̇ t), out.progress(step) after every step.
template <class Real = double, class Exec = Kokkos::DefaultExecutionSpace>
class ShearRun {
 public:
  using Scene = CapsuleScene<Real, Exec>;

  ShearRun(const CapsuleRunParameters& par, double ca, bool quiet) : par_(par) {
    const double d = par.resolution;
    const auto g = shear_channel({par.shear_box_x * d, par.shear_box_y * d, par.shear_box_z * d}, 1.0);
    scene_ = std::make_unique<Scene>(scene_parameters(par, g, ca, 0.5 * g.length[1], 0.0, phys_));
    dt0_ = double(scene_->system().dt());
    governor_ = std::make_unique<StepGovernor>(dt0_, par.dt == 0, quiet, 1 / phys_.shear_rate, "1/shear rate");
  }

  template <class Output>
  void run(Output& out) {
    const double gamma = phys_.shear_rate;
    long sample_every = std::max(1L, long(std::lround(par_.sample_every / (gamma * dt0_))));
    watchdog::NanWatchdog watch(scene_->watched(), par_.check_every);
    double t_lattice = 0;  // simulated time, lattice units (the step may change)
    for (long step = 0, next_sample = 0;; ++step) {
      if (step > 0) {
        const double h = governor_->dt();
        scene_->step();
        t_lattice += h;
        watch.after_step();
        out.progress(step);
      }
      const bool last = t_lattice * gamma >= par_.t_max * (1 - 1e-12);
      if (step < next_sample) {
        if (last) break;
        continue;
      }
      watch.check();  // nothing is sampled or written from a non-finite state
      const auto y = scene_->outer_layer_positions();
      const double dens = scene_->max_density_deviation();
      const double t = t_lattice * gamma;
      check_not_diverged(dens, step, t, "1/shear rate");
      max_density_deviation_ = std::max(max_density_deviation_, dens);
      out.sample(t, y, dens, governor_->dt() * gamma);
      if (last) break;
      if (governor_->revise(*scene_, scene_->running_time_step_limits(), t))
        sample_every = std::max(1L, long(std::lround(par_.sample_every / (gamma * governor_->dt()))));
      next_sample = step + sample_every;
    }
  }

  const Scene& scene() const { return *scene_; }
  const Physical& physical() const { return phys_; }
  const StepGovernor& governor() const { return *governor_; }
  double start_dt() const { return dt0_; }
  long max_steps() const { return long(std::ceil(par_.t_max / (phys_.shear_rate * dt0_))); }  // an estimate
  double max_density_deviation() const { return max_density_deviation_; }

 private:
  CapsuleRunParameters par_;
  Physical phys_{};
  std::unique_ptr<Scene> scene_;
  std::unique_ptr<StepGovernor> governor_;
  double dt0_ = 0, max_density_deviation_ = 0;
};

}  // namespace mesoflow::capsule
