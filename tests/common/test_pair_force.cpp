// The generic pair loop with the Lennard-Jones evaluator: forces are minus the energy gradient
// (central finite differences), full and half lists agree, Newton's third law holds, and the loop
// adds to forces already present.
#include "kernels/common/lennard_jones.hpp"
#include "kernels/common/pair_force.hpp"
#include "test_types.hpp"

#include <cmath>
#include <random>

namespace mesoflow {
namespace {

template <class T>
class PairForceTest : public ::testing::Test {};
TYPED_TEST_SUITE(PairForceTest, testing::BackendsAndPrecisions);

// A dilute random configuration without close overlaps (minimum separation 0.9σ).
template <int D, class Real, class Exec>
Particles<D, Real, Exec> lj_configuration(int n, double L, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(0.0, L);
  std::vector<std::array<double, D>> pos;
  while (int(pos.size()) < n) {
    std::array<double, D> r;
    for (int d = 0; d < D; ++d) r[d] = u(gen);
    bool clear = true;
    for (const auto& q : pos) {
      double r2 = 0;
      for (int d = 0; d < D; ++d) {
        double dx = r[d] - q[d];
        dx -= L * std::round(dx / L);
        r2 += dx * dx;
      }
      clear = clear && r2 > 0.81;
    }
    if (clear) pos.push_back(r);
  }
  Particles<D, Real, Exec> p(n);
  auto x = Kokkos::create_mirror_view(p.x);
  for (int i = 0; i < n; ++i)
    for (int d = 0; d < D; ++d) x(i, d) = Real(pos[i][d]);
  Kokkos::deep_copy(p.x, x);
  return p;
}

template <int D, class Real, class Exec>
struct LJSystem {
  Particles<D, Real, Exec> p;
  Box<D, Real> box;
  LennardJones<Real> lj{Real(1), Real(1), Real(2.5)};
  NeighborList<D, Real, Exec> list;
  PairForce<D, Real, Exec> pair;

  LJSystem(int n, double L, NeighborListKind kind, unsigned seed)
      : p(lj_configuration<D, Real, Exec>(n, L, seed)),
        box(Box<D, Real>::cube(Real(L), true)),
        list(Real(2.5), Real(0.4), kind) {}

  double compute() {
    list.update(p, box);
    Kokkos::deep_copy(p.f, Real(0));
    return pair.accumulate(lj, p, list, box);
  }
};

template <int D>
void check_gradient() {
  using Exec = Kokkos::DefaultHostExecutionSpace;
  LJSystem<D, double, Exec> s(D == 2 ? 40 : 60, D == 2 ? 8.0 : 6.0, NeighborListKind::full, 7);
  s.compute();
  auto f = Kokkos::create_mirror(s.p.f);
  Kokkos::deep_copy(f, s.p.f);
  auto x = Kokkos::create_mirror_view(s.p.x);
  const double h = 1e-6;
  double max_rel = 0;
  for (int i = 0; i < int(s.p.size()); ++i)
    for (int d = 0; d < D; ++d) {
      const double x0 = x(i, d);
      x(i, d) = x0 + h;
      const double e_plus = s.compute();
      x(i, d) = x0 - h;
      const double e_minus = s.compute();
      x(i, d) = x0;
      const double numeric = -(e_plus - e_minus) / (2 * h);
      const double rel = std::abs(numeric - f(i, d)) / std::max(1.0, std::abs(f(i, d)));
      max_rel = std::max(max_rel, rel);
    }
  EXPECT_LT(max_rel, 1e-6);
}

TEST(PairForceGradient, LennardJonesForceIsMinusEnergyGradient2D) { check_gradient<2>(); }
TEST(PairForceGradient, LennardJonesForceIsMinusEnergyGradient3D) { check_gradient<3>(); }

TYPED_TEST(PairForceTest, FullAndHalfListsAgreeAndConserveMomentum) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  LJSystem<3, Real, Exec> full(400, 9.0, NeighborListKind::full, 3);
  LJSystem<3, Real, Exec> half(400, 9.0, NeighborListKind::half, 3);
  const double e_full = full.compute(), e_half = half.compute();
  EXPECT_NEAR(e_full, e_half, 1e3 * testing::eps<Real>() * std::abs(e_full));
  auto ff = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), full.p.f);
  auto fh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), half.p.f);
  double total[3] = {0, 0, 0}, scale = 0;
  for (int i = 0; i < 400; ++i)
    for (int d = 0; d < 3; ++d) {
      scale = std::max(scale, std::abs(double(ff(i, d))));
      total[d] += ff(i, d);
    }
  for (int i = 0; i < 400; ++i)
    for (int d = 0; d < 3; ++d) EXPECT_NEAR(double(ff(i, d)), double(fh(i, d)), 1e3 * testing::eps<Real>() * scale);
  for (double t : total) EXPECT_NEAR(t, 0.0, 400 * 64 * testing::eps<Real>() * scale);
}

TYPED_TEST(PairForceTest, AddsToForcesAlreadyPresent) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  for (auto kind : {NeighborListKind::full, NeighborListKind::half}) {
    LJSystem<2, Real, Exec> s(100, 12.0, kind, 5);
    s.compute();
    auto alone = Kokkos::create_mirror(s.p.f);
    Kokkos::deep_copy(alone, s.p.f);
    Kokkos::deep_copy(s.p.f, Real(1.5));  // another term's contribution
    s.pair.accumulate(s.lj, s.p, s.list, s.box);
    s.pair.accumulate(s.lj, s.p, s.list, s.box);  // twice: the scatter buffer must be reset
    auto both = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.p.f);
    for (int i = 0; i < 100; ++i)
      for (int d = 0; d < 2; ++d)
        EXPECT_NEAR(double(both(i, d)), 1.5 + 2.0 * alone(i, d), 1e3 * testing::eps<Real>() * (1 + std::abs(alone(i, d))));
  }
}

TYPED_TEST(PairForceTest, FullListForcesAreBitwiseReproducible) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  LJSystem<3, Real, Exec> a(500, 10.0, NeighborListKind::full, 9);
  LJSystem<3, Real, Kokkos::DefaultHostExecutionSpace> b(500, 10.0, NeighborListKind::full, 9);
  a.compute();
  b.compute();
  auto fa = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), a.p.f);
  auto fb = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), b.p.f);
  for (int i = 0; i < 500; ++i)
    for (int d = 0; d < 3; ++d) ASSERT_EQ(fa(i, d), fb(i, d));
}

// accumulate_forces (dynamic schedule, no energy) gives the forces of accumulate bitwise on a full
// list, and adds to what is there; on a half list it is accumulate.
TYPED_TEST(PairForceTest, ForcesOnlyLoopEqualsTheEnergyLoop) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  for (auto kind : {NeighborListKind::full, NeighborListKind::half}) {
    LJSystem<3, Real, Exec> s(500, 10.0, kind, 9);
    s.compute();
    auto with_energy = Kokkos::create_mirror(s.p.f);
    Kokkos::deep_copy(with_energy, s.p.f);
    Kokkos::deep_copy(s.p.f, Real(0.25));
    s.pair.accumulate_forces(s.lj, s.p, s.list, s.box);
    auto forces_only = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.p.f);
    double scale = 0;
    for (int i = 0; i < 500; ++i)
      for (int d = 0; d < 3; ++d) {
        scale = std::max(scale, std::abs(double(with_energy(i, d))));
        if (kind == NeighborListKind::full)
          ASSERT_EQ(forces_only(i, d), Real(0.25) + with_energy(i, d));
        else
          EXPECT_NEAR(double(forces_only(i, d)), 0.25 + double(with_energy(i, d)), 1e3 * testing::eps<Real>() * scale);
      }
    EXPECT_GT(scale, 1.0);
  }
}

TEST(LennardJones, WcaIsRepulsiveAndVanishesSmoothlyAtItsCutoff) {
  const auto wca = LennardJones<double>::wca(1.0, 1.0);
  double f, e;
  const double rc = std::pow(2.0, 1.0 / 6.0);
  ASSERT_TRUE(wca.evaluate(0.999999 * rc * rc, 0, 0, f, e));
  EXPECT_NEAR(e, 0.0, 1e-6);
  EXPECT_NEAR(f, 0.0, 1e-3);
  EXPECT_FALSE(wca.evaluate(rc * rc * 1.0001, 0, 0, f, e));
  ASSERT_TRUE(wca.evaluate(1.0, 0, 0, f, e));
  EXPECT_DOUBLE_EQ(e, 1.0);  // U(σ) = 0 + ε shift
  EXPECT_DOUBLE_EQ(f, 24.0);
  EXPECT_THROW(LennardJones<double>(1.0, 0.0, 2.5), std::invalid_argument);
}

}  // namespace
}  // namespace mesoflow
