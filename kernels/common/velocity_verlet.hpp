// velocity_verlet.hpp — velocity Verlet for forces that depend on velocity (drag, friction,
// dissipative DPD forces), in the predicted-velocity form of Groot & Warren, J. Chem. Phys. 107,
// 4423 (1997), eq. 17:
//
//   first_half:   v ← v + ½Δt F(t)/m                  (v now at t + Δt/2)
//                 x ← x + Δt v                         (x at t + Δt)
//                 ṽ = v(t) + λ Δt F(t)/m               (velocity prediction at t + Δt)
//   forces:       F(t+Δt) = F(x(t+Δt), ṽ)
//   second_half:  v ← v + ½Δt F(t+Δt)/m               (v at t + Δt)
//
// λ = ½ evaluates the forces at the half-step velocity (ṽ is then v itself and no extra array is
// used); the scheme is then first-order accurate in the velocity-dependent part. λ = 1 predicts ṽ
// by an explicit Euler step, which makes the scheme second-order for smooth velocity-dependent
// forces (tests/common/test_integrators.cpp measures both orders on a damped oscillator). For
// purely conservative forces every λ reduces to standard, time-reversible velocity Verlet.
#pragma once

#include "kernel_launch.hpp"
#include "box.hpp"
#include "kokkos_compat.hpp"
#include "particles.hpp"

#include <stdexcept>
#include <string>

namespace mesoflow {

template <int D, class Real, class ExecSpace>
class VelocityVerlet {
 public:
  using vector_view = typename Particles<D, Real, ExecSpace>::vector_view;

  explicit VelocityVerlet(Real dt, Real lambda = Real(0.5)) : dt_(dt), lambda_(lambda) {
    if (!(dt > Real(0))) throw std::invalid_argument("velocity_verlet: dt must be > 0, got " + std::to_string(dt));
    if (!(lambda >= Real(0.5) && lambda <= Real(1)))
      throw std::invalid_argument("velocity_verlet: lambda must be in [0.5, 1], got " + std::to_string(lambda));
  }

  Real dt() const { return dt_; }
  Real lambda() const { return lambda_; }

  // Per-particle time steps: particle i advances by particle_dt(i) (each body of a batch at its own
  // stability limit; the arithmetic of each particle is that of a uniform step of its Δt). An empty
  // View returns to the uniform dt().
  void set_particle_time_steps(const Kokkos::View<Real*, ExecSpace>& particle_dt) { particle_dt_ = particle_dt; }
  const Kokkos::View<Real*, ExecSpace>& particle_time_steps() const { return particle_dt_; }

  void first_half(const Particles<D, Real, ExecSpace>& p) {
    const auto x = p.x, v = p.v, f = p.f;
    const auto m = p.mass;
    const Real half_dt = Real(0.5) * dt_, dt = dt_;
    if (particle_dt_.extent(0) > 0) {
      check_particle_dt(p);
      const auto pdt = particle_dt_;
      if (lambda_ != Real(0.5) && v_pred_.extent(0) != p.size())
        v_pred_ = vector_view(Kokkos::ViewAllocateWithoutInitializing("mesoflow::velocity_verlet::v_pred"), p.size());
      const auto vp = v_pred_;
      const Real lambda = lambda_;
      const bool predict = lambda_ != Real(0.5);
      mesoflow::launch::parallel_for(
          "mesoflow::velocity_verlet::first_half_per_particle", Kokkos::RangePolicy<ExecSpace>(0, p.size()),
          KOKKOS_LAMBDA(int i) {
            const Real inv_m = Real(1) / m(i);
            const Real dt_i = pdt(i), half_dt_i = Real(0.5) * dt_i;
            // The uniform kernels' arithmetic, term for term (bitwise the same at equal Δt).
            for (int d = 0; d < D; ++d) {
              if (predict) {
                const Real a = f(i, d) * inv_m;
                vp(i, d) = v(i, d) + (lambda * dt_i) * a;
                v(i, d) += half_dt_i * a;
              } else {
                v(i, d) += half_dt_i * f(i, d) * inv_m;
              }
              x(i, d) += dt_i * v(i, d);
            }
          });
      return;
    }
    if (lambda_ == Real(0.5)) {
      mesoflow::launch::parallel_for(
          "mesoflow::velocity_verlet::first_half", Kokkos::RangePolicy<ExecSpace>(0, p.size()),
          KOKKOS_LAMBDA(int i) {
            const Real inv_m = Real(1) / m(i);
            for (int d = 0; d < D; ++d) {
              v(i, d) += half_dt * f(i, d) * inv_m;
              x(i, d) += dt * v(i, d);
            }
          });
      return;
    }
    if (v_pred_.extent(0) != p.size())
      v_pred_ = vector_view(Kokkos::ViewAllocateWithoutInitializing("mesoflow::velocity_verlet::v_pred"), p.size());
    const auto vp = v_pred_;
    const Real predict_dt = lambda_ * dt_;
    mesoflow::launch::parallel_for(
        "mesoflow::velocity_verlet::first_half_predict", Kokkos::RangePolicy<ExecSpace>(0, p.size()),
        KOKKOS_LAMBDA(int i) {
          const Real inv_m = Real(1) / m(i);
          for (int d = 0; d < D; ++d) {
            const Real a = f(i, d) * inv_m;
            vp(i, d) = v(i, d) + predict_dt * a;
            v(i, d) += half_dt * a;
            x(i, d) += dt * v(i, d);
          }
        });
  }

  // The velocities that velocity-dependent forces must use after first_half().
  vector_view velocity_for_forces(const Particles<D, Real, ExecSpace>& p) const {
    return lambda_ == Real(0.5) ? p.v : v_pred_;
  }

  void second_half(const Particles<D, Real, ExecSpace>& p) {
    const auto v = p.v, f = p.f;
    const auto m = p.mass;
    const Real half_dt = Real(0.5) * dt_;
    if (particle_dt_.extent(0) > 0) {
      check_particle_dt(p);
      const auto pdt = particle_dt_;
      mesoflow::launch::parallel_for(
          "mesoflow::velocity_verlet::second_half_per_particle", Kokkos::RangePolicy<ExecSpace>(0, p.size()),
          KOKKOS_LAMBDA(int i) {
            const Real inv_m = Real(1) / m(i);
            const Real half_dt_i = Real(0.5) * pdt(i);
            for (int d = 0; d < D; ++d) v(i, d) += half_dt_i * f(i, d) * inv_m;
          });
      return;
    }
    mesoflow::launch::parallel_for(
        "mesoflow::velocity_verlet::second_half", Kokkos::RangePolicy<ExecSpace>(0, p.size()),
        KOKKOS_LAMBDA(int i) {
          const Real inv_m = Real(1) / m(i);
          for (int d = 0; d < D; ++d) v(i, d) += half_dt * f(i, d) * inv_m;
        });
  }

 private:
  void check_particle_dt(const Particles<D, Real, ExecSpace>& p) const {
    if (particle_dt_.extent(0) != p.size())
      throw std::invalid_argument("velocity_verlet: " + std::to_string(particle_dt_.extent(0)) +
                                  " per-particle time steps for " + std::to_string(p.size()) + " particles");
  }

  Real dt_, lambda_;
  vector_view v_pred_;
  Kokkos::View<Real*, ExecSpace> particle_dt_;  // empty: the uniform dt_
};

// Folds positions back into the box on its periodic axes (bounded axes untouched).
template <int D, class Real, class ExecSpace>
void wrap_positions(const Particles<D, Real, ExecSpace>& p, const Box<D, Real>& box) {
  const auto x = p.x;
  mesoflow::launch::parallel_for(
      "mesoflow::box::wrap_positions", Kokkos::RangePolicy<ExecSpace>(0, p.size()), KOKKOS_LAMBDA(int i) {
        Vec<D, Real> xi = Vec<D, Real>::load(x, i);
        box.wrap(xi);
        xi.store(x, i);
      });
}

}  // namespace mesoflow
