// lj_fluid_scene.hpp — the initial state of the Lennard-Jones reference scene (drivers/lj_fluid):
// N particles on a square/cubic lattice of per_side = ⌈N^{1/D}⌉ sites per edge, jittered by ±0.1 of
// the spacing from the counter-based stream (seed, 0, initial_condition, i, 0); Maxwell velocities
// at k_BT from (seed, 0, initial_condition, i, 1), with zero total momentum, rescaled to exactly
// k_BT over D (N − 1) degrees of freedom.
#pragma once

#include "kernels/common/particles.hpp"
#include "kernels/common/random.hpp"
#include "kernels/common/reductions.hpp"

#include <cmath>
#include <cstdint>

namespace mesoflow::lj_fluid {

template <int D, class Real, class Exec>
void place_on_lattice(const Particles<D, Real, Exec>& p, Real L, std::uint64_t seed) {
  const int n = int(p.size());
  const int per_side = int(std::ceil(std::pow(double(n), 1.0 / D) - 1e-9));
  const Real a = L / Real(per_side);
  const auto x = p.x;
  Kokkos::parallel_for(
      "mesoflow::lj_fluid::lattice", Kokkos::RangePolicy<Exec>(0, n), KOKKOS_LAMBDA(int i) {
        RandomStream jitter(seed, 0, stream_tag::initial_condition, std::uint32_t(i), 0);
        int site = i;
        for (int d = 0; d < D; ++d) {
          x(i, d) = (Real(site % per_side) + Real(0.5) + Real(0.1) * jitter.template uniform_symmetric<Real>()) * a;
          site /= per_side;
        }
      });
}

// Maxwell velocities at k_BT with zero total momentum, rescaled to exactly k_BT.
template <int D, class Real, class Exec>
void thermalize(const Particles<D, Real, Exec>& p, double kT, std::uint64_t seed) {
  const auto v = p.v;
  const Real sd = Real(std::sqrt(kT));
  Kokkos::parallel_for(
      "mesoflow::lj_fluid::maxwell", Kokkos::RangePolicy<Exec>(0, p.size()), KOKKOS_LAMBDA(int i) {
        RandomStream g(seed, 0, stream_tag::initial_condition, std::uint32_t(i), 1);
        for (int d = 0; d < D; ++d) v(i, d) = sd * g.template normal<Real>();
      });
  const auto P = momentum(p);
  double mass = 0;
  const auto m = p.mass;
  Kokkos::parallel_reduce(
      "mesoflow::lj_fluid::total_mass", Kokkos::RangePolicy<Exec>(0, p.size()),
      KOKKOS_LAMBDA(int i, double& acc) { acc += m(i); }, mass);
  Real drift[D];
  for (int d = 0; d < D; ++d) drift[d] = Real(P[d] / mass);
  const double dof = double(D) * (double(p.size()) - 1.0);
  const double ke = kinetic_energy(p) - 0.5 * mass * [&] {
    double s = 0;
    for (int d = 0; d < D; ++d) s += double(drift[d]) * drift[d];
    return s;
  }();
  const Real scale = Real(std::sqrt(kT * dof / (2.0 * ke)));
  Kokkos::parallel_for(
      "mesoflow::lj_fluid::rescale", Kokkos::RangePolicy<Exec>(0, p.size()), KOKKOS_LAMBDA(int i) {
        for (int d = 0; d < D; ++d) v(i, d) = scale * (v(i, d) - drift[d]);
      });
}

}  // namespace mesoflow::lj_fluid
