// Ensembles of droplets in random obstacle arrays (capillary-droplets §4.2, App. C): a replica in a
// batch gives bitwise the record it gives alone, and clog detection (E_k/E_t below a threshold)
// fires where clogging is certain and never where the droplet cannot be held, for both models.
#include "analysis/droplets/clogging_statistics.hpp"
#include "scenes/droplets/obstacles_ensemble.hpp"

#include <gtest/gtest.h>

#include <iostream>

#include <cmath>
#include <cstring>
#include <vector>

namespace mesoflow::droplets {
namespace {

std::vector<ReplicaRecord> run(const ObstacleEnsembleParameters& par, const std::vector<std::uint64_t>& seeds) {
  std::vector<ReplicaRecord> out(seeds.size());
  std::vector<int> reported(seeds.size(), 0);
  run_obstacle_batch<double>(par, seeds, [&](int k, const ReplicaRecord& r) {
    out[std::size_t(k)] = r;
    ++reported[std::size_t(k)];
  });
  for (const int n : reported) EXPECT_EQ(n, 1);  // every replica reported exactly once
  return out;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

void expect_batch_equals_alone(const ObstacleEnsembleParameters& par) {
  const std::vector<std::uint64_t> seeds = {replica_seed(1, 0), replica_seed(1, 1), replica_seed(1, 2)};
  const auto batch = run(par, seeds);
  for (std::size_t k = 0; k < seeds.size(); ++k) {
    const auto alone = run(par, {seeds[k]})[0];
    EXPECT_EQ(batch[k].clogged, alone.clogged) << "replica " << k;
    EXPECT_TRUE(same_bits(batch[k].distance, alone.distance)) << batch[k].distance << " vs " << alone.distance;
    EXPECT_TRUE(same_bits(batch[k].final_x, alone.final_x) && same_bits(batch[k].final_y, alone.final_y));
    EXPECT_TRUE(same_bits(batch[k].time, alone.time));
    EXPECT_TRUE(same_bits(batch[k].steady_speed, alone.steady_speed));
  }
  // The replicas have different arrays, so they end in different places.
  EXPECT_NE(batch[0].final_x, batch[1].final_x);
}

ObstacleEnsembleParameters small_dp() {
  ObstacleEnsembleParameters par;
  par.droplet.vertices = 32;
  par.droplet.near_wall_drag = 0;
  par.box_length = 12;
  par.relax_iterations = 2000;
  return par;
}

ObstacleEnsembleParameters small_sp(double wall_energy) {
  ObstacleEnsembleParameters par;
  par.model = DropletModel::soft_particle;
  par.soft.wall_energy = wall_energy;
  par.box_length = 12;
  return par;
}

TEST(ObstacleEnsemble, DeformableReplicaInABatchIsBitwiseTheReplicaAlone) {
  auto par = small_dp();
  par.gap = 0.4;
  par.time_limit = 20;  // the start disk is clear of obstacles: the droplet needs ~10 t0 to reach some
  expect_batch_equals_alone(par);
}

TEST(ObstacleEnsemble, SoftReplicaInABatchIsBitwiseTheReplicaAlone) {
  auto par = small_sp(1.0);
  par.time_limit = 20;
  expect_batch_equals_alone(par);
}

// E_w = 100: eq. 8's largest force 2E_w/σ is 250 Mg, so a disk of diameter σ cannot squeeze
// through w_ob = 0.2σ and every replica clogs; at E_w = 0.1 it is 0.25 Mg, no obstacle can hold the
// droplet and every replica is censored, λ̂ infinite with the lower bound of clogging_statistics.
TEST(ObstacleEnsemble, SoftParticleClogsWhenStiffAndNeverWhenSoft) {
  const std::vector<std::uint64_t> seeds = {replica_seed(2, 0), replica_seed(2, 1), replica_seed(2, 2), replica_seed(2, 3)};
  auto stiff = small_sp(100.0);
  stiff.time_limit = 40;
  std::vector<ReplicaOutcome> outcomes;
  for (const auto& r : run(stiff, seeds)) {
    EXPECT_TRUE(r.clogged);
    EXPECT_LT(r.time, stiff.time_limit);
    EXPECT_EQ(r.steady_speed, 0.0);
    outcomes.push_back({std::max(0.0, r.distance), r.clogged});
  }
  EXPECT_EQ(decay_length(outcomes).clogged, 4);
  EXPECT_TRUE(std::isfinite(decay_length(outcomes).upper));

  auto soft = small_sp(0.1);
  soft.time_limit = 40;
  outcomes.clear();
  for (const auto& r : run(soft, seeds)) {
    EXPECT_FALSE(r.clogged);
    EXPECT_EQ(r.time, soft.time_limit);
    // Free fall at v_t with brief obstacle contacts: the fitted steady speed is within 10% of v_t.
    EXPECT_NEAR(r.steady_speed / soft.soft.terminal_speed, 1.0, 0.1);
    outcomes.push_back({r.distance, r.clogged});
  }
  const auto lambda = decay_length(outcomes);
  EXPECT_EQ(lambda.clogged, 0);
  EXPECT_TRUE(std::isinf(lambda.lambda) && std::isinf(lambda.upper));
  EXPECT_NEAR(lambda.lower, lambda.total_distance / (0.5 * chi_square_1_quantile(0.95)), 1e-12 * lambda.lower);
}

// A stiff droplet (Γ = 10) among obstacles 0.05σ apart is held by the first pair it meets: every
// replica clogs at the paper's threshold E_k/E_t < 10⁻¹⁷. How soon E_k gets there is set by the
// slowest mode of a held droplet: its vertices sliding along the interface under gravity against
// the segment springs, overdamped by the drag b∞/N_v per vertex, at the rate ≈ π² k_l/b∞
// independent of N_v — 10⁻²/t0 at the paper's K_l/Γ = 10⁻³, so E_k falls by 10⁻¹³ in ~1500 t0
// (the paper runs T = 2·10⁵ t0). K_l/Γ = 0.1 makes it ~100× faster for this CI test.
TEST(ObstacleEnsemble, StiffDeformablePolygonClogsInTightGaps) {
  const std::vector<std::uint64_t> seeds = {replica_seed(4, 0), replica_seed(4, 1), replica_seed(4, 2), replica_seed(4, 3)};
  auto stiff = small_dp();
  stiff.droplet.line_tension = 10;
  stiff.droplet.perimeter_stiffness = 0.1 * 10;
  stiff.gap = 0.05;
  stiff.time_limit = 300;
  std::vector<ReplicaOutcome> outcomes;
  for (const auto& r : run(stiff, seeds)) {
    EXPECT_TRUE(r.clogged) << "replica ended at t = " << r.time << " after r = " << r.distance;
    EXPECT_LT(r.time, stiff.time_limit);
    std::cout << "[ measured ] Γ = 10, w_ob = 0.05σ: clogged " << r.clogged << " at t = " << r.time
              << " t0 after r = " << r.distance << "σ\n";
    outcomes.push_back({std::max(0.0, r.distance), r.clogged});
  }
  EXPECT_EQ(decay_length(outcomes).clogged, 4);
}

// The early clog test (clog_detection.hpp) against the threshold on SP replicas (E_w = 1, slow
// arrests, rates 0.2–1/t0): under ClogTest::both every replica gets the same classification from
// both tests and, when clogged, r at the early decision within the tolerance of r at the threshold;
// under ClogTest::early the replicas stop at those decisions with bitwise the same records.
TEST(ObstacleEnsemble, EarlyClogTestAgreesWithTheThresholdOnSoftReplicas) {
  const std::vector<std::uint64_t> seeds = {replica_seed(5, 0), replica_seed(5, 1), replica_seed(5, 2), replica_seed(5, 3),
                                            replica_seed(5, 4), replica_seed(5, 5)};
  auto par = small_sp(1.0);
  par.time_limit = 300;
  par.clog_test = ClogTest::both;
  const auto both = run(par, seeds);
  int by_test = 0;
  for (std::size_t k = 0; k < seeds.size(); ++k) {
    const ReplicaRecord& r = both[k];
    EXPECT_EQ(r.early_clogged(), r.clogged) << "replica " << k << " early t = " << r.early_time << ", end t = " << r.time;
    if (r.clogged) {
      EXPECT_LT(std::abs(r.early_distance - r.distance), par.early.tolerance) << "replica " << k;
    }
    if (r.early == early_decision::test) {
      ++by_test;
      EXPECT_LT(r.early_time, r.time);
    }
    std::cout << "[ measured ] replica " << k << ": clogged " << r.clogged << " at t = " << r.time << ", early "
              << r.early << " at t = " << r.early_time << ", |dr| = " << std::abs(r.early_distance - r.distance) << "\n";
  }
  EXPECT_GE(by_test, 2);  // the early test decided, not only the threshold
  par.clog_test = ClogTest::early;
  const auto early = run(par, seeds);
  for (std::size_t k = 0; k < seeds.size(); ++k) {
    EXPECT_EQ(early[k].clogged, both[k].early_clogged());
    EXPECT_TRUE(same_bits(early[k].distance, both[k].early_distance)) << "replica " << k;
    EXPECT_TRUE(same_bits(early[k].time, both[k].early_time)) << "replica " << k;
  }
}

// With w_ob = 3σ no pair of obstacles can hold a droplet of diameter σ: every replica is censored
// and moves on at a good fraction of v_t.
TEST(ObstacleEnsemble, DeformablePolygonNeverClogsInWideGaps) {
  const std::vector<std::uint64_t> seeds = {replica_seed(3, 0), replica_seed(3, 1)};
  auto wide = small_dp();
  wide.box_length = 20;
  wide.droplet.line_tension = 1;
  wide.gap = 3;
  wide.time_limit = 10;
  std::vector<ReplicaOutcome> outcomes;
  for (const auto& r : run(wide, seeds)) {
    EXPECT_FALSE(r.clogged);
    EXPECT_EQ(r.time, wide.time_limit);
    EXPECT_GT(r.distance, 0.3 * wide.droplet.terminal_speed * wide.time_limit);
    outcomes.push_back({r.distance, r.clogged});
  }
  EXPECT_TRUE(std::isinf(decay_length(outcomes).lambda));
}

}  // namespace
}  // namespace mesoflow::droplets
