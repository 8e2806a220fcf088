// Particle sorting (kernels/common/particle_sort.hpp): a pure permutation into cell order — every
// field of every particle, and the extra per-particle views, travel together; consecutive particles
// end up close in space; forces computed after the sort are those of before, permuted (to round-off:
// each particle's neighbours are summed in another order). Serial and OpenMP, float and double.
#include "kernels/common/neighbor_list.hpp"
#include "kernels/common/pair_force.hpp"
#include "kernels/common/particle_sort.hpp"
#include "kernels/sp/pair_repulsion.hpp"
#include "test_types.hpp"

#include <cmath>
#include <iostream>
#include <random>
#include <vector>

namespace mesoflow {
namespace {

template <class T>
class ParticleSortTest : public ::testing::Test {};
TYPED_TEST_SUITE(ParticleSortTest, testing::BackendsAndPrecisions);

// A host copy that does not alias the device view (create_mirror_view_and_copy returns the view
// itself when it is host-accessible).
template <class View>
auto snapshot(const View& a) {
  auto h = Kokkos::create_mirror(a);
  Kokkos::deep_copy(h, a);
  return h;
}

template <class Real, class Exec>
double mean_consecutive_distance(const Particles<2, Real, Exec>& p, const Box<2, Real>& box) {
  const auto x = snapshot(p.x);
  double sum = 0;
  for (std::size_t i = 0; i + 1 < p.size(); ++i) {
    Vec<2, Real> dr{{x(i + 1, 0) - x(i, 0), x(i + 1, 1) - x(i, 1)}};
    box.minimum_image(dr);
    sum += std::sqrt(double(norm2(dr)));
  }
  return sum / double(p.size() - 1);
}

TYPED_TEST(ParticleSortTest, PermutesEveryFieldIntoCellOrderAndKeepsTheForces) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  const int n = 3000;
  const double L = 50.0;
  const Box<2, Real> box = Box<2, Real>::cube(Real(L), true);
  Particles<2, Real, Exec> p(n, "sorted");
  Kokkos::View<int*, Exec> ids("ids", n);
  Kokkos::View<double*, Exec> tag("tag", n);
  {
    std::mt19937 gen(4);
    std::uniform_real_distribution<double> u(0, L), w(-1, 1);
    auto x = Kokkos::create_mirror_view(p.x);
    auto v = Kokkos::create_mirror_view(p.v);
    auto m = Kokkos::create_mirror_view(p.mass);
    auto t = Kokkos::create_mirror_view(p.type);
    auto b = Kokkos::create_mirror_view(p.body);
    auto id = Kokkos::create_mirror_view(ids);
    auto g = Kokkos::create_mirror_view(tag);
    for (int i = 0; i < n; ++i) {
      x(i, 0) = Real(u(gen)), x(i, 1) = Real(u(gen)), v(i, 0) = Real(w(gen)), v(i, 1) = Real(w(gen));
      t(i) = i % 2, m(i) = Real(1 + t(i)), b(i) = i / 7, id(i) = i, g(i) = 0.5 * i;
    }
    Kokkos::deep_copy(p.x, x), Kokkos::deep_copy(p.v, v), Kokkos::deep_copy(p.mass, m);
    Kokkos::deep_copy(p.type, t), Kokkos::deep_copy(p.body, b), Kokkos::deep_copy(ids, id), Kokkos::deep_copy(tag, g);
  }
  const sp::SoftSphereRepulsion<Real> contacts(Real(100), {Real(1), Real(1.4)});
  NeighborList<2, Real, Exec> list(contacts.cutoff(), Real(0.3));
  PairForce<2, Real, Exec> pair;
  list.build(p, box);
  p.zero_forces();
  const double u_before = pair.accumulate(contacts, p, list, box);
  const auto x0 = snapshot(p.x);
  const auto v0 = snapshot(p.v);
  const auto f0 = snapshot(p.f);
  const double spread_before = mean_consecutive_distance(p, box);

  sort_particles_by_cell(p, list.cells(), ids, tag);

  const auto x = snapshot(p.x);
  const auto v = snapshot(p.v);
  const auto f = snapshot(p.f);
  const auto m = snapshot(p.mass);
  const auto t = snapshot(p.type);
  const auto b = snapshot(p.body);
  const auto id = snapshot(ids);
  const auto g = snapshot(tag);
  std::vector<int> seen(n, 0);
  for (int s = 0; s < n; ++s) {
    const int i = id(s);
    ASSERT_GE(i, 0);
    ASSERT_LT(i, n);
    ++seen[i];
    for (int d = 0; d < 2; ++d) {
      EXPECT_EQ(x(s, d), x0(i, d));
      EXPECT_EQ(v(s, d), v0(i, d));
      EXPECT_EQ(f(s, d), f0(i, d));
    }
    EXPECT_EQ(t(s), i % 2);
    EXPECT_EQ(m(s), Real(1 + i % 2));
    EXPECT_EQ(b(s), i / 7);
    EXPECT_EQ(g(s), 0.5 * i);
  }
  for (int i = 0; i < n; ++i) EXPECT_EQ(seen[i], 1) << "particle " << i;

  const double spread_after = mean_consecutive_distance(p, box);
  std::cout << "[ sort ] mean distance between consecutive particles: " << spread_before << " → " << spread_after
            << "\n";
  EXPECT_LT(spread_after, 0.1 * spread_before);

  list.build(p, box);
  p.zero_forces();
  const double u_after = pair.accumulate(contacts, p, list, box);
  // The same pair terms, summed in another order: a few round-offs of the precision.
  EXPECT_NEAR(u_after, u_before, 64 * testing::eps<Real>() * std::abs(u_before));
  const auto f1 = snapshot(p.f);
  double worst = 0, scale = 0;
  for (int s = 0; s < n; ++s)
    for (int d = 0; d < 2; ++d) {
      worst = std::max(worst, std::abs(double(f1(s, d)) - double(f0(id(s), d))));
      scale = std::max(scale, std::abs(double(f0(id(s), d))));
    }
  std::cout << "[ sort ] forces after the sort: max |ΔF| / max |F| = " << worst / scale << " (ε = " << testing::eps<Real>()
            << ")\n";
  EXPECT_GT(scale, 1.0);
  EXPECT_LE(worst, 64 * testing::eps<Real>() * scale);

  Particles<2, Real, Exec> other(n - 1, "other");
  EXPECT_THROW(sort_particles_by_cell(other, list.cells()), std::invalid_argument);
}

}  // namespace
}  // namespace mesoflow
