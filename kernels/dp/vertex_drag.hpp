// vertex_drag.hpp — uniform viscous drag of the background fluid on the vertices of deformable
// polygons (hopper study, eq. 11):
//   F_m,i = −(ζ/N_v) v_m,i,
// N_v the number of vertices of polygon m, so a rigidly moving polygon feels −ζ v in total whatever
// its N_v. Unlike the SP drag of eq. 5 (kernels/sp/mass_proportional_drag.hpp) it is not
// proportional to mass: a large polygon relaxes at the rate ζ/M_l, a small one at ζ/M_s. The same
// coefficient acts everywhere (no near-wall enhancement, cf. near_wall_drag.hpp). v is the
// integrator's velocity for velocity-dependent forces (velocity_verlet.hpp). It dissipates:
// Σ F·v = −Σ_m (ζ/N_v) Σ_i |v_m,i|² ≤ 0.
//
// Only the polygon vertices [0, polygons.num_vertices()) feel it; free particles after them are
// left alone. Each vertex writes its own force (adds, never overwrites).
#pragma once

#include "../common/kernel_launch.hpp"
#include "polygons.hpp"

#include "kernels/common/kokkos_compat.hpp"
#include "kernels/common/particles.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace mesoflow::dp {

// Adds eq. 11's drag to p.f; skipped at ζ = 0.
template <class Real, class ExecSpace>
void accumulate_vertex_drag(Real zeta, const Polygons<Real, ExecSpace>& polygons,
                            const Particles<2, Real, ExecSpace>& p,
                            const typename Particles<2, Real, ExecSpace>::vector_view& velocity) {
  if (!(zeta >= Real(0)) || !std::isfinite(double(zeta)))
    throw std::invalid_argument("dp::vertex_drag: zeta must be finite and >= 0, got " + std::to_string(double(zeta)));
  if (int(p.size()) < polygons.num_vertices() || int(velocity.extent(0)) < polygons.num_vertices())
    throw std::invalid_argument("dp::vertex_drag: the polygons have " + std::to_string(polygons.num_vertices()) +
                                " vertices but the particle set only " + std::to_string(p.size()));
  if (zeta == Real(0)) return;  // a term whose coefficient is zero costs nothing
  const auto offset = polygons.offset;
  const auto body = polygons.body;
  const auto v = velocity;
  const auto f = p.f;
  mesoflow::launch::parallel_for(
      "mesoflow::dp::vertex_drag", Kokkos::RangePolicy<ExecSpace>(0, polygons.num_vertices()), KOKKOS_LAMBDA(int i) {
        const int b = body(i);
        const Real c = -zeta / Real(offset(b + 1) - offset(b));
        for (int d = 0; d < 2; ++d) f(i, d) += c * v(i, d);
      });
}

}  // namespace mesoflow::dp
