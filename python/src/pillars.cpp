// pillars.cpp — bindings of the pillar-array flow (mdpd-pillar-array-permeability: MDPD fluid
// driven through tethered pillars, scenes/pillars/pillar_flow.hpp and pillar_runs.hpp), in 2D or 3D.
// The scene and its run loop (PillarFlow) are the `pillars` driver's, and so are the permeability
// estimates of its samples (permeability(), assembled as the driver does); output files and
// checkpoints stay in the driver (mesoflow.analysis has the theory and the Brinkman fit).
#include "analysis/pillars/permeability_estimates.hpp"
#include "python/src/lifetime.hpp"
#include "scenes/pillars/pillar_runs.hpp"

#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>

namespace py = pybind11;

namespace mesoflow::python {
namespace {

template <int D>
using PyPillars = Owned<pillars::PillarFlow<D>>;

// PillarFlow::run's output: each sample to a Python callback (a false return is not possible
// mid-run: samples are recorded), nothing written to files.
struct CallbackOutput {
  std::function<void(py::dict)> on_sample;
  void sample(const pillars::SampleObservables& o) {
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    if (!on_sample) return;
    py::dict d;
    d["mean_velocity_x"] = o.mean_velocity_x, d["pillar_force_x"] = o.pillar_force_x;
    d["fluid_temperature"] = o.fluid_temperature;
    on_sample(d);
  }
  void final() {}
  void checkpoint() {}
  void progress(long long) {}
};

template <int D>
void bind_flow(py::module_& m, const char* name) {
  using S = PyPillars<D>;
  py::class_<S>(m, name, "MDPD fluid in a pillar array (built, not yet filled: call equilibrate())")
      .def(py::init([](const pillars::PillarRunParameters& par) {
             return std::make_unique<S>(pillars::flow_settings(par, pillars::make_layout(par), D));
           }),
           py::arg("parameters"))
      .def("equilibrate", [](S& s, long long steps, long long check_every) { s.get().equilibrate_and_carve(steps, check_every); },
           py::arg("steps"), py::arg("check_every") = 100,
           "fills the box with fluid, equilibrates it without driving, carves the pillars out of it")
      .def(
          "run",
          [](S& s, long long warmup, long long steps, long long sample_every, const std::function<void(py::dict)>& cb,
             long long check_every) {
            if (warmup < 0 || steps < 0 || sample_every < 1)
              throw std::invalid_argument("warmup and steps must be >= 0 and sample_every >= 1");
            CallbackOutput out{cb};
            s.get().run(warmup, steps, sample_every, std::numeric_limits<long long>::max(), check_every, out);
          },
          py::arg("warmup"), py::arg("steps"), py::arg("sample_every") = 10, py::arg("on_sample") = nullptr,
          py::arg("check_every") = 100, "driven steps: warmup, then steps sampled every sample_every")
      .def_property_readonly("steps", [](S& s) { return (long long)s.get().system().current_step(); },
                             "steps done since the fluid was filled in (equilibration included)")
      .def_property_readonly("time", [](S& s) { return s.get().system().time(); })
      .def(
          "permeability",
          [](S& s, double viscosity, double kappa_p) {
            const auto& f = s.get();
            const auto& st = f.settings();
            const auto& g = st.geometry;
            const auto& rec = f.record();
            if (rec.samples == 0) throw std::invalid_argument("permeability: no samples yet (call run() first)");
            if (!(viscosity >= 0) || !std::isfinite(viscosity))
              throw std::invalid_argument("permeability: viscosity must be finite and >= 0 (0: the paper's), got " +
                                          std::to_string(viscosity));
            if (!(kappa_p >= 0) || !std::isfinite(kappa_p))
              throw std::invalid_argument("permeability: kappa_p must be finite and >= 0 (0: none), got " +
                                          std::to_string(kappa_p));
            pillars::PillarRunParameters par;
            par.viscosity = viscosity;
            const double mu = par.viscosity_for_kappa(D);
            // as the `pillars` driver assembles it (drivers/pillars/pillars.cpp)
            const pillars::FlowMeasurement m{D, g.Lx, g.Ly, g.Lz, g.H, g.diameter, st.porosity, g.centres, f.x_lo(),
                                             f.x_hi(), mu, st.driving_force, st.density, st.driving_length, rec.count,
                                             rec.velocity, rec.pillar_force, rec.tether, rec.driven, rec.sum_u,
                                             rec.sum_u2, rec.sample_u, rec.sample_tether, rec.samples, rec.count_all,
                                             rec.velocity_all, rec.tether_all, rec.sample_u_box,
                                             rec.sample_count_profile, rec.sample_velocity_profile};
            const auto e = pillars::estimate_permeability(m);
            py::dict d;
            d["viscosity_used"] = mu, d["mean_ux"] = e.mean_u, d["mean_ux_naive_error"] = e.mean_u_naive_error;
            d["mean_ux_block_error"] = e.mean_u_block_error, d["superficial_velocity"] = e.superficial_velocity;
            d["pressure_difference"] = e.pressure_difference;
            d["pressure_difference_force_balance"] = e.pressure_difference_force_balance;
            d["kappa_darcy"] = e.kappa_darcy, d["kappa_darcy_force_balance"] = e.kappa_darcy_force_balance;
            d["kappa_darcy_relative_error"] = e.kappa_darcy_relative_error;
            d["kappa_drag_pair"] = e.kappa_drag_pair, d["kappa_drag_tether"] = e.kappa_drag_tether;
            d["kappa_drag_tether_relative_error"] = e.kappa_drag_tether_relative_error;
            d["measured_pillars"] = e.measured_pillars, d["kappa_darcy_box"] = e.kappa_darcy_box;
            d["kappa_darcy_box_relative_error"] = e.kappa_darcy_box_relative_error;
            d["kappa_drag_tether_region"] = e.kappa_drag_tether_region;
            d["superficial_velocity_box"] = e.superficial_velocity_box;
            if (e.fit) {  // 3D with walls: Brinkman's eq. 5, as the driver's JSON "brinkman"
              const auto& fit = *e.fit;
              py::dict b;
              b["B"] = fit.B, b["alpha"] = fit.alpha, b["rms_residual"] = fit.rms_residual;
              b["alpha_at_bound"] = fit.alpha_at_lower_bound || fit.alpha_at_upper_bound;
              b["jackknife_blocks"] = e.jackknife_blocks, b["alpha_error"] = e.alpha_jackknife_error;
              b["B_error"] = e.B_jackknife_error;
              if (kappa_p > 0)
                for (const auto& [name, value] : pillars::brinkman_theory(kappa_p, fit.alpha, e.alpha_jackknife_error,
                                                                          g.H, e.pressure_difference, mu, g.Lx))
                  b[name] = value;
              d["brinkman"] = b;
            }
            return d;
          },
          py::arg("viscosity") = 0.0, py::arg("kappa_p") = 0.0,
          "the `pillars` driver's permeability estimates from the samples so far (Darcy, eqs. 1-2; drag, eq. 3): "
          "κ_darcy, κ_drag_tether, ... with μ = viscosity (0: the paper's 26.1 in 2D, 17.5 in 3D); between walls "
          "also 'brinkman' (eq. 5's B and α with their jackknife errors; with kappa_p > 0, μ_eff/μ and eq. 7)")
      .def_property_readonly("components", [](S& s) { return s.get().components(); })
      .def_property_readonly("solid_particles", [](S& s) { return s.get().solid_particles(); })
      .def_property_readonly("porosity", [](S& s) { return s.get().settings().porosity; })
      .def_property_readonly("box", [](S& s) {
        const auto& g = s.get().settings().geometry;
        return py::make_tuple(g.Lx, g.Ly, g.Lz);
      }, "(Lx, Ly, Lz) of the periodic box [0, L) per axis (Lz = 0 in 2D); walls fill z in [H, Lz)")
      .def_property_readonly("height", [](S& s) { return s.get().settings().geometry.H; },
                             "channel height H between the walls (0: no walls)")
      .def_property_readonly("record", [](S& s) {
        const auto& r = s.get().record();
        py::dict d;
        d["samples"] = r.samples;
        d["mean_velocity_x"] = r.samples > 0 ? r.sum_u / double(r.samples) : 0.0;
        d["sample_velocity_x"] = r.sample_u;
        d["count"] = r.count, d["velocity"] = r.velocity, d["pillar_force"] = r.pillar_force;
        d["tether"] = r.tether;
        return d;
      }, "the accumulated flow record: per-sample mean u_x in the measurement region, elevation profiles")
      .def_property_readonly(
          "positions", [](py::object self) { return numpy_view(self.cast<S&>().get().system().particles.x, self); },
          "every particle's position (n, D): fluid and solid; a view on host backends")
      .def_property_readonly(
          "velocities", [](py::object self) { return numpy_view(self.cast<S&>().get().system().particles.v, self); })
      .def_property_readonly(
          "types", [](py::object self) { return numpy_view(self.cast<S&>().get().system().particles.type, self); },
          "0 fluid, 1 solid surface, 2 solid core (mdpd::particle_type)");
}

}  // namespace

void bind_pillars(py::module_& top) {
  py::module_ m = top.def_submodule("pillars", "MDPD flow through pillar arrays (mdpd-pillar-array-permeability)");
  using P = pillars::PillarRunParameters;
  py::class_<P>(m, "PillarRunParameters")
      .def(py::init<>())
      .def_readwrite("layout", &P::layout)
      .def_readwrite("porosity", &P::porosity)
      .def_readwrite("diameter", &P::diameter)
      .def_readwrite("cells_x", &P::cells_x)
      .def_readwrite("cells_y", &P::cells_y)
      .def_readwrite("pillars", &P::pillars)
      .def_readwrite("aspect", &P::aspect)
      .def_readwrite("exclusion", &P::exclusion)
      .def_readwrite("mc_sweeps", &P::mc_sweeps)
      .def_readwrite("height", &P::height)
      .def_readwrite("lz", &P::lz)
      .def_readwrite("box", &P::box)
      .def_readwrite("fb", &P::fb)
      .def_readwrite("driving_length", &P::driving_length)
      .def_readwrite("bin_width", &P::bin_width)
      .def_readwrite("density", &P::density)
      .def_readwrite("A", &P::A)
      .def_readwrite("B", &P::B)
      .def_readwrite("r_B", &P::r_B)
      .def_readwrite("R", &P::R)
      .def_readwrite("dt", &P::dt)
      .def_readwrite("k_S", &P::k_S)
      .def_readwrite("density_kernel", &P::density_kernel)
      .def_readwrite("list", &P::list)
      .def_readwrite("density_self_term", &P::density_self_term)
      .def_readwrite("seed", &P::seed);
  bind_flow<2>(m, "PillarFlow2D");
  bind_flow<3>(m, "PillarFlow3D");
}

}  // namespace mesoflow::python
