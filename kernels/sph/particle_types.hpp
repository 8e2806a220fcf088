// particle_types.hpp — the particle types of an SPH scene with walls (paper §2.4, §3, Fig. 1a: the
// red boundary particles).
//
// Wall particles are SPH particles that are never accelerated: they keep their prescribed velocity
// — zero for the paper's fixed walls, ±V along the wall for the sliding walls of the simple-shear
// validation (§4.1: "setting x-velocity in opposite directions to the top and bottom boundaries")
// — and move with it (sph_integrator.hpp), and take part in everything else — they carry mass, integrate their density by the continuity
// eq. (4), have a pressure from the equation of state eq. (6) and a viscosity in eq. (5). Fluid
// particles near a wall thus see a full kernel support, are pushed back by the wall's pressure
// (no penetration) and dragged by its zero velocity through the viscous term (no slip). This is
// what the paper's DMP model does with its fixed boundary particles (LAMMPS' `fix sph/stationary`:
// density integrated, position and velocity not).
//
// The capsule scene (§3, Fig. 1: four types) adds membrane particles — MSM and SPH particles at
// once (§2.4), moving like fluid, with bond forces on top (kernels/msm) — and the inner fluid, the
// fluid enclosed by the membrane: SPH fluid like the outer one, its own type so that it can carry
// its own viscosity (set per particle in SphSystem::mu) and be told apart in analysis. The body
// force of eq. (2) drives the fluids only, outer and inner (§4: "fluid particles are accelerated in
// the x-direction"): not walls, not membrane particles, which the fluid carries.
#pragma once

#include <Kokkos_Core.hpp>

namespace mesoflow::sph {

namespace particle_type {
constexpr int fluid = 0;
constexpr int wall = 1;  // boundary particle: prescribed velocity (zero: fixed), never accelerated
constexpr int membrane = 2;  // MSM membrane particle: moves as fluid does, bond forces add (kernels/msm)
constexpr int inner_fluid = 3;  // fluid inside a capsule (§3, Fig. 1a: white); outer fluid is `fluid`
}  // namespace particle_type

KOKKOS_INLINE_FUNCTION bool is_fixed(int type) { return type == particle_type::wall; }

}  // namespace mesoflow::sph
