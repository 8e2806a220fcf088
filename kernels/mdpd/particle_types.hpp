// particle_types.hpp — the particle types of an MDPD scene with solids (paper §2.5.1).
//
// All particles interact through the MDPD forces. Solid particles (walls, pillars) are also
// tethered to their sites (tether_springs.hpp); those more than 1.2σ below the solid surface
// additionally repel fluid particles with a WCA potential, so the soft fluid cannot diffuse deep
// into a solid.
#pragma once

namespace mesoflow::mdpd {

namespace particle_type {
constexpr int fluid = 0;
constexpr int solid = 1;       // tethered, within 1.2σ of the solid surface
constexpr int solid_core = 2;  // tethered, deeper: WCA with fluid particles
}  // namespace particle_type

KOKKOS_INLINE_FUNCTION bool is_solid(int type) { return type != particle_type::fluid; }

}  // namespace mesoflow::mdpd
