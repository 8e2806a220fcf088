// launch_violations.hpp — fixture for the direct-dispatch rule of scripts/check_kernel_portability
// (never compiled). The marker below puts it in the rule's scope, as a file under kernels/ or
// scenes/ is: launches there go through mesoflow::launch::parallel_* (kernels/common/kernel_launch.hpp).
// lint-scope: kernels
#pragma once

#include "kernels/common/kernel_launch.hpp"

namespace fixture {

template <class ExecSpace>
void launches(const Kokkos::View<double*, ExecSpace>& v, int n) {
  Kokkos::parallel_for("fixture::direct", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) { v(i) = 0; });  // expect: direct-dispatch
  double sum = 0;
  Kokkos::parallel_reduce(  // expect: direct-dispatch
      "fixture::direct_sum", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i, double& s) { s += v(i); }, sum);
  // fine: the checked launches
  mesoflow::launch::parallel_for("fixture::checked", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) { v(i) = 1; });
  mesoflow::launch::parallel_scan(
      "fixture::checked_scan", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i, double& partial, bool final) {
        partial += v(i);
        if (final) v(i) = partial;
      });
}

}  // namespace fixture
