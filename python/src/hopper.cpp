// hopper.cpp — bindings of the hopper scenes (hopper-flows §2): the soft-particle scene in 2D and 3D
// (scenes/hopper/hopper_scene.hpp) and the deformable-polygon scene in 2D (dp_hopper_scene.hpp),
// stepped from Python, with their particles or vertices as arrays and their crossing counts.
// One width of the driver's Q(w) sweep (measure_width: the same scene parameters, FIRE, windows,
// steady-state test, block errors and profiles as `hopper --widths`) is bound too, so that
// mesoflow.hopper.sweep() loops over widths with a resume file; the loop over ranks and the output
// files stay in the driver.
#include "analysis/common/block_average.hpp"
#include "analysis/hopper/flow_rate_fits.hpp"
#include "python/src/lifetime.hpp"
#include "scenes/hopper/dp_hopper_scene.hpp"
#include "scenes/hopper/hopper_scene.hpp"
#include "scenes/hopper/hopper_runs.hpp"
#include "scenes/hopper/hopper_sweep.hpp"

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

// A width's run (hopper::WidthRun) as a dict: the scalars of the driver's CSV and JSON, the window
// rates and the window-averaged axis profile (h, n, v_g mean as in <out>_profile.csv).
py::dict width_run_dict(const hopper::WidthRun& run) {
  const auto& v = run.scalars;
  py::dict d;
  d["Q"] = v.Q, d["Q_error"] = v.Q_error, d["Q_corrected"] = v.Q_corrected;
  d["number_density_orifice"] = v.rho_n, d["clogged"] = v.clogged, d["steady"] = v.steady;
  d["steady_time"] = v.steady_time, d["end_time"] = v.result_end_time, d["steps"] = v.steps, d["time"] = v.time;
  d["insertions"] = v.insertions, d["max_insertion_overlap"] = v.max_insertion_overlap;
  d["seconds"] = v.seconds;
  std::vector<double> wt, wq, h, n, vg;
  for (const auto& w : run.windows) wt.push_back(w.time), wq.push_back(w.q);
  d["window_time"] = wt, d["window_rate"] = wq;
  const auto& m = run.measured;
  if (m.samples > 0)
    for (int j = 0; j < hopper::profile_points; ++j) {
      h.push_back(j * hopper::profile_dh), n.push_back(m.n[std::size_t(j)]);
      vg.push_back(m.n[std::size_t(j)] > 1e-6 ? m.vg_sum[std::size_t(j)] / m.n[std::size_t(j)] : 0.0);
    }
  d["profile_h"] = h, d["profile_n"] = n, d["profile_vg"] = vg;
  return d;
}

// run_width's report of a finished width: nothing here (the Python loop reports).
constexpr auto no_report = [](const auto&, const hopper::FlowResult&) {};

template <int D>
hopper::WidthRun measure_sp(const hopper::HopperParameters& p, double w, std::size_t k, const hopper::FlowSettings& flow) {
  const hopper::HopperParameters base = hopper::particle_parameters(p, p.dt, D);
  hopper::validate(hopper::at_width(base, w, k), D);
  flow.validate();
  hopper::WidthRun run = hopper::run_width<hopper::HopperScene<D>>(base, w, k, flow, analysis::block_average, no_report);
  std::vector<hopper::WidthRun> one{run};
  hopper::correct_flow_rates(one, hopper::HopperScene<D>::mean_particle_measure(), hopper::corrected_flow_rate);
  return one.front();
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

  using F = hopper::FlowSettings;
  py::class_<F>(m, "FlowSettings", "the Q measurement of one width (the driver's --window ... --max-time)")
      .def(py::init<>())
      .def_readwrite("window", &F::window)
      .def_readwrite("steady_windows", &F::steady_windows)
      .def_readwrite("measure_windows", &F::measure_windows)
      .def_readwrite("clog_time", &F::clog_time)
      .def_readwrite("max_time", &F::max_time)
      .def_readwrite("check_interval", &F::check_interval)
      .def("validate", &F::validate);
  m.def(
      "measure_width",
      [](const hopper::HopperParameters& p, int dimension, double w, std::size_t k, const F& flow) {
        if (dimension != 2 && dimension != 3)
          throw std::invalid_argument("dimension must be 2 or 3, got " + std::to_string(dimension));
        return width_run_dict(dimension == 2 ? measure_sp<2>(p, w, k, flow) : measure_sp<3>(p, w, k, flow));
      },
      py::arg("parameters"), py::arg("dimension"), py::arg("width"), py::arg("index"), py::arg("flow"),
      "width index `index` of the driver's sweep (orifice w, seed + index; dt 0: min(1e-3, 0.9 × limit)): "
      "FIRE, flow to a steady state, Q over the measuring windows with its block error");
  m.def(
      "measure_width",
      [](const hopper::DpHopperParameters& p, int dimension, double w, std::size_t k, const F& flow) {
        if (dimension != 2) throw std::invalid_argument("dimension: the dp model is 2D only, got " + std::to_string(dimension));
        hopper::validate(hopper::at_width(p, w, k), 2);  // the driver's polygon_parameters are p itself
        flow.validate();
        return width_run_dict(hopper::run_width<hopper::DpHopperScene<>>(p, w, k, flow, analysis::block_average, no_report));
      },
      py::arg("parameters"), py::arg("dimension"), py::arg("width"), py::arg("index"), py::arg("flow"));
}

}  // namespace mesoflow::python
