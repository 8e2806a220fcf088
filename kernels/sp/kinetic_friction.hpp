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
// One pass over a full neighbor list, each particle summing its own contacts (deterministic, no
// atomics; dynamically scheduled, as pair_force.hpp's accumulate_forces); v is the integrator's velocity for velocity-dependent forces (velocity_verlet.hpp).
#pragma once

#include "kernels/common/box.hpp"
#include "kernels/common/kokkos_compat.hpp"
#include "kernels/common/neighbor_list.hpp"
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
  const auto x = p.x;
  const auto v = velocity;
  const auto f = p.f;
  const auto type = p.type;
  const auto nbr = list.data();
  const bool tangential = component == FrictionComponent::tangential;
  Kokkos::parallel_for(
      "mesoflow::sp::kinetic_friction", Kokkos::RangePolicy<ExecSpace, Kokkos::Schedule<Kokkos::Dynamic>>(0, p.size()).set_chunk_size(64),
      KOKKOS_LAMBDA(int row) {
        const int i = nbr.particle(row);
        const Vec<D, Real> xi = Vec<D, Real>::load(x, i);
        const Vec<D, Real> vi = Vec<D, Real>::load(v, i);
        const int ti = type(i);
        Vec<D, Real> fi = Vec<D, Real>::zero();
        const int nn = nbr.num_neighbors(row);
        for (int k = 0; k < nn; ++k) {
          const int j = nbr.neighbor(row, k);
          Vec<D, Real> dr = xi - Vec<D, Real>::load(x, j);
          box.minimum_image(dr);
          const Real s = contacts.contact[ti][type(j)];
          const Real r2 = norm2(dr);
          if (!(r2 < s * s)) continue;
          Vec<D, Real> dv = vi - Vec<D, Real>::load(v, j);
          if (tangential && r2 > Real(0)) dv -= (dot(dv, dr) / r2) * dr;
          fi += (-mu) * dv;
        }
        for (int d = 0; d < D; ++d) f(i, d) += fi[d];
      });
}

}  // namespace mesoflow::sp
