// disc_wca.hpp — steric repulsion of the rigid discs, eq. (B.4):
//   V_WCA(r) = 4ε [(r0/r)^12 − (r0/r)^6] + ε   for 0 < r < 2^{1/6} r0, 0 beyond,
// with r = |X_i − X_j| − 2R between discs (minimum image on periodic axes) and r = (distance of the
// centre from the wall surface) − R between a disc and each channel wall (y = lo_1 and
// y = lo_1 + length_1 when axis 1 of the box is bounded). The paper takes ε = k_BT, r0 = Δx.
// The potential is defined for r > 0 (surfaces not touching); the steps of the disc dynamics are
// small enough that r never reaches 0 (V(0.8 r0) ≈ 44 ε already).
//
// A full neighbour loop over the disc bins (RigidDiscs::bins(), bins ≥ 2R + 2^{1/6} r0 wide): each
// disc sums its own force, so the pair forces are equal and opposite bitwise and the result does not
// depend on the thread count. The forces are central: no torque.
#pragma once

#include "../common/kernel_launch.hpp"
#include "kernels/common/kokkos_compat.hpp"
#include "kernels/common/vec.hpp"
#include "kernels/mpc/rigid_discs.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace mesoflow::mpc {

template <class Real>
struct WcaPotential {
  Real epsilon, r0, cutoff;  // cutoff = 2^{1/6} r0

  WcaPotential(Real epsilon_, Real r0_)
      : epsilon(epsilon_), r0(r0_), cutoff(Real(std::pow(2.0, 1.0 / 6.0) * double(r0_))) {
    if (!(epsilon_ >= Real(0)) || !std::isfinite(double(epsilon_)))
      throw std::invalid_argument("WCA: epsilon must be finite and >= 0, got " + std::to_string(double(epsilon_)));
    if (!(r0_ > Real(0)) || !std::isfinite(double(r0_)))
      throw std::invalid_argument("WCA: r0 must be finite and > 0, got " + std::to_string(double(r0_)));
  }

  // For a surface separation r: returns false beyond the cutoff; otherwise sets the energy V(r)
  // and force = −dV/dr = (24ε/r)[2(r0/r)^12 − (r0/r)^6] (positive: repulsive).
  KOKKOS_INLINE_FUNCTION bool evaluate(Real r, Real& force, Real& energy) const {
    if (!(r < cutoff)) return false;
    const Real s2 = (r0 / r) * (r0 / r);
    const Real s6 = s2 * s2 * s2;
    energy = Real(4) * epsilon * (s6 * s6 - s6) + epsilon;
    force = Real(24) * epsilon * (Real(2) * s6 * s6 - s6) / r;
    return true;
  }
};

namespace wca_detail {

// Force on disc k (pairs and walls) and its energy, the pair energy counted half.
template <class Real, class ExecSpace>
KOKKOS_INLINE_FUNCTION Vec<2, Real> disc_force(int k, const WcaPotential<Real>& wca,
                                               const Kokkos::View<Real* [2], Kokkos::LayoutLeft, ExecSpace>& X,
                                               const DiscBinsView<Real, ExecSpace>& bins, Real radius, double& energy) {
  const Vec<2, Real> xk = Vec<2, Real>::load(X, k);
  Vec<2, Real> f = Vec<2, Real>::zero();
  const Real contact = Real(2) * radius;
  bins.for_each_near(xk, [&](int j) {
    if (j == k) return;
    const Vec<2, Real> dr = bins.separation(xk, Vec<2, Real>::load(X, j));
    const Real dist = kmath::sqrt(norm2(dr));
    Real fr, e;
    if (wca.evaluate(dist - contact, fr, e)) {
      f += (fr / dist) * dr;
      energy += 0.5 * double(e);
    }
  });
  if (!bins.box.periodic[1]) {
    const Real bottom = bins.box.lo[1], top = bins.box.lo[1] + bins.box.length[1];
    Real fr, e;
    if (wca.evaluate(xk[1] - bottom - radius, fr, e)) {
      f[1] += fr;
      energy += double(e);
    }
    if (wca.evaluate(top - xk[1] - radius, fr, e)) {
      f[1] -= fr;
      energy += double(e);
    }
  }
  return f;
}

}  // namespace wca_detail

// discs.force += the WCA forces of the current centres; the bins must be those of the current
// centres (RigidDiscs::build_bins / move) with a width ≥ 2R + wca.cutoff.
template <class Real, class ExecSpace>
void accumulate_disc_wca(const WcaPotential<Real>& wca, const RigidDiscs<Real, ExecSpace>& discs) {
  const auto bins = discs.bins();
  if (!(discs.bin_width() >= Real(2) * discs.radius() + wca.cutoff))
    throw std::invalid_argument("disc WCA: disc bins of width " + std::to_string(double(discs.bin_width())) +
                                " are narrower than 2R + cutoff = " +
                                std::to_string(double(Real(2) * discs.radius() + wca.cutoff)));
  const auto X = discs.x;
  const auto F = discs.force;
  const Real radius = discs.radius();
  mesoflow::launch::parallel_for(
      "mesoflow::mpc::disc_wca::forces", Kokkos::RangePolicy<ExecSpace>(0, discs.size()), KOKKOS_LAMBDA(int k) {
        double e = 0;
        const Vec<2, Real> f = wca_detail::disc_force<Real, ExecSpace>(k, wca, X, bins, radius, e);
        F(k, 0) += f[0];
        F(k, 1) += f[1];
      });
}

// Total WCA energy of the current centres (a reduction: diagnostics and tests).
template <class Real, class ExecSpace>
double disc_wca_energy(const WcaPotential<Real>& wca, const RigidDiscs<Real, ExecSpace>& discs) {
  const auto bins = discs.bins();
  const auto X = discs.x;
  const Real radius = discs.radius();
  double energy = 0;
  mesoflow::launch::parallel_reduce(
      "mesoflow::mpc::disc_wca::energy", Kokkos::RangePolicy<ExecSpace>(0, discs.size()),
      KOKKOS_LAMBDA(int k, double& acc) {
        wca_detail::disc_force<Real, ExecSpace>(k, wca, X, bins, radius, acc);
      },
      energy);
  return energy;
}

}  // namespace mesoflow::mpc
