// The generic pair loop with the Lennard-Jones evaluator: forces are minus the energy gradient
// (central finite differences), full and half lists agree, Newton's third law holds, and the loop
// adds to forces already present. The loop's evaluator contract itself (issue 24, item 3): a toy
// evaluator with a vector and a scalar per particle against an O(N²) sum, for every screen and
// image convention, full and half lists, the reduction, inner rows and the tag check.
#include "kernels/common/lennard_jones.hpp"
#include "kernels/common/pair_force.hpp"
#include "test_types.hpp"

#include <cmath>
#include <random>
#include <utility>
#include <vector>

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

// Full lists: each particle sums its own pairs in the cell list's sorted order, so two evaluations
// on one backend agree to the bit; against the host, to the bit on a host backend and within the
// FMA contraction bound on a device (item 3 of issue 26: bitwise only within one backend). The
// bound's scale is Σ_j |F_ij| of the particle (brute force on the host), its operation count
// 20 roundings per pair within the cutoff.
TYPED_TEST(PairForceTest, FullListForcesAreBitwiseReproducible) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  constexpr int n = 500;
  const double L = 10.0, rc = 2.5;
  LJSystem<3, Real, Exec> a(n, L, NeighborListKind::full, 9), a2(n, L, NeighborListKind::full, 9);
  LJSystem<3, Real, Kokkos::DefaultHostExecutionSpace> b(n, L, NeighborListKind::full, 9);
  a.compute();
  a2.compute();
  b.compute();
  auto fa = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), a.p.f);
  auto fa2 = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), a2.p.f);
  auto fb = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), b.p.f);
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), b.p.x);
  for (int i = 0; i < n; ++i) {
    double magnitude = 0;  // Σ_j |F_ij| and the pair count, brute force
    int pairs = 0;
    for (int j = 0; j < n; ++j) {
      if (j == i) continue;
      double r2 = 0;
      for (int d = 0; d < 3; ++d) {
        double dx = double(x(i, d)) - double(x(j, d));
        dx -= L * std::round(dx / L);
        r2 += dx * dx;
      }
      if (r2 >= rc * rc) continue;
      const double s6 = 1.0 / (r2 * r2 * r2);
      magnitude += std::abs(24.0 * s6 * (2.0 * s6 - 1.0)) / std::sqrt(r2);
      ++pairs;
    }
    for (int d = 0; d < 3; ++d) {
      ASSERT_EQ(fa(i, d), fa2(i, d)) << "particle " << i << ", two evaluations on one backend";
      ASSERT_TRUE((testing::agrees_with_host<Exec, Real>(double(fa(i, d)), double(fb(i, d)), 20 * pairs + 1,
                                                         magnitude)))
          << "particle " << i;
    }
  }
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

// A toy evaluator: per particle a[0..D) = Σ_j w_ij (x_i − x_j) and a[D] = Σ_j w_ij, with
// w_ij = 1 − r²/rc² inside rc; the reduction slot receives Σ w over the pairs the loop visits.
template <int D, class Real, class Exec, PairScreen Screen, MinimumImage Image>
struct ToyEvaluator : PairEvaluatorTraits {
  static constexpr PairScreen screen = Screen;
  static constexpr MinimumImage image = Image;
  using out_view = Kokkos::View<double* [D + 1], Exec>;
  Real cutoff2;
  out_view out;
  typename PairScatter<out_view>::scatter_view scatter;

  struct FullRow {
    double a[D + 1];
  };
  struct HalfRow {
    typename PairScatter<out_view>::access_type access;
    double a[D + 1];
  };
  KOKKOS_INLINE_FUNCTION static double weight(Real r2, Real rc2) { return 1.0 - double(r2) / double(rc2); }

  KOKKOS_INLINE_FUNCTION FullRow begin(FullList, int) const {
    FullRow s;
    for (int c = 0; c <= D; ++c) s.a[c] = 0;
    return s;
  }
  KOKKOS_INLINE_FUNCTION void operator()(FullList, FullRow& s, int, int, const Vec<D, Real>& dr, Real r2,
                                         double& sum) const {
    if (Screen == PairScreen::evaluator && !(r2 < cutoff2)) return;
    const double w = weight(r2, cutoff2);
    for (int d = 0; d < D; ++d) s.a[d] += w * double(dr[d]);
    s.a[D] += w;
    sum += w;
  }
  KOKKOS_INLINE_FUNCTION void end(FullList, FullRow& s, int i, double&) const {
    for (int c = 0; c <= D; ++c) out(i, c) = s.a[c];
  }

  KOKKOS_INLINE_FUNCTION HalfRow begin(HalfList, int) const {
    HalfRow s{scatter.access(), {}};
    for (int c = 0; c <= D; ++c) s.a[c] = 0;
    return s;
  }
  KOKKOS_INLINE_FUNCTION void operator()(HalfList, HalfRow& s, int, int j, const Vec<D, Real>& dr, Real r2,
                                         double& sum) const {
    if (Screen == PairScreen::evaluator && !(r2 < cutoff2)) return;
    const double w = weight(r2, cutoff2);
    for (int d = 0; d < D; ++d) {
      s.a[d] += w * double(dr[d]);
      s.access(j, d) -= w * double(dr[d]);
    }
    s.a[D] += w;
    s.access(j, D) += w;
    sum += w;
  }
  KOKKOS_INLINE_FUNCTION void end(HalfList, HalfRow& s, int i, double&) const {
    for (int c = 0; c <= D; ++c) s.access(i, c) += s.a[c];
  }
};

// Runs the toy evaluator over a list of `kind` and returns (per-particle sums, reduction).
template <PairScreen Screen, MinimumImage Image, int D, class Real, class Exec>
std::pair<std::vector<double>, double> toy_sums(const Particles<D, Real, Exec>& p, const Box<D, Real>& box,
                                                NeighborListKind kind, Real rc, Real list_cutoff,
                                                PairRows rows = PairRows::all, Real inner = Real(0)) {
  NeighborList<D, Real, Exec> list(list_cutoff, Real(0.3), kind);
  if (inner > Real(0)) list.set_inner_cutoff(inner);
  list.build(p, box);
  using Ev = ToyEvaluator<D, Real, Exec, Screen, Image>;
  Ev ev{{}, rc * rc, typename Ev::out_view("toy", p.size()), {}};
  double total = 0;
  if (kind == NeighborListKind::full) {
    total = reduce_pairs("test::toy_full", FullList{}, list, box, p.x, ev, rows);
  } else {
    PairScatter<typename Ev::out_view> scatter;
    ev.scatter = scatter.prepare(ev.out);
    total = reduce_pairs("test::toy_half", HalfList{}, list, box, p.x, ev, rows);
    scatter.contribute(ev.out);
  }
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ev.out);
  std::vector<double> out;
  for (int i = 0; i < int(p.size()); ++i)
    for (int c = 0; c <= D; ++c) out.push_back(h(i, c));
  return {out, total};
}

// The same sums by brute force over all pairs (minimum image by rounding), in double.
template <int D, class Real, class Exec>
std::pair<std::vector<double>, double> toy_brute_force(const Particles<D, Real, Exec>& p, double L, double rc) {
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.x);
  const int n = int(p.size());
  std::vector<double> out(std::size_t(n) * (D + 1), 0.0);
  double total = 0;
  const double rc2 = double(Real(rc) * Real(rc));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      if (i == j) continue;
      double dr[D], r2 = 0;
      for (int d = 0; d < D; ++d) {
        dr[d] = double(x(i, d)) - double(x(j, d));
        dr[d] -= L * std::round(dr[d] / L);
        r2 += dr[d] * dr[d];
      }
      if (!(r2 < rc2)) continue;
      const double w = 1.0 - r2 / rc2;
      for (int d = 0; d < D; ++d) out[i * (D + 1) + d] += w * dr[d];
      out[i * (D + 1) + D] += w;
      total += w;
    }
  return {out, total};
}

template <PairScreen Screen, MinimumImage Image, class Real, class Exec>
void check_toy_against_brute_force() {
  constexpr int D = 3;
  const double L = 7.0, rc = 1.6;
  const int n = 200;
  Particles<D, Real, Exec> p = lj_configuration<D, Real, Exec>(n, L, 11);
  const Box<D, Real> box = Box<D, Real>::cube(Real(L), true);
  const auto ref = toy_brute_force<D, Real, Exec>(p, L, rc);
  const double tol = 1e3 * testing::eps<Real>();
  // The list reaches beyond rc, so every screen has pairs to drop.
  for (auto kind : {NeighborListKind::full, NeighborListKind::half}) {
    const auto got = toy_sums<Screen, Image>(p, box, kind, Real(rc), Real(rc + 0.4));
    ASSERT_EQ(got.first.size(), ref.first.size());
    for (std::size_t k = 0; k < ref.first.size(); ++k) EXPECT_NEAR(got.first[k], ref.first[k], tol * 10) << k;
    // Full lists visit each pair from both ends, half lists once.
    const double visits = kind == NeighborListKind::full ? 1.0 : 0.5;
    EXPECT_NEAR(got.second, visits * ref.second, tol * ref.second);
  }
}

TYPED_TEST(PairForceTest, GenericLoopMatchesBruteForceForEveryScreenAndImage) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  check_toy_against_brute_force<PairScreen::evaluator, MinimumImage::exact, Real, Exec>();
  check_toy_against_brute_force<PairScreen::branch, MinimumImage::near, Real, Exec>();
  check_toy_against_brute_force<PairScreen::chunked, MinimumImage::near, Real, Exec>();
  check_toy_against_brute_force<PairScreen::chunked, MinimumImage::exact, Real, Exec>();
}

TYPED_TEST(PairForceTest, GenericLoopFullListIsBitwiseTheSameForEveryScreen) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  Particles<3, Real, Exec> p = lj_configuration<3, Real, Exec>(200, 7.0, 4);
  const Box<3, Real> box = Box<3, Real>::cube(Real(7.0), true);
  const auto a = toy_sums<PairScreen::evaluator, MinimumImage::near>(p, box, NeighborListKind::full, Real(1.5), Real(2));
  const auto b = toy_sums<PairScreen::branch, MinimumImage::near>(p, box, NeighborListKind::full, Real(1.5), Real(2));
  const auto c = toy_sums<PairScreen::chunked, MinimumImage::near>(p, box, NeighborListKind::full, Real(1.5), Real(2));
  EXPECT_EQ(a.first, b.first);
  EXPECT_EQ(a.first, c.first);
}

TYPED_TEST(PairForceTest, GenericLoopInnerRowsHoldEveryPairWithinTheInnerCutoff) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  const double L = 7.0, inner = 1.2;
  Particles<3, Real, Exec> p = lj_configuration<3, Real, Exec>(200, L, 8);
  const Box<3, Real> box = Box<3, Real>::cube(Real(L), true);
  const auto ref = toy_brute_force<3, Real, Exec>(p, L, inner);
  for (auto kind : {NeighborListKind::full, NeighborListKind::half}) {
    const auto got = toy_sums<PairScreen::branch, MinimumImage::near>(p, box, kind, Real(inner), Real(2.0),
                                                                       PairRows::inner, Real(inner));
    for (std::size_t k = 0; k < ref.first.size(); ++k)
      EXPECT_NEAR(got.first[k], ref.first[k], 1e4 * testing::eps<Real>()) << k;
    // Screened at the outer cutoff instead, inner rows miss pairs that whole rows hold.
    const auto inner_only = toy_sums<PairScreen::branch, MinimumImage::near>(p, box, kind, Real(2.0), Real(2.0),
                                                                              PairRows::inner, Real(inner));
    const auto whole = toy_sums<PairScreen::branch, MinimumImage::near>(p, box, kind, Real(2.0), Real(2.0),
                                                                         PairRows::all, Real(inner));
    EXPECT_LT(inner_only.second, whole.second);
  }
}

TEST(PairLoop, RefusesAListOfTheOtherKind) {
  using Exec = Kokkos::DefaultExecutionSpace;
  Particles<2, double, Exec> p = lj_configuration<2, double, Exec>(20, 6.0, 2);
  const Box<2, double> box = Box<2, double>::cube(6.0, true);
  NeighborList<2, double, Exec> half(1.5, 0.2, NeighborListKind::half);
  half.build(p, box);
  using Ev = ToyEvaluator<2, double, Exec, PairScreen::branch, MinimumImage::near>;
  const Ev ev{{}, 2.25, Ev::out_view("toy", 20), {}};
  EXPECT_THROW(for_each_pair("test::toy", FullList{}, half, box, p.x, ev), std::invalid_argument);
}

}  // namespace
}  // namespace mesoflow
