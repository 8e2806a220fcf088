// oversized_closure.cpp — must NOT compile: a kernel that captures a 1 KB object by value through a
// checked launch (kernels/common/kernel_launch.hpp). The ctest KernelLaunch.OversizedClosureDoesNotCompile
// builds it and passes only if the compiler names the closure's size against the bound.
#include "kernels/common/kernel_launch.hpp"

namespace {
struct Heavy {
  double coefficients[128];  // 1024 bytes: the size of the closures that failed on the first GPU run
};
}  // namespace

int main(int argc, char** argv) {
  Kokkos::ScopeGuard guard(argc, argv);
  Kokkos::View<double*> out("out", 4);
  const Heavy heavy{};
  mesoflow::launch::parallel_for("oversized", Kokkos::RangePolicy<>(0, 4),
                                 KOKKOS_LAMBDA(int i) { out(i) = heavy.coefficients[i]; });
  return 0;
}
