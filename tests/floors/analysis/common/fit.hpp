// fit.hpp — fixture for scripts/check_floors: analysis/ includes io/ and analysis/, host-only.
#pragma once

#include "analysis/common/stats.hpp"  // fine
#include "stats.hpp"                  // fine: analysis, beside this file
#include "io/writer.hpp"              // fine: io is host infrastructure
#include <Eigen/Dense>                // fine: host libraries
#include <vector>                     // fine
#include "kernels/common/vec.hpp"     // expect: analysis-device
#include "scenes/study/scene.hpp"     // expect: analysis-device
#include "drivers/study/main.cpp"     // expect: upward-include
#include <Kokkos_Core.hpp>            // expect: host-floor-kokkos
#include <impl/Kokkos_Error.hpp>      // expect: host-floor-kokkos
#include "KokkosExp_MDRangePolicy.hpp"  // expect: host-floor-kokkos
