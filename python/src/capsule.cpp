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
      .def_property_readonly("num_outer_fluid", [](PyCapsule& c) { return c.get().num_outer_fluid(); })
      .def_property_readonly("num_walls", [](PyCapsule& c) { return c.get().num_walls(); })
      .def_property_readonly(
          "box",
          [](PyCapsule& c) {
            const auto& b = c.get().system().box();
            return py::make_tuple(py::make_tuple(b.lo[0], b.lo[1], b.lo[2]),
                                  py::make_tuple(b.length[0], b.length[1], b.length[2]),
                                  py::make_tuple(b.periodic[0], b.periodic[1], b.periodic[2]));
          },
          "(lo, length, periodic) of the SPH box; walled axes extend over the wall layers")
      .def_property_readonly(
          "particle_slot",
          [](py::object self) { return numpy_view(self.cast<PyCapsule&>().get().particle_slot(), self); },
          "particle_slot[i]: where particle i of the initial order (outer fluid, inner fluid, walls, "
          "membrane) is stored now, through memory sorts; positions[particle_slot] is that order")
      .def_property_readonly(
          "membrane_bonds",
          [](PyCapsule& c) {
            const auto& mesh = c.get().mesh();
            const int offset = c.get().membrane_offset();
            py::array_t<int> a(std::vector<py::ssize_t>{py::ssize_t(mesh.num_bonds()), 2});
            auto r = a.mutable_unchecked<2>();
            for (int b = 0; b < mesh.num_bonds(); ++b)
              for (int e = 0; e < 2; ++e) r(b, e) = offset + mesh.bond[std::size_t(b)][std::size_t(e)];
            return a;
          },
          "the membrane's springs (n_b, 2) as particle indices of the initial order (a copy)")
      .def_property_readonly(
          "membrane_triangles",
          [](PyCapsule& c) {
            const auto& mesh = c.get().mesh();
            const int offset = c.get().membrane_offset();
            py::array_t<int> a(std::vector<py::ssize_t>{py::ssize_t(mesh.triangle.size()), 3});
            auto r = a.mutable_unchecked<2>();
            for (std::size_t t = 0; t < mesh.triangle.size(); ++t)
              for (std::size_t e = 0; e < 3; ++e) r(py::ssize_t(t), py::ssize_t(e)) = offset + mesh.triangle[t][e];
            return a;
          },
          "the outer layer's triangles (n_t, 3) as particle indices of the initial order (a copy)")
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
