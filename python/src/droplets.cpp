// droplets.cpp — bindings of the capillary-droplet study (capillary-droplets-clogging): the orifice
// passage (scenes/droplets/orifice_run.hpp, OrificeRun, the loop the `orifice` driver runs), the
// obstacle-array clogging sweep (scenes/droplets/obstacles_ensemble.hpp, what the `obstacles`
// driver runs) and the clogging statistics (analysis/droplets/clogging_statistics.hpp).
#include "analysis/droplets/clogging_statistics.hpp"
#include "python/src/lifetime.hpp"
#include "scenes/droplets/obstacles_ensemble.hpp"
#include "scenes/droplets/orifice_run.hpp"

#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>

namespace py = pybind11;

namespace mesoflow::python {
namespace {

using droplets::OrificeRun;

// One passage, owned by Python; its scene's Views are released before Kokkos is finalised.
using PyOrificeRun = Owned<OrificeRun<double>>;

py::dict profile_dict(const droplets::OrificeProfile& p) {
  py::dict d;
  d["t"] = py::array_t<double>(py::ssize_t(p.t.size()), p.t.data());
  d["h"] = py::array_t<double>(py::ssize_t(p.h.size()), p.h.data());
  d["vg"] = py::array_t<double>(py::ssize_t(p.vg.size()), p.vg.data());
  d["shape_parameter"] = py::array_t<double>(py::ssize_t(p.shape.size()), p.shape.data());
  d["area_over_a0"] = py::array_t<double>(py::ssize_t(p.area.size()), p.area.data());
  d["kinetic_over_terminal"] = py::array_t<double>(py::ssize_t(p.kinetic.size()), p.kinetic.data());
  d["outcome"] = droplets::to_string(p.outcome);
  d["dt"] = p.dt;
  d["steps"] = p.steps;
  d["free_area_over_a0"] = p.free_area;
  d["max_area_error"] = p.max_area_error;
  d["components"] = p.components;
  return d;
}

py::dict record_dict(const droplets::ReplicaRecord& r) {
  py::dict d;
  d["clogged"] = r.clogged;
  d["distance"] = r.distance;
  d["time"] = r.time;
  d["final_x"] = r.final_x;
  d["final_y"] = r.final_y;
  d["steady_speed"] = r.steady_speed;
  d["early_decision"] = r.early;
  d["early_clogged"] = r.early_clogged();
  d["early_distance"] = r.early_distance;
  d["early_time"] = r.early_time;
  d["early_rate"] = r.early_rate;
  d["early_crossing"] = r.early_crossing;
  return d;
}

std::vector<droplets::ReplicaOutcome> outcomes_of(const std::vector<double>& distance, const std::vector<bool>& clogged) {
  if (distance.size() != clogged.size())
    throw std::invalid_argument("distances and clogged must have the same length, got " +
                                std::to_string(distance.size()) + " and " + std::to_string(clogged.size()));
  std::vector<droplets::ReplicaOutcome> o;
  for (std::size_t i = 0; i < distance.size(); ++i) o.push_back({distance[i], bool(clogged[i])});
  return o;
}

// Lets Ctrl-C stop a long C++ loop at its next callback.
void check_signals() {
  if (PyErr_CheckSignals() != 0) throw py::error_already_set();
}

}  // namespace

void bind_droplets(py::module_& top) {
  py::module_ m = top.def_submodule("droplets", "capillary droplets: orifice passage, obstacle-array clogging");

  py::class_<droplets::DropletParameters>(m, "DropletParameters",
                                          "One deformable-polygon droplet (capillary-droplets §2.1; units σ, g, ρ)")
      .def(py::init<>())
      .def_readwrite("vertices", &droplets::DropletParameters::vertices)
      .def_readwrite("line_tension", &droplets::DropletParameters::line_tension)
      .def_readwrite("area_stiffness", &droplets::DropletParameters::area_stiffness)
      .def_readwrite("perimeter_stiffness", &droplets::DropletParameters::perimeter_stiffness)
      .def_readwrite("bending_stiffness", &droplets::DropletParameters::bending_stiffness)
      .def_readwrite("wall_energy", &droplets::DropletParameters::wall_energy)
      .def_readwrite("vertex_diameter", &droplets::DropletParameters::vertex_diameter)
      .def_readwrite("edge_obstacle_contacts", &droplets::DropletParameters::edge_obstacle_contacts)
      .def_readwrite("near_wall_drag", &droplets::DropletParameters::near_wall_drag)
      .def_readwrite("terminal_speed", &droplets::DropletParameters::terminal_speed)
      .def_readwrite("drag_exponent", &droplets::DropletParameters::drag_exponent)
      .def_readwrite("drag_floor", &droplets::DropletParameters::drag_floor)
      .def_readwrite("dt", &droplets::DropletParameters::dt)
      .def_readwrite("drag", &droplets::DropletParameters::drag)
      .def_readwrite("force_dt", &droplets::DropletParameters::force_dt)
      .def_readwrite("gravity_angle", &droplets::DropletParameters::gravity_angle)
      .def("validate", &droplets::DropletParameters::validate);

  py::class_<droplets::OrificeScene>(m, "OrificeScene", "The orifice of capillary-droplets Fig. 1a (defaults: Fig. 2)")
      .def(py::init<>())
      .def_readwrite("droplet", &droplets::OrificeScene::droplet)
      .def_readwrite("width", &droplets::OrificeScene::width)
      .def_readwrite("start_h", &droplets::OrificeScene::start_h)
      .def_readwrite("end_h", &droplets::OrificeScene::end_h)
      .def_readwrite("max_time", &droplets::OrificeScene::max_time)
      .def_readwrite("sample_interval", &droplets::OrificeScene::sample_interval)
      .def_readwrite("clog_threshold", &droplets::OrificeScene::clog_threshold)
      .def_readwrite("check_interval", &droplets::OrificeScene::check_interval)
      .def("validate", &droplets::OrificeScene::validate);

  py::class_<PyOrificeRun>(m, "OrificeRun",
                           "One passage: builds and relaxes the scene and takes the first sample; advance() runs "
                           "to the next sample")
      .def(py::init<const droplets::OrificeScene&>(), py::arg("scene"))
      .def("advance", [](PyOrificeRun& r) { return r.get().advance(); },
           "Steps to the next profile sample; False once the run has ended (passed, clogged, time limit, stopped)")
      .def("stop", [](PyOrificeRun& r) { r.get().stop(); }, "Ends the run here (outcome 'stopped')")
      .def_property_readonly("done", [](PyOrificeRun& r) { return r.get().done(); })
      .def_property_readonly("outcome", [](PyOrificeRun& r) { return droplets::to_string(r.get().profile().outcome); })
      .def_property_readonly("time", [](PyOrificeRun& r) { return r.get().scene().time(); })
      .def_property_readonly("steps", [](PyOrificeRun& r) { return (long long)r.get().scene().steps(); })
      .def_property_readonly("dt", [](PyOrificeRun& r) { return r.get().profile().dt; })
      .def_property_readonly("max_time", [](PyOrificeRun& r) { return r.get().setup().max_time; })
      .def_property_readonly("samples", [](PyOrificeRun& r) { return r.get().profile().t.size(); })
      .def_property_readonly(
          "positions", [](py::object self) { return numpy_view(self.cast<PyOrificeRun&>().get().scene().particles().x, self); },
          "vertex positions (N_v, 2) in σ: a view of the scene's memory on host backends (valid while the run "
          "lives; copy to keep), a copy on device backends")
      .def_property_readonly(
          "velocities", [](py::object self) { return numpy_view(self.cast<PyOrificeRun&>().get().scene().particles().v, self); },
          "vertex velocities (N_v, 2) in σ/t0, as positions")
      .def_property_readonly(
          "forces", [](py::object self) { return numpy_view(self.cast<PyOrificeRun&>().get().scene().particles().f, self); },
          "forces on the vertices (N_v, 2) after the last step, as positions")
      .def("profile", [](PyOrificeRun& r) { return profile_dict(r.get().profile()); },
           "the profiles so far (copies): t, h, vg, shape_parameter, area_over_a0, kinetic_over_terminal, and the "
           "outcome, dt, steps");

  py::enum_<droplets::ClogTest>(m, "ClogTest")
      .value("full", droplets::ClogTest::full)
      .value("early", droplets::ClogTest::early)
      .value("both", droplets::ClogTest::both);

  py::class_<droplets::EarlyClogParameters>(m, "EarlyClogParameters")
      .def(py::init<>())
      .def_readwrite("sample_interval", &droplets::EarlyClogParameters::sample_interval)
      .def_readwrite("window", &droplets::EarlyClogParameters::window)
      .def_readwrite("tolerance", &droplets::EarlyClogParameters::tolerance)
      .def_readwrite("max_scatter", &droplets::EarlyClogParameters::max_scatter)
      .def_readwrite("min_rate", &droplets::EarlyClogParameters::min_rate)
      .def("validate", &droplets::EarlyClogParameters::validate);

  py::class_<droplets::ObstacleSweep>(m, "ObstacleSweep",
                                      "Everything of an obstacle-array clogging sweep but the swept (strength, gap) "
                                      "(the `obstacles` driver's parameters)")
      .def(py::init<>())
      .def_readwrite("soft_particles", &droplets::ObstacleSweep::soft_particles)
      .def_readwrite("vertices", &droplets::ObstacleSweep::vertices)
      .def_readwrite("area_stiffness", &droplets::ObstacleSweep::area_stiffness)
      .def_readwrite("perimeter_ratio", &droplets::ObstacleSweep::perimeter_ratio)
      .def_readwrite("dp_wall_energy", &droplets::ObstacleSweep::dp_wall_energy)
      .def_readwrite("edge_contacts", &droplets::ObstacleSweep::edge_contacts)
      .def_readwrite("near_wall_drag", &droplets::ObstacleSweep::near_wall_drag)
      .def_readwrite("terminal_speed", &droplets::ObstacleSweep::terminal_speed)
      .def_readwrite("dt", &droplets::ObstacleSweep::dt)
      .def_readwrite("force_dt", &droplets::ObstacleSweep::force_dt)
      .def_readwrite("shape_dt_target", &droplets::ObstacleSweep::shape_dt_target)
      .def_readwrite("box_length", &droplets::ObstacleSweep::box_length)
      .def_readwrite("obstacle_diameter", &droplets::ObstacleSweep::obstacle_diameter)
      .def_readwrite("obstacle_fraction", &droplets::ObstacleSweep::obstacle_fraction)
      .def_readwrite("time_limit", &droplets::ObstacleSweep::time_limit)
      .def_readwrite("clog_threshold", &droplets::ObstacleSweep::clog_threshold)
      .def_readwrite("clog_test", &droplets::ObstacleSweep::clog_test)
      .def_readwrite("early", &droplets::ObstacleSweep::early)
      .def_readwrite("relax_iterations", &droplets::ObstacleSweep::relax_iterations)
      .def_readwrite("batch", &droplets::ObstacleSweep::batch)
      .def("check", &droplets::ObstacleSweep::check, py::arg("strength"), py::arg("gap"),
           "Refuses the point (ValueError naming the parameter) or returns its time step")
      .def("may_revisit_own_path", &droplets::ObstacleSweep::may_revisit_own_path);

  m.def(
      "obstacle_centres",
      [](const droplets::ObstacleSweep& sweep, double strength, double gap, std::uint64_t seed, int replica) {
        const auto centres = droplets::ensemble_detail::replica_obstacles(sweep.at(strength, gap),
                                                                          droplets::replica_seed(seed, replica));
        py::array_t<double> a(std::vector<py::ssize_t>{py::ssize_t(centres.size()), 2});
        auto r = a.mutable_unchecked<2>();
        for (std::size_t i = 0; i < centres.size(); ++i) {
          r(py::ssize_t(i), 0) = centres[i][0];
          r(py::ssize_t(i), 1) = centres[i][1];
        }
        return a;
      },
      py::arg("sweep"), py::arg("strength"), py::arg("gap"), py::arg("seed"), py::arg("replica"),
      "the obstacle centres (n, 2) of replica `replica` at point (strength, gap), as the sweep places them");
  m.def("replica_seed", [](std::uint64_t seed, int replica) { return droplets::replica_seed(seed, replica); },
        py::arg("seed"), py::arg("replica"), "the obstacle-array seed of a replica (as the obstacles driver)");

  m.def(
      "run_sweep",
      [](const droplets::ObstacleSweep& sweep, const std::vector<std::pair<double, double>>& points,
         const std::vector<std::vector<int>>& todo, std::uint64_t seed, const std::string& schedule,
         const std::function<void(int, int, std::uint64_t, py::dict)>& on_finished,
         const std::function<void(long long)>& on_steps) {
        require_kokkos();
        if (todo.size() != points.size()) throw std::invalid_argument("todo: one replica list per point");
        if (schedule != "sweep" && schedule != "points")
          throw std::invalid_argument("schedule must be 'sweep' or 'points', got '" + schedule + "'");
        for (const auto& [strength, gap] : points) sweep.check(strength, gap);
        const auto finished = [&](std::size_t p, int replica, std::uint64_t s, const droplets::ReplicaRecord& r) {
          on_finished(int(p), replica, s, record_dict(r));
        };
        const auto steps = [&](long long s) {
          check_signals();
          if (on_steps) on_steps(s);
        };
        py::dict stats;
        if (!sweep.soft_particles && schedule == "sweep") {
          std::vector<droplets::ObstacleEnsembleParameters> scenes;
          for (const auto& [strength, gap] : points) scenes.push_back(sweep.at(strength, gap));
          const auto s = droplets::run_sweep_batched<double>(scenes, todo, seed, sweep.batch, finished, steps);
          stats["steps"] = s.steps;
          stats["replica_steps"] = s.replica_steps;
        } else {
          const auto s = droplets::run_sweep_points<double>(sweep, points, todo, seed,
                                                            [](std::size_t, const std::vector<int>&, long long) {},
                                                            finished, steps);
          stats["steps"] = s.steps;
          stats["replica_steps"] = s.replica_steps;
        }
        return stats;
      },
      py::arg("sweep"), py::arg("points"), py::arg("todo"), py::arg("seed"), py::arg("schedule") = "sweep",
      py::arg("on_finished"), py::arg("on_steps") = nullptr,
      "Runs replicas todo[p] of each point p = (strength, gap) as the obstacles driver does (DP: one refilled "
      "batch, schedule 'sweep'; SP or 'points': batch after batch); on_finished(point, replica, seed, record) as "
      "each finishes");

  m.def(
      "decay_length",
      [](const std::vector<double>& distance, const std::vector<bool>& clogged, double level) {
        const auto e = droplets::decay_length(outcomes_of(distance, clogged), level);
        py::dict d;
        d["decay_length"] = e.lambda;
        d["lower"] = e.lower;
        d["upper"] = e.upper;
        d["clogged"] = e.clogged;
        d["censored"] = e.censored;
        d["total_distance"] = e.total_distance;
        return d;
      },
      py::arg("distances"), py::arg("clogged"), py::arg("level") = 0.95,
      "Maximum-likelihood clogging decay length λ of P(r) = exp(-r/λ) with right censoring (eq. 16) and its "
      "likelihood-ratio interval");
  m.def(
      "survival_curve",
      [](const std::vector<double>& distance, const std::vector<bool>& clogged) {
        const auto curve = droplets::survival_curve(outcomes_of(distance, clogged));
        std::vector<double> r, p;
        for (const auto& s : curve) {
          r.push_back(s.distance);
          p.push_back(s.probability);
        }
        return py::make_tuple(py::array_t<double>(py::ssize_t(r.size()), r.data()),
                              py::array_t<double>(py::ssize_t(p.size()), p.data()));
      },
      py::arg("distances"), py::arg("clogged"), "Kaplan-Meier P(r): (distances, probabilities)");
}

}  // namespace mesoflow::python
