// crystal.cpp — bindings of the microfluidic crystal's channel flow (mpc-microfluidic-crystal-phonons:
// MPC-AT+a solvent between no-slip walls with rigid discs, scenes/crystal/channel_flow.hpp), stepped
// from Python, the solvent and the discs as arrays. The phonon analysis is in mesoflow.analysis.
#include "python/src/lifetime.hpp"
#include "scenes/crystal/channel_flow.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>

namespace py = pybind11;

namespace mesoflow::python {
namespace {

using Params = mpc::ChannelFlowParameters<double>;
using Flow = mpc::ChannelFlow<double>;

using PyChannel = Owned<Flow>;

}  // namespace

void bind_crystal(py::module_& top) {
  py::module_ m = top.def_submodule("crystal", "rigid discs in an MPC channel flow (mpc-microfluidic-crystal-phonons)");
  py::enum_<mpc::CollisionRule>(m, "CollisionRule")
      .value("srd", mpc::CollisionRule::srd)
      .value("at_minus_a", mpc::CollisionRule::at_minus_a)
      .value("at_plus_a", mpc::CollisionRule::at_plus_a);
  py::class_<Params>(m, "ChannelFlowParameters")
      .def(py::init<>())
      .def_readwrite("length", &Params::length)
      .def_readwrite("width", &Params::width)
      .def_readwrite("walls", &Params::walls)
      .def_readwrite("cell_size", &Params::cell_size)
      .def_readwrite("density", &Params::density)
      .def_readwrite("kT", &Params::kT)
      .def_readwrite("mass", &Params::mass)
      .def_readwrite("h", &Params::h)
      .def_readwrite("rule", &Params::rule)
      .def_readwrite("srd_angle", &Params::srd_angle)
      .def_readwrite("body_acceleration", &Params::body_acceleration)
      .def_readwrite("disc_radius", &Params::disc_radius)
      .def_readwrite("friction", &Params::friction)
      .def_readwrite("wca_epsilon", &Params::wca_epsilon)
      .def_readwrite("wca_r0", &Params::wca_r0)
      .def_readwrite("seed", &Params::seed)
      .def_readwrite("sort_interval", &Params::sort_interval)
      .def_readwrite("deterministic", &Params::deterministic);
  py::class_<PyChannel>(m, "ChannelFlow", "The channel with its solvent at temperature and the discs at rest")
      .def(py::init<const Params&, const std::vector<std::array<double, 2>>&>(), py::arg("parameters"),
           py::arg("disc_centres") = std::vector<std::array<double, 2>>{})
      .def(
          "advance",
          [](PyChannel& c, long long steps) { advance_steps(c.get(), steps, 200); },
          py::arg("steps"))
      .def_property_readonly("parameters", [](PyChannel& c) { return c.get().parameters(); },
                             "the scene's ChannelFlowParameters (a copy)")
      .def_property_readonly("time", [](PyChannel& c) { return c.get().time(); })
      .def_property_readonly("steps", [](PyChannel& c) { return (long long)c.get().steps_done(); })
      .def_property_readonly("components", [](PyChannel& c) { return c.get().components(); })
      .def_property_readonly("solvent_momentum", [](PyChannel& c) { return c.get().solvent_momentum(); })
      .def_property_readonly("total_momentum", [](PyChannel& c) { return c.get().total_momentum(); })
      .def_property_readonly("wall_momentum", [](PyChannel& c) { return c.get().wall_momentum(); })
      .def_property_readonly(
          "positions", [](py::object self) { return numpy_view(self.cast<PyChannel&>().get().positions(), self); },
          "solvent positions (n, 2): a view on host backends, a copy on devices")
      .def_property_readonly(
          "velocities", [](py::object self) { return numpy_view(self.cast<PyChannel&>().get().velocities(), self); })
      .def_property_readonly(
          "disc_positions", [](py::object self) { return numpy_view(self.cast<PyChannel&>().get().discs().x, self); })
      .def_property_readonly(
          "disc_velocities", [](py::object self) { return numpy_view(self.cast<PyChannel&>().get().discs().u, self); });
}

}  // namespace mesoflow::python
