// Kokkos::BinSort where mesoflow sorts (issue 26 items 4–5): SegmentOrder (the deterministic-sum
// mode's grouping, kernels/common/segment_order.hpp) and the cell list's CSR (cell_list.hpp). Both
// must give exactly the stable order — by segment (cell), then by index — that a host counting sort
// gives, on every backend, and again when the sorter is reused or rebuilt at another size.
#include "kernels/common/cell_list.hpp"
#include "kernels/common/segment_order.hpp"
#include "../test_types.hpp"

#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace mesoflow {
namespace {

template <class T>
class SegmentOrderTest : public ::testing::Test {};
TYPED_TEST_SUITE(SegmentOrderTest, testing::BackendsAndPrecisions);

// Each segment's listed rows, skipped ones removed, are exactly the rows of that segment in
// increasing order; every row in [0, rows) is listed once.
template <class Exec>
void check_order(SegmentOrder<Exec>& order, const std::vector<int>& seg, int used) {
  const int rows = order.rows(), segments = order.segments();
  Kokkos::View<int*, Exec> seg_d("seg", std::size_t(rows));
  auto h = Kokkos::create_mirror_view(seg_d);
  for (int i = 0; i < rows; ++i) h(i) = seg[std::size_t(i)];
  Kokkos::deep_copy(seg_d, h);
  order.sort(used, seg_d);
  // Copy the handle's ranges and rows to the host through a kernel (the handle is device data).
  const auto v = order.view();
  Kokkos::View<int*, Exec> start("start", std::size_t(segments) + 1), listed("listed", std::size_t(rows));
  mesoflow::launch::parallel_for(
      "test::segment_ranges", Kokkos::RangePolicy<Exec>(0, segments + 1),
      KOKKOS_LAMBDA(int s) { start(s) = s < segments ? v.begin(s) : v.end(segments - 1); });
  mesoflow::launch::parallel_for(
      "test::segment_rows", Kokkos::RangePolicy<Exec>(0, rows), KOKKOS_LAMBDA(int q) { listed(q) = v.row(q); });
  const auto sh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), start);
  const auto lh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), listed);
  EXPECT_EQ(sh(0), 0);
  EXPECT_EQ(sh(segments), rows);
  std::vector<int> seen(std::size_t(rows), 0);
  for (int s = 0; s < segments; ++s) {
    std::vector<int> got, want;
    for (int q = sh(s); q < sh(s + 1); ++q) {
      const int i = lh(q);
      ++seen[std::size_t(i)];
      if (i < used && seg[std::size_t(i)] == s) got.push_back(i);
    }
    for (int i = 0; i < used; ++i)
      if (seg[std::size_t(i)] == s) want.push_back(i);
    EXPECT_EQ(got, want) << "segment " << s;
  }
  for (int i = 0; i < rows; ++i) EXPECT_EQ(seen[std::size_t(i)], 1) << "row " << i;
}

TYPED_TEST(SegmentOrderTest, SegmentsListTheirRowsInIndexOrder) {
  using Exec = typename TypeParam::exec;
  std::mt19937 gen(4);
  // Discs: 7 segments, most rows in none (−1), padding beyond `used`.
  const int rows = 5000, segments = 7;
  std::vector<int> seg(rows);
  std::uniform_int_distribution<int> pick(-20, segments - 1);
  for (auto& s : seg) s = std::max(-1, pick(gen));
  SegmentOrder<Exec> order(rows, segments);
  check_order(order, seg, 4600);
  // Reused with other data (the bin counts must start from zero again), every row used.
  for (auto& s : seg) s = std::uniform_int_distribution<int>(0, segments - 1)(gen);
  check_order(order, seg, rows);
  // Cells: many small segments.
  SegmentOrder<Exec> cells(3000, 400);
  std::vector<int> cell(3000);
  for (auto& c : cell) c = std::uniform_int_distribution<int>(0, 399)(gen);
  check_order(cells, cell, 2500);
  EXPECT_THROW(SegmentOrder<Exec>(0, 3), std::invalid_argument);
  EXPECT_THROW(SegmentOrder<Exec>(10, 0), std::invalid_argument);
  EXPECT_THROW(order.sort(rows + 1, Kokkos::View<int*, Exec>("s", std::size_t(rows + 1))), std::invalid_argument);
}

// The cell list's CSR equals a host counting sort (stable: by cell, then index) and its binned
// positions are the folded positions of the listed particles; rebuilt at another size too.
TYPED_TEST(SegmentOrderTest, CellListIsTheStableCountingSort) {
  using Exec = typename TypeParam::exec;
  using Real = typename TypeParam::real;
  std::mt19937 gen(9);
  // 784 particles in 16 cells: the size at which BinSort's own bin of the key k·n (a floating-point
  // product) rounds down into the previous cell, which a cell list taking BinSort's bin offsets for
  // its cell offsets got wrong (SphFlow.PlaneCouetteBetweenSlidingMorrisWalls found it).
  for (const int n : {2000, 3100, 784, 0}) {
    const bool small = n == 784;
    const Real lo[3] = {0, 0, 0}, len[3] = {Real(small ? 4 : 6), Real(small ? 4 : 5), Real(small ? 1 : 4)};
    const bool periodic[3] = {true, true, false};
    const Box<3, Real> box(lo, len, periodic);
    Kokkos::View<Real* [3], Kokkos::LayoutLeft, Exec> x("x", std::size_t(n));
    auto xh = Kokkos::create_mirror_view(x);
    std::uniform_real_distribution<double> u(-1.0, 7.0);  // outside the periodic box: folded
    for (int i = 0; i < n; ++i) {
      xh(i, 0) = Real(u(gen));
      xh(i, 1) = Real(u(gen) * 5.0 / 6.0);
      xh(i, 2) = Real(std::uniform_real_distribution<double>(0.0, small ? 1.0 : 4.0)(gen));
    }
    Kokkos::deep_copy(x, xh);
    CellList<3, Real, Exec> cells;
    cells.build(x, box, Real(n == 3100 ? 0.7 : 1.0));
    const auto& grid = cells.grid();
    if (small) ASSERT_EQ(grid.total, 16);
    const auto offset = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), cells.cell_offset());
    const auto slots = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), cells.cell_particles());
    const auto binned = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), cells.binned_x());
    const auto cell_of = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), cells.cell_of());
    std::vector<std::vector<int>> want(std::size_t(grid.total));
    for (int i = 0; i < n; ++i) want[std::size_t(cell_of(i))].push_back(i);
    int bad = 0;
    for (int k = 0; k < grid.total; ++k) {
      std::vector<int> got(slots.data() + offset(k), slots.data() + offset(k + 1));
      bad += got != want[std::size_t(k)];
    }
    EXPECT_EQ(bad, 0) << n << " particles";
    EXPECT_EQ(offset(grid.total), n);
    if (small) {
      // The key of particle 0 in cell k is k·n exactly: put it in every cell in turn.
      for (int k = 0; k < grid.total; ++k) {
        int c[3];
        grid.coordinates(k, c);
        xh(0, 0) = Real(c[0] + 0.5);
        xh(0, 1) = Real(c[1] + 0.5);
        xh(0, 2) = Real(0.5);
        Kokkos::deep_copy(x, xh);
        cells.build(x, box, Real(1.0));
        const auto off = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), cells.cell_offset());
        const auto sl = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), cells.cell_particles());
        EXPECT_EQ(sl(off(k)), 0) << "particle 0 is not first in its cell " << k;
      }
      continue;
    }
    int misplaced = 0;
    for (int s = 0; s < n; ++s) {
      Vec<3, Real> xi{{xh(slots(s), 0), xh(slots(s), 1), xh(slots(s), 2)}};
      box.wrap(xi);
      for (int d = 0; d < 3; ++d) misplaced += binned(s, d) != xi[d];
    }
    EXPECT_EQ(misplaced, 0);
  }
}

}  // namespace
}  // namespace mesoflow
