// test_types.hpp — the (execution space, precision) combinations every kernel test runs on.
#pragma once

#include <gtest/gtest.h>

#include <Kokkos_Core.hpp>

#include <cmath>
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

// Comparisons across backends (issue 26, item 3). Host backends (Serial, OpenMP) are compiled by the
// host compiler, which mesoflow builds without FMA contraction, so their results agree to the bit and
// tests compare them bitwise. Device compilers (nvcc, hipcc) contract a*b + c into one fused
// multiply-add by default: every contracted operation skips one rounding, so an expression of
// `operations` roundings whose intermediates are at most `scale` in magnitude can differ from the
// host's value by up to operations · u · scale (to first order, Higham's γ_n; u the unit round-off,
// eps()/2, doubled here for the one-ulp rounding of the final result on either side).
template <class ExecSpace>
constexpr bool has_host_arithmetic() {
  return Kokkos::SpaceAccessibility<Kokkos::HostSpace, typename ExecSpace::memory_space>::accessible;
}

// Run-to-run bitwise reproducibility (docs/design.md, "Determinism"). On a host backend the default
// paths give it (per-thread copies summed in a fixed order), and a test checks the default. A device
// backend's default sums several threads' contributions with float atomics, whose order changes
// from run to run (the first H200 runs: MPC cell sums, disc impulses, half-list scatters), so a test
// that compares two runs bit for bit there runs in the deterministic-sum mode: full neighbor lists,
// sorted MPC cell sums, disc impulses summed in index order.
template <class ExecSpace>
constexpr bool reproducible_by_default() {
  return has_host_arithmetic<ExecSpace>();
}

template <class Real>
constexpr double contraction_bound(int operations, double scale) {
  return double(operations) * eps<Real>() * scale;
}

// a (from ExecSpace) against b (from the host): bitwise where ExecSpace has host arithmetic, within
// contraction_bound<Real>(operations, scale) otherwise.
template <class ExecSpace, class Real>
::testing::AssertionResult agrees_with_host(double a, double b, int operations, double scale) {
  if (has_host_arithmetic<ExecSpace>()) {
    if (a == b) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << a << " != " << b << " (bitwise on a host backend)";
  }
  const double bound = contraction_bound<Real>(operations, scale);
  if (std::abs(a - b) <= bound) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << a << " vs " << b << ": |difference| " << std::abs(a - b) << " > "
                                       << bound << " (" << operations << " contracted operations at scale " << scale
                                       << ")";
}

}  // namespace mesoflow::testing
