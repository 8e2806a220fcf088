// orifice_run.hpp — one DP droplet falling through the narrow orifice of capillary-droplets §2.1
// (Fig. 1a): two 45° wedges leave a gap of width w; the droplet starts above it at rest, FIRE removes
// overlaps without gravity (§2.4), then it falls under gravity with drag (eqs. 5–7) until it has
// passed (centre of mass end_h below the orifice), clogged (E_k/E_t below the threshold of
// Appendix C) or the time limit ends the run. Shared by the `orifice` and `calibrate` drivers and
// the tests; calibration_scene gives the `calibrate` driver's passages (the fit itself is host
// analysis, analysis/droplets/profile_calibration.hpp).
//
// Units as in droplet_scene.hpp: σ, g, ρ; t0 = √(σ/g); speeds in σ/t0, so v_t = V_t.
// Frame: gravity along −y, the orifice at y = 0, x = 0; h = −y_com is the distance of the centre
// of mass past the orifice (h < 0 before it, as in the paper's Fig. 2–4), v_g = −v_y,com the speed
// along the driving direction.
#pragma once

#include "scenes/droplets/droplet_scene.hpp"
#include "kernels/common/geometry.hpp"
#include "kernels/common/reductions.hpp"

#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace mesoflow::droplets {

struct OrificeScene {
  DropletParameters droplet;       // the Fig. 2 droplet by default
  double width = 0.4;              // w/σ
  double start_h = -2.0;           // initial h/σ: 1.5σ above first contact at w = 0.4σ; v_t is reached within ~1 t0
  double end_h = 1.0;              // passed once h ≥ end_h
  double max_time = 2000;          // t/t0 limit
  double sample_interval = 0.05;   // t0 between profile samples
  double clog_threshold = 1e-17;   // E_k/E_t below which the droplet is clogged (Appendix C)
  long long check_interval = 100;  // steps between NaN-watchdog checks (scenes/common/nan_watchdog.hpp)

  void validate() const {
    droplet.validate();
    auto require = [](bool ok, const char* name, const char* range, double value) {
      if (!ok)
        throw std::invalid_argument(std::string("orifice scene: ") + name + " must be " + range + ", got " +
                                    std::to_string(value));
    };
    require(droplet.shape_dt_target == 0, "shape time-step target",
            "0 in the orifice (shape-following steps are for the obstacle ensembles, whose clocks follow them)",
            droplet.shape_dt_target);
    require(std::isfinite(width) && width > 0 && width <= 10, "orifice width w", "in (0, 10]", width);
    require(std::isfinite(start_h) && start_h <= -1.0, "start height start_h", "<= -1 (above the funnel)", start_h);
    require(std::isfinite(end_h) && end_h > 0 && end_h <= 100, "end height end_h", "in (0, 100]", end_h);
    require(std::isfinite(max_time) && max_time > 0, "time limit max_time", "finite and > 0", max_time);
    require(std::isfinite(sample_interval) && sample_interval > 0, "sample interval", "finite and > 0", sample_interval);
    require(check_interval >= 1 && check_interval <= 1000000, "watchdog interval check_interval", "in [1, 10^6] steps",
            double(check_interval));
    require(std::isfinite(clog_threshold) && clog_threshold > 0 && clog_threshold < 1, "clog threshold E_k/E_t",
            "in (0, 1)", clog_threshold);
  }
};

enum class OrificeOutcome { passed, clogged, time_limit, stopped };  // stopped: OrificeRun::stop()

inline const char* to_string(OrificeOutcome o) {
  switch (o) {
    case OrificeOutcome::passed: return "passed";
    case OrificeOutcome::clogged: return "clogged";
    case OrificeOutcome::stopped: return "stopped";
    default: return "time_limit";
  }
}

// The profiles, one entry per sample (every sample_interval, plus the last state).
struct OrificeProfile {
  std::vector<double> t, h, vg, shape, area, kinetic;  // t/t0, h/σ, v_g/(σ/t0), 𝒜, a/a0, E_k/E_t
  OrificeOutcome outcome = OrificeOutcome::time_limit;
  double dt = 0;                 // the time step used
  double max_area_error = 0;     // max |a/a_eq − 1| after contact, a_eq the area of the free droplet
  double free_area = 0;          // a_eq/a0: the droplet's area before contact (line tension compresses it)
  long long steps = 0;
  std::vector<std::string> components;  // DropletScene::components(): what each step evaluates
};

template <class Real = double>
Surfaces<Real, Kokkos::DefaultExecutionSpace> orifice_surfaces(double width) {
  const auto wedges = orifice_wedges<Real>(Real(width), Real(0), Real(0));
  return Surfaces<Real, Kokkos::DefaultExecutionSpace>(std::vector<Shape<2, Real>>{wedges[0], wedges[1]});
}

// One passage in precision Real, sample by sample: the constructor builds the scene, relaxes it
// and takes the first sample; advance() steps to the next sample (or the end) and returns whether
// it appended one. The `orifice` driver (through run_orifice below) and the Python front end
// (python/src/droplets.cpp) both run this loop, so they give the same profile bit for bit.
template <class Real = double>
class OrificeRun {
 public:
  using Exec = Kokkos::DefaultExecutionSpace;
  using Scene = DropletScene<Real, Exec>;

  explicit OrificeRun(const OrificeScene& setup)
      : setup_((setup.validate(), setup)),
        scene_(setup.droplet, orifice_surfaces<Real>(setup.width), {Vec<2, double>{{0.0, -setup.start_h}}}),
        watch_((scene_.relax(), scene_.watched()), setup.check_interval) {
    prof_.dt = scene_.dt();
    prof_.components = scene_.components();
    terminal_energy_ = 0.5 * droplet_mass * setup.droplet.terminal_speed * setup.droplet.terminal_speed;  // E_t
    sample_every_ = std::max(1LL, std::llround(setup.sample_interval / scene_.dt()));
    max_steps_ = std::llround(setup.max_time / scene_.dt());
    // Contact with the funnel begins where the droplet's disk touches the 45° walls:
    // (−h + w/2)/√2 = 1/2 ⇒ h = w/2 − √2/2. Area is measured against the free droplet's before it.
    contact_h_ = 0.5 * setup.width - std::sqrt(0.5);
    sample();
  }

  // Steps until the next sample is appended (true) or the run has ended without one (false). The
  // run ends when the droplet has passed (h ≥ end_h), clogged (E_k/E_t below the threshold once it
  // has moved), at the time limit, or by stop(); the last state is always a sample.
  bool advance() {
    if (done_) return false;
    constexpr long long clog_check_every = 10;  // steps; E_k decays at ~2b∞/M per t0, so 10 steps lose nothing
    while (scene_.steps() < max_steps_) {
      scene_.step();
      watch_.after_step();
      const bool at_sample = scene_.steps() % sample_every_ == 0;
      const bool at_check = at_sample || scene_.steps() % clog_check_every == 0;
      const double ek = at_check ? kinetic_energy(scene_.particles()) / terminal_energy_ : 1.0;
      if (at_check && ek > 0.25) moving_ = true;  // (v/v_t)² > 1/4: the clog test starts
      if (moving_ && ek < setup_.clog_threshold) return end(OrificeOutcome::clogged);
      if (at_sample) {
        watch_.check();  // no sample is taken from a non-finite state
        sample();
        if (prof_.h.back() >= setup_.end_h) end(OrificeOutcome::passed);
        return true;
      }
    }
    return end(OrificeOutcome::time_limit);
  }

  // Ends the run at the current step (outcome `stopped`, unless it had already ended); returns
  // whether a last sample was appended.
  bool stop() { return done_ ? false : end(OrificeOutcome::stopped); }

  bool done() const { return done_; }
  const OrificeProfile& profile() const { return prof_; }
  const OrificeScene& setup() const { return setup_; }
  Scene& scene() { return scene_; }
  const Scene& scene() const { return scene_; }

 private:
  void sample() {
    const auto o = scene_.observables();
    const double ek = kinetic_energy(scene_.particles()) / terminal_energy_;
    prof_.t.push_back(scene_.time());
    prof_.h.push_back(-o.com[0][1]);
    prof_.vg.push_back(-o.com_velocity[0][1]);
    prof_.shape.push_back(o.shape_parameter[0]);
    prof_.area.push_back(o.area[0] / droplet_area);
    prof_.kinetic.push_back(ek);
    if (prof_.h.back() < contact_h_ - 0.1)
      prof_.free_area = prof_.area.back();
    else if (prof_.free_area > 0)
      prof_.max_area_error = std::max(prof_.max_area_error, std::abs(prof_.area.back() / prof_.free_area - 1));
  }
  // Records the outcome; the last state becomes a sample if it is not one. Returns whether it was appended.
  bool end(OrificeOutcome outcome) {
    prof_.outcome = outcome;
    done_ = true;
    bool appended = false;
    if (prof_.t.empty() || prof_.t.back() != scene_.time()) {
      sample();
      appended = true;
    }
    prof_.steps = scene_.steps();
    return appended;
  }

  OrificeScene setup_;
  Scene scene_;
  watchdog::NanWatchdog watch_;
  OrificeProfile prof_;
  double terminal_energy_ = 0, contact_h_ = 0;
  long long sample_every_ = 1, max_steps_ = 0;
  bool moving_ = false, done_ = false;
};

// Runs one passage in precision Real (the drivers use double; perf/tradeoff compares float).
// `on_sample(scene, profile)` is called after every sample is appended (the driver writes frames
// from it); pass [](auto&, auto&) {} when none is wanted.
template <class Real = double, class OnSample>
OrificeProfile run_orifice(const OrificeScene& setup, OnSample&& on_sample) {
  OrificeRun<Real> run(setup);
  on_sample(run.scene(), run.profile());
  while (run.advance()) on_sample(run.scene(), run.profile());
  return run.profile();
}

inline OrificeProfile run_orifice(const OrificeScene& setup) {
  return run_orifice(setup, [](const auto&, const auto&) {});
}

// One passage of the calibration (capillary-droplets §4.1): `scene` with the line tension Γ and/or
// the near-wall drag b0/b∞ replaced (std::nullopt: the scene's own), the perimeter elasticity K_l
// following Γ so that K_l/Γ stays the scene's (App. B).
inline OrificeScene calibration_scene(const OrificeScene& scene, std::optional<double> line_tension,
                                      std::optional<double> near_wall_drag) {
  OrificeScene s = scene;
  if (line_tension) {
    const double perimeter_ratio = scene.droplet.perimeter_stiffness / scene.droplet.line_tension;
    s.droplet.line_tension = *line_tension;
    s.droplet.perimeter_stiffness = perimeter_ratio * s.droplet.line_tension;  // K_l/Γ held
  }
  if (near_wall_drag) s.droplet.near_wall_drag = *near_wall_drag;
  return s;
}

}  // namespace mesoflow::droplets
