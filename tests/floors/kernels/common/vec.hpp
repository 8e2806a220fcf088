// vec.hpp — fixture for scripts/check_floors: kernels/ include kernels/ only.
#pragma once

#include <Kokkos_Core.hpp>              // fine: kernels are device code
#include "kernels/common/box.hpp"       // fine: kernels
#include "box.hpp"                      // fine: kernels, beside this file
#  include "kernels/common/box.hpp"     // fine: kernels (spaces after the #)
// #include "scenes/study/scene.hpp"    fine: a comment
/* #include "scenes/study/scene.hpp"    fine: a block comment
#include "drivers/study/main.cpp"       fine: still inside it
*/
#include "io/writer.hpp"                // expect: beside-include
#include "scenes/study/scene.hpp"       // expect: upward-include
#include "../../scenes/study/scene.hpp" // expect: upward-include
#include "analysis/common/fit.hpp"      // expect: upward-include
#include "drivers/study/main.cpp"       // expect: upward-include
