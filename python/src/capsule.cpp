// capsule.cpp — bindings of the SPH + mass-spring capsule (sph-microcapsules-constriction,
// scenes/capsule/capsule_scene.hpp) in a periodic box: a two-layer icosphere membrane with inner and
// outer fluids, stepped from Python. The constriction channel and the Ca/η sweeps stay in the
// `capsule` driver; this is the scene for scripts that want their own loop.
#include "python/src/lifetime.hpp"
#include "scenes/capsule/capsule_scene.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>

namespace py = pybind11;

namespace mesoflow::python {
namespace {

using Params = capsule::CapsuleSceneParameters;
using Scene = capsule::CapsuleScene<double>;

using PyCapsule = Owned<Scene>;

}  // namespace

void bind_capsule(py::module_& top) {
  py::module_ m = top.def_submodule("capsule", "SPH fluid with a mass-spring capsule (sph-microcapsules-constriction)");
  py::class_<Params>(m, "CapsuleSceneParameters")
      .def(py::init<>())
      .def_readwrite("sites", &Params::sites)
      .def_readwrite("spacing", &Params::spacing)
      .def_readwrite("support", &Params::support)
      .def_readwrite("rho0", &Params::rho0)
      .def_readwrite("mu_outer", &Params::mu_outer)
      .def_readwrite("mu_inner", &Params::mu_inner)
      .def_readwrite("u_max", &Params::u_max)
      .def_readwrite("body_force", &Params::body_force)
      .def_readwrite("radius", &Params::radius)
      .def_readwrite("thickness", &Params::thickness)
      .def_readwrite("level", &Params::level)
      .def_readwrite("k_b", &Params::k_b)
      .def_readwrite("clearance", &Params::clearance)
      .def_readwrite("stretch", &Params::stretch)
      .def_readwrite("capsule_velocity", &Params::capsule_velocity)
      .def_readwrite("velocity_noise", &Params::velocity_noise)
      .def_readwrite("seed", &Params::seed)
      .def_property(
          "dt", [](const Params& p) { return p.dt ? *p.dt : 0.0; },
          [](Params& p, double dt) {
            if (dt > 0)
              p.dt = dt;
            else
              p.dt.reset();
          },
          "time step (0: the smallest stability limit)")
      .def_readwrite("force_dt", &Params::force_dt)
      .def("validate", &Params::validate);
  py::class_<PyCapsule>(m, "CapsuleScene", "The capsule in its fluid, at rest (or with its initial velocity)")
      .def(py::init([](const Params& p) {
             p.validate();
             return std::make_unique<PyCapsule>(p);
           }),
           py::arg("parameters"))
      .def(
          "advance",
          [](PyCapsule& c, long long steps) { advance_steps(c.get(), steps, 100); },
          py::arg("steps"))
      .def_property_readonly("steps", [](PyCapsule& c) { return c.get().steps(); })
      .def_property_readonly("dt", [](PyCapsule& c) { return double(c.get().system().dt()); })
      .def_property_readonly("time", [](PyCapsule& c) { return double(c.get().steps()) * double(c.get().system().dt()); })
      .def_property_readonly("components", [](PyCapsule& c) { return c.get().components(); })
      .def_property_readonly("total_momentum", [](PyCapsule& c) { return c.get().total_momentum(); })
      .def_property_readonly("max_density_deviation", [](PyCapsule& c) { return c.get().max_density_deviation(); })
      .def_property_readonly("surface_shear_modulus", [](PyCapsule& c) { return c.get().surface_shear_modulus(); },
                             "G_s of the paper's formula from the bond constant and thickness")
      .def_property_readonly("num_membrane", [](PyCapsule& c) { return c.get().num_membrane(); })
      .def_property_readonly("num_fluid", [](PyCapsule& c) { return c.get().num_fluid(); })
      .def(
          "outer_layer",
          [](PyCapsule& c) {
            const auto y = c.get().outer_layer_positions();
            py::array_t<double> a(std::vector<py::ssize_t>{py::ssize_t(y.size()), 3});
            auto r = a.mutable_unchecked<2>();
            for (std::size_t i = 0; i < y.size(); ++i)
              for (int d = 0; d < 3; ++d) r(py::ssize_t(i), d) = y[i][d];
            return a;
          },
          "the membrane's outer-layer vertices (n, 3), unwrapped into one surface (a copy)")
      .def_property_readonly(
          "positions", [](py::object self) { return numpy_view(self.cast<PyCapsule&>().get().system().particles.x, self); },
          "every particle's position (fluids, walls, membrane) (n, 3): a view on host backends")
      .def_property_readonly(
          "velocities", [](py::object self) { return numpy_view(self.cast<PyCapsule&>().get().system().particles.v, self); });
}

}  // namespace mesoflow::python
