// obstacle_repulsion.hpp — repulsion between a soft-particle droplet and the obstacles and walls
// (capillary-droplet study, eq. 8):
//   U_w = Σ_s (ε_w/2)(1 − 2d_s/σ)² Θ(1 − 2d_s/σ),
// σ the droplet diameter and d_s the signed distance from the droplet's centre to surface s
// (d = r − σ_ob/2 for an obstacle of diameter σ_ob whose centre is r away): the droplet is a soft
// disk that overlaps a surface when d_s < σ/2; eq. 8 is written for the closest obstacle and summed
// over every obstacle it overlaps. The harmonic contact law is shared with the DP model
// (kernels/common/harmonic_surface_repulsion.hpp).
#pragma once

#include "kernels/common/harmonic_surface_repulsion.hpp"

namespace mesoflow::sp {

// ObstacleRepulsion<Real>(ε_w, droplet diameter σ).
template <class Real>
using ObstacleRepulsion = HarmonicSurfaceRepulsion<Real>;

}  // namespace mesoflow::sp
