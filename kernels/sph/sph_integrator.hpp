// sph_integrator.hpp — the paper's velocity-Verlet scheme with density integration and an
// extrapolated velocity, eqs. (11)–(16) (§2.5; LAMMPS' `fix sph`, which the DMP model runs on):
//
//   first_half:   u*_i = u_i^n + Δt/(2 m_i) f_i^n                     (11)
//                 ρ*_i = ρ_i^n + Δt/2 ρ̇_i^n                          (12)
//                 ū_i  = u_i^n + Δt/m_i f_i^n                         (13)
//                 x_i^{n+1} = x_i^n + Δt u*_i                         (14)
//   then:         ρ̇^{n+1} (eq. 4) and f^{n+1} (eq. 5) at x^{n+1}, with p = p(ρ*) (eq. 6) and
//                 u_ij = ū_i − ū_j in both (sph_pair_interactions.hpp)
//   second_half:  u_i^{n+1} = u*_i + Δt/(2 m_i) f_i^{n+1}             (15)
//                 ρ_i^{n+1} = ρ*_i + Δt/2 ρ̇_i^{n+1}                  (16)
//
// The paper introduces ū for the continuity equation (to stop the lag of the half-step velocity
// from spoiling mass conservation) and writes both eq. (4) and eq. (5) with the same u_ij; LAMMPS
// uses ū in both too, and so do we. ū is the explicit-Euler prediction of u^{n+1}: the
// velocity-dependent (viscous) force is then evaluated at the velocity of the time it belongs to.
// Its price is a tighter stability limit for the viscous term (sph_time_step.hpp).
//
// Wall particles (particle_types.hpp) integrate their density by eqs. (12) and (16) but are never
// accelerated: they keep their prescribed velocity (zero for fixed walls, ±V for the sliding walls
// of a shear cell) and move with it, x^{n+1} = x^n + Δt v; their ū is that velocity.
#pragma once

#include "../common/kernel_launch.hpp"
#include "kernels/common/particles.hpp"
#include "particle_types.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace mesoflow::sph {

template <int D, class Real, class ExecSpace>
class SphIntegrator {
 public:
  using vector_view = typename Particles<D, Real, ExecSpace>::vector_view;
  using scalar_view = Kokkos::View<Real*, ExecSpace>;

  explicit SphIntegrator(Real dt) { set_dt(dt); }

  Real dt() const { return dt_; }
  void set_dt(Real dt) {
    if (!(std::isfinite(double(dt)) && dt > Real(0)))
      throw std::invalid_argument("sph: time step dt must be > 0, got " + std::to_string(double(dt)));
    dt_ = dt;
  }

  // Eqs. (11)–(14): p.v ← u*, rho ← ρ*, u_bar ← ū, p.x ← x^{n+1}, from p.f = f^n and drho = ρ̇^n.
  void first_half(const Particles<D, Real, ExecSpace>& p, const scalar_view& rho, const scalar_view& drho,
                  const vector_view& u_bar) const {
    const auto x = p.x, v = p.v, f = p.f;
    const auto m = p.mass;
    const auto type = p.type;
    const Real dt = dt_, half_dt = Real(0.5) * dt_;
    mesoflow::launch::parallel_for(
        "mesoflow::sph::integrate_first_half", Kokkos::RangePolicy<ExecSpace>(0, p.size()), KOKKOS_LAMBDA(int i) {
          rho(i) += half_dt * drho(i);
          if (is_fixed(type(i))) {
            for (int d = 0; d < D; ++d) {
              u_bar(i, d) = v(i, d);
              x(i, d) += dt * v(i, d);
            }
            return;
          }
          const Real inv_m = Real(1) / m(i);
          for (int d = 0; d < D; ++d) {
            const Real a = f(i, d) * inv_m;
            u_bar(i, d) = v(i, d) + dt * a;
            v(i, d) += half_dt * a;
            x(i, d) += dt * v(i, d);
          }
        });
  }

  // Eqs. (15)–(16): p.v ← u^{n+1}, rho ← ρ^{n+1}, from p.f = f^{n+1} and drho = ρ̇^{n+1}.
  void second_half(const Particles<D, Real, ExecSpace>& p, const scalar_view& rho, const scalar_view& drho) const {
    const auto v = p.v, f = p.f;
    const auto m = p.mass;
    const auto type = p.type;
    const Real half_dt = Real(0.5) * dt_;
    mesoflow::launch::parallel_for(
        "mesoflow::sph::integrate_second_half", Kokkos::RangePolicy<ExecSpace>(0, p.size()), KOKKOS_LAMBDA(int i) {
          rho(i) += half_dt * drho(i);
          if (is_fixed(type(i))) return;
          const Real inv_m = Real(1) / m(i);
          for (int d = 0; d < D; ++d) v(i, d) += half_dt * f(i, d) * inv_m;
        });
  }

 private:
  Real dt_ = 0;
};

}  // namespace mesoflow::sph
