// The paper's MDPD fluids in equilibrium (periodic box, ρ = 6): the DPD thermostat holds the
// kinetic temperature at k_BT, total momentum is conserved by the time step, and results are
// reproducible for a fixed seed and thread count.
//
// Measured (mean over the production run): 3D at the paper's dt = 0.01: +0.2 to +0.4%; 2D at
// dt = 0.01: +0.90% (six seeds, 3456 particles, 10⁴ steps each: 1.0086–1.0092), +0.16% at
// dt = 0.005. The 2D excess is the leap-frog's: its friction rate per particle is ≈ 2× the 3D one
// (113/τ against 60/τ), and the dissipative force sees the velocity half a step late. Groot and
// Warren's prediction λ > ½ does not help here: λ = 0.55 gives −3.1% (2D) and −2.0% (3D), λ = 0.65
// is unstable in 2D.
#include "kernels/common/random.hpp"
#include "scenes/pillars/mdpd_system.hpp"
#include "test_types.hpp"

#include <cmath>

namespace mesoflow {
namespace {

struct EquilibriumResult {
  double temperature, max_momentum;
};

template <int D>
EquilibriumResult equilibrium(double dt, double L, int warmup, int production,
                              NeighborListKind kind = NeighborListKind::half) {
  using Exec = Kokkos::DefaultExecutionSpace;
  mdpd::MdpdParameters par;
  if (D == 2) par.B = 30;
  par.dt = dt;
  mdpd::MdpdOptions opt;
  opt.list_kind = kind;
  mdpd::MdpdSystem<D, double, Exec> sys(par, Box<D, double>::cube(L, true), 4242, opt);
  const int n = int(std::lround(6.0 * std::pow(L, D)));
  sys.allocate(n);
  double lo[D], hi[D];
  for (int d = 0; d < D; ++d) {
    lo[d] = 0;
    hi[d] = L;
  }
  fill_uniform_counter(sys.particles.x, lo, hi, 8, 0);
  sys.begin();
  for (int s = 0; s < warmup; ++s) sys.step();
  double t_sum = 0, p_max = 0;
  int samples = 0;
  for (int s = 0; s < production; ++s) {
    sys.step();
    if (s % 5 == 0) {
      t_sum += mdpd::kinetic_temperature(sys.particles);
      ++samples;
      for (double p : momentum(sys.particles)) p_max = std::max(p_max, std::abs(p));
    }
  }
  return {t_sum / samples, p_max};
}

TEST(MdpdEquilibrium, ThermostatHoldsTemperature3D) {
  const auto r = equilibrium<3>(0.01, 6.0, 500, 4000);
  EXPECT_NEAR(r.temperature, 1.0, 0.01);
  EXPECT_LT(r.max_momentum, 1e-9);  // starts at rest; 1296 particles
}

TEST(MdpdEquilibrium, ThermostatHoldsTemperature2D) {
  const auto fine = equilibrium<2>(0.005, 16.0, 1000, 6000);
  EXPECT_NEAR(fine.temperature, 1.0, 0.005);
  const auto paper = equilibrium<2>(0.01, 24.0, 500, 8000);  // 3456 particles: ±0.02% noise
  EXPECT_NEAR(paper.temperature, 1.0, 0.01);
  EXPECT_GT(paper.temperature, fine.temperature);  // the time-step error heats the fluid
  EXPECT_LT(paper.max_momentum, 1e-9);
}

// On a device backend with full lists, the deterministic-sum mode (testing::reproducible_by_default).
TEST(MdpdEquilibrium, ReproducibleForAFixedSeed) {
  const auto kind = testing::reproducible_by_default<Kokkos::DefaultExecutionSpace>() ? NeighborListKind::half
                                                                                      : NeighborListKind::full;
  const auto a = equilibrium<3>(0.01, 4.0, 100, 100, kind);
  const auto b = equilibrium<3>(0.01, 4.0, 100, 100, kind);
  EXPECT_EQ(a.temperature, b.temperature);
}

}  // namespace
}  // namespace mesoflow
