// packed_state.hpp — per-particle rows that the MDPD pair loops gather for every neighbor j,
// packed four to a row (LayoutRight, 32 bytes in double): position and many-body density in one
// row, velocity in another, pair forces in a third. A neighbor then costs one cache line per
// array instead of one per Cartesian component of the (n × D) LayoutLeft particle storage; the
// packing is an O(n) copy per step, against O(25 n) gathers in each pair loop (LAMMPS' KOKKOS
// package packs x the same way for its pair styles).
#pragma once

#include "../common/kernel_launch.hpp"
#include "kernels/common/particles.hpp"

namespace mesoflow::mdpd {

constexpr int packed_width = 4;
// Column of ρ̄ in the position rows (2D and 3D). An enumerator, not a constexpr int: Kokkos 3's View
// takes indices by reference, and nvcc has no device copy of a namespace-scope variable to refer to.
enum : int { rho_column = 3 };

template <class Real, class ExecSpace>
using PackedRows = Kokkos::View<Real* [packed_width], Kokkos::LayoutRight, ExecSpace>;

// Read access to PackedRows through a pointer (8 bytes in a kernel's closure instead of a View's 32).
template <class Real>
struct PackedRowsRef {
  const Real* data;
  KOKKOS_INLINE_FUNCTION Real operator()(int i, int column) const { return data[i * packed_width + column]; }
};

// rows(i, 0…D−1) ← a(i, 0…D−1).
template <int D, class Real, class ExecSpace, class Source>
void pack_vectors(const Source& a, const PackedRows<Real, ExecSpace>& rows) {
  mesoflow::launch::parallel_for(
      "mesoflow::mdpd::pack_vectors", Kokkos::RangePolicy<ExecSpace>(0, a.extent(0)), KOKKOS_LAMBDA(int i) {
        for (int d = 0; d < D; ++d) rows(i, d) = a(i, d);
      });
}

}  // namespace mesoflow::mdpd
