// vertex_contacts.hpp — contacts between deformable polygons with surface roughness (hopper study):
// each vertex of particle m is a disk of diameter δ_m = l_m,0, and vertices of different particles
// repel (eq. 9)
//   U_int = Σ_{m<n} Σ_{i,j} (ε_c/2)(1 − δ_mi,nj/δ_mn)² Θ(1 − δ_mi,nj/δ_mn),   δ_mn = (δ_m + δ_n)/2,
// and rub with kinetic friction (eq. 12) F_mi = −μ Σ_{n≠m} Σ_j (v_mi − v_nj) Θ(1 − δ_mi,nj/δ_mn).
// These are the soft-sphere repulsion and friction of the SP model (kernels/sp/pair_repulsion.hpp,
// kinetic_friction.hpp) applied to vertices, the particle type of a vertex selecting its δ, over a
// neighbor list that excludes pairs of the same body (BodyExclusion::same_body, Particles::body =
// the polygon): a pair within one particle is never a contact. The functions below refuse any other
// list, so the exclusion cannot be forgotten.
#pragma once

#include "kernels/common/neighbor_list.hpp"
#include "kernels/common/pair_force.hpp"
#include "kernels/sp/kinetic_friction.hpp"
#include "kernels/sp/pair_repulsion.hpp"

#include <stdexcept>

namespace mesoflow::dp {

// VertexContactRepulsion<Real>(ε_c, {δ of each vertex type}).
template <class Real>
using VertexContactRepulsion = sp::SoftSphereRepulsion<Real>;

template <class Real, class ExecSpace>
void require_same_body_exclusion(const NeighborList<2, Real, ExecSpace>& list) {
  if (list.exclusion() != BodyExclusion::same_body)
    throw std::invalid_argument(
        "dp vertex contacts: the neighbor list must exclude pairs of the same body (BodyExclusion::same_body)");
}

// Adds eq. 9's forces to p.f and returns U_int.
template <class Real, class ExecSpace>
double accumulate_vertex_contacts(const VertexContactRepulsion<Real>& contacts, const Particles<2, Real, ExecSpace>& p,
                                  const NeighborList<2, Real, ExecSpace>& list, const Box<2, Real>& box,
                                  PairForce<2, Real, ExecSpace>& pair) {
  require_same_body_exclusion(list);
  return pair.accumulate(contacts, p, list, box);
}

// Adds eq. 12's friction to p.f (full list; skipped at μ = 0); `component` as in kinetic_friction.hpp
// (tangential: the part of v_mi − v_nj perpendicular to the vertex–vertex vector).
template <class Real, class ExecSpace>
void accumulate_vertex_friction(Real mu, const VertexContactRepulsion<Real>& contacts,
                                const Particles<2, Real, ExecSpace>& p,
                                const typename Particles<2, Real, ExecSpace>::vector_view& velocity,
                                const NeighborList<2, Real, ExecSpace>& list, const Box<2, Real>& box,
                                sp::FrictionComponent component = sp::FrictionComponent::full) {
  require_same_body_exclusion(list);
  sp::accumulate_kinetic_friction(mu, contacts, p, velocity, list, box, component);
}

}  // namespace mesoflow::dp
