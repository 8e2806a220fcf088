// mass_proportional_drag.hpp — viscous drag of the background fluid on each soft particle (hopper
// study, eq. 5): F_m = −ζ M_m v_m, ζ the drag coefficient per unit mass (units ζ0 = ρσ_avg^{d−1} g t0
// over the mass unit ρσ_avg^d, i.e. 1/t0). v is the integrator's velocity for velocity-dependent
// forces (velocity_verlet.hpp). It dissipates: F_m·v_m = −ζ M_m |v_m|² ≤ 0.
#pragma once

#include "../common/kernel_launch.hpp"
#include "kernels/common/kokkos_compat.hpp"
#include "kernels/common/particles.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace mesoflow::sp {

template <int D, class Real, class ExecSpace>
void accumulate_mass_proportional_drag(Real zeta, const Particles<D, Real, ExecSpace>& p,
                                       const typename Particles<D, Real, ExecSpace>::vector_view& velocity) {
  if (!(zeta >= Real(0)) || !std::isfinite(double(zeta)))
    throw std::invalid_argument("mass_proportional_drag: zeta must be finite and >= 0, got " +
                                std::to_string(double(zeta)));
  if (zeta == Real(0)) return;  // a term whose coefficient is zero costs nothing
  const auto v = velocity;
  const auto f = p.f;
  const auto m = p.mass;
  mesoflow::launch::parallel_for(
      "mesoflow::sp::mass_proportional_drag", Kokkos::RangePolicy<ExecSpace>(0, p.size()), KOKKOS_LAMBDA(int i) {
        const Real c = -zeta * m(i);
        for (int d = 0; d < D; ++d) f(i, d) += c * v(i, d);
      });
}

}  // namespace mesoflow::sp
