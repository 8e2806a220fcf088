// langevin.hpp — Langevin thermostat: friction and random force on every particle,
//   F_i += −γ m_i v_i + √(2 γ m_i k_BT / Δt) ξ_i,   ⟨ξ⟩ = 0, ⟨ξ ξ⟩ = 1,
// whose random and frictional parts balance (fluctuation–dissipation) so that free particles
// sample the Maxwell distribution at k_BT (the scheme of LAMMPS' fix langevin). ξ comes from the
// counter-based generator keyed on (seed, step, particle), so a run is reproducible for any thread
// count and restarts continue the same noise.
#pragma once

#include "kernel_launch.hpp"
#include "kokkos_compat.hpp"
#include "particles.hpp"
#include "random.hpp"

#include <cstdint>
#include <stdexcept>
#include <string>

namespace mesoflow {

template <class Real>
struct LangevinThermostat {
  Real gamma;        // friction rate 1/τ_damp
  Real temperature;  // k_BT
  std::uint64_t seed;

  LangevinThermostat(Real gamma_, Real temperature_, std::uint64_t seed_)
      : gamma(gamma_), temperature(temperature_), seed(seed_) {
    if (!(gamma_ >= Real(0))) throw std::invalid_argument("langevin: gamma must be >= 0");
    if (!(temperature_ >= Real(0))) throw std::invalid_argument("langevin: temperature must be >= 0");
  }

  bool active() const { return gamma > Real(0); }

  // Adds the thermostat forces for time step `step`; v is the velocity the integrator hands to
  // velocity-dependent forces.
  template <int D, class ExecSpace>
  void accumulate(const Particles<D, Real, ExecSpace>& p,
                  const typename Particles<D, Real, ExecSpace>::vector_view& v, Real dt,
                  std::int64_t step) const {
    const auto f = p.f;
    const auto m = p.mass;
    const Real g = gamma, noise2 = Real(2) * gamma * temperature / dt;
    const std::uint64_t key = seed;
    mesoflow::launch::parallel_for(
        "mesoflow::langevin::accumulate", Kokkos::RangePolicy<ExecSpace>(0, p.size()), KOKKOS_LAMBDA(int i) {
          RandomStream xi = particle_stream(key, std::uint64_t(step), std::uint32_t(i));
          const Real amplitude = kmath::sqrt(noise2 * m(i));
          for (int d = 0; d < D; ++d) f(i, d) += -g * m(i) * v(i, d) + amplitude * xi.template normal<Real>();
        });
  }
};

}  // namespace mesoflow
