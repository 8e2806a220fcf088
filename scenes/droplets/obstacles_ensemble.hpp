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
// run_obstacle_batch runs one batch of one sweep point to its slowest replica (a replica that
// finishes keeps being stepped, its record final). run_sweep_batched runs a whole DP sweep in one
// batch: every point's arrays in one multi-array ObstacleArray, each droplet with its point's
// coefficients and time step (DropletScene's per-droplet parameters), a finished replica's slot
// refilled with the next pending one and the batch compacted once none is left (issue 25 item 3).
#pragma once

#include "scenes/droplets/clog_detection.hpp"
#include "scenes/droplets/droplet_scene.hpp"
#include "scenes/droplets/soft_particle_scene.hpp"
#include "kernels/common/obstacle_array.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
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
  // The obstacle grid's cell width is σ_ob + cell_gap (0: the gap). A batch mixing gaps uses the
  // smallest for all; a replica's record depends on it only through the order in which its nearby
  // obstacles are summed (last bits), so a replica compares bitwise with a run of the same cell_gap.
  double cell_gap = 0;
  double time_limit = 200.0;      // T/t0
  double clog_threshold = 1e-17;  // on E_k/E_t (App. C)
  ClogTest clog_test = ClogTest::full;  // what ends a replica (clog_detection.hpp)
  EarlyClogParameters early;      // the early clog test
  int relax_iterations = 20000;   // FIRE iterations of the initial relaxation

  double cell_width() const { return obstacle_diameter + (cell_gap > 0 ? cell_gap : gap); }
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

// Where a replica's droplet starts: the centre of the box (§2.4).
inline Vec<2, double> start_centre(const ObstacleEnsembleParameters& par) {
  return Vec<2, double>{{0.5 * par.box_length, 0.5 * par.box_length}};
}

// The obstacle array of the replica with obstacle seed `seed`: φ-limited random sequential
// (par.obstacle_fraction > 0) or maximal Poisson-disk. DP: the start disk is cleared. Eq. 3 repels
// vertices only, so FIRE pushes the vertices off the obstacles under the initial droplet but leaves
// those it encloses inside the polygon: at φ = 0.195 every replica started with 1–3 obstacles inside
// the droplet (7 of 16 at φ = 0.05) and hung on them from inside (docs/droplets.md). Obstacles whose
// centre lies within (σ + σ_ob)/2 + w_ob/4 of the start are removed. (The SP droplet is one disk:
// FIRE resolves its overlaps.)
inline std::vector<Vec<2, double>> replica_obstacles(const ObstacleEnsembleParameters& par, std::uint64_t seed) {
  std::vector<Vec<2, double>> a =
      par.obstacle_fraction > 0
          ? random_sequential_obstacles(par.box_length, par.box_length, par.obstacle_diameter, par.gap,
                                        obstacle_count(par), seed)
          : poisson_disk_obstacles(par.box_length, par.box_length, par.obstacle_diameter, par.gap, seed);
  if (par.model == DropletModel::deformable_polygon) {
    const Vec<2, double> centre = start_centre(par);
    const double clear = 0.5 * (1.0 + par.obstacle_diameter) + 0.25 * par.gap;
    a.erase(std::remove_if(a.begin(), a.end(),
                           [&](const Vec<2, double>& c) {
                             double dx = c[0] - centre[0], dy = c[1] - centre[1];
                             dx -= par.box_length * std::round(dx / par.box_length);
                             dy -= par.box_length * std::round(dy / par.box_length);
                             return dx * dx + dy * dy < clear * clear;
                           }),
            a.end());
  }
  return a;
}

template <class Real>
Box<2, Real> periodic_square(double length) {
  const Real lo[2] = {0, 0}, len[2] = {Real(length), Real(length)};
  const bool periodic[2] = {true, true};
  return Box<2, Real>(lo, len, periodic);
}

// Steps `scene` until every replica has finished, reporting each as it does; prepare(detector)
// once the clocks have started (a DP scene with shape-following steps lets them follow).
template <class Scene, class StateOf, class Prepare>
void run_until_finished(const ObstacleEnsembleParameters& par, Scene& scene, int replicas, StateOf&& state_of,
                        const std::function<void(int, const ReplicaRecord&)>& on_finished,
                        const std::function<void(long long)>& on_steps, Prepare&& prepare) {
  const double angle = par.gravity_angle() * dp::pi / 180.0;
  const double terminal_energy = 0.5 * droplet_mass * par.terminal_speed() * par.terminal_speed();
  ClogDetector<typename Scene::particles_type::execution_space> detector(
      replicas, par.clog_threshold, Vec<2, double>{{std::cos(angle), std::sin(angle)}}, par.clog_test, par.early,
      sample_steps);
  detector.start(ReplicaLimits{terminal_energy, par.terminal_speed(), par.time_limit, scene.dt()}, state_of());
  prepare(detector);
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
    detector.observe(state_of());
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
  const Real diameter = Real(par.obstacle_diameter), cell = Real(par.cell_width());
  std::vector<std::vector<Vec<2, double>>> arrays;
  for (const std::uint64_t seed : seeds) arrays.push_back(replica_obstacles(par, seed));
  const Vec<2, double> centre = start_centre(par);
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
    run_until_finished(par, scene, n, state_of, on_finished, on_steps, [&scene](auto& detector) {
      if (scene.shape_following()) detector.follow_time_steps(scene.body_time_steps());
    });
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
    run_until_finished(par, scene, n, state_of, on_finished, on_steps, [](auto&) {});
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
  bool edge_contacts = false;    // DP: obstacles repel whole edges (DropletParameters::edge_obstacle_contacts)
  double near_wall_drag = 0.0;   // DP: b0/b∞
  double terminal_speed = 0.08;  // V_t (eq. 15)
  double dt = 0.0;               // Δt/t0; 0: 10⁻³ or the stability limit if smaller
  bool force_dt = false;
  double shape_dt_target = 0.0;  // DP: shape-following steps (DropletParameters::shape_dt_target; 0: off)
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
    ens.droplet.edge_obstacle_contacts = edge_contacts;
    ens.droplet.near_wall_drag = near_wall_drag;
    ens.droplet.terminal_speed = terminal_speed;
    ens.droplet.dt = dt;
    ens.droplet.force_dt = force_dt;
    ens.droplet.shape_dt_target = shape_dt_target;
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

namespace mesoflow::droplets {

// A whole DP sweep in one batch (issue 25 item 3): every (point, replica) of `todo` advances in
// the same Kokkos launches. `points[p]` is point p's scene (any Γ, K_l, b0/b∞, V_t and w_ob; the
// other fields shared); replica j of point p lives in the obstacle array of replica_seed(seed, j)
// at that point's w_ob and runs at its point's own stable Δt (per-particle steps).
//
// `slots` droplets are stepped together. A replica that finishes (clogged or at its time limit) is
// reported and its slot refilled with the next pending (point, replica) — relaxed alone by FIRE as
// in run_obstacle_batch — so the batch stays full while work remains; once the queue is empty and
// at most half the slots still run, the batch is compacted to its running replicas (their state,
// candidates and clocks carried over bitwise), so finished replicas stop costing work. Every
// replica's record is bitwise that of a batch of its own with the sweep's cell width
// (ObstacleEnsembleParameters::cell_gap; tests/dp/test_obstacle_sweep_batch.cpp).
//
// on_finished(p, replica, seed, record) as each finishes; on_steps(replica_steps_done) every few
// hundred steps. Returns the steps run and the replica-steps run (slots × steps, summed).
struct BatchedSweepStats {
  long long steps = 0, replica_steps = 0, refills = 0, compactions = 0;
  int deepest_dt_level = 0;  // shape-following steps: the smallest step used was Δt0/2^this
};
template <class Real = double, class ExecSpace = Kokkos::DefaultExecutionSpace, class OnFinished, class OnSteps>
BatchedSweepStats run_sweep_batched(std::vector<ObstacleEnsembleParameters> points,
                                    const std::vector<std::vector<int>>& todo, std::uint64_t seed, int slots,
                                    OnFinished&& on_finished, OnSteps&& on_steps) {
  using namespace ensemble_detail;
  using Scene = DropletScene<Real, ExecSpace>;
  BatchedSweepStats stats;
  if (points.empty() || todo.size() != points.size())
    throw std::invalid_argument("batched sweep: one replica list per point");
  if (slots < 1) throw std::invalid_argument("batched sweep: --batch must be >= 1");
  double smallest_gap = points.front().gap;
  for (const auto& par : points) {
    if (par.model != DropletModel::deformable_polygon)
      throw std::invalid_argument("batched sweep: DP points only (SP sweeps run point by point)");
    if (par.box_length != points.front().box_length || par.obstacle_diameter != points.front().obstacle_diameter ||
        par.time_limit != points.front().time_limit || par.clog_threshold != points.front().clog_threshold ||
        par.clog_test != points.front().clog_test || par.relax_iterations != points.front().relax_iterations)
      throw std::invalid_argument(
          "batched sweep: the points must share the box, obstacle diameter, time limit, clog test and relaxation");
    smallest_gap = std::min(smallest_gap, par.gap);
  }
  for (auto& par : points) par.cell_gap = smallest_gap;
  const ObstacleEnsembleParameters& common = points.front();

  // The work items, point-major, and the obstacle arrays they need (one per (w_ob, replica)).
  struct Task {
    int point, replica, array;
    std::uint64_t seed;
  };
  std::vector<Task> tasks;
  std::vector<std::vector<Vec<2, double>>> arrays;
  std::vector<std::pair<double, int>> array_key;  // (w_ob, replica) of each array
  for (std::size_t p = 0; p < points.size(); ++p)
    for (const int j : todo[p]) {
      const std::pair<double, int> key{points[p].gap, j};
      auto it = std::find(array_key.begin(), array_key.end(), key);
      const std::uint64_t s = replica_seed(seed, j);
      if (it == array_key.end()) {
        array_key.push_back(key);
        arrays.push_back(replica_obstacles(points[p], s));
        it = array_key.end() - 1;
      }
      tasks.push_back({int(p), j, int(it - array_key.begin()), s});
    }
  if (tasks.empty()) return stats;
  const auto box = periodic_square<Real>(common.box_length);
  const Real diameter = Real(common.obstacle_diameter), cell = Real(common.cell_width());
  const Surfaces<Real, ExecSpace> surfaces(ObstacleArray<Real, ExecSpace>::from_arrays(box, arrays, diameter, cell));
  const Vec<2, double> centre = start_centre(common);
  const double angle = common.gravity_angle() * dp::pi / 180.0;
  const Vec<2, double> gravity{{std::cos(angle), std::sin(angle)}};

  // A task's relaxed start (alone, in a scene of its own array) and its detector limits.
  const auto relaxed = [&](const Task& t) {
    Scene alone(points[std::size_t(t.point)].droplet,
                Surfaces<Real, ExecSpace>(ObstacleArray<Real, ExecSpace>(box, arrays[std::size_t(t.array)], diameter, cell)),
                {centre});
    alone.relax(common.relax_iterations);
    return alone.droplet_vertices(0);
  };
  const auto limits_of = [&](const Task& t, double dt) {
    const double v_t = points[std::size_t(t.point)].terminal_speed();
    return ReplicaLimits{0.5 * droplet_mass * v_t * v_t, v_t, common.time_limit, dt};
  };

  // The first slots.
  std::size_t next = 0;
  std::vector<int> slot_task;  // task of each slot
  const int n0 = int(std::min<std::size_t>(std::size_t(slots), tasks.size()));
  std::vector<DropletParameters> per_body;
  std::vector<int> which_array;
  for (int k = 0; k < n0; ++k, ++next) {
    slot_task.push_back(int(next));
    per_body.push_back(points[std::size_t(tasks[next].point)].droplet);
    which_array.push_back(tasks[next].array);
  }
  auto scene = std::make_unique<Scene>(per_body, surfaces, std::vector<Vec<2, double>>(std::size_t(n0), centre), which_array);
  for (int k = 0; k < n0; ++k) scene->place_droplet(k, relaxed(tasks[std::size_t(slot_task[std::size_t(k)])]));
  scene->compute_step_forces();
  const auto state_of = [&scene] {
    const auto& s = scene->update_body_state();
    return DeformableReplicaState<Real, ExecSpace>{s.com, s.kinetic_energy};
  };
  auto detector = std::make_unique<ClogDetector<ExecSpace>>(n0, common.clog_threshold, gravity, common.clog_test,
                                                            common.early, sample_steps);
  {
    std::vector<int> all(static_cast<std::size_t>(n0));
    std::vector<ReplicaLimits> limits;
    for (int k = 0; k < n0; ++k) {
      all[std::size_t(k)] = k;
      limits.push_back(limits_of(tasks[std::size_t(slot_task[std::size_t(k)])], scene->dt(k)));
    }
    detector->restart(all, limits, state_of());
  }
  const auto follow = [&] {
    if (scene->shape_following()) detector->follow_time_steps(scene->body_time_steps());
  };
  follow();
  auto watch = watchdog::watch_if_possible(*scene, watchdog_interval);
  int live = n0;
  long long step = 0;
  while (live > 0) {
    for (int k = 0; k < sample_steps; ++k) {
      scene->step();
      if (watch) watch->after_step();
    }
    step += sample_steps;
    stats.replica_steps += (long long)(slot_task.size()) * sample_steps;
    detector->observe(state_of());
    if (step % report_steps != 0) continue;
    on_steps(stats.replica_steps);
    const int now = detector->running();
    if (now == live) continue;
    // Report the finished replicas; refill their slots while tasks remain.
    const std::vector<int> status = detector->status();
    std::vector<int> refill;
    std::vector<ReplicaLimits> refill_limits;
    for (std::size_t k = 0; k < slot_task.size(); ++k) {
      if (slot_task[k] < 0 || status[k] == replica_status::running) continue;
      const Task& done = tasks[std::size_t(slot_task[k])];
      on_finished(std::size_t(done.point), done.replica, done.seed, detector->record(int(k)));
      slot_task[k] = -1;
      if (next < tasks.size()) {
        const Task& t = tasks[next];
        scene->replace_droplet(int(k), points[std::size_t(t.point)].droplet, t.array, relaxed(t));
        slot_task[k] = int(next++);
        refill.push_back(int(k));
        refill_limits.push_back(limits_of(t, scene->dt(int(k))));
      }
    }
    if (!refill.empty()) {
      scene->refresh_forces(refill);
      detector->restart(refill, refill_limits, state_of());
      watch.reset();  // the watchdog's last good state predates the refill
      watch = watchdog::watch_if_possible(*scene, watchdog_interval);
      stats.refills += (long long)(refill.size());
    }
    live = 0;
    for (const int t : slot_task) live += t >= 0 ? 1 : 0;
    // Compact: the queue is empty and at most half the slots still run.
    if (live > 0 && next == tasks.size() && 2 * live <= int(slot_task.size())) {
      std::vector<int> keep, kept_task;
      std::vector<DropletParameters> kept_par;
      std::vector<int> kept_array;
      for (std::size_t k = 0; k < slot_task.size(); ++k)
        if (slot_task[k] >= 0) {
          keep.push_back(int(k));
          kept_task.push_back(slot_task[k]);
          kept_par.push_back(scene->parameters(int(k)));
          kept_array.push_back(tasks[std::size_t(slot_task[k])].array);
        }
      const auto states = scene->export_droplets();
      std::vector<typename Scene::DropletState> kept_states;
      for (const int k : keep) kept_states.push_back(states[std::size_t(k)]);
      const long long scene_steps = scene->steps();
      stats.deepest_dt_level = std::max(stats.deepest_dt_level, scene->deepest_time_step_level());
      watch.reset();
      scene = std::make_unique<Scene>(kept_par, surfaces, std::vector<Vec<2, double>>(keep.size(), centre), kept_array);
      scene->import_droplets(kept_states, scene_steps);
      detector = std::make_unique<ClogDetector<ExecSpace>>(detector->compacted(keep));
      follow();
      watch = watchdog::watch_if_possible(*scene, watchdog_interval);
      slot_task = kept_task;
      ++stats.compactions;
    }
  }
  stats.steps = step;
  stats.deepest_dt_level = std::max(stats.deepest_dt_level, scene->deepest_time_step_level());
  return stats;
}

}  // namespace mesoflow::droplets
