// obstacle_repulsion.hpp — repulsion between a soft-particle droplet and the obstacles and walls
// (capillary-droplet study, eq. 8):
//   U_w = (ε_w/2)(1 − 2d/σ)² Θ(1 − 2d/σ),
// σ the droplet diameter and d the signed distance from the droplet's centre to the nearest surface
// (d = r − σ_ob/2 for an obstacle of diameter σ_ob whose centre is r away): the droplet is a soft
// disk that overlaps the surface when d < σ/2. The harmonic contact law is shared with the DP model
// (kernels/common/harmonic_surface_repulsion.hpp).
#pragma once

#include "kernels/common/harmonic_surface_repulsion.hpp"

namespace mesoflow::sp {

// ObstacleRepulsion<Real>(ε_w, droplet diameter σ).
template <class Real>
using ObstacleRepulsion = HarmonicSurfaceRepulsion<Real>;

}  // namespace mesoflow::sp
