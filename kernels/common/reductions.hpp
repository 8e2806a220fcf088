// reductions.hpp — global observables of a particle set: kinetic energy, momentum, centre of mass,
// maximum displacement. All sums accumulate in double whatever the storage precision, and use
// Kokkos' static-schedule reductions, so they are deterministic at a fixed thread count.
#pragma once

#include "kernel_launch.hpp"
#include "box.hpp"
#include "kokkos_compat.hpp"
#include "particles.hpp"

#include <array>
#include <string>

namespace mesoflow {

// Sum of N doubles per work item: the building block for vector-valued reductions.
template <int N>
struct SumArray {
  double v[N];
};

template <int N, class Body>
struct SumArrayFunctor {
  using value_type = SumArray<N>;
  Body body;
  KOKKOS_INLINE_FUNCTION void operator()(int i, value_type& acc) const { body(i, acc.v); }
  KOKKOS_INLINE_FUNCTION void init(value_type& acc) const {
    for (int k = 0; k < N; ++k) acc.v[k] = 0.0;
  }
  KOKKOS_INLINE_FUNCTION void join(MESOFLOW_JOIN_ARGS(value_type)) const {
    for (int k = 0; k < N; ++k) dst.v[k] += src.v[k];
  }
};

// Runs body(i, double (&acc)[N]) for i in [0, n) and returns the summed accumulators.
template <int N, class ExecSpace, class Body>
std::array<double, N> parallel_sum(const std::string& label, int n, const Body& body) {
  SumArray<N> result;
  mesoflow::launch::parallel_reduce(label, Kokkos::RangePolicy<ExecSpace>(0, n), SumArrayFunctor<N, Body>{body},
                          result);
  std::array<double, N> out;
  for (int k = 0; k < N; ++k) out[k] = result.v[k];
  return out;
}

// Σ_i ½ m_i |v_i|².
template <int D, class Real, class ExecSpace>
double kinetic_energy(const Particles<D, Real, ExecSpace>& p) {
  auto v = p.v;
  auto m = p.mass;
  double ke = 0.0;
  mesoflow::launch::parallel_reduce(
      "mesoflow::reductions::kinetic_energy", Kokkos::RangePolicy<ExecSpace>(0, p.size()),
      KOKKOS_LAMBDA(int i, double& acc) {
        double v2 = 0.0;
        for (int d = 0; d < D; ++d) v2 += double(v(i, d)) * double(v(i, d));
        acc += 0.5 * double(m(i)) * v2;
      },
      ke);
  return ke;
}

// Σ_i m_i v_i.
template <int D, class Real, class ExecSpace>
std::array<double, D> momentum(const Particles<D, Real, ExecSpace>& p) {
  auto v = p.v;
  auto m = p.mass;
  return parallel_sum<D, ExecSpace>("mesoflow::reductions::momentum", int(p.size()),
                                    KOKKOS_LAMBDA(int i, double(&acc)[D]) {
                                      for (int d = 0; d < D; ++d) acc[d] += double(m(i)) * double(v(i, d));
                                    });
}

// Mass-weighted mean of the stored positions (Σ m_i x_i / Σ m_i). Positions are used as stored:
// for a periodic system pass unwrapped coordinates if the centre of a body that straddles the
// boundary is wanted.
template <int D, class Real, class ExecSpace>
std::array<double, D> center_of_mass(const Particles<D, Real, ExecSpace>& p) {
  auto x = p.x;
  auto m = p.mass;
  const auto s = parallel_sum<D + 1, ExecSpace>("mesoflow::reductions::center_of_mass", int(p.size()),
                                                KOKKOS_LAMBDA(int i, double(&acc)[D + 1]) {
                                                  for (int d = 0; d < D; ++d)
                                                    acc[d] += double(m(i)) * double(x(i, d));
                                                  acc[D] += double(m(i));
                                                });
  std::array<double, D> com;
  for (int d = 0; d < D; ++d) com[d] = s[D] > 0 ? s[d] / s[D] : 0.0;
  return com;
}

// max_i |x_i − x_ref,i|, with the minimum-image convention on periodic axes so that a particle
// folded back into the box does not count as having jumped by a box length.
template <int D, class Real, class ExecSpace, class RefView>
Real max_displacement(const typename Particles<D, Real, ExecSpace>::vector_view& x, const RefView& x_ref,
                      const Box<D, Real>& box) {
  Real max_d2 = 0;
  mesoflow::launch::parallel_reduce(
      "mesoflow::reductions::max_displacement", Kokkos::RangePolicy<ExecSpace>(0, x.extent(0)),
      KOKKOS_LAMBDA(int i, Real& acc) {
        Vec<D, Real> dr;
        for (int d = 0; d < D; ++d) dr[d] = x(i, d) - x_ref(i, d);
        box.minimum_image(dr);
        const Real d2 = norm2(dr);
        if (d2 > acc) acc = d2;
      },
      Kokkos::Max<Real>(max_d2));
  return kmath::sqrt(max_d2);
}

}  // namespace mesoflow
