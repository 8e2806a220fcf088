// pair_force.hpp — the one generic neighbor loop for central pair potentials.
//
// Physics lives in a small evaluator (see lennard_jones.hpp); this loop owns iteration, image
// convention, scatter and the energy reduction (HOOMD's EvaluatorPair + PotentialPair split).
// An evaluator provides
//     KOKKOS_INLINE_FUNCTION bool evaluate(Real r2, int type_i, int type_j,
//                                          Real& force_over_r, Real& energy) const;
// returning false outside its cutoff, with F_i = force_over_r · (x_i − x_j) and the pair energy.
//
// Full list: each particle sums its own force — deterministic, no atomics. Half list: each pair
// once, the reaction scattered through a ScatterView (thread-duplicated on OpenMP, atomic on GPUs);
// results are then reproducible at a fixed thread count only.
//
// accumulate_forces() skips the energy: on a full list it is a parallel_for with dynamic scheduling
// (rows of a cell-ordered list differ in cost where the density does, e.g. the dense bottom and the
// dilute top of a hopper; a static split left one of two threads idle 30% of a step), each row still
// summed by one thread in list order, so the forces are deterministic. accumulate() keeps the static
// split, which makes its energy reduction reproducible at a fixed thread count.
#pragma once

#include "box.hpp"
#include "kokkos_compat.hpp"
#include "neighbor_list.hpp"
#include "particles.hpp"

#include <Kokkos_ScatterView.hpp>

namespace mesoflow {

template <int D, class Real, class ExecSpace>
class PairForce {
 public:
  using vector_view = typename Particles<D, Real, ExecSpace>::vector_view;

  // Adds the pair forces to p.f and returns the total pair energy.
  template <class Evaluator>
  double accumulate(const Evaluator& eval, const Particles<D, Real, ExecSpace>& p,
                    const NeighborList<D, Real, ExecSpace>& list, const Box<D, Real>& box) {
    return list.kind() == NeighborListKind::full ? accumulate_full(eval, p, list, box)
                                                 : accumulate_half(eval, p, list, box);
  }

  // Adds the pair forces to p.f, without the energy (see the file comment).
  template <class Evaluator>
  void accumulate_forces(const Evaluator& eval, const Particles<D, Real, ExecSpace>& p,
                         const NeighborList<D, Real, ExecSpace>& list, const Box<D, Real>& box) {
    if (list.kind() != NeighborListKind::full) {
      accumulate_half(eval, p, list, box);
      return;
    }
    const auto x = p.x;
    const auto f = p.f;
    const auto type = p.type;
    const auto nbr = list.data();
    Kokkos::parallel_for(
        "mesoflow::pair_force::full_forces",
        Kokkos::RangePolicy<ExecSpace, Kokkos::Schedule<Kokkos::Dynamic>>(0, p.size()).set_chunk_size(64),
        KOKKOS_LAMBDA(int row) {
          const int i = nbr.particle(row);
          double unused = 0;
          const Vec<D, Real> fi = full_row_force(eval, nbr, x, type, box, row, i, unused);
          for (int d = 0; d < D; ++d) f(i, d) += fi[d];
        });
  }

  // full_row_force, accumulate_full and accumulate_half are implementation details, public only
  // because nvcc rejects a KOKKOS_LAMBDA in a private or protected member function.

  // Σ_j F_ij over row `row` (particle i) of a full list, in list order; adds the pair energies to e_sum.
  template <class Evaluator, class Neighbors, class Positions, class Types>
  KOKKOS_INLINE_FUNCTION static Vec<D, Real> full_row_force(const Evaluator& eval, const Neighbors& nbr,
                                                            const Positions& x, const Types& type,
                                                            const Box<D, Real>& box, int row, int i, double& e_sum) {
    const Vec<D, Real> xi = Vec<D, Real>::load(x, i);
    const int ti = type(i);
    Vec<D, Real> fi = Vec<D, Real>::zero();
    const int nn = nbr.num_neighbors(row);
    for (int k = 0; k < nn; ++k) {
      const int j = nbr.neighbor(row, k);
      Vec<D, Real> dr = xi - Vec<D, Real>::load(x, j);
      box.minimum_image(dr);
      Real force_over_r, e;
      if (eval.evaluate(norm2(dr), ti, type(j), force_over_r, e)) {
        fi += force_over_r * dr;
        e_sum += e;
      }
    }
    return fi;
  }

  template <class Evaluator>
  double accumulate_full(const Evaluator& eval, const Particles<D, Real, ExecSpace>& p,
                         const NeighborList<D, Real, ExecSpace>& list, const Box<D, Real>& box) {
    const auto x = p.x;
    const auto f = p.f;
    const auto type = p.type;
    const auto nbr = list.data();
    double energy = 0;
    Kokkos::parallel_reduce(
        "mesoflow::pair_force::full", Kokkos::RangePolicy<ExecSpace>(0, p.size()),
        KOKKOS_LAMBDA(int row, double& e_acc) {
          const int i = nbr.particle(row);
          double ei = 0;
          const Vec<D, Real> fi = full_row_force(eval, nbr, x, type, box, row, i, ei);
          for (int d = 0; d < D; ++d) f(i, d) += fi[d];
          e_acc += 0.5 * ei;
        },
        energy);
    return energy;
  }

  template <class Evaluator>
  double accumulate_half(const Evaluator& eval, const Particles<D, Real, ExecSpace>& p,
                         const NeighborList<D, Real, ExecSpace>& list, const Box<D, Real>& box) {
    // Created once per force array. On backends where the ScatterView aliases p.f (Serial, GPUs)
    // reset_except leaves the forces other terms already added; duplicates are zeroed.
    if (scatter_target_ != p.f.data()) {
      scatter_ = Kokkos::Experimental::create_scatter_view(p.f);
      scatter_target_ = p.f.data();
    }
    scatter_.reset_except(p.f);
    auto scatter = scatter_;
    const auto x = p.x;
    const auto type = p.type;
    const auto nbr = list.data();
    double energy = 0;
    Kokkos::parallel_reduce(
        "mesoflow::pair_force::half", Kokkos::RangePolicy<ExecSpace>(0, p.size()),
        KOKKOS_LAMBDA(int row, double& e_acc) {
          auto access = scatter.access();
          const int i = nbr.particle(row);
          const Vec<D, Real> xi = Vec<D, Real>::load(x, i);
          const int ti = type(i);
          Vec<D, Real> fi = Vec<D, Real>::zero();
          const int nn = nbr.num_neighbors(row);
          for (int k = 0; k < nn; ++k) {
            const int j = nbr.neighbor(row, k);
            Vec<D, Real> dr = xi - Vec<D, Real>::load(x, j);
            box.minimum_image(dr);
            Real force_over_r, e;
            if (eval.evaluate(norm2(dr), ti, type(j), force_over_r, e)) {
              const Vec<D, Real> fij = force_over_r * dr;
              fi += fij;
              for (int d = 0; d < D; ++d) access(j, d) -= fij[d];
              e_acc += e;
            }
          }
          for (int d = 0; d < D; ++d) access(i, d) += fi[d];
        },
        energy);
    auto f = p.f;
    Kokkos::Experimental::contribute(f, scatter_);
    return energy;
  }

 private:
  Kokkos::Experimental::ScatterView<Real* [D], Kokkos::LayoutLeft, ExecSpace> scatter_;
  const Real* scatter_target_ = nullptr;
};

}  // namespace mesoflow
