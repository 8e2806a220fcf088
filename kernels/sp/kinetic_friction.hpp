// kinetic_friction.hpp — kinetic friction between overlapping soft particles (hopper study, eq. 6):
//   F_m = −μ Σ_{n≠m} (v_m − v_n) Θ(1 − r_mn/σ_mn),
// σ_mn from the particles' types as in pair_repulsion.hpp. Each contact contributes −μ(v_m − v_n) to
// m and −μ(v_n − v_m) to n, exact negatives in floating point, so the friction exchanges momentum
// pairwise and the total is zero up to the rounding of the per-particle sums; it dissipates,
// Σ_m F_m·v_m = −(μ/2) Σ_contacts |v_m − v_n|² ≤ 0.
//
// FrictionComponent::tangential damps only the part of v_m − v_n perpendicular to r_mn,
//   Δv_t = Δv − (Δv·r_mn) r_mn / r_mn²,
// as the hopper authors' public code does (github.com/YUXUANCHENG/DPM_OMP, hopperForcesSP: the
// normal coefficient is set to 0); eq. 6 as printed is FrictionComponent::full. The tangential form
// is also pairwise exactly opposite (Δv and r_mn both change sign) and dissipates
// −(μ/2) Σ_contacts |Δv_t|²; it leaves head-on collisions undamped.
//
// An evaluator of the generic pair loop (kernels/common/pair_force.hpp) over a full neighbor list,
// each particle summing its own contacts (deterministic, no atomics; dynamically scheduled, as
// PairForce::accumulate_forces); v is the integrator's velocity for velocity-dependent forces
// (velocity_verlet.hpp).
#pragma once

#include "kernels/common/box.hpp"
#include "kernels/common/kokkos_compat.hpp"
#include "kernels/common/neighbor_list.hpp"
#include "kernels/common/pair_force.hpp"
#include "kernels/common/particles.hpp"
#include "kernels/sp/pair_repulsion.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace mesoflow::sp {

// Which part of the relative velocity of two contacting particles eq. 6 damps.
enum class FrictionComponent { full, tangential };

// "full" / "tangential" (the drivers' --friction-component values).
inline FrictionComponent parse_friction_component(const std::string& name) {
  if (name == "full") return FrictionComponent::full;
  if (name == "tangential") return FrictionComponent::tangential;
  throw std::invalid_argument("friction component must be full or tangential, got '" + name + "'");
}

inline const char* to_string(FrictionComponent c) { return c == FrictionComponent::full ? "full" : "tangential"; }

// Eq. 6 as an evaluator of the generic pair loop (full lists: each particle sums its own contacts).
template <int D, class Real, class ExecSpace>
struct KineticFrictionEvaluator : PairEvaluatorTraits {
  using vector_view = typename Particles<D, Real, ExecSpace>::vector_view;
  Real mu;
  SoftSphereRepulsion<Real> contacts;
  vector_view v, f;
  Kokkos::View<int*, ExecSpace> type;
  bool tangential;

  struct Row {
    Vec<D, Real> vi;
    int ti;
    Vec<D, Real> fi;
  };
  KOKKOS_INLINE_FUNCTION Row begin(FullList, int i) const {
    return {Vec<D, Real>::load(v, i), type(i), Vec<D, Real>::zero()};
  }
  KOKKOS_INLINE_FUNCTION void operator()(FullList, Row& s, int, int j, const Vec<D, Real>& dr, Real r2,
                                         double&) const {
    const Real sigma = contacts.contact[s.ti][type(j)];
    if (!(r2 < sigma * sigma)) return;
    Vec<D, Real> dv = s.vi - Vec<D, Real>::load(v, j);
    if (tangential && r2 > Real(0)) dv -= (dot(dv, dr) / r2) * dr;
    s.fi += (-mu) * dv;
  }
  KOKKOS_INLINE_FUNCTION void end(FullList, Row& s, int i, double&) const {
    for (int d = 0; d < D; ++d) f(i, d) += s.fi[d];
  }
};

template <int D, class Real, class ExecSpace>
void accumulate_kinetic_friction(Real mu, const SoftSphereRepulsion<Real>& contacts,
                                 const Particles<D, Real, ExecSpace>& p,
                                 const typename Particles<D, Real, ExecSpace>::vector_view& velocity,
                                 const NeighborList<D, Real, ExecSpace>& list, const Box<D, Real>& box,
                                 FrictionComponent component = FrictionComponent::full) {
  if (!(mu >= Real(0)) || !std::isfinite(double(mu)))
    throw std::invalid_argument("kinetic_friction: mu must be finite and >= 0, got " + std::to_string(double(mu)));
  if (list.kind() != NeighborListKind::full)
    throw std::invalid_argument("kinetic_friction: needs a full neighbor list");
  if (mu == Real(0)) return;  // a term whose coefficient is zero costs nothing
  const KineticFrictionEvaluator<D, Real, ExecSpace> ev{
      {}, mu, contacts, velocity, p.f, p.type, component == FrictionComponent::tangential};
  for_each_pair<Kokkos::Dynamic>("mesoflow::sp::kinetic_friction", FullList{}, list, box, p.x, ev);
}

}  // namespace mesoflow::sp
