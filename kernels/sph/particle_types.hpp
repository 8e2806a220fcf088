// particle_types.hpp — the particle types of an SPH scene with walls (paper §2.4, §3, Fig. 1a: the
// red boundary particles).
//
// Wall particles are SPH particles that never move: they keep zero velocity and their positions,
// and take part in everything else — they carry mass, integrate their density by the continuity
// eq. (4), have a pressure from the equation of state eq. (6) and a viscosity in eq. (5). Fluid
// particles near a wall thus see a full kernel support, are pushed back by the wall's pressure
// (no penetration) and dragged by its zero velocity through the viscous term (no slip). This is
// what the paper's DMP model does with its fixed boundary particles (LAMMPS' `fix sph/stationary`:
// density integrated, position and velocity not).
#pragma once

#include <Kokkos_Core.hpp>

namespace mesoflow::sph {

namespace particle_type {
constexpr int fluid = 0;
constexpr int wall = 1;  // fixed boundary particle: zero velocity, never moves
}  // namespace particle_type

KOKKOS_INLINE_FUNCTION bool is_fixed(int type) { return type == particle_type::wall; }

}  // namespace mesoflow::sph
