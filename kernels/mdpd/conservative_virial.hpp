// conservative_virial.hpp — the virial W = Σ_{i<j} r_ij · F^C_ij of the MDPD conservative force,
// eq. (9a) (conservative_force.hpp), for the pressure P = (Σ_i m_i v_i² + W)/(D V) of a bulk run.
//
// With F^C_ij = f(r) r̂_ij, r_ij·F^C_ij = f(r) r. The densities are those of the last force
// evaluation (MdpdSystem::rho), the positions the current ones: after a step they are the same
// state.
//
// dissipative_virial: W_D = Σ_{i<j} r_ij · F^D_ij = −Σ D w_D(r) (r_ij · v_ij), eq. (9b), with the
// velocities the dissipative force saw (the half-step ones, v − ½dt f/m after a step). Its mean is
// not zero: the half-step velocities carry ½dt of the mean pair force. LAMMPS' pressure tallies it
// (pair_mdpd.cpp: fpair holds the conservative, dissipative and random parts); the random force's
// virial has zero mean (fresh θ_ij) and is left out.
//
// An evaluator of the generic pair loop (kernels/common/pair_force.hpp), summed by reduce_pairs:
// a half list counts each pair once, a full list twice (weighted ½).
#pragma once

#include "conservative_force.hpp"
#include "kernels/common/neighbor_list.hpp"
#include "kernels/common/pair_force.hpp"

namespace mesoflow::mdpd {

template <int D, class Real, class ExecSpace>
struct ConservativeVirialEvaluator : PairEvaluatorTraits {
  static constexpr MinimumImage image = MinimumImage::near;
  static constexpr PairScreen screen = PairScreen::branch;
  ConservativeForce<D, Real> law;
  Real cutoff2;   // r_A²
  Kokkos::View<const Real*, ExecSpace> rho;
  double weight;  // 1 on a half list, ½ on a full one

  struct Row {
    Real rho_i;
  };
  template <class Tag>
  KOKKOS_INLINE_FUNCTION Row begin(Tag, int i) const {
    return {rho(i)};
  }
  template <class Tag>
  KOKKOS_INLINE_FUNCTION void operator()(Tag, Row& s, int, int j, const Vec<D, Real>&, Real r2, double& sum) const {
    const Real r = kmath::sqrt(r2);
    sum += weight * double(r * law.magnitude(r, r2, s.rho_i, rho(j)));
  }
  template <class Tag>
  KOKKOS_INLINE_FUNCTION void end(Tag, Row&, int, double&) const {}
};

template <int D, class Real, class ExecSpace, class Velocities>
struct DissipativeVirialEvaluator : PairEvaluatorTraits {
  static constexpr MinimumImage image = MinimumImage::near;
  static constexpr PairScreen screen = PairScreen::branch;
  Real inv_rA, dissipation;
  Real cutoff2;  // r_A²
  Velocities v;
  double weight;  // 1 on a half list, ½ on a full one

  struct Row {
    Vec<D, Real> vi;
  };
  template <class Tag>
  KOKKOS_INLINE_FUNCTION Row begin(Tag, int i) const {
    Row s;
    for (int d = 0; d < D; ++d) s.vi[d] = v(i, d);
    return s;
  }
  template <class Tag>
  KOKKOS_INLINE_FUNCTION void operator()(Tag, Row& s, int, int j, const Vec<D, Real>& dr, Real r2, double& sum) const {
    const Real w = Real(1) - kmath::sqrt(r2) * inv_rA;
    Real dot = 0;
    for (int d = 0; d < D; ++d) dot += dr[d] * (s.vi[d] - v(j, d));
    sum -= weight * double(dissipation * w * w * dot);
  }
  template <class Tag>
  KOKKOS_INLINE_FUNCTION void end(Tag, Row&, int, double&) const {}
};

// W_D = Σ_{i<j} r_ij · F^D_ij over `list` (reach ≥ r_A), positions `x`, velocities `v` (n × ≥D).
template <int D, class Real, class ExecSpace, class Positions, class Velocities>
double dissipative_virial(const MdpdParameters& par, const Positions& x, const Velocities& v,
                          const NeighborList<D, Real, ExecSpace>& list, const Box<D, Real>& box) {
  const bool full = list.kind() == NeighborListKind::full;
  const DissipativeVirialEvaluator<D, Real, ExecSpace, Velocities> ev{
      {}, Real(1 / par.r_A), Real(par.dissipation()), Real(par.r_A * par.r_A), v, full ? 0.5 : 1.0};
  if (full) return reduce_pairs("mesoflow::mdpd::dissipative_virial_full", FullList{}, list, box, x, ev);
  return reduce_pairs("mesoflow::mdpd::dissipative_virial_half", HalfList{}, list, box, x, ev);
}

// W = Σ_{i<j} r_ij · F^C_ij over `list` (reach ≥ r_A), positions `x` (n × ≥D), densities `rho`.
template <int D, class Real, class ExecSpace, class Positions>
double conservative_virial(const MdpdParameters& par, const Positions& x, const Kokkos::View<Real*, ExecSpace>& rho,
                           const NeighborList<D, Real, ExecSpace>& list, const Box<D, Real>& box) {
  const bool full = list.kind() == NeighborListKind::full;
  const ConservativeVirialEvaluator<D, Real, ExecSpace> ev{
      {}, ConservativeForce<D, Real>(par), Real(par.r_A * par.r_A), rho, full ? 0.5 : 1.0};
  if (full) return reduce_pairs("mesoflow::mdpd::conservative_virial_full", FullList{}, list, box, x, ev);
  return reduce_pairs("mesoflow::mdpd::conservative_virial_half", HalfList{}, list, box, x, ev);
}

}  // namespace mesoflow::mdpd
