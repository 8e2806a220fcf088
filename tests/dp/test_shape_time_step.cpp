// Shape-following time steps (DropletParameters::shape_dt_target, issue 25: the wrapping branch at
// K_a = 10⁴): a droplet whose edges have become unequal halves its own Δt while the others keep
// theirs, and evolves bitwise as it would alone; an ensemble clock that follows the steps adds up
// each step's time (the time limit and the steady-speed fit see the true t); a replica with a
// shape-following step gives in a batch, refilled and compacted, bitwise its record alone.
#include "scenes/droplets/obstacles_ensemble.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <iostream>
#include <map>
#include <vector>

// Own namespace: this file shares a unity translation unit with others (tests/CMakeLists.txt).
namespace mesoflow::droplets::shape_time_step_test {
namespace {

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Replica b moves along x at speed v_b = 0.01 (b + 1) from its own clock, E_k = E_t (never clogs).
struct Moving {
  double t0, t1;
  KOKKOS_INLINE_FUNCTION void operator()(int b, double (&c)[2], double& ke) const {
    c[0] = 0.01 * (b + 1) * (b == 0 ? t0 : t1);
    c[1] = 0;
    ke = 1.0;
  }
};

// Replica 0's step drops from 0.01 to 0.0025 after 50 steps; replica 1 keeps 0.01. The limit
// T = 1 is reached at t = 1 by both (25 and 10 observations of 10 steps), and the steady speed fitted
// over [T/2, T] is each replica's v, so the clock's times are right on both sides of the change.
TEST(ClogDetector, AClockThatFollowsTheStepsAddsUpEachStepsTime) {
  ClogDetector<Kokkos::DefaultExecutionSpace> followed(2, 1e-17, Vec<2, double>{{1.0, 0.0}}, ClogTest::full, {}, 10);
  ClogDetector<Kokkos::DefaultExecutionSpace> fixed(2, 1e-17, Vec<2, double>{{1.0, 0.0}}, ClogTest::full, {}, 10);
  Kokkos::View<double*> steps("steps", 2);
  Kokkos::deep_copy(steps, 0.01);
  followed.start(ReplicaLimits{1.0, 0.08, 1.0, 0.01}, Moving{0, 0});
  fixed.start(ReplicaLimits{1.0, 0.08, 1.0, 0.01}, Moving{0, 0});
  followed.follow_time_steps(steps);
  double t0 = 0, t1 = 0, dt0 = 0.01;
  int observations = 0, ended0 = 0, ended1 = 0;
  while (followed.running() > 0 && observations < 100) {
    if (observations == 5) {  // the change happens between observations, as the scene makes it
      const auto h = Kokkos::create_mirror_view(steps);
      h(0) = dt0 = 0.0025;
      h(1) = 0.01;
      Kokkos::deep_copy(steps, h);
    }
    t0 += 10 * dt0;
    t1 += 10 * 0.01;
    followed.observe(Moving{t0, t1});
    if (fixed.running() > 0) fixed.observe(Moving{t1, t1});
    ++observations;
    const auto status = followed.status();
    if (!ended0 && status[0] != replica_status::running) ended0 = observations;
    if (!ended1 && status[1] != replica_status::running) ended1 = observations;
  }
  EXPECT_EQ(ended0, 5 + 20);
  EXPECT_EQ(ended1, 10);
  const ReplicaRecord r0 = followed.record(0), r1 = followed.record(1);
  EXPECT_NEAR(r0.time, 1.0, 1e-12);
  EXPECT_NEAR(r0.distance, 0.01, 1e-12);
  EXPECT_NEAR(r0.steady_speed, 0.01, 1e-9);
  // Replica 1 never changed its step: its clock is bitwise the fixed one's.
  const ReplicaRecord f1 = fixed.record(1);
  EXPECT_TRUE(same_bits(r1.time, f1.time)) << r1.time << " vs " << f1.time;
  EXPECT_TRUE(same_bits(r1.steady_speed, f1.steady_speed));
  EXPECT_NEAR(r1.steady_speed, 0.02, 1e-9);
  // A view of the wrong length is refused.
  Kokkos::View<double*> three("three", 3);
  EXPECT_THROW(followed.follow_time_steps(three), std::invalid_argument);
}

// A polygon of area a0 with 56 of its 64 vertices crowded into a 0.2 rad arc and 8 spread over the
// rest: Σ|∇a|² ≈ 6 P l0, so its area mode is ≈ 2.5 times the regular polygon's.
std::vector<Vec<2, double>> crowded_polygon(const Vec<2, double>& centre) {
  std::vector<double> angle;
  for (int k = 0; k < 56; ++k) angle.push_back(0.2 * k / 56.0);
  for (int k = 0; k < 8; ++k) angle.push_back(0.2 + (2 * dp::pi - 0.2) * (k + 0.5) / 8.0);
  std::vector<Vec<2, double>> v;
  for (const double a : angle) v.push_back(Vec<2, double>{{std::cos(a), std::sin(a)}});
  double area = 0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const auto& p = v[i];
    const auto& q = v[(i + 1) % v.size()];
    area += 0.5 * (p[0] * q[1] - q[0] * p[1]);
  }
  const double scale = std::sqrt(droplet_area / area);
  for (auto& p : v) p = Vec<2, double>{{centre[0] + scale * p[0], centre[1] + scale * p[1]}};
  return v;
}

double area_mode_omega_dt(const DropletScene<double>& scene, int b) {
  const auto v = scene.droplet_vertices(b);
  const auto s = droplet_stiffness(scene.parameters(b), false);
  double sum = 0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const auto& next = v[(i + 1) % v.size()];
    const auto& prev = v[(i + v.size() - 1) % v.size()];
    sum += 0.25 * ((next[0] - prev[0]) * (next[0] - prev[0]) + (next[1] - prev[1]) * (next[1] - prev[1]));
  }
  return std::sqrt(s.area_stiffness * std::max(sum, s.perimeter * s.edge_length) / s.vertex_mass) * scene.dt(b);
}

DropletParameters stiff_droplet(double target) {
  DropletParameters par;
  par.vertices = 64;
  par.area_stiffness = 1e6;  // the area mode sets the step: Δt0 ≈ 1/ω_area of the regular polygon
  par.shape_dt_target = target;
  return par;
}

TEST(DropletScene, AShapeFollowingStepHalvesOnlyTheDeformedDropletsStep) {
  const Surfaces<double> none;
  const Vec<2, double> a{{2.0, 2.0}}, b{{6.0, 2.0}};
  DropletScene<double> scene(stiff_droplet(1.0), none, {a, b});
  ASSERT_TRUE(scene.shape_following());
  const double dt0 = scene.dt(1);
  ASSERT_EQ(scene.dt(0), dt0);
  scene.place_droplet(0, crowded_polygon(a));
  scene.compute_step_forces();
  std::cout << "[ measured ] omega_area dt at the initial step: crowded " << area_mode_omega_dt(scene, 0)
            << ", regular " << area_mode_omega_dt(scene, 1) << "\n";
  ASSERT_GT(area_mode_omega_dt(scene, 0), 1.8);  // a fixed step would stop this run
  DropletScene<double> alone(stiff_droplet(1.0), none, {a});
  alone.place_droplet(0, crowded_polygon(a));
  alone.compute_step_forces();
  double worst = 0;
  for (int step = 0; step < 4000; ++step) {
    scene.step();
    alone.step();
    if (step % 100 == 1) worst = std::max(worst, area_mode_omega_dt(scene, 0));
  }
  const double dt_crowded = scene.dt(0);
  const int level = int(std::lround(std::log2(dt0 / dt_crowded)));
  std::cout << "[ measured ] crowded droplet at dt0/2^" << level << " after 4000 steps (deepest "
            << scene.deepest_time_step_level() << "), largest omega dt just after a check " << worst << "\n";
  EXPECT_EQ(scene.dt(1), dt0);  // the regular droplet kept its step
  EXPECT_GE(scene.deepest_time_step_level(), 1);
  EXPECT_EQ(dt_crowded * double(1 << level), dt0);  // an exact power of two below Δt0
  EXPECT_LE(worst, 1.0 * 1.05);  // each check leaves ω Δt at most the target (plus one check's drift)
  // Bounded and area-preserving, and bitwise the droplet alone.
  const auto x = scene.droplet_vertices(0), y = alone.droplet_vertices(0);
  int differ = 0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    ASSERT_TRUE(std::isfinite(x[k][0]) && std::isfinite(x[k][1]));
    differ += !same_bits(x[k][0], y[k][0]) || !same_bits(x[k][1], y[k][1]);
  }
  EXPECT_EQ(differ, 0);
  const auto obs = scene.observables();
  EXPECT_NEAR(obs.area[0] / droplet_area, 1.0, 1e-3);
}

TEST(DropletScene, ShapeTimeStepTargetOutOfRangeIsRefusedNamingIt) {
  auto par = stiff_droplet(2.0);
  try {
    par.validate();
    FAIL() << "a target above 1.8 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("shape time-step target"), std::string::npos) << e.what();
  }
  auto a = stiff_droplet(1.0), b = stiff_droplet(0.5);
  const Surfaces<double> none;
  EXPECT_THROW(DropletScene<double>({a, b}, none, {Vec<2, double>{{2.0, 2.0}}, Vec<2, double>{{6.0, 2.0}}}, {0, 0}),
               std::invalid_argument);
}

ObstacleEnsembleParameters point(double gamma, double gap) {
  ObstacleEnsembleParameters par;
  par.droplet.vertices = 32;
  par.droplet.line_tension = gamma;
  par.droplet.perimeter_stiffness = 0.1 * gamma;
  par.droplet.near_wall_drag = 0;
  par.box_length = 12;
  par.gap = gap;
  par.relax_iterations = 2000;
  par.time_limit = 16;  // the start disk is clear: the droplets reach obstacles after ~10 t0
  par.clog_test = ClogTest::early;
  par.early.sample_interval = 0.25;
  par.early.window = 2;
  return par;
}

// Two points (Γ = 0.5 and 60, whose initial steps differ) × three replicas through two slots,
// with a target a third of the Γ = 0.5 droplet's ω_area Δt0, so that the replicas run below their
// initial steps: each record (clogged, or at the time limit, whose recorded time is then T on the
// replica's own clock) equals bitwise the record of the replica alone.
TEST(ObstacleSweepBatch, ShapeFollowingReplicasGiveTheirRecordsAloneAndRunToTheirOwnTimeLimit) {
  std::vector<ObstacleEnsembleParameters> points = {point(0.5, 0.2), point(60, 0.05)};
  const double w = droplet_stability(points[0].droplet, true).omega_area * resolve_time_step(points[0].droplet, true);
  for (auto& p : points) p.droplet.shape_dt_target = w / 3;
  std::cout << "[ measured ] regular droplet omega_area dt0 = " << w << ", target " << w / 3 << "\n";
  const std::vector<std::vector<int>> todo = {{0, 1, 2}, {0, 1, 2}};
  const std::uint64_t seed = 5;
  std::map<std::pair<int, int>, ReplicaRecord> batched;
  const auto stats = run_sweep_batched<double>(
      points, todo, seed, 2,
      [&](std::size_t p, int j, std::uint64_t, const ReplicaRecord& r) { batched[{int(p), j}] = r; }, [](long long) {});
  EXPECT_EQ(batched.size(), 6u);
  EXPECT_GE(stats.deepest_dt_level, 1);
  std::cout << "[ measured ] deepest level " << stats.deepest_dt_level << ", refills " << stats.refills
            << ", compactions " << stats.compactions << "\n";
  for (std::size_t p = 0; p < points.size(); ++p)
    for (const int j : todo[p]) {
      ReplicaRecord alone;
      run_obstacle_batch<double>(points[p], {replica_seed(seed, j)}, [&](int, const ReplicaRecord& r) { alone = r; });
      const ReplicaRecord& b = batched.at({int(p), j});
      EXPECT_EQ(b.clogged, alone.clogged) << "point " << p << " replica " << j;
      EXPECT_TRUE(same_bits(b.distance, alone.distance)) << b.distance << " vs " << alone.distance;
      EXPECT_TRUE(same_bits(b.time, alone.time)) << b.time << " vs " << alone.time;
      EXPECT_TRUE(same_bits(b.final_x, alone.final_x) && same_bits(b.final_y, alone.final_y));
      if (!b.clogged) {  // T on the replica's clock, rounded up to whole observations of its last step
        EXPECT_GE(b.time, points[p].time_limit - 1e-9);
        EXPECT_LT(b.time, points[p].time_limit + 10 * resolve_time_step(points[p].droplet, true));
      }
      std::cout << "[ measured ] point " << p << " replica " << j << ": clogged " << b.clogged << " at t = " << b.time
                << ", r = " << b.distance << "\n";
    }
}

}  // namespace
}  // namespace mesoflow::droplets::shape_time_step_test
