// The early clog test of ClogDetector (scenes/droplets/clog_detection.hpp, issue 25) on synthetic
// replicas whose centre of mass and E_k are given functions of time: an exponential arrest is
// declared clogged early with r within the tolerance of r at the threshold, and replicas that still
// move, or whose E_k does not decay, never are.
#include "scenes/droplets/clog_detection.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace mesoflow::droplets {
namespace {

constexpr double v_t = 0.08, e_t = 1.0, k_decay = 0.5;

// Replica 0: an arrest, E_k/E_t = e^{−k t} and x = X − (2 v_t/k) e^{−k t/2} (v = v_t √(E_k/E_t)).
// Replica 1: creeping at 2·10⁻⁴ σ/t0 (E_k/E_t = (v/v_t)², constant).
// Replica 2: E_k decays as replica 0 but the centre of mass keeps creeping (10⁻⁴ σ/t0): (1) fails.
// Replica 3: held still with E_k/E_t = 10⁻¹² constant: no decay, (2) fails.
// Replica 4: an arrest whose rate halves at t = 30 (a slower mode takes over).
struct Synthetic {
  double t;
  KOKKOS_INLINE_FUNCTION void operator()(int b, double (&c)[2], double& ke) const {
    c[1] = 0.5 * b;
    if (b == 0) {
      ke = e_t * kmath::exp(-k_decay * t);
      c[0] = 3.0 - 2 * v_t / k_decay * kmath::exp(-0.5 * k_decay * t);
    } else if (b == 1) {
      const double v = 2e-4;
      ke = e_t * (v / v_t) * (v / v_t);
      c[0] = v * t;
    } else if (b == 2) {
      ke = e_t * kmath::exp(-k_decay * t);
      c[0] = 1e-4 * t;
    } else if (b == 3) {
      ke = 1e-12 * e_t;
      c[0] = 1.0;
    } else {
      const double k = t < 30 ? k_decay : 0.5 * k_decay;
      ke = t < 30 ? e_t * kmath::exp(-k_decay * t) : e_t * kmath::exp(-k_decay * 30 - k * (t - 30));
      c[0] = 2.0 - 2 * v_t / k * kmath::sqrt(ke / e_t);
    }
  }
};

std::vector<ReplicaRecord> run(ClogTest test, double time_limit, const EarlyClogParameters& early = {}) {
  const int n = 5;
  ClogDetector<Kokkos::DefaultExecutionSpace> detector(n, 1e-17, Vec<2, double>{{1.0, 0.0}}, test, early, 1);
  const double dt = 0.01;
  detector.start(ReplicaLimits{e_t, v_t, time_limit, dt}, Synthetic{0.0});
  for (long long step = 1;; ++step) {
    detector.observe(Synthetic{step * dt});
    if (detector.running() == 0) break;
    if (step * dt > time_limit + 1) {
      ADD_FAILURE() << "a replica ran past the time limit";
      break;
    }
  }
  std::vector<ReplicaRecord> out;
  for (int b = 0; b < n; ++b) out.push_back(detector.record(b));
  return out;
}

TEST(EarlyClogTest, ExponentialArrestIsDeclaredEarlyWithinTheTolerance) {
  const double tolerance = EarlyClogParameters{}.tolerance;
  const auto both = run(ClogTest::both, 200);
  // The threshold: e^{−k t} = 10⁻¹⁷ at t = 17 ln 10 / k = 78.3.
  const double crossing = 17 * std::log(10.0) / k_decay;
  EXPECT_TRUE(both[0].clogged);
  EXPECT_NEAR(both[0].time, crossing, 0.02);
  EXPECT_EQ(both[0].early, early_decision::test);
  EXPECT_LT(both[0].early_time, 0.7 * both[0].time);  // decided well before the threshold
  EXPECT_LT(std::abs(both[0].early_distance - both[0].distance), tolerance);
  EXPECT_NEAR(both[0].early_rate, k_decay, 1e-3);
  EXPECT_NEAR(both[0].early_crossing, crossing, 0.1);
  std::cout << "[ measured ] early decision at t = " << both[0].early_time << " t0 (threshold at " << both[0].time
            << "), |dr| = " << std::abs(both[0].early_distance - both[0].distance) << " sigma\n";
  // The slowing arrest is decided too, later than at its first rate, and r is still within the tolerance.
  EXPECT_TRUE(both[4].clogged);
  EXPECT_EQ(both[4].early, early_decision::test);
  EXPECT_GT(both[4].early_time, 30);
  EXPECT_LT(std::abs(both[4].early_distance - both[4].distance), tolerance);

  // `early` ends the arrest at the decision, with the record of the early test.
  const auto early = run(ClogTest::early, 200);
  EXPECT_TRUE(early[0].clogged);
  EXPECT_EQ(early[0].time, both[0].early_time);
  EXPECT_EQ(early[0].distance, both[0].early_distance);
  // `full` never runs the early test.
  const auto full = run(ClogTest::full, 200);
  EXPECT_EQ(full[0].early, early_decision::none);
  EXPECT_EQ(full[0].time, both[0].time);
}

TEST(EarlyClogTest, MovingOrNonDecayingReplicasAreNeverDeclaredEarly) {
  const auto both = run(ClogTest::both, 150);
  for (int b : {1, 3}) {
    EXPECT_FALSE(both[std::size_t(b)].clogged) << "replica " << b;
    EXPECT_EQ(both[std::size_t(b)].early, early_decision::none) << "replica " << b;
    EXPECT_EQ(both[std::size_t(b)].time, 150);
  }
  // Replica 2's E_k crosses 10⁻¹⁷ while it moves: the threshold, the definition, calls it clogged,
  // and the early test never did.
  EXPECT_TRUE(both[2].clogged);
  EXPECT_EQ(both[2].early, early_decision::threshold);
  const auto early = run(ClogTest::early, 150);
  for (int b : {1, 3}) EXPECT_FALSE(early[std::size_t(b)].clogged) << "replica " << b;
}

TEST(EarlyClogTest, ParametersOutOfRangeAreRefusedNamingTheFlag) {
  const auto refused = [](EarlyClogParameters p, const std::string& flag) {
    try {
      p.validate();
      ADD_FAILURE() << flag << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(flag), std::string::npos) << e.what();
    }
  };
  EarlyClogParameters p;
  p.window = 1;  // 2 samples
  refused(p, "--clog-window");
  p = {};
  p.tolerance = 0;
  refused(p, "--clog-tolerance");
  p = {};
  p.min_rate = -1;
  refused(p, "--clog-min-rate");
  p = {};
  p.sample_interval = 0;
  refused(p, "--clog-sample-interval");
  EXPECT_THROW(clog_test_from_name("fast"), std::invalid_argument);
}

}  // namespace
}  // namespace mesoflow::droplets
