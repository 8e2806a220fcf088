// finite_check.hpp — the device side of the NaN watchdog (scenes/common/nan_watchdog.hpp): find the
// first non-finite entry of a per-particle field, and copy fields to and from a last-good buffer.
//
// One reduction per field with Kokkos::Min over the index, so the answer is the lowest particle
// index whatever the backend or thread count; a copy is a kernel, never a host transfer.
#pragma once

#include "kernel_launch.hpp"
#include "kokkos_compat.hpp"

#include <stdexcept>
#include <string>

namespace mesoflow {

// Lowest index i with a non-finite a(i) or a(i, d) (rank 1 or rank 2 View), or -1 if all are finite.
template <class View>
long long first_non_finite(const View& a, const std::string& label = "mesoflow::finite_check::first_non_finite") {
  using exec = typename View::execution_space;
  static_assert(View::rank == 1 || View::rank == 2, "first_non_finite: rank 1 or 2 Views");
  const long long none = static_cast<long long>(a.extent(0));
  long long first = none;
  const int components = View::rank == 2 ? int(a.extent(1)) : 1;
  mesoflow::launch::parallel_reduce(
      label, Kokkos::RangePolicy<exec>(0, a.extent(0)),
      KOKKOS_LAMBDA(long long i, long long& lowest) {
        const View& v = a;  // captured outside `if constexpr` (nvcc rejects a first capture inside)
        bool finite = true;
        for (int d = 0; d < components; ++d) {
          if constexpr (View::rank == 2)
            finite = finite && kmath::isfinite(v(i, d));
          else
            finite = finite && kmath::isfinite(v(i));
        }
        if (!finite && i < lowest) lowest = i;
      },
      Kokkos::Min<long long>(first));
  return first < none ? first : -1;
}

// Largest |a(i)| (Euclidean norm over the components of a rank-2 View with at most 3 of them), in
// double, without overflow for finite entries (the watchdog calls it on finite forces only).
template <class View>
double max_norm(const View& a, const std::string& label = "mesoflow::finite_check::max_norm") {
  using exec = typename View::execution_space;
  static_assert(View::rank == 1 || View::rank == 2, "max_norm: rank 1 or 2 Views");
  if (View::rank == 2 && a.extent(1) > 3) throw std::invalid_argument("max_norm: at most 3 components");
  const int components = View::rank == 2 ? int(a.extent(1)) : 1;
  double largest = 0;
  mesoflow::launch::parallel_reduce(
      label, Kokkos::RangePolicy<exec>(0, a.extent(0)),
      KOKKOS_LAMBDA(long long i, double& m) {
        const View& v = a;  // captured outside `if constexpr` (nvcc rejects a first capture inside)
        double c[3] = {0, 0, 0}, top = 0;  // scaled by the largest component: no overflow below DBL_MAX
        for (int d = 0; d < components && d < 3; ++d) {
          if constexpr (View::rank == 2)
            c[d] = kmath::fabs(double(v(i, d)));
          else
            c[d] = kmath::fabs(double(v(i)));
          if (!(c[d] <= top)) top = c[d];
        }
        double s = 0;
        if (top > 0 && kmath::isfinite(top))
          for (int d = 0; d < components && d < 3; ++d) s += (c[d] / top) * (c[d] / top);
        const double norm = top > 0 && kmath::isfinite(top) ? top * kmath::sqrt(s) : top;
        if (!(norm <= m)) m = norm;
      },
      Kokkos::Max<double>(largest));
  return largest;
}

// dst ← src for Views of the same shape, as a kernel on the Views' execution space.
template <class Dst, class Src>
void copy_field(const Dst& dst, const Src& src, const std::string& label = "mesoflow::finite_check::copy_field") {
  using exec = typename Dst::execution_space;
  static_assert(int(Dst::rank) == int(Src::rank) && (Dst::rank == 1 || Dst::rank == 2), "copy_field: equal ranks 1 or 2");
  const int components = Dst::rank == 2 ? int(dst.extent(1)) : 1;
  mesoflow::launch::parallel_for(
      label, Kokkos::RangePolicy<exec>(0, src.extent(0)), KOKKOS_LAMBDA(long long i) {
        const Dst& to = dst;  // captured outside `if constexpr` (nvcc rejects a first capture inside)
        const Src& from = src;
        for (int d = 0; d < components; ++d) {
          if constexpr (Dst::rank == 2)
            to(i, d) = from(i, d);
          else
            to(i) = from(i);
        }
      });
}

}  // namespace mesoflow
