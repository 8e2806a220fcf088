// fire.hpp — the FIRE minimizer (Bitzek, Koskinen, Gähler, Moseler, Gumbsch, Phys. Rev. Lett. 97,
// 170201 (2006)), used by the droplet and hopper studies to remove overlaps before gravity is
// switched on.
//
// Each iteration, with F the forces at the current positions:
//   P = F·v;  v ← (1−α) v + α |v| F/|F|
//   P > 0 for more than N_min steps: Δt ← min(f_inc Δt, Δt_max), α ← f_α α
//   P ≤ 0: Δt ← f_dec Δt, α ← α_start, v ← 0
//   MD step (semi-implicit Euler, as recommended by Guénolé et al., Comput. Mater. Sci. 175,
//   109584 (2020)):  v ← v + Δt F/m,  x ← x + Δt v;  then F is recomputed.
// Converged when the largest per-particle force norm drops below the tolerance. Non-finite forces
// or velocities (a step beyond the stability limit of the stiffest term) throw instead of passing
// for zero force.
// One fused reduction per iteration gives P, |v|², |F|² and max|F_i|.
#pragma once

#include "kernel_launch.hpp"
#include "kokkos_compat.hpp"
#include "particles.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace mesoflow {

struct FireParameters {
  double dt_start = 1e-3;
  double dt_max = 1e-2;        // Bitzek et al.: about 10 × the MD time step
  double alpha_start = 0.1;
  double f_alpha = 0.99;
  double f_inc = 1.1;
  double f_dec = 0.5;
  int n_min = 5;
  int max_iterations = 100000;
  double force_tolerance = 1e-10;  // on max_i |F_i|

  void validate() const {
    auto require = [](bool ok, const std::string& what) {
      if (!ok) throw std::invalid_argument("fire: " + what);
    };
    require(dt_start > 0, "dt_start must be > 0");
    require(dt_max >= dt_start, "dt_max must be >= dt_start");
    require(alpha_start > 0 && alpha_start < 1, "alpha_start must be in (0, 1)");
    require(f_alpha > 0 && f_alpha <= 1, "f_alpha must be in (0, 1]");
    require(f_inc >= 1, "f_inc must be >= 1");
    require(f_dec > 0 && f_dec < 1, "f_dec must be in (0, 1)");
    require(n_min >= 0, "n_min must be >= 0");
    require(max_iterations > 0, "max_iterations must be > 0");
    require(force_tolerance > 0, "force_tolerance must be > 0");
  }
};

struct FireResult {
  bool converged = false;
  int iterations = 0;
  double energy = 0;
  double max_force = 0;
};

namespace detail {
struct FirePowers {
  double power, v2, f2, max_f2;
};

template <class VectorView, class ScalarView, int D>
struct FirePowerFunctor {
  using value_type = FirePowers;
  VectorView v, f;
  KOKKOS_INLINE_FUNCTION void operator()(int i, value_type& acc) const {
    double fi2 = 0;
    for (int d = 0; d < D; ++d) {
      acc.power += double(f(i, d)) * double(v(i, d));
      acc.v2 += double(v(i, d)) * double(v(i, d));
      fi2 += double(f(i, d)) * double(f(i, d));
    }
    acc.f2 += fi2;
    if (fi2 > acc.max_f2) acc.max_f2 = fi2;
  }
  KOKKOS_INLINE_FUNCTION void init(value_type& acc) const { acc.power = acc.v2 = acc.f2 = acc.max_f2 = 0; }
  KOKKOS_INLINE_FUNCTION void join(MESOFLOW_JOIN_ARGS(value_type)) const {
    dst.power += src.power;
    dst.v2 += src.v2;
    dst.f2 += src.f2;
    if (src.max_f2 > dst.max_f2) dst.max_f2 = src.max_f2;
  }
};

// One FIRE move: v ← zero_v (mix_v v + mix_f F), then v += h F/m, x += h v. A function of its own:
// nvcc rejects a KOKKOS_LAMBDA in a function template instantiated with a host lambda's type, as
// fire_minimize is with its force callback.
template <int D, class Real, class ExecSpace>
void fire_move(const Particles<D, Real, ExecSpace>& p, Real h, Real zero_v, Real mix_v, Real mix_f) {
  const auto x = p.x, v = p.v, f = p.f;
  const auto m = p.mass;
  mesoflow::launch::parallel_for(
      "mesoflow::fire::step", Kokkos::RangePolicy<ExecSpace>(0, p.size()), KOKKOS_LAMBDA(int i) {
        const Real inv_m = Real(1) / m(i);
        for (int d = 0; d < D; ++d) {
          const Real mixed = zero_v * (mix_v * v(i, d) + mix_f * f(i, d));
          v(i, d) = mixed + h * f(i, d) * inv_m;
          x(i, d) += h * v(i, d);
        }
      });
}
}  // namespace detail

// Minimizes the energy whose forces compute_forces() writes into p.f (overwriting them) and
// whose value it returns. Velocities are used as FIRE's inertia and are zero on return.
template <int D, class Real, class ExecSpace, class ForceFunction>
FireResult fire_minimize(const Particles<D, Real, ExecSpace>& p, ForceFunction&& compute_forces,
                         const FireParameters& params) {
  params.validate();
  const auto v = p.v, f = p.f;
  const int n = int(p.size());
  Kokkos::deep_copy(v, Real(0));

  double dt = params.dt_start, alpha = params.alpha_start;
  int steps_since_negative = 0;
  FireResult result;
  result.energy = compute_forces();
  using Functor = detail::FirePowerFunctor<decltype(p.v), decltype(p.mass), D>;
  for (result.iterations = 0;; ++result.iterations) {
    detail::FirePowers s;
    mesoflow::launch::parallel_reduce("mesoflow::fire::powers", Kokkos::RangePolicy<ExecSpace>(0, n), Functor{v, f}, s);
    if (!std::isfinite(s.power) || !std::isfinite(s.v2) || !std::isfinite(s.f2))
      throw std::runtime_error("fire_minimize: non-finite forces or velocities at iteration " +
                               std::to_string(result.iterations) + " (dt_max " + std::to_string(params.dt_max) +
                               " too large for the stiffest term?)");
    result.max_force = kmath::sqrt(s.max_f2);
    if (result.max_force < params.force_tolerance) {
      result.converged = true;
      break;
    }
    if (result.iterations >= params.max_iterations) break;

    Real mix_v = Real(1), mix_f = Real(0), zero_v = Real(1);
    if (s.power > 0) {
      mix_v = Real(1 - alpha);
      mix_f = s.f2 > 0 ? Real(alpha * std::sqrt(s.v2 / s.f2)) : Real(0);
      if (++steps_since_negative > params.n_min) {
        dt = dt * params.f_inc < params.dt_max ? dt * params.f_inc : params.dt_max;
        alpha *= params.f_alpha;
      }
    } else {
      steps_since_negative = 0;
      dt *= params.f_dec;
      alpha = params.alpha_start;
      zero_v = Real(0);
    }
    detail::fire_move(p, Real(dt), zero_v, mix_v, mix_f);
    result.energy = compute_forces();
  }
  Kokkos::deep_copy(v, Real(0));
  return result;
}

}  // namespace mesoflow
