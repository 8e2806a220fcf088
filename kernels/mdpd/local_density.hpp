// local_density.hpp — the many-body density ρ̄_i = self + Σ_{j≠i} w_ρ(r_ij) of MDPD (paper §2.5.1,
// density_weight.hpp), summed over a neighbor list of reach ≥ r_B.
//
// The density needs only the pairs within r_B + skin of a list built for r_A + skin (r_B = 0.75 r_A:
// about half of the entries in 3D). A list whose inner cutoff covers r_B (NeighborList::
// set_inner_cutoff) lists those pairs first in every row, and compute() reads only them (PairRows::inner); on any
// other list it reads whole rows.
//
// An evaluator of the generic pair loop (kernels/common/pair_force.hpp). Full list: each row sums
// its own particle, in list order (deterministic, no atomics). Half list: each pair once, both ends
// through a ScatterView (thread-duplicated on OpenMP, atomic on GPUs).
#pragma once

#include "../common/kernel_launch.hpp"
#include "density_weight.hpp"
#include "packed_state.hpp"
#include "kernels/common/box.hpp"
#include "kernels/common/neighbor_list.hpp"
#include "kernels/common/pair_force.hpp"
#include "kernels/common/particles.hpp"

#include <Kokkos_ScatterView.hpp>

namespace mesoflow::mdpd {

// Σ_j w_ρ(r_ij) as an evaluator of the generic pair loop (screened at r_B by the loop). Full rows
// start from the self term and write ρ̄_i; half rows scatter w_ρ to both ends (the self term is set
// before the loop).
template <int D, class Real, class ExecSpace>
struct LocalDensityEvaluator : PairEvaluatorTraits {
  static constexpr MinimumImage image = MinimumImage::near;
  static constexpr PairScreen screen = PairScreen::branch;
  using scalar_view = Kokkos::View<Real*, ExecSpace>;
  using scatter = PairScatter<scalar_view>;
  DensityWeight<D, Real> w;
  Real cutoff2;
  scalar_view rho;
  typename scatter::scatter_view rho_scatter;  // half lists only

  struct FullRow {
    Real sum;
  };
  struct HalfRow {
    typename scatter::access_type access;
    Real sum;
  };
  KOKKOS_INLINE_FUNCTION FullRow begin(FullList, int) const { return {w.self}; }
  KOKKOS_INLINE_FUNCTION void operator()(FullList, FullRow& s, int, int, const Vec<D, Real>&, Real r2, double&) const {
    s.sum += w(kmath::sqrt(r2));
  }
  KOKKOS_INLINE_FUNCTION void end(FullList, FullRow& s, int i, double&) const { rho(i) = s.sum; }

  KOKKOS_INLINE_FUNCTION HalfRow begin(HalfList, int) const { return {rho_scatter.access(), Real(0)}; }
  KOKKOS_INLINE_FUNCTION void operator()(HalfList, HalfRow& s, int, int j, const Vec<D, Real>&, Real r2,
                                         double&) const {
    const Real wij = w(kmath::sqrt(r2));
    s.sum += wij;
    s.access(j) += wij;
  }
  KOKKOS_INLINE_FUNCTION void end(HalfList, HalfRow& s, int i, double&) const { s.access(i) += s.sum; }
};

template <int D, class Real, class ExecSpace>
class LocalDensity {
 public:
  using scalar_view = Kokkos::View<Real*, ExecSpace>;

  explicit LocalDensity(const DensityWeight<D, Real>& weight) : weight_(weight) {}

  // rho(i) ← ρ̄_i for every particle, from the positions packed in rows xr (packed_state.hpp).
  void compute(const PackedRows<Real, ExecSpace>& xr, const NeighborList<D, Real, ExecSpace>& list,
               const Box<D, Real>& box, const scalar_view& rho) {
    const PairRows rows = list.inner_cutoff() >= weight_.h ? PairRows::inner : PairRows::all;
    LocalDensityEvaluator<D, Real, ExecSpace> ev{{}, weight_, weight_.h2, rho, {}};
    if (list.kind() == NeighborListKind::full) {
      for_each_pair("mesoflow::mdpd::density_full", FullList{}, list, box, xr, ev, rows);
      return;
    }
    const auto w = weight_;
    mesoflow::launch::parallel_for(
        "mesoflow::mdpd::density_self", Kokkos::RangePolicy<ExecSpace>(0, xr.extent(0)),
        KOKKOS_LAMBDA(int i) { rho(i) = w.self; });
    ev.rho_scatter = scatter_.prepare(rho);
    for_each_pair("mesoflow::mdpd::density_half", HalfList{}, list, box, xr, ev, rows);
    scatter_.contribute(rho);
  }

  const DensityWeight<D, Real>& weight() const { return weight_; }

 private:
  DensityWeight<D, Real> weight_;
  PairScatter<scalar_view> scatter_;
};

}  // namespace mesoflow::mdpd
