// dissipative_random_force.hpp — the DPD thermostat pair forces, eqs. (9b), (9c) and (10):
//
//   F^D_ij + F^R_ij = [−D w_R(r)² (v_ij·r̂) + R w_R(r) θ_ij/√dt] r̂_ij,   w_R = 1 − r/r_A,
//   R² = 2 k_BT D.
//
// θ_ij has zero mean and unit variance: √3 times a uniform number in (−1, 1) (Groot & Warren,
// J. Chem. Phys. 107, 4423 (1997), who showed the distribution does not matter beyond its first
// two moments). It comes from the counter-based stream keyed on (seed, step, min(tag), max(tag))
// (random.hpp, pair_uniform_symmetric),
// so θ_ij = θ_ji on any list, thread count or backend, and the pair's momentum exchange cancels.
// Tags are particle identities that survive memory reordering.
#pragma once

#include "kernels/common/random.hpp"
#include "mdpd_parameters.hpp"

#include <cmath>
#include <cstdint>

namespace mesoflow::mdpd {

template <class Real>
struct DissipativeRandomForce {
  Real dissipation, noise, inv_rA;  // D, √3 R/√dt, 1/r_A
  std::uint64_t seed;

  DissipativeRandomForce(const MdpdParameters& p, std::uint64_t seed_)
      : dissipation(Real(p.dissipation())),
        noise(Real(p.R * std::sqrt(3.0 / p.dt))),
        inv_rA(Real(1 / p.r_A)),
        seed(seed_) {}

  bool active() const { return dissipation != Real(0) || noise != Real(0); }

  // |F^D + F^R| along r̂_ij for a pair at distance r < r_A; v_dot_rhat = (v_i − v_j)·r̂_ij.
  KOKKOS_INLINE_FUNCTION Real magnitude(Real r, Real v_dot_rhat, std::uint64_t step, std::uint32_t tag_i,
                                        std::uint32_t tag_j) const {
    const Real w = Real(1) - r * inv_rA;
    const Real theta = pair_uniform_symmetric<Real>(seed, step, tag_i, tag_j);
    return w * (noise * theta - dissipation * w * v_dot_rhat);
  }
};

}  // namespace mesoflow::mdpd
