// writer.hpp — fixture for scripts/check_floors: io/ includes io/ only and no Kokkos.
#pragma once

#include "io/format.hpp"            // fine: io
#include "format.hpp"               // fine: io, beside this file
#include <hdf5.h>                   // fine: a system header
#include "kernels/common/vec.hpp"   // expect: beside-include
#include "scenes/study/scene.hpp"   // expect: upward-include
#include "analysis/common/fit.hpp"  // expect: upward-include
#include <Kokkos_Core.hpp>          // expect: host-floor-kokkos
