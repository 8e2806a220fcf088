// kernel_launch.hpp — the launches of mesoflow's kernels: Kokkos::parallel_for/reduce/scan with a
// compile-time bound on the size of the closure (the functor or KOKKOS_LAMBDA, with everything it
// captures by value).
//
// On a GPU the closure travels to the device with each launch: as a kernel parameter, or through a
// constant-memory buffer above a few hundred bytes (Kokkos' CUDA backend switches at 512 bytes).
// Closures of about 1 KB — whole scene objects captured by value — silently computed nothing in the
// first GPU run (docs/portability.md, "First GPU run"). So device data is reached through Views or a
// small handle of them (ObstacleArray::query(), BodyObstacleList::query()), never by copying owning
// objects into kernels, and every launch in kernels/ and scenes/ goes through these wrappers
// (mesoflow::launch::parallel_for/reduce/scan), which
// refuse to compile a closure above `max_kernel_closure_bytes`. The portability lint
// (scripts/check_kernel_portability, rule direct-dispatch) flags a Kokkos::parallel_* call there that
// bypasses them; tests and benchmarks may launch directly.
#pragma once

#include <Kokkos_Core.hpp>

#include <cstddef>
#include <string>
#include <utility>

namespace mesoflow {

// The largest closure a kernel may capture, in bytes: Kokkos' CUDA backend passes a kernel's driver
// (closure plus policy) as a kernel parameter below 512 bytes and through constant memory above
// (CudaTraits::ConstantMemoryUseThreshold in Kokkos 3.4 and 4.x); the closures that failed were
// about 1 KB.
inline constexpr std::size_t max_kernel_closure_bytes = 512;

namespace launch_detail {
// Instantiated with the closure's size, so the compiler's message names it:
// "kernel_closure_size<608, 512>" reads "this kernel captures 608 bytes, the bound is 512".
template <std::size_t Bytes, std::size_t Limit>
struct kernel_closure_size {
  static_assert(Bytes <= Limit,
                "mesoflow: a kernel closure is larger than max_kernel_closure_bytes; capture Views or a small "
                "query handle (e.g. .query()), not whole objects (kernels/common/kernel_launch.hpp)");
  static constexpr bool fits = true;
};
}  // namespace launch_detail

template <class Functor>
constexpr bool kernel_closure_fits() {
  return launch_detail::kernel_closure_size<sizeof(Functor), max_kernel_closure_bytes>::fits;
}

// A namespace of their own, which no kernel type lives in: argument-dependent lookup of an unqualified
// parallel_* (from a kernel's namespace, or inside Kokkos) never finds them.
namespace launch {

template <class Policy, class Functor>
inline void parallel_for(const std::string& label, const Policy& policy, const Functor& functor) {
  static_assert(kernel_closure_fits<Functor>());
  Kokkos::parallel_for(label, policy, functor);
}

template <class Policy, class Functor, class... Results>
inline void parallel_reduce(const std::string& label, const Policy& policy, const Functor& functor,
                            Results&&... results) {
  static_assert(kernel_closure_fits<Functor>());
  Kokkos::parallel_reduce(label, policy, functor, std::forward<Results>(results)...);
}

template <class Policy, class Functor, class... Results>
inline void parallel_scan(const std::string& label, const Policy& policy, const Functor& functor,
                          Results&&... results) {
  static_assert(kernel_closure_fits<Functor>());
  Kokkos::parallel_scan(label, policy, functor, std::forward<Results>(results)...);
}

}  // namespace launch
}  // namespace mesoflow
