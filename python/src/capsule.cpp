// capsule.cpp — bindings of the SPH + mass-spring capsule (sph-microcapsules-constriction,
// scenes/capsule/capsule_scene.hpp) in a periodic box: a two-layer icosphere membrane with inner and
// outer fluids, stepped from Python; and the `capsule` driver's two runs, one (Ca, η) or one Ca at a
// time (scenes/capsule/capsule_runs.hpp: the constriction with its flow control, simple shear), the
// samples measured as the driver measures them and handed back as arrays.
#include "analysis/capsule/capsule_shape.hpp"
#include "analysis/capsule/sweep_results.hpp"
#include "python/src/lifetime.hpp"
#include "scenes/capsule/capsule_runs.hpp"
#include "scenes/capsule/capsule_scene.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <chrono>
#include <memory>

namespace py = pybind11;

namespace mesoflow::python {
namespace {

using Params = capsule::CapsuleSceneParameters;
using Scene = capsule::CapsuleScene<double>;

using PyCapsule = Owned<Scene>;
using RunParams = capsule::CapsuleRunParameters;

py::dict physical_dict(const capsule::Physical& p) {
  py::dict d;
  d["diameter"] = p.d, d["radius"] = p.a, d["viscosity"] = p.mu, d["surface_shear_modulus"] = p.G_s;
  d["k_b"] = p.k_b, d["c0"] = p.c0, d["shear_rate"] = p.shear_rate;
  d["surface_shear_modulus_network"] = p.G_s_network, d["area_modulus_network"] = p.K_A_network;
  d["surface_shear_modulus_paper_formula"] = p.G_s_paper, d["ca_network"] = p.ca_network;
  d["ca_paper_formula"] = p.ca_paper;
  return d;
}

// One shear run at Ca (the driver's shear mode): per sample γ̇t, D_xy, θ/π, max |ρ − ρ0|/ρ0, dt·γ̇;
// the steady values over the last 30% of t_max, as the driver's result row.
py::dict run_shear(const RunParams& par, double ca, py::object callback) {
  par.validate();
  if (!(ca > 0 && ca <= 100)) throw std::invalid_argument("capsule shear: ca must be in (0, 100], got " + std::to_string(ca));
  RunParams p = par;
  p.mode = "shear";
  capsule::ShearRun<> run(p, ca, true);
  struct Output {
    py::object callback;
    std::vector<double> t, D, theta, dens, dt_gamma;
    bool stopped = false;
    void progress(long) {}
    void sample(double time, const std::vector<Eigen::Vector3d>& y, double de, double dtg) {
      const auto s = capsule::shear_plane_shape(y);
      t.push_back(time), D.push_back(s.taylor), theta.push_back(s.inclination / capsule::pi);
      dens.push_back(de), dt_gamma.push_back(dtg);
      if (!callback.is_none() && callback(time, s.taylor, s.inclination / capsule::pi).equal(py::bool_(false))) {
        stopped = true;
        throw StopRun{};
      }
    }
  } out{callback, {}, {}, {}, {}, {}};
  const auto t0 = std::chrono::steady_clock::now();
  try {
    run.run(out);
  } catch (const StopRun&) {
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double from = 0.7 * p.t_max;  // as the driver: the last 30% of the run
  const auto D = capsule::steady_value(out.t, out.D, from), T = capsule::steady_value(out.t, out.theta, from);
  py::dict r;
  r["ca"] = ca, r["stopped"] = out.stopped;
  r["shear_time"] = array(out.t), r["taylor_deformation"] = array(out.D), r["inclination_over_pi"] = array(out.theta);
  r["max_density_deviation_series"] = array(out.dens), r["dt_gamma_series"] = array(out.dt_gamma);
  r["D_xy"] = D.mean, r["D_xy_std"] = D.std, r["theta_over_pi"] = T.mean, r["theta_over_pi_std"] = T.std;
  r["dt_gamma"] = run.start_dt() * run.physical().shear_rate, r["particles"] = run.scene().num_particles();
  r["max_density_deviation"] = run.max_density_deviation(), r["wall_seconds"] = wall;
  r["signature"] = capsule::shear_signature(p, ca), r["physical"] = physical_dict(run.physical());
  return r;
}

// One constriction run at (Ca, η) (the driver's constriction mode): per sample the time (d/U),
// x_c/d, D_∞,x,y,z, C_f, C_r, the body force and flux ratio; the status, passage time and the values at
// x_c = 4d of the driver's result row.
py::dict run_constriction(const RunParams& par, double ca, double eta, py::object callback) {
  par.validate();
  if (!(ca > 0 && ca <= 100)) throw std::invalid_argument("capsule constriction: ca must be in (0, 100], got " + std::to_string(ca));
  if (!(eta > 0 && eta <= 2)) throw std::invalid_argument("capsule constriction: eta must be in (0, 2], got " + std::to_string(eta));
  RunParams p = par;
  p.mode = "constriction";
  capsule::ConstrictionRun<> run(p, ca, eta, true);
  struct Output {
    const capsule::ConstrictionRun<>& run;
    py::object callback;
    std::vector<double> t, xc, dx, dy, dz, cf, cr, body, flux, dens;
    bool stopped = false;
    void progress(long) {}
    void sample(const capsule::ConstrictionSample& s) {
      const double d = run.physical().d, a = run.physical().a;
      const auto m = capsule::sample_shape(s.y, run.scene().mesh().triangle, s.x_c, d, a);
      t.push_back(s.time), xc.push_back(s.x_c / d), dx.push_back(m.D[0]), dy.push_back(m.D[1]), dz.push_back(m.D[2]);
      cf.push_back(m.cf), cr.push_back(m.cr), body.push_back(s.body_force), flux.push_back(s.flux_ratio);
      dens.push_back(s.density_deviation);
      if (!callback.is_none() && callback(s.time, s.x_c / d).equal(py::bool_(false))) {
        stopped = true;
        throw StopRun{};
      }
    }
  } out{run, callback, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}};
  const auto t0 = std::chrono::steady_clock::now();
  capsule::RunResult r;
  try {
    r.status = run.run(out);
  } catch (const StopRun&) {
    r.status = "stopped";
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  capsule::set_passage(r, run.entry_time(), run.exit_time());
  capsule::set_values_at(r, out.xc, out.dx, out.dy, out.dz, out.cf, out.cr);
  py::dict d;
  d["ca"] = ca, d["eta"] = eta, d["eta_effective"] = run.channel().constriction_width / p.resolution;
  d["status"] = r.status, d["passage_time"] = r.passage_time, d["inverse_passage_time"] = r.inverse_passage_time;
  d["entry_time"] = run.entry_time(), d["exit_time"] = run.exit_time();
  d["Dx_at_4"] = r.Dx4, d["Dy_at_4"] = r.Dy4, d["Dz_at_4"] = r.Dz4;
  d["Cf_at_3.5_4_4.5"] = py::make_tuple(r.Cf[0], r.Cf[1], r.Cf[2]);
  d["Cr_at_3.5_4_4.5"] = py::make_tuple(r.Cr[0], r.Cr[1], r.Cr[2]);
  d["time"] = array(out.t), d["x_c"] = array(out.xc), d["Dx"] = array(out.dx), d["Dy"] = array(out.dy);
  d["Dz"] = array(out.dz), d["Cf"] = array(out.cf), d["Cr"] = array(out.cr), d["body_force"] = array(out.body);
  d["flux_ratio"] = array(out.flux), d["density_deviation"] = array(out.dens);
  d["dt"] = run.start_dt() / p.resolution, d["steps"] = run.steps(), d["particles"] = run.scene().num_particles();
  d["max_density_deviation"] = run.max_density_deviation(), d["wall_seconds"] = wall;
  d["signature"] = capsule::scene_signature(p, ca, eta), d["physical"] = physical_dict(run.physical());
  return d;
}

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
  py::class_<RunParams>(m, "CapsuleRunParameters", "the `capsule` driver's run parameters (its options, snake_case)")
      .def(py::init<>())
      .def_readwrite("resolution", &RunParams::resolution)
      .def_readwrite("reynolds", &RunParams::reynolds)
      .def_readwrite("thickness", &RunParams::thickness)
      .def_readwrite("level", &RunParams::level)
      .def_readwrite("diagonals", &RunParams::diagonals)
      .def_readwrite("shear_modulus", &RunParams::shear_modulus)
      .def_readwrite("support", &RunParams::support)
      .def_readwrite("walls", &RunParams::walls)
      .def_readwrite("viscosity_ratio", &RunParams::viscosity_ratio)
      .def_readwrite("c0", &RunParams::c0)
      .def_readwrite("membrane_strain", &RunParams::membrane_strain)
      .def_readwrite("density_variation", &RunParams::density_variation)
      .def_readwrite("t_max", &RunParams::t_max)
      .def_readwrite("sample_every", &RunParams::sample_every)
      .def_readwrite("frame_every", &RunParams::frame_every)
      .def_readwrite("stall_window", &RunParams::stall_window)
      .def_readwrite("shear_box_x", &RunParams::shear_box_x)
      .def_readwrite("shear_box_y", &RunParams::shear_box_y)
      .def_readwrite("shear_box_z", &RunParams::shear_box_z)
      .def_readwrite("dt", &RunParams::dt)
      .def_readwrite("force_dt", &RunParams::force_dt)
      .def_readwrite("check_every", &RunParams::check_every)
      .def_readwrite("deterministic", &RunParams::deterministic)
      .def("validate", &RunParams::validate);
  m.def("run_shear", &run_shear, py::arg("parameters"), py::arg("ca"), py::arg("callback") = py::none(),
        "one simple-shear run at Ca, as `capsule --mode shear` (callback(shear_time, D_xy, theta_over_pi) per "
        "sample; returning False stops the run)");
  m.def("pearson_r", &capsule::pearson_r, py::arg("x"), py::arg("y"),
        "Pearson's r of eq. (17) over the finite pairs (NaN with fewer than two or no spread)");
  m.def("run_constriction", &run_constriction, py::arg("parameters"), py::arg("ca"), py::arg("eta"),
        py::arg("callback") = py::none(),
        "one constriction run at (Ca, eta), as `capsule --mode constriction` (callback(time, x_c) per sample; "
        "returning False stops the run)");
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
