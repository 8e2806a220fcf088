// test_types.hpp — the (execution space, precision) combinations every kernel test runs on.
#pragma once

#include <gtest/gtest.h>

#include <Kokkos_Core.hpp>

#include <type_traits>

namespace mesoflow::testing {

template <class ExecSpace, class Real>
struct Config {
  using exec = ExecSpace;
  using real = Real;
};

// Three of the four (backend, precision) pairs: a backend bug (a race, a missing fence, a wrong
// reduction join) shows in double on Serial against OpenMP; a precision bug (cancellation,
// float accumulation, a tolerance) shows on OpenMP in float against double. Serial in float adds
// nothing either pair does not test, and it cost a quarter of the code generation of the 28 typed
// test files (issue 24 item 7: docs/results/refactor/build_times.md).
#if defined(KOKKOS_ENABLE_OPENMP) && defined(KOKKOS_ENABLE_SERIAL)
using BackendsAndPrecisions =
    ::testing::Types<Config<Kokkos::Serial, double>, Config<Kokkos::OpenMP, double>,
                     Config<Kokkos::OpenMP, float>>;
#else
using BackendsAndPrecisions = ::testing::Types<Config<Kokkos::DefaultExecutionSpace, double>,
                                               Config<Kokkos::DefaultExecutionSpace, float>>;
#endif

// Round-off scale of a precision, for tolerances stated as multiples of it.
template <class Real>
constexpr double eps() {
  return std::is_same<Real, float>::value ? 1.2e-7 : 2.3e-16;
}

}  // namespace mesoflow::testing
