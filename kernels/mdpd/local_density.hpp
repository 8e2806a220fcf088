// local_density.hpp — the many-body density ρ̄_i = self + Σ_{j≠i} w_ρ(r_ij) of MDPD (paper §2.5.1,
// density_weight.hpp), summed over a neighbor list of reach ≥ r_B.
//
// The density needs only the pairs within r_B + skin of a list built for r_A + skin (r_B = 0.75 r_A:
// about half of the entries in 3D). A list whose inner cutoff covers r_B (NeighborList::
// set_inner_cutoff) lists those pairs first in every row, and compute() reads only them; on any
// other list it reads whole rows.
//
// Full list: each row sums its own particle, in list order (deterministic, no atomics). Half list:
// each pair once, both ends through a ScatterView (thread-duplicated on OpenMP, atomic on GPUs).
#pragma once

#include "density_weight.hpp"
#include "packed_state.hpp"
#include "kernels/common/box.hpp"
#include "kernels/common/neighbor_list.hpp"
#include "kernels/common/particles.hpp"

#include <Kokkos_ScatterView.hpp>

namespace mesoflow::mdpd {

template <int D, class Real, class ExecSpace>
class LocalDensity {
 public:
  using scalar_view = Kokkos::View<Real*, ExecSpace>;

  explicit LocalDensity(const DensityWeight<D, Real>& weight) : weight_(weight) {}

  // rho(i) ← ρ̄_i for every particle, from the positions packed in rows xr (packed_state.hpp).
  void compute(const PackedRows<Real, ExecSpace>& xr, const NeighborList<D, Real, ExecSpace>& list,
               const Box<D, Real>& box, const scalar_view& rho) {
    use_inner_ = list.inner_cutoff() >= weight_.h;
    if (list.kind() == NeighborListKind::full)
      compute_full(xr, list, box, rho);
    else
      compute_half(xr, list, box, rho);
  }

  const DensityWeight<D, Real>& weight() const { return weight_; }

  // compute_full, compute_half and row_vector are implementation details, public only because nvcc
  // rejects a KOKKOS_LAMBDA in a private or protected member function.
  void compute_full(const PackedRows<Real, ExecSpace>& x, const NeighborList<D, Real, ExecSpace>& list,
                    const Box<D, Real>& box, const scalar_view& rho) const {
    const auto nbr = list.data();
    const auto w = weight_;
    const bool use_inner = use_inner_;
    Kokkos::parallel_for(
        "mesoflow::mdpd::density_full", Kokkos::RangePolicy<ExecSpace>(0, x.extent(0)), KOKKOS_LAMBDA(int row) {
          const int i = nbr.particle(row);
          const Vec<D, Real> xi = row_vector(x, i);
          Real sum = w.self;
          const int nn = use_inner ? nbr.num_inner_neighbors(row) : nbr.num_neighbors(row);
          for (int k = 0; k < nn; ++k) {
            Vec<D, Real> dr = xi - row_vector(x, nbr.neighbor(row, k));
            box.minimum_image_near(dr);
            const Real r2 = norm2(dr);
            if (r2 < w.h2) sum += w(kmath::sqrt(r2));
          }
          rho(i) = sum;
        });
  }

  void compute_half(const PackedRows<Real, ExecSpace>& x, const NeighborList<D, Real, ExecSpace>& list,
                    const Box<D, Real>& box, const scalar_view& rho) {
    const auto w = weight_;
    Kokkos::parallel_for(
        "mesoflow::mdpd::density_self", Kokkos::RangePolicy<ExecSpace>(0, x.extent(0)),
        KOKKOS_LAMBDA(int i) { rho(i) = w.self; });
    if (scatter_target_ != rho.data()) {
      scatter_ = Kokkos::Experimental::create_scatter_view(rho);
      scatter_target_ = rho.data();
    }
    scatter_.reset_except(rho);
    auto scatter = scatter_;
    const auto nbr = list.data();
    const bool use_inner = use_inner_;
    Kokkos::parallel_for(
        "mesoflow::mdpd::density_half", Kokkos::RangePolicy<ExecSpace>(0, x.extent(0)), KOKKOS_LAMBDA(int row) {
          auto access = scatter.access();
          const int i = nbr.particle(row);
          const Vec<D, Real> xi = row_vector(x, i);
          Real sum = 0;
          const int nn = use_inner ? nbr.num_inner_neighbors(row) : nbr.num_neighbors(row);
          for (int k = 0; k < nn; ++k) {
            const int j = nbr.neighbor(row, k);
            Vec<D, Real> dr = xi - row_vector(x, j);
            box.minimum_image_near(dr);
            const Real r2 = norm2(dr);
            if (r2 < w.h2) {
              const Real wij = w(kmath::sqrt(r2));
              sum += wij;
              access(j) += wij;
            }
          }
          access(i) += sum;
        });
    auto target = rho;
    Kokkos::Experimental::contribute(target, scatter_);
  }

  KOKKOS_INLINE_FUNCTION static Vec<D, Real> row_vector(const PackedRows<Real, ExecSpace>& rows, int i) {
    Vec<D, Real> r;
    for (int d = 0; d < D; ++d) r[d] = rows(i, d);
    return r;
  }

 private:
  DensityWeight<D, Real> weight_;
  bool use_inner_ = false;
  decltype(Kokkos::Experimental::create_scatter_view(scalar_view())) scatter_;
  const Real* scatter_target_ = nullptr;
};

}  // namespace mesoflow::mdpd
