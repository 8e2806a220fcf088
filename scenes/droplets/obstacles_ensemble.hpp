// obstacles_ensemble.hpp — ensembles of single droplets in random obstacle arrays (capillary-droplets
// §4.2–4.3, Appendices C–E): each replica has its own seed and its own Poisson-disk array in a
// periodic L × L box, and a batch of replicas advances together, one set of Kokkos launches per
// step over all of them (the batch's arrays are one multi-array ObstacleArray).
//
// A replica: the droplet is placed at the centre of the box (§2.4), relaxed alone by FIRE without
// gravity (removing the overlaps with obstacles), then released under gravity in the batch, until
// it clogs (E_k/E_t below the threshold, App. C) or reaches the time limit (right-censored).
// Relaxing alone keeps each replica's trajectory independent of its batch: FIRE's global power and
// step adaptation would otherwise couple the replicas; afterwards every kernel acts per droplet, so
// a replica gives bitwise the same record in any batch as alone (tests/dp/test_obstacle_ensemble.cpp).
//
// Batches are not refilled: a replica that finishes keeps being stepped (its record is final) until
// the whole batch has finished. Refilling would rebuild the multi-array ObstacleArray and the
// candidate lists on the host at every replacement; the driver instead keeps batches of replicas of
// one sweep point, which finish within a factor of a few of each other in the clogging regime, and
// a batch ends as soon as its last replica does.
#pragma once

#include "scenes/droplets/clog_detection.hpp"
#include "scenes/droplets/droplet_scene.hpp"
#include "scenes/droplets/soft_particle_scene.hpp"
#include "kernels/common/obstacle_array.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

namespace mesoflow::droplets {

enum class DropletModel { deformable_polygon, soft_particle };

// One sweep point: the model and its parameters, the obstacle array and the run limits.
struct ObstacleEnsembleParameters {
  DropletModel model = DropletModel::deformable_polygon;
  DropletParameters droplet;      // DP
  SoftParticleParameters soft;    // SP
  double box_length = 40.0;       // L/σ
  double obstacle_diameter = 0.3; // σ_ob/σ
  double obstacle_fraction = 0;   // area fraction φ of the obstacles; 0: maximal Poisson-disk arrays (densest)
  double gap = 0.2;               // w_ob/σ, the minimum surface-to-surface gap of the array
  double time_limit = 200.0;      // T/t0
  double clog_threshold = 1e-17;  // on E_k/E_t (App. C)
  ClogTest clog_test = ClogTest::full;  // what ends a replica (clog_detection.hpp)
  EarlyClogParameters early;      // the early clog test
  int relax_iterations = 20000;   // FIRE iterations of the initial relaxation

  double terminal_speed() const {
    return model == DropletModel::deformable_polygon ? droplet.terminal_speed : soft.terminal_speed;
  }
  double gravity_angle() const {
    return model == DropletModel::deformable_polygon ? droplet.gravity_angle : soft.gravity_angle;
  }
};

// The obstacle-array seed of replica `replica` (SplitMix64 of the base seed and the index): the same
// replica index gets the same seed at every sweep point, so points with the same w_ob compare on the
// same arrays (common random numbers).
inline std::uint64_t replica_seed(std::uint64_t seed, int replica) {
  std::uint64_t z = seed + 0x9E3779B97F4A7C15ULL * (std::uint64_t(replica) + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

// Obstacles per array at area fraction φ: φ L² / (π σ_ob²/4).
inline std::size_t obstacle_count(const ObstacleEnsembleParameters& par) {
  const double area = 0.25 * 3.14159265358979323846 * par.obstacle_diameter * par.obstacle_diameter;
  return std::size_t(std::llround(par.obstacle_fraction * par.box_length * par.box_length / area));
}

namespace ensemble_detail {

constexpr int sample_steps = 10;    // steps between clog checks (10⁻² t0 at Δt = 10⁻³ t0)
constexpr long long watchdog_interval = 100;  // steps between NaN-watchdog checks (scenes/common/nan_watchdog.hpp)
constexpr int report_steps = 1000;  // steps between host reads of the finished count

// Centre of mass and E_k of DP droplet b (BodyState after update_body_state).
template <class Real, class ExecSpace>
struct DeformableReplicaState {
  typename dp::BodyState<Real, ExecSpace>::vector_view com;
  typename dp::BodyState<Real, ExecSpace>::scalar_view kinetic_energy;
  KOKKOS_INLINE_FUNCTION void operator()(int b, double (&c)[2], double& ke) const {
    c[0] = com(b, 0);
    c[1] = com(b, 1);
    ke = kinetic_energy(b);
  }
};

// Position and E_k = ½ M v² of SP droplet b.
template <class Real, class ExecSpace>
struct SoftReplicaState {
  typename Particles<2, Real, ExecSpace>::vector_view x, v;
  typename Particles<2, Real, ExecSpace>::scalar_view mass;
  KOKKOS_INLINE_FUNCTION void operator()(int b, double (&c)[2], double& ke) const {
    c[0] = x(b, 0);
    c[1] = x(b, 1);
    ke = 0.5 * double(mass(b)) * (double(v(b, 0)) * double(v(b, 0)) + double(v(b, 1)) * double(v(b, 1)));
  }
};

template <class Real>
Box<2, Real> periodic_square(double length) {
  const Real lo[2] = {0, 0}, len[2] = {Real(length), Real(length)};
  const bool periodic[2] = {true, true};
  return Box<2, Real>(lo, len, periodic);
}

// Steps `scene` until every replica has finished, reporting each as it does.
template <class Scene, class StateOf>
void run_until_finished(const ObstacleEnsembleParameters& par, Scene& scene, int replicas, StateOf&& state_of,
                        const std::function<void(int, const ReplicaRecord&)>& on_finished,
                        const std::function<void(long long)>& on_steps) {
  const double angle = par.gravity_angle() * dp::pi / 180.0;
  const double terminal_energy = 0.5 * droplet_mass * par.terminal_speed() * par.terminal_speed();
  ClogDetector<typename Scene::particles_type::execution_space> detector(
      replicas, terminal_energy, par.clog_threshold, par.time_limit, Vec<2, double>{{std::cos(angle), std::sin(angle)}},
      par.clog_test, par.early, par.terminal_speed());
  detector.start(state_of());
  const long long limit_steps =
      (static_cast<long long>(std::ceil(par.time_limit / scene.dt() - 1e-9)) + sample_steps - 1) / sample_steps *
      sample_steps;
  std::vector<bool> reported(std::size_t(replicas), false);
  int running = replicas;
  long long step = 0;
  auto watch = watchdog::watch_if_possible(scene, watchdog_interval);
  while (running > 0) {
    for (int k = 0; k < sample_steps; ++k) {
      scene.step();
      if (watch) watch->after_step();
    }
    step += sample_steps;
    detector.observe(scene.time(), step >= limit_steps, state_of());
    if (step % report_steps != 0 && step < limit_steps) continue;
    on_steps(step);
    const int now = detector.running();
    if (now == running) continue;
    running = now;
    const std::vector<int> status = detector.status();
    for (int b = 0; b < replicas; ++b)
      if (status[std::size_t(b)] != replica_status::running && !reported[std::size_t(b)]) {
        reported[std::size_t(b)] = true;
        on_finished(b, detector.record(b));
      }
  }
}

}  // namespace ensemble_detail

// Runs the replicas with obstacle-array seeds `seeds` as one batch; on_finished(k, record) is called
// (on the host) for replica seeds[k] as soon as it finishes, on_steps(steps) every few hundred steps.
template <class Real, class ExecSpace = Kokkos::DefaultExecutionSpace>
void run_obstacle_batch(const ObstacleEnsembleParameters& par, const std::vector<std::uint64_t>& seeds,
                        const std::function<void(int, const ReplicaRecord&)>& on_finished,
                        const std::function<void(long long)>& on_steps = [](long long) {}) {
  using namespace ensemble_detail;
  if (seeds.empty()) throw std::invalid_argument("obstacle ensemble: no replicas");
  const int n = int(seeds.size());
  const auto box = periodic_square<Real>(par.box_length);
  const Real diameter = Real(par.obstacle_diameter), cell = Real(par.obstacle_diameter + par.gap);
  std::vector<std::vector<Vec<2, double>>> arrays;
  for (const std::uint64_t seed : seeds)
    arrays.push_back(par.obstacle_fraction > 0
                         ? random_sequential_obstacles(par.box_length, par.box_length, par.obstacle_diameter, par.gap,
                                                       obstacle_count(par), seed)
                         : poisson_disk_obstacles(par.box_length, par.box_length, par.obstacle_diameter, par.gap, seed));
  const Vec<2, double> centre{{0.5 * par.box_length, 0.5 * par.box_length}};
  // DP: clear the start disk. Eq. 3 repels vertices only, so FIRE pushes the vertices off the
  // obstacles under the initial droplet but leaves those it encloses inside the polygon: at φ = 0.195
  // every replica started with 1–3 obstacles inside the droplet (7 of 16 at φ = 0.05) and hung on
  // them from inside (docs/droplets.md). Obstacles whose centre lies within (σ + σ_ob)/2 + w_ob/4 of
  // the start are removed. (The SP droplet is one disk: FIRE resolves its overlaps.)
  if (par.model == DropletModel::deformable_polygon) {
    const double clear = 0.5 * (1.0 + par.obstacle_diameter) + 0.25 * par.gap;
    for (auto& a : arrays)
      a.erase(std::remove_if(a.begin(), a.end(),
                             [&](const Vec<2, double>& c) {
                               double dx = c[0] - centre[0], dy = c[1] - centre[1];
                               dx -= par.box_length * std::round(dx / par.box_length);
                               dy -= par.box_length * std::round(dy / par.box_length);
                               return dx * dx + dy * dy < clear * clear;
                             }),
              a.end());
  }
  std::vector<int> which(std::size_t(n), 0);  // replica k in array k
  std::iota(which.begin(), which.end(), 0);
  const Surfaces<Real, ExecSpace> batch_surfaces(ObstacleArray<Real, ExecSpace>::from_arrays(box, arrays, diameter, cell));

  if (par.model == DropletModel::deformable_polygon) {
    DropletScene<Real, ExecSpace> scene(par.droplet, batch_surfaces, std::vector<Vec<2, double>>(std::size_t(n), centre),
                                        which);
    for (int k = 0; k < n; ++k) {
      DropletScene<Real, ExecSpace> alone(
          par.droplet, Surfaces<Real, ExecSpace>(ObstacleArray<Real, ExecSpace>(box, arrays[std::size_t(k)], diameter, cell)),
          {centre});
      alone.relax(par.relax_iterations);
      scene.place_droplet(k, alone.droplet_vertices(0));
    }
    scene.compute_step_forces();
    const auto state_of = [&scene] {
      const auto& s = scene.update_body_state();
      return DeformableReplicaState<Real, ExecSpace>{s.com, s.kinetic_energy};
    };
    run_until_finished(par, scene, n, state_of, on_finished, on_steps);
  } else {
    SoftParticleScene<Real, ExecSpace> scene(par.soft, batch_surfaces, std::vector<Vec<2, double>>(std::size_t(n), centre),
                                             which);
    for (int k = 0; k < n; ++k) {
      SoftParticleScene<Real, ExecSpace> alone(
          par.soft, Surfaces<Real, ExecSpace>(ObstacleArray<Real, ExecSpace>(box, arrays[std::size_t(k)], diameter, cell)),
          {centre}, {0});
      alone.relax(par.relax_iterations);
      scene.place_droplet(k, alone.droplet_centre(0));
    }
    scene.compute_step_forces();
    const auto state_of = [&scene] {
      const auto& p = scene.particles();
      return SoftReplicaState<Real, ExecSpace>{p.x, p.v, p.mass};
    };
    run_until_finished(par, scene, n, state_of, on_finished, on_steps);
  }
}

}  // namespace mesoflow::droplets

namespace mesoflow::droplets {

// The sweep of the `obstacles` driver: the model and every parameter but the swept pair
// (strength: Γ for DP, E_w of eq. 8 for SP; the gap w_ob), from which each point's scene follows.
struct ObstacleSweep {
  bool soft_particles = false;   // SP model (else DP)
  int vertices = 64;             // DP: N_v
  double area_stiffness = 1e4;   // DP: K_a
  double perimeter_ratio = 0.1;  // DP: K_l/Γ (the paper: 10⁻³; see drivers/droplets/obstacles.cpp)
  double dp_wall_energy = 0.05;  // DP: E_w of eq. 3
  double near_wall_drag = 0.0;   // DP: b0/b∞
  double terminal_speed = 0.08;  // V_t (eq. 15)
  double dt = 0.0;               // Δt/t0; 0: 10⁻³ or the stability limit if smaller
  bool force_dt = false;
  double box_length = 40.0;
  double obstacle_diameter = 0.3;
  // φ, calibrated once (issue 25 item 1, scripts/calibrate_obstacle_fraction): λ = 24σ at Fig. 13(b)'s
  // Γ = 1.09, σ_ob = 0.3σ, w_ob = 0.2σ with N_v = 64, K_l/Γ = 0.1 (docs/droplets.md). 0: maximal arrays.
  double obstacle_fraction = 0.0248;
  double time_limit = 200.0;
  double clog_threshold = 1e-17;
  ClogTest clog_test = ClogTest::full;
  EarlyClogParameters early;
  int relax_iterations = 20000;
  int batch = 16;                // replicas advanced together

  // The scene of the point (strength, gap).
  ObstacleEnsembleParameters at(double strength, double gap) const {
    ObstacleEnsembleParameters ens;
    ens.model = soft_particles ? DropletModel::soft_particle : DropletModel::deformable_polygon;
    ens.droplet.vertices = vertices;
    ens.droplet.line_tension = soft_particles ? ens.droplet.line_tension : strength;
    ens.droplet.area_stiffness = area_stiffness;
    ens.droplet.perimeter_stiffness = perimeter_ratio * ens.droplet.line_tension;
    ens.droplet.wall_energy = dp_wall_energy;
    ens.droplet.near_wall_drag = near_wall_drag;
    ens.droplet.terminal_speed = terminal_speed;
    ens.droplet.dt = dt;
    ens.droplet.force_dt = force_dt;
    ens.soft.wall_energy = soft_particles ? strength : ens.soft.wall_energy;
    ens.soft.terminal_speed = terminal_speed;
    ens.soft.dt = dt;
    ens.soft.force_dt = force_dt;
    ens.box_length = box_length;
    ens.obstacle_diameter = obstacle_diameter;
    ens.obstacle_fraction = obstacle_fraction;
    ens.gap = gap;
    ens.time_limit = time_limit;
    ens.clog_threshold = clog_threshold;
    ens.clog_test = clog_test;
    ens.early = early;
    ens.relax_iterations = relax_iterations;
    return ens;
  }

  // Refuses a point before any output: its parameters out of range, or a Δt above the stability
  // limit (std::invalid_argument naming the parameter); returns the point's time step.
  double check(double strength, double gap) const {
    check_box(gap);
    early.validate();
    const ObstacleEnsembleParameters ens = at(strength, gap);
    ens.droplet.validate();
    ens.soft.validate();
    return time_step(ens);
  }

  // The box holds at least 4 obstacle cells (σ_ob + w_ob) a side and 10σ.
  void check_box(double gap) const {
    if (box_length < 4 * (obstacle_diameter + gap) || box_length < 10)
      throw std::invalid_argument("--box-length: must be >= 4 (sigma_ob + w_ob) = " +
                                  std::to_string(4 * (obstacle_diameter + gap)) + " for --gap " + std::to_string(gap));
  }

  static double time_step(const ObstacleEnsembleParameters& ens) {
    return ens.model == DropletModel::soft_particle ? resolve_time_step(ens.soft) : resolve_time_step(ens.droplet, true);
  }
  // A replica can travel up to ≈ v_t T; beyond one box length L it falls through the periodic image
  // of its own path and meets obstacles it has already passed, which inflates λ (at Fig. 13(b)'s
  // scene with T = 2000 t0: λ = 38σ at L = 40σ, 9 of 50 replicas beyond L, against 20σ at
  // L = 100σ, none beyond; docs/droplets.md). True when that can happen.
  bool may_revisit_own_path() const { return terminal_speed * time_limit > box_length; }

  // Particle updates per replica-step: N_v vertices (DP) or one disk (SP).
  int bodies() const { return soft_particles ? 1 : vertices; }
};

// Runs the replicas `todo[p]` of each point p of `strengths × gaps` (points[p] = {strength, gap})
// in batches of sweep.batch, replica j with the obstacle array of replica_seed(seed, j).
// on_batch(p, replicas, steps) before a batch of `steps` steps; on_finished(p, replica, seed, record)
// as a replica finishes; on_steps(steps) every few hundred steps. Returns the steps run, and the
// replica-steps (steps × replicas, summed over batches).
struct SweepSteps {
  long long steps = 0, replica_steps = 0;
};
template <class Real = double, class OnBatch, class OnFinished, class OnSteps>
SweepSteps run_sweep_points(const ObstacleSweep& sweep, const std::vector<std::pair<double, double>>& points,
                           const std::vector<std::vector<int>>& todo, std::uint64_t seed, OnBatch&& on_batch,
                           OnFinished&& on_finished, OnSteps&& on_steps) {
  SweepSteps run;
  for (std::size_t p = 0; p < points.size(); ++p) {
    const ObstacleEnsembleParameters ens = sweep.at(points[p].first, points[p].second);
    const std::vector<int>& pending = todo[p];
    for (std::size_t first = 0; first < pending.size(); first += std::size_t(sweep.batch)) {
      const std::vector<int> batch(pending.begin() + std::ptrdiff_t(first),
                                   pending.begin() + std::ptrdiff_t(std::min(pending.size(), first + std::size_t(sweep.batch))));
      std::vector<std::uint64_t> seeds;
      for (const int j : batch) seeds.push_back(replica_seed(seed, j));
      const long long batch_steps = static_cast<long long>(std::ceil(sweep.time_limit / ObstacleSweep::time_step(ens)));
      on_batch(p, batch, batch_steps);
      long long last_steps = 0;
      run_obstacle_batch<Real>(
          ens, seeds,
          [&](int k, const ReplicaRecord& record) {
            on_finished(p, batch[std::size_t(k)], seeds[std::size_t(k)], record);
          },
          [&](long long steps) {
            last_steps = steps;
            on_steps(std::min(steps, batch_steps));
          });
      run.steps += last_steps;
      run.replica_steps += last_steps * (long long)(batch.size());
    }
  }
  return run;
}

}  // namespace mesoflow::droplets
