// hopper.cpp — bindings of the hopper scenes (hopper-flows §2): the soft-particle scene in 2D and 3D
// (scenes/hopper/hopper_scene.hpp) and the deformable-polygon scene in 2D (dp_hopper_scene.hpp),
// stepped from Python, with their particles or vertices as arrays and their crossing counts.
// The drivers' sweep machinery (widths, measurement windows, recycling statistics) stays in the
// `hopper` driver; this is the scene for scripts that want their own loop.
#include "python/src/lifetime.hpp"
#include "scenes/hopper/dp_hopper_scene.hpp"
#include "scenes/hopper/hopper_scene.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>

namespace py = pybind11;

namespace mesoflow::python {
namespace {

// What both hopper scenes offer: FIRE, stepping, clock, crossing counts, the term list, and the
// particles' (SP) or vertices' (DP) positions, velocities and types as arrays.
template <class S>
py::class_<S>& bind_common(py::class_<S>& c, int max_iterations, long long signal_every, const char* crossed) {
  c.def(
       "relax",
       [](S& s, int max_iter) {
         const auto r = s.get().relax(max_iter);
         py::dict d;
         d["converged"] = r.converged, d["iterations"] = r.iterations, d["max_force"] = r.max_force;
         return d;
       },
       py::arg("max_iterations") = max_iterations, "FIRE removes the initial overlaps (no gravity)")
      .def(
          "advance", [signal_every](S& s, long long steps) { advance_steps(s.get(), steps, signal_every); },
          py::arg("steps"), "steps the scene (velocity Verlet, contacts, friction, drag, recycling)")
      .def("set_gravity", [](S& s, bool on) { s.get().set_gravity(on); })
      .def_property_readonly("time", [](S& s) { return s.get().time(); })
      .def_property_readonly("steps", [](S& s) { return s.get().steps(); })
      .def_property_readonly("dt", [](S& s) { return s.get().dt(); })
      .def_property_readonly("crossings", [](S& s) { return s.get().crossings(); },
                             "particles that have left through the orifice (and been reinserted)")
      .def_property_readonly("crossed_measure", [](S& s) { return s.get().crossed_measure(); }, crossed)
      .def_property_readonly("insertions", [](S& s) { return s.get().insertions(); })
      .def_property_readonly("components", [](S& s) { return s.get().components(); })
      .def_property_readonly(
          "positions", [](py::object self) { return numpy_view(self.cast<S&>().get().particles().x, self); },
          "positions (rows, D): a view of the scene's memory on host backends, a copy on devices")
      .def_property_readonly(
          "velocities", [](py::object self) { return numpy_view(self.cast<S&>().get().particles().v, self); })
      .def_property_readonly(
          "types", [](py::object self) { return numpy_view(self.cast<S&>().get().particles().type, self); },
          "each row's particle type: 0 small (σ_s = 1/1.2 σ_avg), 1 large (1.4/1.2 σ_avg)");
  return c;
}

template <int D>
void bind_scene(py::module_& m, const char* name) {
  using S = Owned<hopper::HopperScene<D>>;
  py::class_<S> c(m, name, "The soft-particle hopper scene (hopper-flows §2): built, particles placed at random");
  c.def(py::init<const hopper::HopperParameters&>(), py::arg("parameters"));
  bind_common(c, 50000, 1000, "their total area (2D) or volume (3D), σ_avg units")
      .def_property_readonly(
          "ids", [](py::object self) { return numpy_view(self.cast<S&>().get().ids(), self); },
          "each row's particle id (rows are re-sorted by cell during the run)");
}

// Vertices: polygon b's in rows [b N_v, (b + 1) N_v), counter-clockwise.
void bind_dp_scene(py::module_& m) {
  using S = Owned<hopper::DpHopperScene<>>;
  py::class_<S> c(m, "DpHopperScene",
                  "The deformable-polygon hopper scene (hopper-flows §2.3, 2D): built, polygons placed at random");
  c.def(py::init<const hopper::DpHopperParameters&>(), py::arg("parameters"));
  bind_common(c, 20000, 100, "the polygons' total preferred area, σ_avg² units")
      .def_property_readonly("vertices_per_polygon", [](S& s) { return s.get().parameters().vertices; })
      .def_property_readonly(
          "bodies", [](py::object self) { return numpy_view(self.cast<S&>().get().polygons().body, self); },
          "the polygon of each vertex")
      .def_property_readonly(
          "vertex_diameters",
          [](S& s) {
            const auto& p = s.get().parameters();
            return std::vector<double>{p.vertex_diameter(0), p.vertex_diameter(1)};
          },
          "the vertex-disk diameter δ of a small and a large polygon")
      .def(
          "body_state",
          [](py::object self) {
            const auto& st = self.cast<S&>().get().update_body_state();
            py::dict d;
            d["area"] = numpy_view(st.area, self), d["perimeter"] = numpy_view(st.perimeter, self);
            d["centroid"] = numpy_view(st.com, self), d["velocity"] = numpy_view(st.com_velocity, self);
            return d;
          },
          "per polygon: area, perimeter, centre of mass and its velocity at the current state");
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

  py::class_<hopper::DpHopperParameters>(m, "DpHopperParameters")
      .def(py::init<>())
      .def_readwrite("particles", &hopper::DpHopperParameters::particles)
      .def_readwrite("vertices", &hopper::DpHopperParameters::vertices)
      .def_readwrite("hopper_width", &hopper::DpHopperParameters::hopper_width)
      .def_readwrite("orifice", &hopper::DpHopperParameters::orifice)
      .def_readwrite("wall_angle", &hopper::DpHopperParameters::wall_angle)
      .def_readwrite("area_stiffness", &hopper::DpHopperParameters::area_stiffness)
      .def_readwrite("perimeter_stiffness", &hopper::DpHopperParameters::perimeter_stiffness)
      .def_readwrite("bending_stiffness", &hopper::DpHopperParameters::bending_stiffness)
      .def_readwrite("contact_energy", &hopper::DpHopperParameters::contact_energy)
      .def_readwrite("wall_energy", &hopper::DpHopperParameters::wall_energy)
      .def_readwrite("drag", &hopper::DpHopperParameters::drag)
      .def_readwrite("friction", &hopper::DpHopperParameters::friction)
      .def_readwrite("friction_component", &hopper::DpHopperParameters::friction_component)
      .def_readwrite("smooth", &hopper::DpHopperParameters::smooth)
      .def_readwrite("dt", &hopper::DpHopperParameters::dt)
      .def_readwrite("seed", &hopper::DpHopperParameters::seed)
      .def_readwrite("force_dt", &hopper::DpHopperParameters::force_dt)
      .def("validate", &hopper::DpHopperParameters::validate)
      .def("resolved_dt", &hopper::DpHopperParameters::resolved_dt);
  bind_dp_scene(m);
}

}  // namespace mesoflow::python
