// module.cpp — the `mesoflow._mesoflow` extension (issue 30): thin pybind11 bindings over the
// scenes and the host analysis; no physics here. The Python package `mesoflow` (python/mesoflow/)
// wraps it with keyword validation, progress bars and the resumable sweep.
//
// Kokkos lives once per process: initialize(threads) starts it (the package calls it on first use
// with OMP_NUM_THREADS or all cores), and an atexit hook releases every live scene's device data
// before Kokkos::finalize(), so no View outlives Kokkos.
#include "python/src/lifetime.hpp"

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

namespace py = pybind11;

namespace mesoflow::python {
void bind_droplets(py::module_& m);
void bind_analysis(py::module_& m);
void bind_hopper(py::module_& m);
void bind_crystal(py::module_& m);
void bind_capsule(py::module_& m);
void bind_pillars(py::module_& m);
}  // namespace mesoflow::python

PYBIND11_MODULE(_mesoflow, m) {
  using namespace mesoflow::python;
  m.doc() = "mesoflow's compiled core: scenes, runs and analysis (use the `mesoflow` package)";
  m.def(
      "initialize",
      [](int threads) {
        if (Kokkos::is_initialized()) {
          if (threads > 0 && threads != initialized_threads())
            throw std::runtime_error("mesoflow.initialize: Kokkos already runs with " +
                                     std::to_string(initialized_threads()) + " threads; it starts once per process");
          return;
        }
        if (finalized()) throw std::runtime_error("mesoflow.initialize: Kokkos was finalised; it starts once per process");
        if (threads < 0) throw std::invalid_argument("threads must be >= 0 (0: OMP_NUM_THREADS or all cores), got " +
                                                     std::to_string(threads));
        start_kokkos(threads);
        py::module_::import("atexit").attr("register")(py::cpp_function([] { finalize_kokkos(); }));
      },
      py::arg("threads") = 0,
      "Starts Kokkos with `threads` host threads (0: OMP_NUM_THREADS or all cores). Once per process; "
      "a second call with the same or no thread count does nothing.");
  m.def("is_initialized", [] { return Kokkos::is_initialized(); });
  m.def("finalize", &finalize_kokkos,
        "Releases every scene's device data and finalises Kokkos (also run at interpreter exit).");
  m.def("kokkos_configuration", [] {
    require_kokkos();
    return mesoflow::kokkos_configuration();
  });
  m.def("host_backend", [] { return host_backend(); },
        "True when the default execution space's memory is host memory: arrays are then zero-copy views");
  m.attr("version") = MESOFLOW_VERSION;
  bind_droplets(m);
  bind_analysis(m);
  bind_hopper(m);
  bind_crystal(m);
  bind_capsule(m);
  bind_pillars(m);
}
