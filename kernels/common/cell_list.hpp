// cell_list.hpp — binning of particles into a regular grid of cells, stored as CSR.
//
// Built as a counting sort (count → exclusive scan → fill), then each cell's members are sorted by
// particle index, so the order — and every floating-point sum that later follows it — does not
// depend on thread scheduling. Nothing has a fixed capacity: arrays grow when the particle or cell
// count does, and are reused otherwise (no allocation in a time-step loop at fixed size).
#pragma once

#include "kernel_launch.hpp"
#include "box.hpp"
#include "kokkos_compat.hpp"
#include "vec.hpp"

#include <stdexcept>
#include <string>

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
    auto counts = counts_;
    auto offset = cell_offset_;
    auto slots = cell_particles_;
    auto xb = x_binned_;

    mesoflow::launch::parallel_for(
        "mesoflow::cell_list::clear", Kokkos::RangePolicy<ExecSpace>(0, ncell),
        KOKKOS_LAMBDA(int k) { counts(k) = 0; });
    mesoflow::launch::parallel_for(
        "mesoflow::cell_list::count", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) {
          Vec<D, Real> xi = Vec<D, Real>::load(x, i);
          box.wrap(xi);
          int c[D];
          for (int d = 0; d < D; ++d) c[d] = grid.coordinate(xi[d], d);
          const int k = grid.index(c);
          cell_of(i) = k;
          Kokkos::atomic_add(&counts(k), 1);
        });
    mesoflow::launch::parallel_scan(
        "mesoflow::cell_list::offsets", Kokkos::RangePolicy<ExecSpace>(0, ncell + 1),
        KOKKOS_LAMBDA(int k, int& partial, bool final) {
          const int c = k < ncell ? counts(k) : 0;
          if (final) {
            offset(k) = partial;
            if (k < ncell) counts(k) = 0;  // reused below as the fill cursor
          }
          partial += c;
        });
    // Each particle writes its index and its folded position straight into its slot (one
    // scattered write instead of a gather of D separate SoA components later).
    mesoflow::launch::parallel_for(
        "mesoflow::cell_list::fill", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) {
          const int k = cell_of(i);
          const int s = offset(k) + Kokkos::atomic_fetch_add(&counts(k), 1);
          slots(s) = i;
          Vec<D, Real> xi = Vec<D, Real>::load(x, i);
          box.wrap(xi);
          xi.store(xb, s);
        });
    // Atomics leave each cell in thread-dependent order: sort it by particle index, moving the
    // positions along (insertion sort: cells hold few particles).
    mesoflow::launch::parallel_for(
        "mesoflow::cell_list::order", Kokkos::RangePolicy<ExecSpace>(0, ncell), KOKKOS_LAMBDA(int k) {
          const int begin = offset(k), end = offset(k + 1);
          for (int s = begin + 1; s < end; ++s) {
            const int key = slots(s);
            if (slots(s - 1) < key) continue;
            Real key_x[D];
            for (int d = 0; d < D; ++d) key_x[d] = xb(s, d);
            int t = s - 1;
            while (t >= begin && slots(t) > key) {
              slots(t + 1) = slots(t);
              for (int d = 0; d < D; ++d) xb(t + 1, d) = xb(t, d);
              --t;
            }
            slots(t + 1) = key;
            for (int d = 0; d < D; ++d) xb(t + 1, d) = key_x[d];
          }
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
    if (int(counts_.extent(0)) != ncell) {
      counts_ = int_view(Kokkos::ViewAllocateWithoutInitializing("mesoflow::cell_list::counts"), ncell);
      cell_offset_ = int_view(Kokkos::ViewAllocateWithoutInitializing("mesoflow::cell_list::offset"), ncell + 1);
    }
  }

  CellGrid<D, Real> grid_{};
  int num_particles_ = 0;
  int_view cell_of_, counts_, cell_offset_, cell_particles_;
  binned_positions x_binned_;
};

}  // namespace mesoflow
