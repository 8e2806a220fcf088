// crystal.cpp — bindings of the microfluidic crystal's channel flow (mpc-microfluidic-crystal-phonons:
// MPC-AT+a solvent between no-slip walls with rigid discs, scenes/crystal/channel_flow.hpp), stepped
// from Python, the solvent and the discs as arrays. The phonon analysis is in mesoflow.analysis.
// run_crystal: the `crystal` driver's run (scenes/crystal/crystal_run.hpp) as one call, with its
// results file, K and the phonon analysis (analysis/crystal/run_analysis.hpp) as the driver has them.
#include "analysis/crystal/run_analysis.hpp"
#include "python/src/lifetime.hpp"
#include "scenes/crystal/channel_flow.hpp"
#include "scenes/crystal/crystal_run.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <chrono>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace py = pybind11;

namespace mesoflow::python {
namespace {

using Params = mpc::ChannelFlowParameters<double>;
using Flow = mpc::ChannelFlow<double>;

using PyChannel = Owned<Flow>;
using RunParams = crystal::CrystalRunParameters;

// The driver's run into `output` (<base>.h5, <base>.xdmf, <base>.ckpt.h5, and with two or more discs
// <base>_phonons.h5 and <base>_theory.csv; with one disc <base>_far_profile.csv): the results file's
// parameters are `resolved`; callback(step, time) at every frame, False stops the run (the files so
// far are kept, with a checkpoint at the stop, no analysis). restart: continue from <base>.ckpt.h5 as the
// driver's --restart does (the same scene; time may grow). Returns what the driver's JSON has, with the
// frames as arrays.
py::dict run_crystal(const RunParams& par, const std::string& output, py::object callback,
                     const std::vector<std::pair<std::string, std::string>>& resolved, bool restart) {
  par.validate();
  if (par.precision != "double")
    throw std::invalid_argument("crystal run: the Python module runs in double precision (the crystal driver has "
                                "--precision float), got precision '" + par.precision + "'");
  if (output.size() < 4 || output.compare(output.size() - 3, 3, ".h5") != 0)
    throw std::invalid_argument("crystal run: output must end in .h5, got '" + output + "'");
  require_kokkos();
  const std::string base = output.substr(0, output.size() - 3);
  const auto& f = par.flow;
  const std::string checkpoint = base + ".ckpt.h5", signature = crystal::scene_signature(par);
  crystal::CrystalRun<double> run(par, checkpoint, signature);
  if (restart) {
    if (!std::filesystem::exists(checkpoint))
      throw std::invalid_argument("crystal run: restart=True needs the checkpoint " + checkpoint + ", which does not exist");
    const io::CheckpointReader ck(checkpoint);
    const std::string stored = ck.get_string("scene");
    if (stored != signature)
      throw std::invalid_argument("crystal run: restart: " + checkpoint + " was written by another scene (" + stored +
                                  "); only time, checkpoint_interval and check_every may change");
    run.resume(ck, output);
  } else {
    run.start(output, resolved);
  }
  const long long first = (long long)run.flow().steps_done();
  bool stopped = false;
  const auto t0 = std::chrono::steady_clock::now();
  try {
    run.run([&](std::int64_t step) {
      if (step % run.frame_steps() != 0 && step != run.total_steps()) return;
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
      if (!callback.is_none() && callback(step, double(step) * f.h).equal(py::bool_(false))) throw StopRun{};
    });
  } catch (const StopRun&) {
    stopped = true;
    run.checkpoint_now();  // restart=True continues from this frame
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  run.close(base + ".xdmf");
  const auto& rec = run.record();
  const std::size_t nd = run.discs();
  py::dict r;
  r["stopped"] = stopped, r["discs"] = nd, r["solvent_particles"] = run.flow().num_solvent();
  r["steps"] = (long long)run.flow().steps_done(), r["wall_seconds"] = wall;
  r["resumed_from_step"] = first;
  r["signature"] = crystal::scene_signature(par);
  std::vector<double> frame_time;
  for (const auto s : rec.steps) frame_time.push_back(double(s) * f.h);
  r["frame_time"] = array(frame_time), r["u_d_series"] = array(rec.u_d), r["u_oil_series"] = array(rec.u_oil);
  const std::size_t frames = rec.steps.size();
  py::array_t<double> x({py::ssize_t(frames), py::ssize_t(nd)}), y({py::ssize_t(frames), py::ssize_t(nd)});
  std::copy(rec.x.begin(), rec.x.end(), x.mutable_data());
  std::copy(rec.y.begin(), rec.y.end(), y.mutable_data());
  r["x"] = x, r["y"] = y;
  if (stopped) return r;
  const auto m = crystal::measured_frames(rec.steps, rec.u_d, rec.u_oil, run.warmup_steps());
  const double eta = crystal::viscosity_b3(f);
  const auto numbers =
      crystal::run_numbers(m, eta, f.density * f.mass / (f.cell_size * f.cell_size), f.disc_radius, f.friction, f.kT);
  r["measured_frames"] = m.count, r["u_d"] = m.u_d, r["u_oil"] = m.u_oil, r["K"] = numbers.K;
  r["wall_virtual"] = par.wall_virtual, r["viscosity_b3"] = eta, r["reynolds"] = numbers.reynolds;
  r["peclet"] = numbers.peclet;
  if (run.far_field()) {
    const auto& ff = rec.far_field();
    rec.write_far_profile(base + "_far_profile.csv");
    const auto [u_far, u_axis] = rec.far_speeds();
    py::dict d;
    d["from_disc"] = ff.from_disc, d["u_mean"] = u_far, d["u_axis"] = u_axis;
    d["K_mean"] = u_far != 0 ? m.u_d / u_far : 0.0, d["K_axis"] = u_axis != 0 ? m.u_d / u_axis : 0.0;
    r["far_field"] = d;
  }
  if (nd >= 2) {
    const double dt_frame = double(run.frame_steps()) * f.h;
    const auto ph = crystal::phonon_analysis(rec.x, rec.y, m, nd, f.length, f.width, f.disc_radius,
                                             par.calibrated_ratio, dt_frame, base + "_phonons.h5", base + "_theory.csv");
    r["theory_K"] = m.u_d / ph.theory_uoil, r["spacing"] = ph.spacing, r["B"] = ph.B, r["beta"] = ph.beta;
    r["phase_velocity"] = ph.phase_velocity, r["frame_interval"] = dt_frame;
  }
  return r;
}

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
  py::class_<RunParams>(m, "CrystalRunParameters", "the `crystal` driver's run (defaults: the paper's scene)")
      .def(py::init<>())
      .def_readwrite("flow", &RunParams::flow)
      .def_readwrite("rule", &RunParams::rule)
      .def_readwrite("wall_virtual", &RunParams::wall_virtual)
      .def_readwrite("discs", &RunParams::discs)
      .def_readwrite("wavelength", &RunParams::wavelength)
      .def_readwrite("amplitude", &RunParams::amplitude)
      .def_readwrite("warmup", &RunParams::warmup)
      .def_readwrite("time", &RunParams::time)
      .def_readwrite("frame_interval", &RunParams::frame_interval)
      .def_readwrite("checkpoint_interval", &RunParams::checkpoint_interval)
      .def_readwrite("check_every", &RunParams::check_every)
      .def_readwrite("calibrated_ratio", &RunParams::calibrated_ratio)
      .def_readwrite("seed", &RunParams::seed)
      .def_readwrite("precision", &RunParams::precision)
      .def_readwrite("force_dt", &RunParams::force_dt)
      .def("validate", &RunParams::validate, "the run's ranges and the step's stability limit (ValueError)");
  m.def("run_crystal", &run_crystal, py::arg("parameters"), py::arg("output"), py::arg("callback") = py::none(),
        py::arg("resolved") = std::vector<std::pair<std::string, std::string>>{}, py::arg("restart") = false,
        "the `crystal` driver's run as one call (callback(step, time) per frame; False stops it)");
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
