// cell_list.hpp — binning of particles into a regular grid of cells, stored as CSR.
//
// Built with Kokkos::BinSort (issue 26 item 5: Kokkos' own sort on every backend) on the unique key
// cell · n + i with one exact bin per cell (ExactBinOp, segment_order.hpp: an integer quotient;
// Kokkos' BinOp1D bins by a floating-point product that can round the key k·n down into cell
// k − 1), sorted within bins: by cell, then by particle index, so the order — and every
// floating-point sum that later follows it — does not depend on thread scheduling or backend. Nothing has a fixed capacity: arrays and the sorter are
// rebuilt when the particle or cell count changes, and reused otherwise (no allocation in a
// time-step loop at fixed size).
#pragma once

#include "kernel_launch.hpp"
#include "box.hpp"
#include "kokkos_compat.hpp"
#include "vec.hpp"

#include "segment_order.hpp"

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace mesoflow {

// Regular grid over a box: n[d] cells of width ≥ the requested minimum along each axis.
template <int D, class Real>
struct CellGrid {
  int n[D];
  Real lo[D];
  Real inv_width[D];
  int total;

  CellGrid() = default;
  CellGrid(const Box<D, Real>& box, Real min_width) {
    if (!(min_width > Real(0)))
      throw std::invalid_argument("cell list: cell width must be > 0, got " + std::to_string(min_width));
    total = 1;
    for (int d = 0; d < D; ++d) {
      const double cells = double(box.length[d]) / double(min_width);
      n[d] = cells < 1.0 ? 1 : (cells > 1.0e6 ? 1000000 : int(cells));
      lo[d] = box.lo[d];
      inv_width[d] = Real(n[d]) / box.length[d];
      total *= n[d];
    }
  }

  // Cell coordinate of a position along axis d; positions outside a bounded axis are clamped
  // into the first or last cell (clamping never separates two points by more than one cell
  // more than their true separation does, so stencil searches stay exact).
  KOKKOS_INLINE_FUNCTION int coordinate(Real x, int d) const {
    int c = int(kmath::floor((x - lo[d]) * inv_width[d]));
    c = c < 0 ? 0 : c;
    return c >= n[d] ? n[d] - 1 : c;
  }
  KOKKOS_INLINE_FUNCTION int index(const int (&c)[D]) const {
    int k = c[D - 1];
    for (int d = D - 2; d >= 0; --d) k = k * n[d] + c[d];
    return k;
  }
  KOKKOS_INLINE_FUNCTION void coordinates(int k, int (&c)[D]) const {
    for (int d = 0; d < D; ++d) {
      c[d] = k % n[d];
      k /= n[d];
    }
  }
};

template <int D, class Real, class ExecSpace>
class CellList {
 public:
  using int_view = Kokkos::View<int*, ExecSpace>;
  // Positions in binned order, folded into the box on periodic axes. Array-of-structures on
  // purpose: a stencil search streams through consecutive slots and wants x, y, z together.
  using binned_positions = Kokkos::View<Real* [D], Kokkos::LayoutRight, ExecSpace>;

  // Bins the n rows of x. Afterwards particle cell_particles(s) occupies slot s; the slots of
  // cell k are [cell_offset(k), cell_offset(k+1)).
  template <class PositionView>
  void build(const PositionView& x, const Box<D, Real>& box, Real min_width) {
    grid_ = CellGrid<D, Real>(box, min_width);
    const int n = int(x.extent(0));
    const int ncell = grid_.total;
    ensure_capacity(n, ncell);

    auto grid = grid_;
    auto cell_of = cell_of_;
    auto offset = cell_offset_;
    auto slots = cell_particles_;
    auto xb = x_binned_;
    mesoflow::launch::parallel_for(
        "mesoflow::cell_list::cells", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) {
          Vec<D, Real> xi = Vec<D, Real>::load(x, i);
          box.wrap(xi);
          int c[D];
          for (int d = 0; d < D; ++d) c[d] = grid.coordinate(xi[d], d);
          cell_of(i) = grid.index(c);
        });
    if (n == 0) {
      Kokkos::deep_copy(cell_offset_, 0);
      num_particles_ = 0;
      return;
    }
    // Keys cell · n + i; BinSort with one exact bin per cell (ExactBinOp), sorted within bins.
    const auto keys = keys_;
    const std::int64_t stride = n;
    mesoflow::launch::parallel_for(
        "mesoflow::cell_list::keys", Kokkos::RangePolicy<ExecSpace>(0, n),
        KOKKOS_LAMBDA(int i) { keys(i) = std::int64_t(cell_of(i)) * stride + i; });
    if (!sorter_ || sorter_rows_ != n || sorter_cells_ != ncell) {  // the first build, or another size
      sorter_.emplace(keys_, 0, n, ExactBinOp<std::int64_t>{ncell, stride}, true);
      sorter_rows_ = n;
      sorter_cells_ = ncell;
    }
    zero_bin_counts<ExecSpace>(*sorter_);  // create_permute_vector() adds to the last counts
    sorter_->create_permute_vector();
    const auto order = sorter_->get_permute_vector();
    const auto bin_offsets = sorter_->get_bin_offsets();
    mesoflow::launch::parallel_for(
        "mesoflow::cell_list::offsets", Kokkos::RangePolicy<ExecSpace>(0, ncell + 1),
        KOKKOS_LAMBDA(int k) { offset(k) = k < ncell ? int(bin_offsets(k)) : n; });
    // Each slot gathers its particle's index and folded position.
    mesoflow::launch::parallel_for(
        "mesoflow::cell_list::fill", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int s) {
          const int i = int(order(s));
          slots(s) = i;
          Vec<D, Real> xi = Vec<D, Real>::load(x, i);
          box.wrap(xi);
          xi.store(xb, s);
        });
    num_particles_ = n;
  }

  const CellGrid<D, Real>& grid() const { return grid_; }
  int num_particles() const { return num_particles_; }
  int_view cell_offset() const { return cell_offset_; }
  int_view cell_particles() const { return cell_particles_; }
  int_view cell_of() const { return cell_of_; }
  binned_positions binned_x() const { return x_binned_; }

 private:
  void ensure_capacity(int n, int ncell) {
    if (int(cell_of_.extent(0)) != n) {
      cell_of_ = int_view(Kokkos::ViewAllocateWithoutInitializing("mesoflow::cell_list::cell_of"), n);
      cell_particles_ = int_view(Kokkos::ViewAllocateWithoutInitializing("mesoflow::cell_list::slots"), n);
      x_binned_ = binned_positions(Kokkos::ViewAllocateWithoutInitializing("mesoflow::cell_list::x"), n);
    }
    if (int(keys_.extent(0)) != n)
      keys_ = key_view(Kokkos::ViewAllocateWithoutInitializing("mesoflow::cell_list::keys"), std::size_t(n));
    if (int(cell_offset_.extent(0)) != ncell + 1)
      cell_offset_ = int_view(Kokkos::ViewAllocateWithoutInitializing("mesoflow::cell_list::offset"), ncell + 1);
  }

  CellGrid<D, Real> grid_{};
  int num_particles_ = 0;
  int_view cell_of_, cell_offset_, cell_particles_;
  binned_positions x_binned_;
  using key_view = Kokkos::View<std::int64_t*, ExecSpace>;
  key_view keys_;  // cell · n + i
  std::optional<Kokkos::BinSort<key_view, ExactBinOp<std::int64_t>>> sorter_;
  int sorter_rows_ = -1, sorter_cells_ = -1;
};

}  // namespace mesoflow
