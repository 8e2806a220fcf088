// pair_force.hpp — the one generic neighbor loop, and the central pair potentials on it.
//
// for_each_pair / reduce_pairs own iteration over the rows of a NeighborList, the separation
// x_i − x_j (image convention), the distance screen and the schedule; a small device evaluator owns
// the physics of one pair and what it accumulates (HOOMD's EvaluatorPair + PotentialPair split,
// LAMMPS KOKKOS' PairComputeFunctor<PairStyle>). The evaluator contract, with Tag = FullList or
// HalfList (the list's kind, checked against the list at run time):
//
//   Row begin(Tag, int i) const;        // state of row i: i's cached data, its sums, scatter access
//   void operator()(Tag, Row& s, int i, int j, const Vec<D, Real>& dr, Real r2, double& sum) const;
//   void end(Tag, Row& s, int i, double& sum) const;     // write i's sums (full) or scatter them (half)
//
// called as begin(i), then operator() for each listed j in list order, then end(i), all by one
// thread. dr = x_i − x_j after the evaluator's image convention, r2 = |dr|². `sum` is the slot of
// reduce_pairs' double reduction (a dummy in for_each_pair). Each evaluator captures whatever Views
// it reads (velocities, densities, types, tags) and writes (forces, per-row results) by value, and
// sets its traits (defaults in PairEvaluatorTraits):
//   image         MinimumImage::exact (Box::minimum_image), near (minimum_image_near) or none;
//   screen        PairScreen::evaluator (every listed pair reaches operator(); the evaluator tests
//                 its own, e.g. per-type, cut-off), branch (the loop skips !(r2 < cutoff2)) or
//                 chunked (the loop screens a chunk of entries at a time, branch-free, against
//                 cutoff2, then calls operator() on the kept ones in list order — no branch depends
//                 on a distance: the SPH loop, where a mispredicted branch per dropped entry cost
//                 more than the pair terms), with `Real cutoff2` a member;
//   image_free_rows  with `bool image_free(const Vec<D, Real>& x_i) const`: rows of particles for
//                 which it holds skip the image convention (sph::ImageFreeRegion).
// Full list: each row owns its particle's sums — deterministic for any thread count, no atomics.
// Half list: each pair once; the evaluator's Row holds a ScatterView access (PairScatter below:
// duplicated per thread on OpenMP, atomic on GPUs) for j's share, so results are reproducible at a
// fixed thread count only.
//
// The compile-time choices of a loop are the list tag and the schedule; everything else an
// evaluator needs to switch on is a uniform run-time flag in it, unless a benchmark shows the
// branch costs (kernels/mdpd/mdpd_pair_force.hpp keeps the thermostat a template argument).
//
// PairForce below runs central potentials on it. Their evaluators (see lennard_jones.hpp) provide
//     KOKKOS_INLINE_FUNCTION bool evaluate(Real r2, int type_i, int type_j,
//                                          Real& force_over_r, Real& energy) const;
// returning false outside its cutoff, with F_i = force_over_r · (x_i − x_j) and the pair energy.
//
// accumulate_forces() skips the energy: on a full list it is a parallel_for with dynamic scheduling
// (rows of a cell-ordered list differ in cost where the density does, e.g. the dense bottom and the
// dilute top of a hopper; a static split left one of two threads idle 30% of a step), each row still
// summed by one thread in list order, so the forces are deterministic. accumulate() keeps the static
// split, which makes its energy reduction reproducible at a fixed thread count.
#pragma once

#include "kernel_launch.hpp"
#include "box.hpp"
#include "kokkos_compat.hpp"
#include "neighbor_list.hpp"
#include "particles.hpp"
#include "vec.hpp"

#include <Kokkos_ScatterView.hpp>

#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

namespace mesoflow {

// Which kind of list a pair loop runs over (tags, so an evaluator overloads on them).
struct FullList {};
struct HalfList {};

enum class MinimumImage { none, exact, near };
enum class PairScreen { evaluator, branch, chunked };
// Rows of a list a loop reads: all neighbors, or only those within the inner cutoff
// (NeighborList::set_inner_cutoff; the whole row on a list without one).
enum class PairRows { all, inner };

// Default traits of an evaluator (derive from it and override what differs).
struct PairEvaluatorTraits {
  static constexpr MinimumImage image = MinimumImage::exact;
  static constexpr PairScreen screen = PairScreen::evaluator;
  static constexpr bool image_free_rows = false;
};

namespace pair_loop_detail {

template <class Tag>
constexpr NeighborListKind kind_of() {
  return std::is_same<Tag, HalfList>::value ? NeighborListKind::half : NeighborListKind::full;
}

// The body of a row, shared by the parallel_for and parallel_reduce functors.
template <class Tag, int D, class Real, class ExecSpace, class Positions, class Evaluator>
struct Rows {
  NeighborData<ExecSpace> nbr;
  Positions x;
  PeriodicImages<D, Real> box;  // the box's image convention (56 bytes in 3D double, not the Box)
  Evaluator ev;
  bool inner_only;

  // Entries screened at a time by PairScreen::chunked (a half list of skin 10% holds about 44 per
  // SPH row). An enumerator: nvcc has no device copy of a host variable.
  enum : int { chunk = 32 };

  template <MinimumImage Image>
  KOKKOS_INLINE_FUNCTION Vec<D, Real> separation(const Vec<D, Real>& xi, int j) const {
    Vec<D, Real> dr;
    for (int d = 0; d < D; ++d) dr[d] = xi[d] - x(j, d);
    if (Image == MinimumImage::exact) box.minimum_image(dr);
    if (Image == MinimumImage::near) box.minimum_image_near(dr);
    return dr;
  }

  // Entries [k0, k1) of `row` within the cut-off: their j, dr and r2 land at the front of the
  // arrays, in list order; returns how many.
  template <MinimumImage Image>
  KOKKOS_INLINE_FUNCTION int screen(int row, int k0, int k1, const Vec<D, Real>& xi, int* j_in,
                                    Vec<D, Real>* dr_in, Real* r2_in) const {
    const Real cutoff2 = ev.cutoff2;
    int kept = 0;
    for (int k = k0; k < k1; ++k) {
      const int j = nbr.neighbor(row, k);
      const Vec<D, Real> dr = separation<Image>(xi, j);
      const Real r2 = norm2(dr);
      j_in[kept] = j;
      dr_in[kept] = dr;
      r2_in[kept] = r2;
      kept += r2 < cutoff2;
    }
    return kept;
  }

  template <MinimumImage Image, class State>
  KOKKOS_INLINE_FUNCTION void chunked(int row, int nn, int i, const Vec<D, Real>& xi, State& s, double& sum) const {
    int j_in[chunk];
    Vec<D, Real> dr_in[chunk];
    Real r2_in[chunk];
    for (int k0 = 0; k0 < nn; k0 += chunk) {
      const int k1 = nn - k0 < chunk ? nn : k0 + chunk;
      const int kept = screen<Image>(row, k0, k1, xi, j_in, dr_in, r2_in);
      for (int q = 0; q < kept; ++q) ev(Tag{}, s, i, j_in[q], dr_in[q], r2_in[q], sum);
    }
  }

  template <MinimumImage Image, class State>
  KOKKOS_INLINE_FUNCTION void each(int row, int nn, int i, const Vec<D, Real>& xi, State& s, double& sum) const {
    for (int k = 0; k < nn; ++k) {
      const int j = nbr.neighbor(row, k);
      const Vec<D, Real> dr = separation<Image>(xi, j);
      const Real r2 = norm2(dr);
      if constexpr (Evaluator::screen == PairScreen::branch)
        if (!(r2 < ev.cutoff2)) continue;
      ev(Tag{}, s, i, j, dr, r2, sum);
    }
  }

  KOKKOS_INLINE_FUNCTION void operator()(int row, double& sum) const {
    const int i = nbr.particle(row);
    const Vec<D, Real> xi = Vec<D, Real>::load(x, i);
    auto s = ev.begin(Tag{}, i);
    const int nn = inner_only ? nbr.num_inner_neighbors(row) : nbr.num_neighbors(row);
    if constexpr (Evaluator::screen == PairScreen::chunked) {
      bool image_free = false;
      if constexpr (Evaluator::image_free_rows) image_free = ev.image_free(xi);
      if (image_free)
        chunked<MinimumImage::none>(row, nn, i, xi, s, sum);
      else
        chunked<Evaluator::image>(row, nn, i, xi, s, sum);
    } else {
      bool image_free = false;
      if constexpr (Evaluator::image_free_rows) image_free = ev.image_free(xi);
      if (image_free)
        each<MinimumImage::none>(row, nn, i, xi, s, sum);
      else
        each<Evaluator::image>(row, nn, i, xi, s, sum);
    }
    ev.end(Tag{}, s, i, sum);
  }
};

template <class Body>
struct ForFunctor {
  Body body;
  KOKKOS_INLINE_FUNCTION void operator()(int row) const {
    double unused = 0;
    body(row, unused);
  }
};

template <class Body>
struct ReduceFunctor {
  using value_type = double;
  Body body;
  KOKKOS_INLINE_FUNCTION void operator()(int row, double& sum) const { body(row, sum); }
};

template <class Tag, int D, class Real, class ExecSpace, class Positions, class Evaluator>
Rows<Tag, D, Real, ExecSpace, Positions, Evaluator> rows(const NeighborList<D, Real, ExecSpace>& list,
                                                          const Box<D, Real>& box, const Positions& x,
                                                          const Evaluator& ev, PairRows which) {
  if (list.kind() != kind_of<Tag>())
    throw std::invalid_argument(std::string("pair loop: the evaluator runs on a ") +
                                (kind_of<Tag>() == NeighborListKind::full ? "full" : "half") +
                                " list, got the other kind");
  return {list.data(), x, box.images(), ev, which == PairRows::inner && list.inner_cutoff() > Real(0)};
}

}  // namespace pair_loop_detail

// Runs `ev` over every pair of `list` (see the file comment); `x`: an (n × ≥D) View whose first D
// columns are the positions (Particles::x or a packed row). Schedule: Kokkos::Static, or
// Kokkos::Dynamic (chunks of 64 rows) where rows differ in cost.
template <class Schedule = Kokkos::Static, class Tag, int D, class Real, class ExecSpace, class Positions,
          class Evaluator>
void for_each_pair(const std::string& label, Tag, const NeighborList<D, Real, ExecSpace>& list,
                   const Box<D, Real>& box, const Positions& x, const Evaluator& ev, PairRows which = PairRows::all) {
  using Body = pair_loop_detail::Rows<Tag, D, Real, ExecSpace, Positions, Evaluator>;
  const pair_loop_detail::ForFunctor<Body> f{pair_loop_detail::rows<Tag>(list, box, x, ev, which)};
  const int n = int(x.extent(0));
  if constexpr (std::is_same<Schedule, Kokkos::Dynamic>::value)
    mesoflow::launch::parallel_for(label, Kokkos::RangePolicy<ExecSpace, Kokkos::Schedule<Kokkos::Dynamic>>(0, n).set_chunk_size(64), f);
  else
    mesoflow::launch::parallel_for(label, Kokkos::RangePolicy<ExecSpace>(0, n), f);
}

// for_each_pair with a statically scheduled double reduction (reproducible at a fixed thread count):
// returns the sum of what begin/operator()/end added to `sum`.
template <class Tag, int D, class Real, class ExecSpace, class Positions, class Evaluator>
double reduce_pairs(const std::string& label, Tag, const NeighborList<D, Real, ExecSpace>& list,
                    const Box<D, Real>& box, const Positions& x, const Evaluator& ev, PairRows which = PairRows::all) {
  using Body = pair_loop_detail::Rows<Tag, D, Real, ExecSpace, Positions, Evaluator>;
  const pair_loop_detail::ReduceFunctor<Body> f{pair_loop_detail::rows<Tag>(list, box, x, ev, which)};
  double result = 0;
  mesoflow::launch::parallel_reduce(label, Kokkos::RangePolicy<ExecSpace>(0, int(x.extent(0))), f, result);
  return result;
}

// A half-list loop's scatter target: the ScatterView is created once per target array (thread
// duplicates on OpenMP, atomics on GPUs); prepare() resets the duplicates before a loop (on
// backends where the ScatterView aliases the target, reset_except keeps what the target holds) and
// contribute() adds them to the target after it.
template <class View>
class PairScatter {
 public:
  using scatter_view = decltype(Kokkos::Experimental::create_scatter_view(std::declval<View>()));
  using access_type = decltype(std::declval<const scatter_view&>().access());

  const scatter_view& prepare(const View& target) {
    if (target_ != static_cast<const void*>(target.data())) {
      scatter_ = Kokkos::Experimental::create_scatter_view(target);
      target_ = target.data();
    }
    scatter_.reset_except(target);
    return scatter_;
  }
  void contribute(const View& target) {
    auto t = target;
    Kokkos::Experimental::contribute(t, scatter_);
  }

 private:
  scatter_view scatter_;
  const void* target_ = nullptr;
};

// A central pair law as an evaluator of the generic loop: F_i += force_over_r · dr; full rows sum
// their pair energies (halved in the reduction), half rows add each pair's energy once.
template <int D, class Real, class ExecSpace, class Law>
struct CentralPairEvaluator : PairEvaluatorTraits {
  using vector_view = typename Particles<D, Real, ExecSpace>::vector_view;
  using scatter = PairScatter<vector_view>;
  Law law;
  vector_view f;
  Kokkos::View<int*, ExecSpace> type;
  typename scatter::scatter_view f_scatter;  // half lists only

  struct FullRow {
    int ti;
    Vec<D, Real> fi;
    double energy;
  };
  struct HalfRow {
    typename scatter::access_type access;
    int ti;
    Vec<D, Real> fi;
  };

  KOKKOS_INLINE_FUNCTION FullRow begin(FullList, int i) const { return {type(i), Vec<D, Real>::zero(), 0.0}; }
  KOKKOS_INLINE_FUNCTION void operator()(FullList, FullRow& s, int, int j, const Vec<D, Real>& dr, Real r2,
                                         double&) const {
    Real force_over_r, e;
    if (law.evaluate(r2, s.ti, type(j), force_over_r, e)) {
      s.fi += force_over_r * dr;
      s.energy += e;
    }
  }
  KOKKOS_INLINE_FUNCTION void end(FullList, FullRow& s, int i, double& sum) const {
    for (int d = 0; d < D; ++d) f(i, d) += s.fi[d];
    sum += 0.5 * s.energy;
  }

  KOKKOS_INLINE_FUNCTION HalfRow begin(HalfList, int i) const {
    return {f_scatter.access(), type(i), Vec<D, Real>::zero()};
  }
  KOKKOS_INLINE_FUNCTION void operator()(HalfList, HalfRow& s, int, int j, const Vec<D, Real>& dr, Real r2,
                                         double& sum) const {
    Real force_over_r, e;
    if (law.evaluate(r2, s.ti, type(j), force_over_r, e)) {
      const Vec<D, Real> fij = force_over_r * dr;
      s.fi += fij;
      for (int d = 0; d < D; ++d) s.access(j, d) -= fij[d];
      sum += e;
    }
  }
  KOKKOS_INLINE_FUNCTION void end(HalfList, HalfRow& s, int i, double&) const {
    for (int d = 0; d < D; ++d) s.access(i, d) += s.fi[d];
  }
};

template <int D, class Real, class ExecSpace>
class PairForce {
 public:
  using vector_view = typename Particles<D, Real, ExecSpace>::vector_view;

  // Adds the pair forces to p.f and returns the total pair energy.
  template <class Law>
  double accumulate(const Law& law, const Particles<D, Real, ExecSpace>& p,
                    const NeighborList<D, Real, ExecSpace>& list, const Box<D, Real>& box) {
    if (list.kind() == NeighborListKind::half) return accumulate_half(law, p, list, box);
    return reduce_pairs("mesoflow::pair_force::full", FullList{}, list, box, p.x, evaluator(law, p));
  }

  // Adds the pair forces to p.f, without the energy (see the file comment).
  template <class Law>
  void accumulate_forces(const Law& law, const Particles<D, Real, ExecSpace>& p,
                         const NeighborList<D, Real, ExecSpace>& list, const Box<D, Real>& box) {
    if (list.kind() == NeighborListKind::half) {
      accumulate_half(law, p, list, box);
      return;
    }
    for_each_pair<Kokkos::Dynamic>("mesoflow::pair_force::full_forces", FullList{}, list, box, p.x, evaluator(law, p));
  }

 private:
  template <class Law>
  CentralPairEvaluator<D, Real, ExecSpace, Law> evaluator(const Law& law, const Particles<D, Real, ExecSpace>& p) const {
    return {{}, law, p.f, p.type, {}};
  }

  template <class Law>
  double accumulate_half(const Law& law, const Particles<D, Real, ExecSpace>& p,
                         const NeighborList<D, Real, ExecSpace>& list, const Box<D, Real>& box) {
    auto ev = evaluator(law, p);
    ev.f_scatter = scatter_.prepare(p.f);
    const double energy = reduce_pairs("mesoflow::pair_force::half", HalfList{}, list, box, p.x, ev);
    scatter_.contribute(p.f);
    return energy;
  }

  PairScatter<vector_view> scatter_;
};

}  // namespace mesoflow
