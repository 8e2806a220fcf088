// analysis.cpp — the host analysis of the studies as functions on arrays (issue 30 item 2): the
// hopper's Beverloo and β(λ) fits (analysis/hopper/flow_rate_fits), the pillars' permeability
// theory and Brinkman fit (analysis/pillars/permeability_theory), the crystal's phonon power
// spectrum (analysis/crystal/phonon_spectra) and the capsule's shear-plane Taylor deformation
// (analysis/capsule/capsule_shape). Bad input raises ValueError with the C++ message.
#include "analysis/capsule/capsule_shape.hpp"
#include "analysis/crystal/phonon_spectra.hpp"
#include "analysis/hopper/flow_rate_fits.hpp"
#include "analysis/pillars/permeability_theory.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <stdexcept>
#include <string>

namespace py = pybind11;

namespace mesoflow::python {

void bind_analysis(py::module_& top) {
  py::module_ m = top.def_submodule("analysis", "host analysis of the studies, on arrays");

  // Hopper flows (hopper-flows eqs. 13, 14)
  m.def(
      "fit_beverloo",
      [](const std::vector<double>& w, const std::vector<double>& Q, const std::vector<double>& Q_error) {
        const auto f = hopper::fit_beverloo(w, Q, Q_error);
        py::dict d;
        d["C"] = f.C, d["k"] = f.k, d["beta"] = f.beta;
        d["C_error"] = f.C_error, d["k_error"] = f.k_error, d["beta_error"] = f.beta_error;
        d["chi2"] = f.chi2, d["dof"] = f.dof, d["chi2_per_dof"] = f.chi2_per_dof;
        d["weighted"] = f.weighted, d["converged"] = f.converged;
        return d;
      },
      py::arg("w_over_sigma"), py::arg("Q"), py::arg("Q_error") = std::vector<double>{},
      "Beverloo's Q = C (w/σ − k)^β (eq. 13) by Levenberg–Marquardt, with standard errors");
  m.def("beta_sigmoid", &hopper::beta_sigmoid, py::arg("lambda_"), py::arg("dimension"), py::arg("lambda_c"),
        py::arg("stretch"), "eq. 14: β(λ) between the plateaus d − 1/2 and d − 3/2");
  m.def(
      "fit_beta_sigmoid",
      [](const std::vector<double>& lambda, const std::vector<double>& beta, const std::vector<double>& beta_error,
         int dimension) {
        const auto f = hopper::fit_beta_sigmoid(lambda, beta, beta_error, dimension);
        py::dict d;
        d["lambda_c"] = f.lambda_c, d["lambda_c_error"] = f.lambda_c_error;
        d["stretch"] = f.stretch, d["stretch_error"] = f.stretch_error;
        d["chi2"] = f.chi2, d["dof"] = f.dof, d["converged"] = f.converged;
        return d;
      },
      py::arg("lambda_"), py::arg("beta"), py::arg("beta_error") = std::vector<double>{}, py::arg("dimension") = 2,
      "eq. 14 fitted to β(λ): λ_c and the stretch 1/b with their errors");

  // Pillar arrays (mdpd-pillar-array-permeability)
  m.def("kappa_gebart_square", &pillars::kappa_gebart_square, py::arg("porosity"));
  m.def("kappa_drummond_tahir_square", &pillars::kappa_drummond_tahir_square, py::arg("porosity"));
  m.def("kappa_sangani_acrivos_dilute", &pillars::kappa_sangani_acrivos_dilute, py::arg("porosity"));
  m.def("kappa_sangani_acrivos_dense", &pillars::kappa_sangani_acrivos_dense, py::arg("porosity"));
  m.def("kappa_walls", &pillars::kappa_walls, py::arg("H"), "H²/12, the walls-only channel");
  m.def("brinkman_profile", &pillars::brinkman_profile, py::arg("z"), py::arg("B"), py::arg("alpha"), py::arg("H"),
        "eq. 5: the superficial velocity at z from the mid-plane");
  m.def("kappa_eff_brinkman", &pillars::kappa_eff_brinkman, py::arg("kappa_p"), py::arg("alpha"), py::arg("H"));
  m.def("mu_eff_ratio", &pillars::mu_eff_ratio, py::arg("kappa_p"), py::arg("alpha"), "μ_eff/μ = 1/(κ_p α²)");
  m.def(
      "fit_brinkman",
      [](const std::vector<double>& z, const std::vector<double>& u, double H) {
        const auto f = pillars::fit_brinkman(z, u, H);
        py::dict d;
        d["B"] = f.B, d["alpha"] = f.alpha, d["rms_residual"] = f.rms_residual;
        d["alpha_at_lower_bound"] = f.alpha_at_lower_bound, d["alpha_at_upper_bound"] = f.alpha_at_upper_bound;
        return d;
      },
      py::arg("z"), py::arg("u_s"), py::arg("H"), "eq. 5 fitted to u_s(z): B and α");

  // Crystal phonons (mpc-microfluidic-crystal-phonons eqs. 1–2)
  m.def("wavenumbers", &crystal::wavenumbers, py::arg("droplets"), py::arg("a"));
  m.def("frequencies", &crystal::frequencies, py::arg("frames"), py::arg("dt"));
  m.def(
      "power_spectrum",
      [](py::array_t<double, py::array::c_style | py::array::forcecast> field, bool hann, bool subtract_mean) {
        if (field.ndim() != 2)
          throw std::invalid_argument("field must be (frames, droplets), got " + std::to_string(field.ndim()) +
                                      " dimensions");
        const std::size_t frames = std::size_t(field.shape(0)), droplets = std::size_t(field.shape(1));
        crystal::SpectrumOptions o;
        o.window = hann ? crystal::TimeWindow::hann : crystal::TimeWindow::rectangular;
        o.subtract_mean = subtract_mean;
        const std::vector<double> f(field.data(), field.data() + field.size());
        const auto p = crystal::power_spectrum(f, droplets, frames, o);
        py::array_t<double> out(std::vector<py::ssize_t>{py::ssize_t(droplets), py::ssize_t(frames)});
        std::copy(p.begin(), p.end(), out.mutable_data());
        return out;
      },
      py::arg("field"), py::arg("hann") = true, py::arg("subtract_mean") = true,
      "P(k_p, ω_q) of a (frames, droplets) field: (droplets, frames), on the grids of wavenumbers() and "
      "frequencies()");

  // Capsule shape (sph-microcapsules-constriction)
  m.def(
      "shear_plane_shape",
      [](py::array_t<double, py::array::c_style | py::array::forcecast> points) {
        if (points.ndim() != 2 || points.shape(1) != 3)
          throw std::invalid_argument("points must be (n, 3)");
        std::vector<Eigen::Vector3d> y;
        const auto r = points.unchecked<2>();
        for (py::ssize_t i = 0; i < r.shape(0); ++i) y.emplace_back(r(i, 0), r(i, 1), r(i, 2));
        const auto s = capsule::shear_plane_shape(y);
        py::dict d;
        d["taylor"] = s.taylor, d["inclination"] = s.inclination, d["length"] = s.length, d["breadth"] = s.breadth;
        return d;
      },
      py::arg("points"), "Taylor deformation D_xy = (L − B)/(L + B) and inclination of the shear-plane section");
}

}  // namespace mesoflow::python
