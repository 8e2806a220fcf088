// main.cpp — fixture for scripts/check_floors: drivers/ may include every floor, nothing else.
#include "drivers/study/cli.hpp"      // fine
#include "analysis/common/fit.hpp"    // fine
#include "scenes/study/scene.hpp"     // fine
#include "kernels/common/vec.hpp"     // fine
#include "io/writer.hpp"              // fine
#include <Kokkos_Core.hpp>            // fine
#include "tests/helper.hpp"           // expect: outside-include
#include "python/study/lifetime.hpp"  // expect: beside-include
