// finite_difference.hpp — the central-difference check of forces against their energy, shared by the
// many-body kernel tests: for every particle and component, −(U(x + h e) − U(x − h e))/(2h) against
// the force the kernel computed at x.
#pragma once

#include "kernels/common/particles.hpp"

#include <Kokkos_Core.hpp>

#include <algorithm>
#include <cmath>

namespace mesoflow::testing {

struct GradientCheck {
  double max_error;  // max |finite difference − F| / max |F|
  double max_force;  // max |F| component
};

// `energy()` must zero p.f, add the forces at the current positions and return the energy.
template <int D, class Real, class Exec, class Energy>
GradientCheck check_gradient(const Particles<D, Real, Exec>& p, Energy&& energy, double h) {
  energy();
  // A copy, not a mirror view: on host backends a mirror view aliases p.f, which every later
  // energy() call overwrites with the forces at perturbed positions.
  const auto f = Kokkos::create_mirror(Kokkos::HostSpace(), p.f);
  Kokkos::deep_copy(f, p.f);
  const auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.x);
  GradientCheck c{0, 0};
  for (std::size_t i = 0; i < f.extent(0); ++i)
    for (int d = 0; d < D; ++d) c.max_force = std::max(c.max_force, std::abs(double(f(i, d))));
  for (std::size_t i = 0; i < f.extent(0); ++i)
    for (int d = 0; d < D; ++d) {
      const Real x0 = x(i, d);
      x(i, d) = Real(x0 + h);
      Kokkos::deep_copy(p.x, x);
      const double up = energy();
      x(i, d) = Real(x0 - h);
      Kokkos::deep_copy(p.x, x);
      const double down = energy();
      x(i, d) = x0;
      Kokkos::deep_copy(p.x, x);
      c.max_error = std::max(c.max_error, std::abs(-(up - down) / (2 * h) - double(f(i, d))) / c.max_force);
    }
  energy();  // leave the forces of the unperturbed positions
  return c;
}

}  // namespace mesoflow::testing
