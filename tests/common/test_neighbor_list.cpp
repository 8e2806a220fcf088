// Neighbor lists against an O(N²) brute-force search, on random and adversarial configurations.
#include "kernels/common/neighbor_list.hpp"
#include "test_types.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <utility>
#include <vector>

namespace mesoflow {
namespace {

template <class T>
class NeighborListTest : public ::testing::Test {};
TYPED_TEST_SUITE(NeighborListTest, testing::BackendsAndPrecisions);

template <int D, class Real, class Exec>
Particles<D, Real, Exec> make_particles(const std::vector<std::array<double, D>>& pos,
                                        const std::vector<int>& body = {}) {
  Particles<D, Real, Exec> p(pos.size());
  auto x = Kokkos::create_mirror_view(p.x);
  auto b = Kokkos::create_mirror_view(p.body);
  for (std::size_t i = 0; i < pos.size(); ++i) {
    for (int d = 0; d < D; ++d) x(i, d) = Real(pos[i][d]);
    b(i) = body.empty() ? -1 : body[i];
  }
  Kokkos::deep_copy(p.x, x);
  Kokkos::deep_copy(p.body, b);
  return p;
}

template <int D, class Real>
Box<D, Real> make_box(double L, std::array<bool, D> periodic, double lo = -1.0) {
  Real lo_[D], len[D];
  bool per[D];
  for (int d = 0; d < D; ++d) {
    lo_[d] = Real(lo);
    len[d] = Real(L);
    per[d] = periodic[d];
  }
  return Box<D, Real>(lo_, len, per);
}

// Pairs (i, j) found by the list, as a set; for a half list as (min, max), each pair once.
template <int D, class Real, class Exec>
std::set<std::pair<int, int>> listed_pairs(const NeighborList<D, Real, Exec>& nl) {
  const bool half = nl.kind() == NeighborListKind::half;
  auto data = nl.views();
  auto particle = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), data.row_particle);
  auto count = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), data.count);
  auto index = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), data.index);
  std::set<std::pair<int, int>> pairs;
  std::set<int> rows_of;
  for (std::size_t r = 0; r < count.extent(0); ++r) {
    const int i = particle(r);
    EXPECT_TRUE(rows_of.insert(i).second) << "particle " << i << " owns two rows";
    for (int k = 0; k < count(r); ++k) {
      const int j = index(r, k);
      const bool inserted = pairs.insert(half ? std::pair<int, int>{std::min(i, j), std::max(i, j)} : std::pair<int, int>{i, j}).second;
      EXPECT_TRUE(inserted) << "pair (" << i << ", " << index(r, k) << ") listed twice";
    }
  }
  EXPECT_EQ(rows_of.size(), count.extent(0));
  return pairs;
}

// Checks the list against brute force: every pair closer than `reach` must be listed, none
// farther than it may be. Pairs within `ambiguity` of the reach may go either way (round-off).
template <int D, class Real, class Exec>
void expect_matches_brute_force(const NeighborList<D, Real, Exec>& nl, const Particles<D, Real, Exec>& p,
                                const Box<D, Real>& box, double reach, bool half, bool exclude_body) {
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.x);
  auto body = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.body);
  const auto listed = listed_pairs(nl);
  const double ambiguity = 64 * testing::eps<Real>() * (reach + box.length[0]);
  const int n = int(p.size());
  std::size_t expected = 0, ambiguous_listed = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      if (i == j || (half && j < i)) continue;  // a half list's pairs are stored as (min, max)
      if (exclude_body && body(i) >= 0 && body(i) == body(j)) {
        EXPECT_EQ(listed.count({i, j}), 0u) << "same-body pair " << i << "," << j << " listed";
        continue;
      }
      double r2 = 0;
      for (int d = 0; d < D; ++d) {
        double dx = double(x(i, d)) - double(x(j, d));
        if (box.periodic[d]) dx -= box.length[d] * std::floor(dx / box.length[d] + 0.5);
        r2 += dx * dx;
      }
      const double r = std::sqrt(r2);
      const bool present = listed.count({i, j}) > 0;
      if (std::abs(r - reach) <= ambiguity) {
        ambiguous_listed += present;
        continue;
      }
      if (r < reach) {
        ++expected;
        EXPECT_TRUE(present) << "missing pair " << i << "," << j << " at r=" << r;
      } else {
        EXPECT_FALSE(present) << "spurious pair " << i << "," << j << " at r=" << r;
      }
    }
  EXPECT_EQ(listed.size(), expected + ambiguous_listed);
}

template <int D>
std::vector<std::array<double, D>> random_positions(int n, double lo, double L, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(lo, lo + L);
  std::vector<std::array<double, D>> pos(n);
  for (auto& r : pos)
    for (int d = 0; d < D; ++d) r[d] = u(gen);
  return pos;
}

template <int D, class Real, class Exec>
void check_random(std::array<bool, D> periodic, NeighborListKind kind, unsigned seed) {
  const double L = 6.0, cutoff = 1.0, skin = 0.3;
  const int n = D == 2 ? 300 : 600;
  auto box = make_box<D, Real>(L, periodic);
  auto p = make_particles<D, Real, Exec>(random_positions<D>(n, -1.0, L, seed));
  for (int cells_per_reach = 1; cells_per_reach <= 3; ++cells_per_reach) {
    NeighborList<D, Real, Exec> nl(Real(cutoff), Real(skin), kind, BodyExclusion::none, cells_per_reach);
    EXPECT_TRUE(nl.update(p, box));
    expect_matches_brute_force(nl, p, box, cutoff + skin, kind == NeighborListKind::half, false);
  }
}

TYPED_TEST(NeighborListTest, RandomPeriodicWalledAndMixedMatchBruteForce) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  for (auto kind : {NeighborListKind::full, NeighborListKind::half}) {
    check_random<2, Real, Exec>({true, true}, kind, 1);
    check_random<2, Real, Exec>({false, false}, kind, 2);
    check_random<2, Real, Exec>({true, false}, kind, 3);
    check_random<3, Real, Exec>({true, true, true}, kind, 4);
    check_random<3, Real, Exec>({false, false, false}, kind, 5);
    check_random<3, Real, Exec>({true, true, false}, kind, 6);
  }
}

TYPED_TEST(NeighborListTest, SmallestAllowedPeriodicBoxHasTwoCellsPerAxis) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  // L = 2 (cutoff + skin) exactly: two cells per axis, each reached through both periodic images.
  auto box = make_box<3, Real>(2.6, {true, true, true});
  auto p = make_particles<3, Real, Exec>(random_positions<3>(120, -1.0, 2.6, 7));
  for (auto kind : {NeighborListKind::full, NeighborListKind::half})
    for (int cells_per_reach = 1; cells_per_reach <= 4; ++cells_per_reach) {
      NeighborList<3, Real, Exec> nl(Real(1.0), Real(0.3), kind, BodyExclusion::none, cells_per_reach);
      nl.build(p, box);
      EXPECT_EQ(nl.cells().grid().total, 8 * cells_per_reach * cells_per_reach * cells_per_reach);
      expect_matches_brute_force(nl, p, box, 1.3, kind == NeighborListKind::half, false);
    }
}

TYPED_TEST(NeighborListTest, EmptyCellsAndEverythingInOneCell) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  {  // five particles in a big box: almost every cell empty
    auto box = make_box<3, Real>(20.0, {true, true, true});
    // Box [-1, 19)³: 2 and 4 are near 0 only through the periodic images.
    auto p = make_particles<3, Real, Exec>({{{-0.8, -0.8, -0.8}}, {{-0.3, -0.3, -0.3}}, {{18.6, -0.8, -0.8}},
                                            {{10.0, 10.0, 10.0}}, {{-0.8, 18.7, 18.7}}});
    NeighborList<3, Real, Exec> nl(Real(1.0), Real(0.2));
    nl.build(p, box);
    expect_matches_brute_force(nl, p, box, 1.2, false, false);
    EXPECT_EQ(nl.num_entries(), 8);  // 0–1, 0–2 (through x), 0–4 (through y, z), 2–4, both ways
  }
  {  // walled box smaller than the cutoff: a single cell holds everything
    auto box = make_box<2, Real>(0.8, {false, false});
    auto p = make_particles<2, Real, Exec>(random_positions<2>(50, -1.0, 0.8, 8));
    NeighborList<2, Real, Exec> nl(Real(1.0), Real(0.2));
    nl.build(p, box);
    EXPECT_EQ(nl.cells().grid().total, 1);
    EXPECT_EQ(nl.num_entries(), 50 * 49);
  }
  {  // a large periodic box with all particles clustered inside one cell
    auto box = make_box<3, Real>(10.0, {true, true, true});
    auto p = make_particles<3, Real, Exec>(random_positions<3>(40, 2.05, 0.3, 9));
    NeighborList<3, Real, Exec> nl(Real(1.0), Real(0.2));
    nl.build(p, box);
    EXPECT_EQ(nl.num_entries(), 40 * 39);
    NeighborList<3, Real, Exec> half(Real(1.0), Real(0.2), NeighborListKind::half);
    half.build(p, box);
    EXPECT_EQ(half.num_entries(), 40 * 39 / 2);
  }
}

TYPED_TEST(NeighborListTest, ParticlesExactlyOnCellBoundariesAndBoxEdges) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  // Cell width is exactly 1.25 (L = 5, reach = 1.25): put particles on the grid lines, on the
  // lower box edge and on the upper edge (which folds onto the lower one), and outside a wall.
  std::vector<std::array<double, 2>> pos;
  for (int a = 0; a <= 4; ++a)
    for (int b = 0; b <= 4; ++b) pos.push_back({-1.0 + 1.25 * a, -1.0 + 1.25 * b});
  pos.push_back({4.0, 1.5});   // x on the upper periodic edge
  pos.push_back({0.0, -1.7});  // y below the lower wall
  pos.push_back({0.3, 4.6});   // y above the upper wall
  auto box = make_box<2, Real>(5.0, {true, false});
  auto p = make_particles<2, Real, Exec>(pos);
  for (auto kind : {NeighborListKind::full, NeighborListKind::half}) {
    NeighborList<2, Real, Exec> nl(Real(1.0), Real(0.25), kind);
    nl.build(p, box);
    expect_matches_brute_force(nl, p, box, 1.25, kind == NeighborListKind::half, false);
  }
}

TYPED_TEST(NeighborListTest, ExcludesPairsWithinTheSameBody) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  const int n = 200;
  std::vector<int> body(n);
  for (int i = 0; i < n; ++i) body[i] = i < 150 ? i / 10 : -1;  // 15 bodies of 10, 50 free
  auto box = make_box<2, Real>(5.0, {true, true});
  auto p = make_particles<2, Real, Exec>(random_positions<2>(n, -1.0, 5.0, 10), body);
  for (auto kind : {NeighborListKind::full, NeighborListKind::half}) {
    NeighborList<2, Real, Exec> nl(Real(0.8), Real(0.2), kind, BodyExclusion::same_body);
    nl.build(p, box);
    expect_matches_brute_force(nl, p, box, 1.0, kind == NeighborListKind::half, true);
  }
}

TYPED_TEST(NeighborListTest, RebuildsOnlyWhenSomethingMovedMoreThanHalfTheSkin) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  const double cutoff = 1.0, skin = 0.4, L = 6.0;
  auto box = make_box<3, Real>(L, {true, true, false});
  auto pos = random_positions<3>(400, -1.0, L, 11);
  auto p = make_particles<3, Real, Exec>(pos);
  NeighborList<3, Real, Exec> nl{Real(cutoff), Real(skin)};
  EXPECT_TRUE(nl.update(p, box));
  EXPECT_FALSE(nl.update(p, box));

  // Every particle moves by just under skin/2 (some across the periodic boundary, folded back):
  // no rebuild, yet every pair now within the cutoff must still be in the list.
  std::mt19937 gen(12);
  std::normal_distribution<double> g(0.0, 1.0);
  for (auto& r : pos) {
    double dir[3], norm = 0;
    for (double& c : dir) {
      c = g(gen);
      norm += c * c;
    }
    for (int d = 0; d < 3; ++d) {
      r[d] += 0.49 * skin * dir[d] / std::sqrt(norm);
      if (d < 2) r[d] -= L * std::floor((r[d] + 1.0) / L);
    }
  }
  p = make_particles<3, Real, Exec>(pos);
  EXPECT_FALSE(nl.update(p, box));
  EXPECT_EQ(nl.num_builds(), 1);
  const auto listed = listed_pairs(nl);
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.x);
  for (int i = 0; i < int(pos.size()); ++i)
    for (int j = 0; j < int(pos.size()); ++j) {
      if (i == j) continue;
      double r2 = 0;
      for (int d = 0; d < 3; ++d) {
        double dx = double(x(i, d)) - double(x(j, d));
        if (d < 2) dx -= L * std::floor(dx / L + 0.5);
        r2 += dx * dx;
      }
      if (r2 < cutoff * cutoff) {
        EXPECT_TRUE(listed.count({i, j})) << i << "," << j;
      }
    }

  // One particle moves on by 1.01 skin: whatever its first move, it is now more than skin/2 away.
  pos[7][2] += 1.01 * skin;
  p = make_particles<3, Real, Exec>(pos);
  EXPECT_TRUE(nl.update(p, box));
  EXPECT_EQ(nl.num_builds(), 2);
}

TYPED_TEST(NeighborListTest, CapacityGrowsWhenTheSystemCompresses) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  auto box = make_box<2, Real>(10.0, {true, true});
  auto sparse = make_particles<2, Real, Exec>(random_positions<2>(200, -1.0, 10.0, 13));
  for (auto kind : {NeighborListKind::full, NeighborListKind::half}) {
    NeighborList<2, Real, Exec> nl(Real(1.0), Real(0.2), kind);
    nl.build(sparse, box);
    const int capacity_before = nl.capacity();
    // Same count, all squeezed into a 2 × 2 corner: far more neighbors than first estimated.
    auto dense = make_particles<2, Real, Exec>(random_positions<2>(200, -1.0, 2.0, 14));
    nl.build(dense, box);
    EXPECT_GT(nl.capacity(), capacity_before);
    EXPECT_GE(nl.capacity(), nl.max_neighbors());
    expect_matches_brute_force(nl, dense, box, 1.2, kind == NeighborListKind::half, false);
  }
}

// With an inner cutoff, every row lists first exactly its neighbors within inner cutoff + skin;
// the set of pairs is that of the same list without the split. Also through a capacity overflow.
TYPED_TEST(NeighborListTest, InnerCutoffListsTheNearNeighborsFirst) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  const double cutoff = 1.0, inner_cutoff = 0.75, skin = 0.2, L = 6.0;
  auto box = make_box<3, Real>(L, {true, true, false});
  auto sparse = make_particles<3, Real, Exec>(random_positions<3>(500, -1.0, L, 21));
  auto dense = make_particles<3, Real, Exec>(random_positions<3>(500, -1.0, 2.5, 22));
  for (auto kind : {NeighborListKind::full, NeighborListKind::half}) {
    NeighborList<3, Real, Exec> plain(Real(cutoff), Real(skin), kind, BodyExclusion::none, 2);
    NeighborList<3, Real, Exec> split(Real(cutoff), Real(skin), kind, BodyExclusion::none, 2);
    split.set_inner_cutoff(Real(inner_cutoff));
    int sparse_capacity = 0;
    for (const auto* p : {&sparse, &dense}) {
      plain.build(*p, box);
      split.build(*p, box);
      EXPECT_EQ(listed_pairs(plain), listed_pairs(split));
      auto data = split.views();
      auto particle = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), data.row_particle);
      auto count = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), data.count);
      auto inner = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), data.inner);
      auto index = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), data.index);
      auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p->x);
      const double reach = inner_cutoff + skin, ambiguity = 64 * testing::eps<Real>() * (reach + L);
      long long inner_total = 0;
      for (std::size_t r = 0; r < count.extent(0); ++r) {
        const int i = particle(r);
        ASSERT_LE(inner(r), count(r));
        inner_total += inner(r);
        for (int k = 0; k < count(r); ++k) {
          const int j = index(r, k);
          double r2 = 0;
          for (int d = 0; d < 3; ++d) {
            double dx = double(x(i, d)) - double(x(j, d));
            if (d < 2) dx -= L * std::floor(dx / L + 0.5);
            r2 += dx * dx;
          }
          const double dist = std::sqrt(r2);
          if (std::abs(dist - reach) <= ambiguity) continue;
          EXPECT_EQ(k < inner(r), dist < reach) << "row of " << i << ", entry " << k << " at r = " << dist;
        }
      }
      EXPECT_GT(inner_total, 0);
      EXPECT_LT(inner_total, plain.num_entries());
      if (p == &sparse) sparse_capacity = split.capacity();
    }
    EXPECT_GT(split.capacity(), sparse_capacity);  // the dense build overflowed and was refilled
  }
}

TYPED_TEST(NeighborListTest, RejectsPeriodicBoxShorterThanTwiceTheReach) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  auto box = make_box<2, Real>(2.0, {true, true});
  auto p = make_particles<2, Real, Exec>(random_positions<2>(10, -1.0, 2.0, 15));
  NeighborList<2, Real, Exec> nl(Real(1.0), Real(0.2));
  try {
    nl.build(p, box);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("cutoff + skin"), std::string::npos) << e.what();
  }
  EXPECT_THROW((NeighborList<2, Real, Exec>(Real(0), Real(0.1))), std::invalid_argument);
  EXPECT_THROW((NeighborList<2, Real, Exec>(Real(1), Real(-0.1))), std::invalid_argument);
}

TYPED_TEST(NeighborListTest, RowsAreIdenticalOnEveryBackendAndThreadCount) {
  using Real = typename TypeParam::real;
  using Exec = typename TypeParam::exec;
  auto box = make_box<3, Real>(7.0, {true, true, true});
  const auto pos = random_positions<3>(1500, -1.0, 7.0, 16);
  auto p = make_particles<3, Real, Exec>(pos);
  auto q = make_particles<3, Real, Kokkos::DefaultHostExecutionSpace>(pos);
  NeighborList<3, Real, Exec> a(Real(1.0), Real(0.3));
  NeighborList<3, Real, Kokkos::DefaultHostExecutionSpace> b(Real(1.0), Real(0.3));
  a.build(p, box);
  b.build(q, box);
  auto ca = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), a.views().count);
  auto ia = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), a.views().index);
  auto cb = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), b.views().count);
  auto ib = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), b.views().index);
  for (int i = 0; i < 1500; ++i) {
    ASSERT_EQ(ca(i), cb(i));
    for (int k = 0; k < ca(i); ++k) ASSERT_EQ(ia(i, k), ib(i, k)) << "row " << i << " entry " << k;
  }
}

}  // namespace
}  // namespace mesoflow
