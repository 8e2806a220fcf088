// vertex_wall_repulsion.hpp — repulsion between the vertices of a deformable polygon and the walls and
// obstacles (capillary-droplet study, eq. 3):
//   U_w = Σ_i (ε_w/2)(1 − 2d_i/δ)² Θ(1 − 2d_i/δ),
// d_i the signed distance from vertex i to the nearest surface, δ the vertex diameter. The harmonic
// contact law is shared with the SP model (kernels/common/harmonic_surface_repulsion.hpp).
#pragma once

#include "kernels/common/harmonic_surface_repulsion.hpp"

namespace mesoflow::dp {

// VertexWallRepulsion<Real>(ε_w, vertex diameter δ).
template <class Real>
using VertexWallRepulsion = HarmonicSurfaceRepulsion<Real>;

}  // namespace mesoflow::dp
