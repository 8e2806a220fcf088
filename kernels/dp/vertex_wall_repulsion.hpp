// vertex_wall_repulsion.hpp — repulsion between the vertices of a deformable polygon and the walls and
// obstacles (capillary-droplet study, eq. 3: "pairwise purely repulsive forces between the droplet
// vertices and walls"):
//   U_w = Σ_i Σ_s (ε_w/2)(1 − 2d_is/δ)² Θ(1 − 2d_is/δ),
// d_is the signed distance from vertex i to surface s (each wall shape, each obstacle), δ the vertex
// diameter. The harmonic contact law, summed over every surface within δ/2, is shared with the SP
// model (kernels/common/harmonic_surface_repulsion.hpp).
#pragma once

#include "kernels/common/harmonic_surface_repulsion.hpp"

namespace mesoflow::dp {

// VertexWallRepulsion<Real>(ε_w, vertex diameter δ).
template <class Real>
using VertexWallRepulsion = HarmonicSurfaceRepulsion<Real>;

}  // namespace mesoflow::dp
