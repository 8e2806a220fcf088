// A whole sweep in one batch (scenes/droplets/obstacles_ensemble.hpp run_sweep_batched, issue 25
// item 3): droplets with their own Γ, K_l, b0/b∞, V_t and Δt in one scene evolve bitwise as alone;
// a sweep whose slots are refilled and then compacted gives every replica bitwise the record of a
// batch of its own; the per-particle time steps of velocity Verlet are bitwise the uniform ones.
#include "scenes/droplets/obstacles_ensemble.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <iostream>
#include <map>
#include <vector>

// Own namespace: this file shares a unity translation unit with others (tests/CMakeLists.txt).
namespace mesoflow::droplets::obstacle_sweep_batch_test {
namespace {

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

ObstacleEnsembleParameters point(double gamma, double gap) {
  ObstacleEnsembleParameters par;
  par.droplet.vertices = 32;
  par.droplet.line_tension = gamma;
  par.droplet.perimeter_stiffness = 0.1 * gamma;
  par.droplet.near_wall_drag = 0;
  par.box_length = 12;
  par.gap = gap;
  par.relax_iterations = 2000;
  par.time_limit = 16;
  par.clog_test = ClogTest::early;
  par.early.sample_interval = 0.25;  // a 4 t0 window: held droplets are decided within T
  par.early.window = 4;
  return par;
}

// Three points that differ in everything a sweep varies: Γ (and K_l with it), b0/b∞, V_t, w_ob and,
// through Γ = 60, the time step.
std::vector<ObstacleEnsembleParameters> three_points() {
  auto a = point(60, 0.05);
  auto b = point(0.5, 0.3);
  b.droplet.near_wall_drag = 0.064;
  auto c = point(2, 0.2);
  c.droplet.terminal_speed = 0.16;
  return {a, b, c};
}

TEST(DropletScene, DropletsWithTheirOwnParametersEvolveBitwiseAsAlone) {
  const auto points = three_points();
  const auto box = ensemble_detail::periodic_square<double>(12);
  std::vector<std::vector<Vec<2, double>>> arrays;
  for (std::size_t p = 0; p < points.size(); ++p) arrays.push_back(ensemble_detail::replica_obstacles(points[p], 7 + p));
  const double cell = 0.3 + 0.05;
  std::vector<DropletParameters> per_body;
  for (const auto& p : points) per_body.push_back(p.droplet);
  const Vec<2, double> centre{{6.0, 6.0}};
  DropletScene<double> mixed(per_body, Surfaces<double>(ObstacleArray<double>::from_arrays(box, arrays, 0.3, cell)),
                             {centre, centre, centre}, {0, 1, 2});
  ASSERT_TRUE(mixed.mixed());
  ASSERT_LT(mixed.dt(0), mixed.dt(1));  // Γ = 60 runs below the paper's 10⁻³ t0
  std::cout << "[ measured ] time steps " << mixed.dt(0) << ", " << mixed.dt(1) << ", " << mixed.dt(2) << " t0\n";
  std::vector<std::unique_ptr<DropletScene<double>>> alone;
  for (std::size_t p = 0; p < points.size(); ++p) {
    alone.push_back(std::make_unique<DropletScene<double>>(
        points[p].droplet, Surfaces<double>(ObstacleArray<double>(box, arrays[p], 0.3, cell)),
        std::vector<Vec<2, double>>{centre}));
    ASSERT_EQ(alone.back()->dt(), mixed.dt(int(p)));
  }
  mixed.compute_step_forces();
  for (auto& s : alone) s->compute_step_forces();
  for (int step = 0; step < 3000; ++step) {
    mixed.step();
    for (auto& s : alone) s->step();
  }
  for (std::size_t p = 0; p < points.size(); ++p) {
    const auto a = alone[p]->droplet_vertices(0), m = mixed.droplet_vertices(int(p));
    int differ = 0;
    for (std::size_t k = 0; k < a.size(); ++k) differ += !same_bits(a[k][0], m[k][0]) || !same_bits(a[k][1], m[k][1]);
    EXPECT_EQ(differ, 0) << "droplet " << p;
    EXPECT_GT(std::abs(m[0][1] - centre[1]), 0.05);  // it has fallen
  }
}

TEST(DropletScene, MixedDropletsMustShareTheCommonParameters) {
  auto a = point(1, 0.2).droplet, b = a;
  b.vertices = 48;
  const Surfaces<double> none;
  try {
    DropletScene<double> scene({a, b}, none, {Vec<2, double>{{3.0, 3.0}}, Vec<2, double>{{8.0, 8.0}}}, {0, 0});
    FAIL() << "droplets of different N_v accepted in one batch";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("vertex count N_v"), std::string::npos) << e.what();
  }
}

// 3 points × 3 replicas through 2 slots: 7 refills, then a compaction to the last running
// replica. Each record equals, bit for bit, that of the replica run in a batch of its own (with the
// sweep's cell width), and every (point, replica) is reported exactly once.
TEST(ObstacleSweepBatch, RefilledAndCompactedSweepGivesEveryReplicaItsRecordAlone) {
  const auto points = three_points();
  const std::vector<std::vector<int>> todo = {{0, 1, 2}, {0, 1, 2}, {0, 1, 2}};
  const std::uint64_t seed = 11;
  std::map<std::pair<int, int>, ReplicaRecord> batched;
  int reports = 0;
  const auto stats = run_sweep_batched<double>(
      points, todo, seed, 2,
      [&](std::size_t p, int j, std::uint64_t s, const ReplicaRecord& r) {
        EXPECT_EQ(s, replica_seed(seed, j));
        EXPECT_EQ(batched.count({int(p), j}), 0u) << "reported twice";
        batched[{int(p), j}] = r;
        ++reports;
      },
      [](long long) {});
  EXPECT_EQ(reports, 9);
  EXPECT_EQ(stats.refills, 7);
  EXPECT_GE(stats.compactions, 1);
  int clogged = 0;
  for (std::size_t p = 0; p < points.size(); ++p) {
    auto alone_par = points[p];
    alone_par.cell_gap = 0.05;  // the sweep's smallest gap sets everyone's grid
    for (const int j : todo[p]) {
      ReplicaRecord alone;
      run_obstacle_batch<double>(alone_par, {replica_seed(seed, j)}, [&](int, const ReplicaRecord& r) { alone = r; });
      const ReplicaRecord& b = batched.at({int(p), j});
      EXPECT_EQ(b.clogged, alone.clogged) << "point " << p << " replica " << j;
      EXPECT_TRUE(same_bits(b.distance, alone.distance)) << b.distance << " vs " << alone.distance;
      EXPECT_TRUE(same_bits(b.time, alone.time)) << b.time << " vs " << alone.time;
      EXPECT_TRUE(same_bits(b.final_x, alone.final_x) && same_bits(b.final_y, alone.final_y));
      EXPECT_TRUE(same_bits(b.steady_speed, alone.steady_speed));
      EXPECT_EQ(b.early, alone.early);
      clogged += b.clogged;
      std::cout << "[ measured ] point " << p << " replica " << j << ": clogged " << b.clogged << " at t = " << b.time
                << ", r = " << b.distance << "\n";
    }
  }
  // Some replicas clog early and some run to T: the slots finish at different times.
  EXPECT_GT(clogged, 0);
  EXPECT_LT(clogged, 9);
}

TEST(ObstacleSweepBatch, RefusesMixedBoxesAndSoftParticles) {
  auto a = point(1, 0.2), b = point(2, 0.2);
  b.box_length = 20;
  const auto nothing = [](std::size_t, int, std::uint64_t, const ReplicaRecord&) {};
  EXPECT_THROW(run_sweep_batched<double>({a, b}, {{0}, {0}}, 1, 2, nothing, [](long long) {}), std::invalid_argument);
  b = a;
  b.model = DropletModel::soft_particle;
  EXPECT_THROW(run_sweep_batched<double>({a, b}, {{0}, {0}}, 1, 2, nothing, [](long long) {}), std::invalid_argument);
  EXPECT_THROW(run_sweep_batched<double>({a}, {{0}}, 1, 0, nothing, [](long long) {}), std::invalid_argument);
}

TEST(VelocityVerlet, PerParticleTimeStepsAreBitwiseTheUniformOnes) {
  for (const double lambda : {0.5, 0.65}) {
    Particles<2, double> p(6, "pv"), q(6, "pu");
    const auto init = [](Particles<2, double>& s) {
      auto x = Kokkos::create_mirror_view(s.x);
      auto v = Kokkos::create_mirror_view(s.v);
      auto f = Kokkos::create_mirror_view(s.f);
      auto m = Kokkos::create_mirror_view(s.mass);
      for (int i = 0; i < 6; ++i) {
        m(i) = 0.3 + 0.1 * i;
        for (int d = 0; d < 2; ++d) {
          x(i, d) = 0.1 * i + d;
          v(i, d) = 0.01 * (i - d);
          f(i, d) = 0.7 * (d - i) + 0.13;
        }
      }
      Kokkos::deep_copy(s.x, x);
      Kokkos::deep_copy(s.v, v);
      Kokkos::deep_copy(s.f, f);
      Kokkos::deep_copy(s.mass, m);
    };
    init(p);
    init(q);
    const double dt_a = 1e-3, dt_b = 3.7e-4;  // particles 0–2 at dt_a, 3–5 at dt_b
    VelocityVerlet<2, double, Kokkos::DefaultExecutionSpace> per(dt_a, lambda), uni_a(dt_a, lambda), uni_b(dt_b, lambda);
    Kokkos::View<double*> pdt("pdt", 6);
    auto h = Kokkos::create_mirror_view(pdt);
    for (int i = 0; i < 6; ++i) h(i) = i < 3 ? dt_a : dt_b;
    Kokkos::deep_copy(pdt, h);
    per.set_particle_time_steps(pdt);
    Particles<2, double> qa(6, "qa"), qb(6, "qb");
    init(qa);
    init(qb);
    per.first_half(p);
    uni_a.first_half(qa);
    uni_b.first_half(qb);
    const auto vp = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), per.velocity_for_forces(p));
    const auto va = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), uni_a.velocity_for_forces(qa));
    const auto vb = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), uni_b.velocity_for_forces(qb));
    per.second_half(p);
    uni_a.second_half(qa);
    uni_b.second_half(qb);
    const auto xp = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.x);
    const auto vvp = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.v);
    const auto xa = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), qa.x);
    const auto xb = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), qb.x);
    const auto vva = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), qa.v);
    const auto vvb = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), qb.v);
    for (int i = 0; i < 6; ++i)
      for (int d = 0; d < 2; ++d) {
        const bool a = i < 3;
        EXPECT_TRUE(same_bits(xp(i, d), a ? xa(i, d) : xb(i, d))) << "lambda " << lambda << " x " << i;
        EXPECT_TRUE(same_bits(vvp(i, d), a ? vva(i, d) : vvb(i, d))) << "lambda " << lambda << " v " << i;
        EXPECT_TRUE(same_bits(vp(i, d), a ? va(i, d) : vb(i, d))) << "lambda " << lambda << " predicted v " << i;
      }
    EXPECT_NE(xa(4, 0), xb(4, 0));  // the two steps differ
  }
  Particles<2, double> wrong(4, "w");
  VelocityVerlet<2, double, Kokkos::DefaultExecutionSpace> vv(1e-3);
  vv.set_particle_time_steps(Kokkos::View<double*>("pdt", 3));
  EXPECT_THROW(vv.first_half(wrong), std::invalid_argument);
}

}  // namespace
}  // namespace mesoflow::droplets::obstacle_sweep_batch_test
