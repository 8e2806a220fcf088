// gravity.hpp — uniform gravity on whole particles, one particle per body: F_i = M_i g,
// U_g = −Σ_i M_i g·r_i (hopper-flows eq. 4 for the soft particles; capillary-droplets eq. 4,
// U_g = −M g h, for the soft-particle droplet). The DP counterpart, gravity on the vertices inside
// the fused shape loop, is kernels/dp/gravity.hpp.
//
// It *sets* the force array (f ← M g): a scene evaluates it first in a step, so it also clears the
// previous step's forces. g = 0 gives f = 0 (a scene with gravity switched off). M_i is the
// particle's Particles::mass.
#pragma once

#include "../common/kernel_launch.hpp"
#include "kernels/common/particles.hpp"
#include "kernels/common/vec.hpp"

#include <Kokkos_Core.hpp>

namespace mesoflow::sp {

template <int D, class Real, class ExecSpace>
void set_gravity_forces(const Particles<D, Real, ExecSpace>& p, const Vec<D, Real>& g) {
  const auto f = p.f;
  const auto m = p.mass;
  mesoflow::launch::parallel_for(
      "mesoflow::sp::gravity", Kokkos::RangePolicy<ExecSpace>(0, p.size()), KOKKOS_LAMBDA(int i) {
        for (int d = 0; d < D; ++d) f(i, d) = m(i) * g[d];
      });
}

}  // namespace mesoflow::sp
