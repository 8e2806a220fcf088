// kokkos_compat.hpp — the only place where mesoflow depends on the Kokkos version.
//
// mesoflow builds against Kokkos 3.4 (Debian 12's Trilinos sources) and Kokkos 4.x. The calls that
// differ between the two are wrapped here; everything else uses the Kokkos API common to both.
#pragma once

#include <Kokkos_Core.hpp>

#include <string>

namespace mesoflow {

// Math functions usable in kernels: Kokkos::Experimental:: in 3.x, Kokkos:: from 3.7 on.
namespace kmath {
#if KOKKOS_VERSION >= 30700
using Kokkos::cbrt;
using Kokkos::exp;
using Kokkos::fabs;
using Kokkos::floor;
using Kokkos::isfinite;
using Kokkos::log;
using Kokkos::pow;
using Kokkos::sqrt;
using Kokkos::cos;
using Kokkos::sin;
using Kokkos::atan2;
#else
using Kokkos::Experimental::cbrt;
using Kokkos::Experimental::exp;
using Kokkos::Experimental::fabs;
using Kokkos::Experimental::floor;
using Kokkos::Experimental::isfinite;
using Kokkos::Experimental::log;
using Kokkos::Experimental::pow;
using Kokkos::Experimental::sqrt;
using Kokkos::Experimental::cos;
using Kokkos::Experimental::sin;
using Kokkos::Experimental::atan2;
#endif
}  // namespace kmath

// Kokkos initialisation with an explicit thread count (≤ 0: Kokkos' default, i.e.
// OMP_NUM_THREADS or all cores).
inline void initialize_kokkos(int num_threads) {
#if KOKKOS_VERSION >= 30700
  Kokkos::InitializationSettings settings;
  if (num_threads > 0) settings.set_num_threads(num_threads);
  settings.set_disable_warnings(true);
  Kokkos::initialize(settings);
#else
  Kokkos::InitArguments args;
  args.num_threads = num_threads > 0 ? num_threads : -1;
  args.disable_warnings = true;
  Kokkos::initialize(args);
#endif
}

// Kokkos initialised for the lifetime of a scope (drivers, benchmarks).
class KokkosScope {
 public:
  explicit KokkosScope(int num_threads) { initialize_kokkos(num_threads); }
  ~KokkosScope() { Kokkos::finalize(); }
  KokkosScope(const KokkosScope&) = delete;
  KokkosScope& operator=(const KokkosScope&) = delete;
};

// Number of threads (host) or concurrent work items (device) of an execution space.
// (A static member in 3.x, a member function in 4.x: calling it on an instance works for both.)
template <class ExecSpace>
int concurrency() {
  return ExecSpace().concurrency();
}

// Signature of a custom reduction functor's join(): volatile arguments are required by Kokkos 3.x
// and deprecated from 4.0 on.
#if KOKKOS_VERSION >= 40000
#define MESOFLOW_JOIN_ARGS(T) T &dst, const T &src
#else
#define MESOFLOW_JOIN_ARGS(T) volatile T &dst, const volatile T &src
#endif

// One line naming the Kokkos version and its enabled backends, for logs and benchmark context.
inline std::string kokkos_configuration() {
  const int v = KOKKOS_VERSION;
  std::string s = "Kokkos " + std::to_string(v / 10000) + "." + std::to_string(v / 100 % 100) + "." +
                  std::to_string(v % 100) + " default=" + Kokkos::DefaultExecutionSpace::name();
#ifdef KOKKOS_ENABLE_SERIAL
  s += " +Serial";
#endif
#ifdef KOKKOS_ENABLE_OPENMP
  s += " +OpenMP(" + std::to_string(concurrency<Kokkos::OpenMP>()) + " threads)";
#endif
#ifdef KOKKOS_ENABLE_CUDA
  s += " +Cuda";
#endif
#ifdef KOKKOS_ENABLE_HIP
  s += " +HIP";
#endif
  return s;
}

}  // namespace mesoflow
