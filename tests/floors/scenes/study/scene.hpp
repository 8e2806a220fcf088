// scene.hpp — fixture for scripts/check_floors: scenes/ include kernels/, io/ and scenes/.
#pragma once

#include "kernels/common/vec.hpp"   // fine
#include "io/writer.hpp"            // fine
#include "scenes/study/setup.hpp"   // fine
#include "setup.hpp"                // fine: scenes, beside this file
#include "hdf5.h"                   // fine: a third-party header on another include path
#include <Kokkos_Core.hpp>          // fine: scenes may use Kokkos
#include "analysis/common/fit.hpp"  // expect: upward-include
#include "drivers/study/main.cpp"   // expect: upward-include
#include "tests/helper.hpp"         // expect: outside-include
