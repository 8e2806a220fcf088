// particle_sort.hpp — reorders particles in memory into the slot order of a cell list, so that
// particles close in space are close in memory and a pair loop's neighbours j share cache lines
// (LAMMPS' atom sorting, `atom_modify sort`). A pure permutation: the same particles, positions,
// velocities and forces, in another order; neighbor lists and anything else indexed by particle
// must be rebuilt or permuted with it (pass such per-particle views as `extra`).
//
// The order is cells.cell_particles() of the cell list's last build: slot s receives the particle
// that occupied slot s then. Any permutation is valid, so a cell list built from slightly older
// positions only costs a little locality. Deterministic: cells list their particles by index.
//
// Indices that name particles (bond ends, a body's vertex → particle map) are renumbered, not
// permuted: invert_permutation() turns the order into new_index(old) = new slot, and
// renumber_particle_indices() maps every entry of an index view through it.
#pragma once

#include "kernel_launch.hpp"
#include "cell_list.hpp"
#include "kokkos_compat.hpp"
#include "particles.hpp"

#include <stdexcept>
#include <string>

namespace mesoflow {

namespace sort_detail {

// a ← a(order), through a scratch copy; rank 1 or rank 2 (n × D) views.
template <class View, class OrderView>
void permute(const View& a, const OrderView& order) {
  using exec = typename View::execution_space;
  const int n = int(a.extent(0));
  View scratch(Kokkos::ViewAllocateWithoutInitializing(a.label() + "::sort_scratch"), a.layout());
  if constexpr (View::rank == 1) {
    mesoflow::launch::parallel_for(
        "mesoflow::particle_sort::gather", Kokkos::RangePolicy<exec>(0, n),
        KOKKOS_LAMBDA(int s) { scratch(s) = a(order(s)); });
    mesoflow::launch::parallel_for(
        "mesoflow::particle_sort::copy_back", Kokkos::RangePolicy<exec>(0, n),
        KOKKOS_LAMBDA(int s) { a(s) = scratch(s); });
  } else {
    const int cols = int(a.extent(1));
    mesoflow::launch::parallel_for(
        "mesoflow::particle_sort::gather", Kokkos::RangePolicy<exec>(0, n), KOKKOS_LAMBDA(int s) {
          for (int d = 0; d < cols; ++d) scratch(s, d) = a(order(s), d);
        });
    mesoflow::launch::parallel_for(
        "mesoflow::particle_sort::copy_back", Kokkos::RangePolicy<exec>(0, n), KOKKOS_LAMBDA(int s) {
          for (int d = 0; d < cols; ++d) a(s, d) = scratch(s, d);
        });
  }
}

}  // namespace sort_detail

// Permutes x, v, f, mass, body, type of p, and each view in `extra` (extent(0) = p.size()), into
// the slot order of `cells`. The views keep their allocations (no handle held elsewhere goes stale).
template <int D, class Real, class ExecSpace, class... Extra>
void sort_particles_by_cell(const Particles<D, Real, ExecSpace>& p, const CellList<D, Real, ExecSpace>& cells,
                            const Extra&... extra) {
  const int n = int(p.size());
  if (cells.num_particles() != n)
    throw std::invalid_argument("sort_particles_by_cell: the cell list holds " + std::to_string(cells.num_particles()) +
                                " particles, the particle set " + std::to_string(n));
  const auto order = cells.cell_particles();
  sort_detail::permute(p.x, order);
  sort_detail::permute(p.v, order);
  sort_detail::permute(p.f, order);
  sort_detail::permute(p.mass, order);
  sort_detail::permute(p.body, order);
  sort_detail::permute(p.type, order);
  (sort_detail::permute(extra, order), ...);
}

// new_index(order(s)) ← s: for a sort by `order` (cell_particles() of the cell list it used, read
// before that list is rebuilt), the slot where the particle formerly at index i now lives.
template <class OrderView, class IndexView>
void invert_permutation(const OrderView& order, const IndexView& new_index) {
  using exec = typename IndexView::execution_space;
  if (order.extent(0) != new_index.extent(0))
    throw std::invalid_argument("invert_permutation: a permutation of " + std::to_string(order.extent(0)) +
                                " into a view of " + std::to_string(new_index.extent(0)));
  mesoflow::launch::parallel_for(
      "mesoflow::particle_sort::invert_permutation", Kokkos::RangePolicy<exec>(0, int(order.extent(0))),
      KOKKOS_LAMBDA(int s) { new_index(order(s)) = s; });
}

// a(...) ← new_index(a(...)) for every entry of a rank-1 or rank-2 view of particle indices.
template <class IndexView, class NewIndexView>
void renumber_particle_indices(const IndexView& a, const NewIndexView& new_index) {
  using exec = typename IndexView::execution_space;
  const int n = int(a.extent(0));
  if constexpr (IndexView::rank == 1) {
    mesoflow::launch::parallel_for(
        "mesoflow::particle_sort::renumber", Kokkos::RangePolicy<exec>(0, n),
        KOKKOS_LAMBDA(int r) { a(r) = new_index(a(r)); });
  } else {
    const int cols = int(a.extent(1));
    mesoflow::launch::parallel_for(
        "mesoflow::particle_sort::renumber", Kokkos::RangePolicy<exec>(0, n), KOKKOS_LAMBDA(int r) {
          for (int c = 0; c < cols; ++c) a(r, c) = new_index(a(r, c));
        });
  }
}

}  // namespace mesoflow
