// contact_number.hpp — how many surfaces touch each soft particle: other particles closer than
// their contact distance σ_mn (eq. 2's overlap, pair_repulsion.hpp) and walls closer than σ_m/2
// (eq. 3's, wall_repulsion.hpp). Not a force: the hopper's continuous flow (hopper-flows §2.4)
// re-inserts a particle "in contact with one of the bulk particles", and a particle belongs to the
// bulk packing when at least two surfaces hold it; a particle in free flight above the pile touches
// none (scenes/hopper/hopper_scene.hpp). One pass over a full neighbor list (each row counts its
// own contacts, deterministic) plus, per particle, every wall shape.
#pragma once

#include "kernels/common/geometry.hpp"
#include "kernels/common/kokkos_compat.hpp"
#include "kernels/common/neighbor_list.hpp"
#include "kernels/common/pair_force.hpp"
#include "kernels/common/particles.hpp"
#include "kernels/sp/pair_repulsion.hpp"

#include <stdexcept>
#include <string>

namespace mesoflow::sp {

template <int D, class Real, class ExecSpace>
struct ContactNumberEvaluator : PairEvaluatorTraits {
  using shape_view = typename Geometry<D, Real, ExecSpace>::shape_view;
  SoftSphereRepulsion<Real> contacts;
  Kokkos::View<int*, ExecSpace> type, z;
  typename Particles<D, Real, ExecSpace>::vector_view x;
  shape_view shapes;
  int n_walls;

  struct Row {
    int ti, n;
  };
  KOKKOS_INLINE_FUNCTION Row begin(FullList, int i) const { return {type(i), 0}; }
  KOKKOS_INLINE_FUNCTION void operator()(FullList, Row& s, int, int j, const Vec<D, Real>&, Real r2, double&) const {
    const Real sigma = contacts.contact[s.ti][type(j)];
    if (r2 < sigma * sigma) ++s.n;
  }
  KOKKOS_INLINE_FUNCTION void end(FullList, Row& s, int i, double&) const {
    const Vec<D, Real> xi = Vec<D, Real>::load(x, i);
    const Real radius = Real(0.5) * contacts.contact[s.ti][s.ti];
    for (int k = 0; k < n_walls; ++k)
      if (shapes(k).query(xi).distance < radius) ++s.n;
    z(i) = s.n;
  }
};

// z(i) ← the number of particles and walls in contact with particle i. `list` must be a full list
// built for positions within its skin of the current ones.
template <int D, class Real, class ExecSpace>
void count_contacts(const SoftSphereRepulsion<Real>& contacts, const Geometry<D, Real, ExecSpace>& walls,
                    const Particles<D, Real, ExecSpace>& p, const NeighborList<D, Real, ExecSpace>& list,
                    const Box<D, Real>& box, const Kokkos::View<int*, ExecSpace>& z) {
  if (list.kind() != NeighborListKind::full) throw std::invalid_argument("count_contacts: needs a full neighbor list");
  if (z.extent(0) != p.size()) throw std::invalid_argument("count_contacts: z must have one entry per particle");
  const ContactNumberEvaluator<D, Real, ExecSpace> ev{{}, contacts, p.type, z, p.x, walls.shapes(), walls.size()};
  for_each_pair<Kokkos::Dynamic>("mesoflow::sp::contact_number", FullList{}, list, box, p.x, ev);
}

}  // namespace mesoflow::sp
