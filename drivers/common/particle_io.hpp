// particle_io.hpp — the drivers' names for moving particle data between Kokkos Views and H5MD
// frames (scenes/common/particle_frames.hpp; checkpoints are declared once per scene:
// scenes/common/checkpoint_fields.hpp). Only output steps touch the host.
#pragma once

#include "kernels/common/box.hpp"
#include "kernels/common/neighbor_list.hpp"
#include "kernels/common/particles.hpp"
#include "io/h5md_writer.hpp"
#include "scenes/common/particle_frames.hpp"

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace mesoflow::driver {

// The host copies and H5MD frames (scenes/common/particle_frames.hpp), under their driver names.
using scene::add_particles_group;
using scene::from_host_vector;
using scene::from_row_major;
using scene::to_host_vector;
using scene::to_row_major;
using scene::write_frame;

}  // namespace mesoflow::driver
