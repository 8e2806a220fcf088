// maxwell_boltzmann.hpp — Maxwell–Boltzmann velocities of the ideal-gas MPC solvent (Appendix B):
// each component normal with variance k_BT/m. thermal_velocity draws one (the v^ran of eq. B.2,
// the virtual particles' velocities); fill_maxwell_boltzmann sets initial velocities and removes
// their mean so the total momentum is zero.
#pragma once

#include "../common/kernel_launch.hpp"
#include "kernels/common/kokkos_compat.hpp"
#include "kernels/common/random.hpp"
#include "kernels/common/reductions.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace mesoflow::mpc {

// Two independent standard normal deviates by Marsaglia's polar method (SIAM Rev. 6, 260 (1964)):
// (u, w) uniform in the open square until s = u² + w² < 1, then (u, w) √(−2 ln s / s). One log, one
// square root and one division per pair and no trigonometric function: about 1.27 tries of two
// Real uniforms each. s > 0 always (uniform_symmetric never returns 0).
template <class Real>
KOKKOS_INLINE_FUNCTION void normal_pair(RandomStream& rs, Real& z0, Real& z1) {
  Real u, w, s;
  do {
    u = rs.uniform_symmetric<Real>();
    w = rs.uniform_symmetric<Real>();
    s = u * u + w * w;
  } while (s >= Real(1));
  const Real f = kmath::sqrt(Real(-2) * kmath::log(s) / s);
  z0 = u * f;
  z1 = w * f;
}

// A Maxwell–Boltzmann velocity: each component `speed` (= √(k_BT/m)) times a standard normal, from
// ⌈D/2⌉ polar pairs of the stream.
template <int D, class Real>
KOKKOS_INLINE_FUNCTION void thermal_velocity(RandomStream& rs, Real speed, Real (&v)[D]) {
  Real z[D + D % 2];
  for (int k = 0; k < D; k += 2) normal_pair(rs, z[k], z[k + 1]);
  for (int d = 0; d < D; ++d) v[d] = speed * z[d];
}

// v(i, ·) = thermal_velocity from the stream (seed, step 0, initial_condition, i, field), so the same
// velocities at any thread count before the mean is removed; the mean is summed in double
// (deterministic at a fixed thread count; with `ordered_mean`, summed on the host in index order:
// the same bits on every backend and thread count, for the deterministic-sum mode — setup only, a
// copy to the host). `field` keeps the velocities independent of positions filled from the same
// seed by fill_uniform_counter (field 0 by default).
template <int D, class Real, class ExecSpace>
void fill_maxwell_boltzmann(const Kokkos::View<Real* [D], Kokkos::LayoutLeft, ExecSpace>& v, Real kT, Real mass,
                            std::uint64_t seed, std::uint32_t field = 1, bool ordered_mean = false) {
  if (!(kT >= Real(0)) || !std::isfinite(double(kT)))
    throw std::invalid_argument("Maxwell-Boltzmann velocities: kT must be finite and >= 0, got " +
                                std::to_string(double(kT)));
  if (!(mass > Real(0)) || !std::isfinite(double(mass)))
    throw std::invalid_argument("Maxwell-Boltzmann velocities: mass must be finite and > 0, got " +
                                std::to_string(double(mass)));
  const int n = int(v.extent(0));
  if (n == 0) return;
  const Real speed = Real(std::sqrt(double(kT) / double(mass)));
  mesoflow::launch::parallel_for(
      "mesoflow::mpc::maxwell_boltzmann::draw", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(const int i) {
        RandomStream rs(seed, 0, stream_tag::initial_condition, static_cast<std::uint32_t>(i), field);
        Real vi[D];
        thermal_velocity(rs, speed, vi);
        for (int d = 0; d < D; ++d) v(i, d) = vi[d];
      });
  std::array<double, D> total{};
  if (ordered_mean) {
    const auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), v);
    for (int i = 0; i < n; ++i)
      for (int d = 0; d < D; ++d) total[std::size_t(d)] += double(h(i, d));
  } else {
    total = parallel_sum<D, ExecSpace>("mesoflow::mpc::maxwell_boltzmann::momentum", n,
                                       KOKKOS_LAMBDA(const int i, double(&acc)[D]) {
                                         for (int d = 0; d < D; ++d) acc[d] += double(v(i, d));
                                       });
  }
  Kokkos::Array<Real, D> mean;
  for (int d = 0; d < D; ++d) mean[d] = Real(total[d] / n);
  mesoflow::launch::parallel_for(
      "mesoflow::mpc::maxwell_boltzmann::remove_mean", Kokkos::RangePolicy<ExecSpace>(0, n),
      KOKKOS_LAMBDA(const int i) {
        for (int d = 0; d < D; ++d) v(i, d) -= mean[d];
      });
}

}  // namespace mesoflow::mpc
