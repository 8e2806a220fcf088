// region_body_force.hpp — body forces that drive MDPD flows. The driving force of the pillar study (paper §2.5.2, Fig. 2): a body
// force f_b along +x on every fluid particle inside the driving region x ∈ [x_0, x_0 + L_d)
// (periodic in x), which imposes a pressure difference Δp = −f_b ρ L_d across the rest of the box.
// L_d = box length drives every fluid particle (periodic Poiseuille flow).
#pragma once

#include "../common/kernel_launch.hpp"
#include "kernels/common/box.hpp"
#include "kernels/common/particles.hpp"
#include "particle_types.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace mesoflow::mdpd {

template <class Real>
struct DrivingRegion {
  Real force = 0;     // f_b
  Real x0 = 0;        // start of the region
  Real length = 0;    // L_d

  bool active() const { return force != Real(0) && length > Real(0); }

  // Is x (already wrapped into the box along axis 0) inside the region, box length Lx?
  KOKKOS_INLINE_FUNCTION bool contains(Real x, Real Lx) const {
    Real s = x - x0;
    s -= Lx * kmath::floor(s / Lx);
    return s < length;
  }
};

template <int D, class Real, class ExecSpace>
void add_region_body_force(const Particles<D, Real, ExecSpace>& p, const DrivingRegion<Real>& region,
                           const Box<D, Real>& box) {
  if (!region.active()) return;
  const auto x = p.x, f = p.f;
  const auto type = p.type;
  const Real Lx = box.length[0];
  mesoflow::launch::parallel_for(
      "mesoflow::mdpd::region_body_force", Kokkos::RangePolicy<ExecSpace>(0, p.size()), KOKKOS_LAMBDA(int i) {
        if (type(i) == particle_type::fluid && region.contains(x(i, 0), Lx)) f(i, 0) += region.force;
      });
}

// The periodic-Poiseuille force of the viscosity measurement (Backer et al., J. Chem. Phys. 122,
// 154503 (2005)): +f along x on fluid particles in the lower half of the box along axis D−1,
// −f in the upper half. The steady profile is a pair of opposite parabolas,
//   u_x(z) = ±(ρ f / 2η) z' (L/2 − z'),   z' = z mod L/2,
// from whose amplitude the viscosity η follows.
template <class Real>
struct SplitBodyForce {
  Real force = 0;
  bool active() const { return force != Real(0); }
};

template <int D, class Real, class ExecSpace>
void add_split_body_force(const Particles<D, Real, ExecSpace>& p, const SplitBodyForce<Real>& split,
                          const Box<D, Real>& box) {
  if (!split.active()) return;
  const auto x = p.x, f = p.f;
  const auto type = p.type;
  const Real lo = box.lo[D - 1], L = box.length[D - 1], g = split.force;
  mesoflow::launch::parallel_for(
      "mesoflow::mdpd::split_body_force", Kokkos::RangePolicy<ExecSpace>(0, p.size()), KOKKOS_LAMBDA(int i) {
        if (type(i) != particle_type::fluid) return;
        Real s = (x(i, D - 1) - lo) / L;
        s -= kmath::floor(s);
        f(i, 0) += s < Real(0.5) ? g : -g;
      });
}

inline void validate_driving_region(double force, double length, double box_length) {
  if (!std::isfinite(force))
    throw std::invalid_argument("driving force f_b must be finite, got " + std::to_string(force));
  if (!(std::isfinite(length) && length > 0 && length <= box_length))
    throw std::invalid_argument("driving length L_d must be in (0, L_x = " + std::to_string(box_length) +
                                "], got " + std::to_string(length));
}

}  // namespace mesoflow::mdpd
