// bindings.cpp — fixture for scripts/check_floors: python/ (the Python front end) may include every
// floor below it and itself, not drivers/ (the other front end beside it).
#include "python/study/lifetime.hpp"  // fine
#include "scenes/study/scene.hpp"     // fine
#include "analysis/common/fit.hpp"    // fine
#include "kernels/common/vec.hpp"     // fine
#include "io/writer.hpp"              // fine
#include <pybind11/pybind11.h>        // fine
#include "drivers/study/cli.hpp"      // expect: beside-include
