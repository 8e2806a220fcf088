// tether_springs.hpp — Hookean springs holding solid particles (walls, pillars) at their sites
// (paper §2.5.1: k_S = 12.5 ε/σ², on top of the MDPD forces):
//   F_i = −k_S (x_i − s_i)   (minimum image),   U = ½ k_S |x_i − s_i|²,
// for solid particles only; fluid particles have no site.
#pragma once

#include "../common/kernel_launch.hpp"
#include "kernels/common/box.hpp"
#include "kernels/common/particles.hpp"
#include "particle_types.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace mesoflow::mdpd {

template <int D, class Real, class ExecSpace>
class TetherSprings {
 public:
  using vector_view = typename Particles<D, Real, ExecSpace>::vector_view;

  explicit TetherSprings(Real k_S) : k_(k_S) {
    if (!(std::isfinite(double(k_S)) && k_S >= Real(0)))
      throw std::invalid_argument("tether springs: k_S must be >= 0, got " + std::to_string(double(k_S)));
  }

  Real stiffness() const { return k_; }

  void accumulate(const Particles<D, Real, ExecSpace>& p, const vector_view& site, const Box<D, Real>& box) const {
    if (k_ == Real(0)) return;
    const auto x = p.x, f = p.f;
    const auto type = p.type;
    const Real k = k_;
    mesoflow::launch::parallel_for(
        "mesoflow::mdpd::tether_springs", Kokkos::RangePolicy<ExecSpace>(0, p.size()), KOKKOS_LAMBDA(int i) {
          if (!is_solid(type(i))) return;
          Vec<D, Real> dr = Vec<D, Real>::load(x, i) - Vec<D, Real>::load(site, i);
          box.minimum_image(dr);
          for (int d = 0; d < D; ++d) f(i, d) -= k * dr[d];
        });
  }

  double energy(const Particles<D, Real, ExecSpace>& p, const vector_view& site, const Box<D, Real>& box) const {
    const auto x = p.x;
    const auto type = p.type;
    const double k = k_;
    double e = 0;
    mesoflow::launch::parallel_reduce(
        "mesoflow::mdpd::tether_energy", Kokkos::RangePolicy<ExecSpace>(0, p.size()),
        KOKKOS_LAMBDA(int i, double& acc) {
          if (!is_solid(type(i))) return;
          Vec<D, Real> dr = Vec<D, Real>::load(x, i) - Vec<D, Real>::load(site, i);
          box.minimum_image(dr);
          acc += 0.5 * k * double(norm2(dr));
        },
        e);
    return e;
  }

 private:
  Real k_;
};

}  // namespace mesoflow::mdpd
