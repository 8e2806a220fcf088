// neighbor_list.hpp — Verlet neighbor lists with a skin, built from a cell list.
//
// A list holds, for every particle i, the particles j with |x_i − x_j| < cutoff + skin (minimum
// image on periodic axes). Full lists hold every such j; half lists hold each pair once, in the row
// of the particle whose cell comes first (LAMMPS' half/bin/newton stencil: only the cells on one
// side of a particle's own cell are searched, which halves the candidates a build tests). Pairs within one body (Particles::body ≥ 0 and equal) can be excluded: the vertices of a
// deformable polygon interact through its own bonded terms, never as contacts.
//
// `update()` rebuilds only when some particle has moved more than skin/2 since the last build
// (then no pair can have crossed from beyond cutoff + skin to within cutoff), or when the particle
// count or the box changed. Storage is an (n × capacity) array; the capacity grows automatically
// when a build finds more neighbors than fit, so nothing has a fixed limit.
//
// The order of j in each row follows the cell order and, within a cell, particle index: the list —
// and every force summed over it — is identical for any thread count.
//
// Optionally (set_inner_cutoff) each row lists first the neighbors within inner cutoff + skin, and
// inner_count(row) says how many: a kernel with a shorter range (the MDPD density, r_B < r_A)
// then reads only the front of each row. The split costs one comparison per candidate in the build.
#pragma once

#include "kernel_launch.hpp"
#include "box.hpp"
#include "cell_list.hpp"
#include "kokkos_compat.hpp"
#include "particles.hpp"
#include "reductions.hpp"

#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace mesoflow {

enum class NeighborListKind { full, half };
enum class BodyExclusion { none, same_body };

// What a kernel needs from a neighbor list, copied by value into lambdas: pointers into the list's
// Views and the index array's outer stride (48 bytes; kernels/common/kernel_launch.hpp), valid until the
// list's next build. Rows are stored in cell order (row r holds the neighbors of particle
// particle(r)), so a build writes them sequentially whatever the order of the particle arrays; loop
// over rows, not particles.
template <class ExecSpace>
struct NeighborData {
  // The index array's layout: the execution space's default (row-major on host backends, so a row's
  // neighbors are contiguous; column-major on GPUs, so a warp's rows are). The unit stride stays a
  // compile-time constant; the other one is `stride`.
  static constexpr bool row_major =
      std::is_same<typename Kokkos::View<int**, ExecSpace>::array_layout, Kokkos::LayoutRight>::value;
  const int* row_particle;
  const int* count;
  const int* index;  // neighbor k of row r: index[r * stride + k] (row-major) or index[r + k * stride]
  const int* inner;  // neighbors within the inner cutoff + skin (front of the row)
  long stride;
  int rows;
  KOKKOS_INLINE_FUNCTION int particle(int row) const { return row_particle[row]; }
  KOKKOS_INLINE_FUNCTION int num_neighbors(int row) const { return count[row]; }
  KOKKOS_INLINE_FUNCTION int num_inner_neighbors(int row) const { return inner[row]; }
  KOKKOS_INLINE_FUNCTION int neighbor(int row, int k) const {
    return row_major ? index[row * stride + k] : index[row + k * stride];
  }
  int num_rows() const { return rows; }
};

// The list's Views themselves, for host-side inspection (tests, output): not for kernels.
template <class ExecSpace>
struct NeighborViews {
  Kokkos::View<int*, ExecSpace> row_particle;
  Kokkos::View<int*, ExecSpace> count;
  Kokkos::View<int**, ExecSpace> index;
  Kokkos::View<int*, ExecSpace> inner;
};

template <int D, class Real, class ExecSpace>
class NeighborList {
 public:
  static constexpr int max_cells_per_reach = 4;
  using vector_view = typename Particles<D, Real, ExecSpace>::vector_view;
  using int_view = Kokkos::View<int*, ExecSpace>;

  // `cells_per_reach`: cells are (cutoff + skin)/cells_per_reach wide. 2 (LAMMPS' bin size)
  // halves the candidate pairs tested but visits 25 rows of cells per particle instead of 9; on
  // the CI machine 1 builds faster (benchmarks/bench_common.cpp, BM_NeighborListBuild).
  NeighborList(Real cutoff, Real skin, NeighborListKind kind = NeighborListKind::full,
               BodyExclusion exclusion = BodyExclusion::none, int cells_per_reach = 1)
      : cutoff_(cutoff), skin_(skin), kind_(kind), exclusion_(exclusion), cells_per_reach_(cells_per_reach) {
    if (cells_per_reach < 1 || cells_per_reach > max_cells_per_reach)
      throw std::invalid_argument("neighbor list: cells_per_reach must be in [1, 4], got " +
                                  std::to_string(cells_per_reach));
    if (!(cutoff > Real(0)))
      throw std::invalid_argument("neighbor list: cutoff must be > 0, got " + std::to_string(cutoff));
    if (!(skin >= Real(0)))
      throw std::invalid_argument("neighbor list: skin must be >= 0, got " + std::to_string(skin));
  }

  // Rows list the neighbors within `inner_cutoff` + skin first (0 < inner_cutoff ≤ cutoff); takes
  // effect at the next build.
  void set_inner_cutoff(Real inner_cutoff) {
    if (!(inner_cutoff > Real(0) && inner_cutoff <= cutoff_))
      throw std::invalid_argument("neighbor list: inner cutoff must be in (0, cutoff = " + std::to_string(cutoff_) +
                                  "], got " + std::to_string(inner_cutoff));
    inner_cutoff_ = inner_cutoff;
  }

  // Rebuilds if needed (see file comment); returns whether it did.
  bool update(const Particles<D, Real, ExecSpace>& p, const Box<D, Real>& box) {
    if (!needs_rebuild(p.x, box)) return false;
    build(p, box);
    return true;
  }

  bool needs_rebuild(const vector_view& x, const Box<D, Real>& box) const {
    if (num_builds_ == 0 || x.extent(0) != x_ref_.extent(0) || !same_box(box)) return true;
    return max_displacement<D, Real, ExecSpace>(x, x_ref_, box) > Real(0.5) * skin_;
  }

  // Unconditional rebuild from the current positions.
  void build(const Particles<D, Real, ExecSpace>& p, const Box<D, Real>& box) {
    const Real reach = cutoff_ + skin_;
    for (int d = 0; d < D; ++d)
      if (box.periodic[d] && box.length[d] < Real(2) * reach)
        throw std::invalid_argument("neighbor list: periodic box length " + std::to_string(box.length[d]) +
                                    " along axis " + std::to_string(d) +
                                    " must be at least 2 × (cutoff + skin) = " + std::to_string(2 * reach));
    const int n = int(p.size());
    cells_.build(p.x, box, reach / Real(cells_per_reach_));
    if (int(count_.extent(0)) != n) {
      count_ = int_view("mesoflow::neighbor_list::count", n);
      inner_ = int_view("mesoflow::neighbor_list::inner_count", n);
      x_ref_ = vector_view(Kokkos::ViewAllocateWithoutInitializing("mesoflow::neighbor_list::x_ref"), n);
      if (capacity_ == 0) capacity_ = initial_capacity(box, n);
      index_ = Kokkos::View<int**, ExecSpace>(
          Kokkos::ViewAllocateWithoutInitializing("mesoflow::neighbor_list::index"), n, capacity_ + 1);
    }
    int needed = fill(p.body, box);
    if (needed > capacity_) {
      capacity_ = needed + needed / 8 + 1;
      index_ = Kokkos::View<int**, ExecSpace>(
          Kokkos::ViewAllocateWithoutInitializing("mesoflow::neighbor_list::index"), n, capacity_ + 1);
      needed = fill(p.body, box);
    }
    max_neighbors_ = needed;
    auto x = p.x;
    auto x_ref = x_ref_;
    mesoflow::launch::parallel_for(
        "mesoflow::neighbor_list::remember_positions", Kokkos::RangePolicy<ExecSpace>(0, n),
        KOKKOS_LAMBDA(int i) {
          for (int d = 0; d < D; ++d) x_ref(i, d) = x(i, d);
        });
    box_ = box;
    ++num_builds_;
  }

  NeighborViews<ExecSpace> views() const { return {cells_.cell_particles(), count_, index_, inner_}; }
  NeighborData<ExecSpace> data() const {
    static_assert(std::is_same<typename decltype(index_)::array_layout,
                               typename Kokkos::View<int**, ExecSpace>::array_layout>::value);
    return {cells_.cell_particles().data(), count_.data(), index_.data(), inner_.data(),
            long(NeighborData<ExecSpace>::row_major ? index_.stride(0) : index_.stride(1)), int(count_.extent(0))};
  }
  NeighborListKind kind() const { return kind_; }
  BodyExclusion exclusion() const { return exclusion_; }
  Real cutoff() const { return cutoff_; }
  Real inner_cutoff() const { return inner_cutoff_; }
  Real skin() const { return skin_; }
  int num_builds() const { return num_builds_; }
  int max_neighbors() const { return max_neighbors_; }
  int capacity() const { return capacity_; }
  const CellList<D, Real, ExecSpace>& cells() const { return cells_; }
  // Positions at the last build (the reference for the skin criterion; saved in checkpoints so a
  // restart rebuilds exactly the same list).
  vector_view reference_positions() const { return x_ref_; }

  // Total number of stored (i, j) entries.
  long long num_entries() const {
    auto count = count_;
    long long total = 0;
    mesoflow::launch::parallel_reduce(
        "mesoflow::neighbor_list::num_entries", Kokkos::RangePolicy<ExecSpace>(0, count.extent(0)),
        KOKKOS_LAMBDA(int i, long long& acc) { acc += count(i); }, total);
    return total;
  }

 private:
  bool same_box(const Box<D, Real>& b) const {
    for (int d = 0; d < D; ++d)
      if (b.lo[d] != box_.lo[d] || b.length[d] != box_.length[d] || b.periodic[d] != box_.periodic[d])
        return false;
    return true;
  }

  // Expected neighbors within the reach at the mean density, with headroom for fluctuations.
  int initial_capacity(const Box<D, Real>& box, int n) const {
    const double reach = double(cutoff_ + skin_);
    const double ball = D == 2 ? 3.14159265358979 * reach * reach : 4.18879020478639 * reach * reach * reach;
    const double expected = n * ball / double(box.volume());
    const double c = 1.5 * expected + 16.0;
    return int(c < n ? c : n);
  }

  int fill(const int_view& body, const Box<D, Real>& box) {
    const bool half = kind_ == NeighborListKind::half;
    if (exclusion_ == BodyExclusion::same_body) {
      gather_body(body);
      return half ? fill<true, true>(box) : fill<false, true>(box);
    }
    return half ? fill<true, false>(box) : fill<false, false>(box);
  }

 public:
  // gather_body and fill<Half, ExcludeBody> are implementation details, public only because nvcc
  // rejects a KOKKOS_LAMBDA in a private or protected member function.

  // Body ids in binned order, so the exclusion test streams like the positions do.
  void gather_body(const int_view& body) {
    const int n = cells_.num_particles();
    if (int(body_binned_.extent(0)) != n)
      body_binned_ = int_view(Kokkos::ViewAllocateWithoutInitializing("mesoflow::neighbor_list::body"), n);
    const auto slots = cells_.cell_particles();
    const auto binned = body_binned_;
    mesoflow::launch::parallel_for(
        "mesoflow::neighbor_list::gather_body", Kokkos::RangePolicy<ExecSpace>(0, n),
        KOKKOS_LAMBDA(int s) { binned(s) = body(slots(s)); });
  }

  // Writes the rows (up to the capacity) and returns the longest row found. The inner loop is
  // branch-free: every candidate is written at the row's next free slot at each end — neighbors
  // within the inner reach fill the row from the front, the others from the back (column
  // `capacity`) — and kept only if it qualifies; a row that would overflow only writes slots that
  // the refill with a larger capacity rewrites. The back part is then moved behind the front part.
  //
  // Half lists search the half stencil: cell offsets δ (in the cell-list row order, axis D−1
  // first) that are lexicographically positive, and in the particle's own cell only the slots
  // after its own. A pair (i, j) is met from exactly one end, since j sees i at −δ.
  template <bool Half, bool ExcludeBody>
  int fill(const Box<D, Real>& box) {
    const auto grid = cells_.grid();
    const auto offset = cells_.cell_offset();
    const auto slots = cells_.cell_particles();
    const auto xb = cells_.binned_x();
    const auto body = body_binned_;
    const auto count = count_;
    const auto inner_count = inner_;
    const auto index = index_;
    const int capacity = capacity_;
    const int m = cells_per_reach_;
    const Real reach2 = (cutoff_ + skin_) * (cutoff_ + skin_);
    const Real inner_reach = (inner_cutoff_ > Real(0) ? inner_cutoff_ : cutoff_) + skin_;
    const Real inner2 = inner_reach * inner_reach;
    // A cell is skipped only when clearly out of reach, so round-off in the gap can never drop
    // a pair that the exact distance test would keep.
    const Real skip_gap2 = reach2 * (Real(1) + Real(64) * std::numeric_limits<Real>::epsilon());
    const int n = cells_.num_particles();
    int needed = 0;
    mesoflow::launch::parallel_reduce(
        "mesoflow::neighbor_list::fill", Kokkos::RangePolicy<ExecSpace>(0, n),
        KOKKOS_LAMBDA(int s, int& longest) {
          const int body_i = ExcludeBody ? body(s) : -1;
          Real xi[D], to_lower[D], to_upper[D], width[D];
          int ci[D];
          bool in_own_cell = true;  // false for a particle clamped in from beyond a wall
          for (int d = 0; d < D; ++d) {
            xi[d] = xb(s, d);
            ci[d] = grid.coordinate(xi[d], d);
            width[d] = Real(1) / grid.inv_width[d];
            to_lower[d] = xi[d] - (grid.lo[d] + Real(ci[d]) * width[d]);
            to_upper[d] = width[d] - to_lower[d];
            in_own_cell = in_own_cell && to_lower[d] >= Real(0) && to_upper[d] >= Real(0);
          }
          // Squared distance along axis d from x_i to the cells `step` away (0 when unknown).
          auto axis_gap2 = [&](int d, int step) {
            if (step == 0 || !in_own_cell) return Real(0);
            const Real g = (step < 0 ? to_lower[d] : to_upper[d]) + Real((step < 0 ? -step : step) - 1) * width[d];
            return g * g;
          };
          int front = 0, back = capacity;  // next free slot at each end of the row
          // Rows of cells along axis 0 are contiguous in the CSR order, so each row within reach
          // is one run of slots (two where it wraps around a periodic boundary).
          int row_step[D];
          for (int d = 1; d < D; ++d) row_step[d] = Half ? 0 : -m;
          for (;;) {
            Real row_gap2 = 0;
            int row_cell = 0;
            bool inside = true;
            bool own_row = true;  // the row through the particle's own cell
            Real shifted[D];
            shifted[0] = xi[0];
            for (int d = D - 1; d >= 1; --d) {
              row_gap2 += axis_gap2(d, row_step[d]);
              own_row = own_row && row_step[d] == 0;
              int c = ci[d] + row_step[d];
              shifted[d] = xi[d];
              if (c < 0 || c >= grid.n[d]) {
                if (!box.periodic[d]) inside = false;
                else if (c < 0) { c += grid.n[d]; shifted[d] += box.length[d]; }
                else { c -= grid.n[d]; shifted[d] -= box.length[d]; }
              }
              row_cell = row_cell * grid.n[d] + c;
            }
            if (inside && row_gap2 < skip_gap2) {
              int first = Half && own_row ? 0 : -m, last = m;
              while (first < 0 && row_gap2 + axis_gap2(0, first) >= skip_gap2) ++first;
              while (last > 0 && row_gap2 + axis_gap2(0, last) >= skip_gap2) --last;
              int c_begin = ci[0] + first, c_end = ci[0] + last;  // inclusive, unwrapped
              if (!box.periodic[0]) {
                c_begin = c_begin < 0 ? 0 : c_begin;
                c_end = c_end >= grid.n[0] ? grid.n[0] - 1 : c_end;
              }
              for (int c = c_begin; c <= c_end;) {
                int wrapped = c;
                Real shift = 0;
                if (c < 0) { wrapped += grid.n[0]; shift = box.length[0]; }
                else if (c >= grid.n[0]) { wrapped -= grid.n[0]; shift = -box.length[0]; }
                const int run_cells = (c_end - c < grid.n[0] - 1 - wrapped ? c_end - c : grid.n[0] - 1 - wrapped) + 1;
                const int k = row_cell * grid.n[0] + wrapped;
                const int t_end = offset(k + run_cells);
                shifted[0] = xi[0] + shift;
                // The half stencil's own cell: only the slots after s.
                const int t_begin = Half && own_row && c == ci[0] ? s + 1 : offset(k);
                for (int t = t_begin; t < t_end; ++t) {
                  Real r2 = 0;
                  for (int d = 0; d < D; ++d) {
                    const Real dx = shifted[d] - xb(t, d);
                    r2 += dx * dx;
                  }
                  const int j = slots(t);
                  bool keep = (r2 < reach2) & (t != s);
                  if (ExcludeBody) keep &= (body_i < 0) | (body(t) != body_i);
                  const bool near = r2 < inner2;
                  index(s, front < capacity ? front : capacity) = j;
                  index(s, back > 0 ? back : 0) = j;
                  front += keep & near;
                  back -= keep & !near;
                }
                c += run_cells;
              }
            }
            int d = 1;  // next row, axis 1 fastest
            while (d < D && ++row_step[d] > m) row_step[d++] = -m;
            if (d == D) break;
          }
          const int outer = capacity - back;
          const int found = front + outer;
          if (found <= capacity)
            for (int q = 0; q < outer; ++q) index(s, front + q) = index(s, back + 1 + q);
          count(s) = found;
          inner_count(s) = front;
          if (found > longest) longest = found;
        },
        Kokkos::Max<int>(needed));
    return needed;
  }

 private:
  Real cutoff_, skin_;
  Real inner_cutoff_ = 0;  // 0: no inner split (every neighbor counts as inner)
  NeighborListKind kind_;
  BodyExclusion exclusion_;
  int cells_per_reach_;
  CellList<D, Real, ExecSpace> cells_;
  int_view count_, inner_;
  Kokkos::View<int**, ExecSpace> index_;  // n × (capacity + 1): the last column is scratch
  int_view body_binned_;
  vector_view x_ref_;
  Box<D, Real> box_{};
  int capacity_ = 0;
  int max_neighbors_ = 0;
  int num_builds_ = 0;
};

}  // namespace mesoflow
