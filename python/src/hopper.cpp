// hopper.cpp — bindings of the soft-particle hopper (hopper-flows §2, scenes/hopper/hopper_scene.hpp):
// the scene in 2D and 3D, stepped from Python, with its particles as arrays and its crossing count.
// The drivers' sweep machinery (widths, measurement windows, recycling statistics) stays in the
// `hopper` driver; this is the scene for scripts that want their own loop.
#include "python/src/lifetime.hpp"
#include "scenes/hopper/hopper_scene.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>

namespace py = pybind11;

namespace mesoflow::python {
namespace {

template <int D>
using PyHopper = Owned<hopper::HopperScene<D>>;

template <int D>
void bind_scene(py::module_& m, const char* name) {
  using S = PyHopper<D>;
  py::class_<S>(m, name, "The soft-particle hopper scene (hopper-flows §2): built, particles placed at random")
      .def(py::init<const hopper::HopperParameters&>(), py::arg("parameters"))
      .def(
          "relax",
          [](S& s, int max_iterations) {
            const auto r = s.get().relax(max_iterations);
            py::dict d;
            d["converged"] = r.converged, d["iterations"] = r.iterations, d["max_force"] = r.max_force;
            return d;
          },
          py::arg("max_iterations") = 50000, "FIRE removes the initial overlaps (no gravity)")
      .def(
          "advance",
          [](S& s, long long steps) { advance_steps(s.get(), steps, 1000); },
          py::arg("steps"), "steps the scene (velocity Verlet, contacts, friction, drag, recycling)")
      .def("set_gravity", [](S& s, bool on) { s.get().set_gravity(on); })
      .def_property_readonly("time", [](S& s) { return s.get().time(); })
      .def_property_readonly("steps", [](S& s) { return s.get().steps(); })
      .def_property_readonly("dt", [](S& s) { return s.get().dt(); })
      .def_property_readonly("crossings", [](S& s) { return s.get().crossings(); },
                             "particles that have left through the orifice (and been reinserted)")
      .def_property_readonly("crossed_measure", [](S& s) { return s.get().crossed_measure(); },
                             "their total area (2D) or volume (3D), σ_avg units")
      .def_property_readonly("insertions", [](S& s) { return s.get().insertions(); })
      .def_property_readonly("components", [](S& s) { return s.get().components(); })
      .def_property_readonly(
          "positions", [](py::object self) { return numpy_view(self.cast<S&>().get().particles().x, self); },
          "particle positions (N, D): a view of the scene's memory on host backends, a copy on devices")
      .def_property_readonly(
          "velocities", [](py::object self) { return numpy_view(self.cast<S&>().get().particles().v, self); })
      .def_property_readonly(
          "ids", [](py::object self) { return numpy_view(self.cast<S&>().get().ids(), self); },
          "each row's particle id (rows are re-sorted by cell during the run)");
}

}  // namespace

void bind_hopper(py::module_& top) {
  py::module_ m = top.def_submodule("hopper", "soft-particle hopper flows (hopper-flows)");
  py::enum_<sp::FrictionComponent>(m, "FrictionComponent")
      .value("full", sp::FrictionComponent::full)
      .value("tangential", sp::FrictionComponent::tangential);
  py::class_<hopper::HopperParameters>(m, "HopperParameters")
      .def(py::init<>())
      .def_readwrite("particles", &hopper::HopperParameters::particles)
      .def_readwrite("hopper_width", &hopper::HopperParameters::hopper_width)
      .def_readwrite("orifice", &hopper::HopperParameters::orifice)
      .def_readwrite("wall_angle", &hopper::HopperParameters::wall_angle)
      .def_readwrite("pair_energy", &hopper::HopperParameters::pair_energy)
      .def_readwrite("wall_energy", &hopper::HopperParameters::wall_energy)
      .def_readwrite("drag", &hopper::HopperParameters::drag)
      .def_readwrite("friction", &hopper::HopperParameters::friction)
      .def_readwrite("friction_component", &hopper::HopperParameters::friction_component)
      .def_readwrite("dt", &hopper::HopperParameters::dt)
      .def_readwrite("seed", &hopper::HopperParameters::seed)
      .def_readwrite("force_dt", &hopper::HopperParameters::force_dt)
      .def("validate", &hopper::HopperParameters::validate, py::arg("dimension"))
      .def("max_stable_dt", &hopper::HopperParameters::max_stable_dt, py::arg("dimension"));
  bind_scene<2>(m, "HopperScene2D");
  bind_scene<3>(m, "HopperScene3D");
}

}  // namespace mesoflow::python
