// particles.hpp — structure-of-arrays particle storage in Kokkos Views.
#pragma once

#include "kernel_launch.hpp"
#include "kokkos_compat.hpp"

#include <cstddef>
#include <string>

namespace mesoflow {

// Per-particle data, one View per field. Vector fields are (n × D) with LayoutLeft, so each
// Cartesian component is contiguous (SoA). `body` is -1 for a free particle and otherwise the index
// of the deformable body (polygon, capsule) the particle belongs to; pairs within one body are not
// contacts and are excluded from neighbor lists on request. `type` selects per-type parameters.
template <int D, class Real, class ExecSpace = Kokkos::DefaultExecutionSpace>
struct Particles {
  using execution_space = ExecSpace;
  using real_type = Real;
  static constexpr int dim = D;
  using vector_view = Kokkos::View<Real* [D], Kokkos::LayoutLeft, ExecSpace>;
  using scalar_view = Kokkos::View<Real*, ExecSpace>;
  using int_view = Kokkos::View<int*, ExecSpace>;

  vector_view x, v, f;
  scalar_view mass;
  int_view body, type;

  Particles() = default;
  explicit Particles(std::size_t n, const std::string& name = "particles") { allocate(n, name); }

  std::size_t size() const { return x.extent(0); }

  // Fresh storage for n particles: zero positions, velocities and forces, unit mass, no body,
  // type 0.
  void allocate(std::size_t n, const std::string& name = "particles") {
    const std::string p = "mesoflow::" + name + "::";
    x = vector_view(p + "x", n);
    v = vector_view(p + "v", n);
    f = vector_view(p + "f", n);
    mass = scalar_view(p + "mass", n);
    body = int_view(p + "body", n);
    type = int_view(p + "type", n);
    Kokkos::deep_copy(mass, Real(1));
    Kokkos::deep_copy(body, -1);
  }

  // f ← 0 before the force terms of a step add to it (a kernel, not a host transfer).
  void zero_forces() const {
    const auto f_ = f;
    mesoflow::launch::parallel_for(
        "mesoflow::particles::zero_forces", Kokkos::RangePolicy<ExecSpace>(0, size()), KOKKOS_LAMBDA(int i) {
          for (int d = 0; d < D; ++d) f_(i, d) = Real(0);
        });
  }
};

}  // namespace mesoflow
