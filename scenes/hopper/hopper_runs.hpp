// hopper_runs.hpp — the sweeps of the `hopper` driver (hopper-flows §2.4, §4) as its parameters
// give them: the study's parameters and the combinations of them that are refused, the scene
// parameters of a sweep, the w sweeps (one, or one per --vary value, each with its scene
// parameters, output path and label), the check of every width's scene before any output, the
// runs of one sweep and their Q' (Appendix B, by the analysis' formula), and the files of a
// sweep's widths (its results file and tables) with the widths that enter the Beverloo fit and the
// steps and wall time of its runs. One width's run and the tables of its outputs: hopper_sweep.hpp;
// the fits: analysis/hopper/flow_rate_fits.hpp.
//
// Units (§2.2): σ_avg, g, ρ; t0 = √(σ_avg/g); Q in σ_avg^d/t0.
#pragma once

#include "io/h5md_writer.hpp"
#include "scenes/hopper/hopper_sweep.hpp"

#include <cmath>
#include <cstddef>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace mesoflow::hopper {

// The study's parameters (defaults: the driver's).
struct HopperRunParameters {
  std::string vary;    // empty, or the parameter swept in an outer loop (--vary)
  std::string values;  // its values (--values)
  HopperParameters scene;
  DpHopperParameters dp;
  FlowSettings flow;
  std::string model = "sp";
  std::string friction_component = "full";  // --friction-component
  double dt = 0;  // 0: automatic
  std::string widths = "4,5,6,7,8";
  std::string dimension = "2";

  // Refuses the combinations of options that name no scene (std::invalid_argument naming them).
  void check_combinations() const {
    if (model == "dp" && dimension != "2")
      throw std::invalid_argument("--dimension: the dp model is 2D only, got " + dimension);
    if (vary == "pair-energy" && model != "sp")
      throw std::invalid_argument("--vary pair-energy: needs --model sp");
    if ((vary == "perimeter-stiffness" || vary == "bending") && model != "dp")
      throw std::invalid_argument("--vary " + vary + ": needs --model dp");
    if (vary.empty() && !values.empty()) throw std::invalid_argument("--values: needs --vary");
  }
};

// The scene parameters of a sweep from the study's parameters: deformable polygons (DP, 2D) or soft
// particles (SP) in D dimensions (polygon_parameters, particle_parameters).
inline DpHopperParameters polygon_sweep_parameters(const HopperRunParameters& p) {
  return polygon_parameters(p.scene, p.dp, p.dt);
}
template <int D>
HopperParameters particle_sweep_parameters(const HopperRunParameters& p) {
  return particle_parameters(p.scene, p.dt, D);
}

// One w sweep: its scene parameters (with the --vary value set), output path and console label
// ("--drag 0.3" with --vary, else empty).
template <class SceneParameters>
struct SweepSpec {
  SceneParameters base;
  std::string output, label;
};

// The sweeps of the --vary values `values` of `par` (outputs <stem>_<vary><value>.h5, labels
// "--<vary> <value>"), their scene parameters make(par) with the value set (set_varied); λ = ζ/μ
// of each (∞ without friction) in `lambdas`.
template <class SceneParameters, class Make>
std::vector<SweepSpec<SceneParameters>> vary_sweeps(HopperRunParameters par, const std::vector<double>& values,
                                                    const std::string& stem, Make&& make,
                                                    std::vector<double>& lambdas) {
  std::vector<SweepSpec<SceneParameters>> sweeps;
  for (const double v : values) {
    set_varied(par.vary, v, par.scene, par.dp);
    std::ostringstream name, label;
    name << stem << '_' << par.vary << v << ".h5";
    label << "--" << par.vary << " " << v;
    sweeps.push_back({make(par), name.str(), label.str()});
    lambdas.push_back(par.scene.friction > 0 ? par.scene.drag / par.scene.friction : HUGE_VAL);
  }
  return sweeps;
}

// Checks the scene of every width of a sweep (before any output).
template <class SceneParameters>
void validate_widths(const SceneParameters& base, const std::vector<double>& widths, int dim) {
  for (std::size_t k = 0; k < widths.size(); ++k) validate(at_width(base, widths[k], k), dim);
}

// The runs of sweep `s` out of the sweep-major list `runs` of `n_widths` widths per sweep.
inline std::vector<WidthRun> sweep_runs(const std::vector<WidthRun>& runs, std::size_t s, std::size_t n_widths) {
  return std::vector<WidthRun>(runs.begin() + std::ptrdiff_t(s * n_widths),
                               runs.begin() + std::ptrdiff_t((s + 1) * n_widths));
}

// Q' of Appendix B, correct(Q, ρ_n, a_avg) (analysis/hopper/flow_rate_fits.hpp), for every soft-particle
// run with a number density ρ_n; a_avg the scene's mean particle area (volume in 3D).
template <class Correct>
void correct_flow_rates(std::vector<WidthRun>& runs, double mean_particle_measure, Correct&& correct) {
  for (WidthRun& r : runs)
    if (r.scalars.rho_n > 0) r.scalars.Q_corrected = correct(r.scalars.Q, r.scalars.rho_n, mean_particle_measure);
}

// The widths of a sweep that enter the Beverloo fit (flowing, steady, with a rate and its error):
// w, Q and its error; and the steps and wall time of all its widths' runs.
struct SweepTotals {
  std::vector<double> x, Q, Qe;
  double wall = 0;
  long long steps = 0;
};

// A sweep's files: the results file at `h5_path` (the resolved parameters (key, value) and the
// widths' outputs, write_width_outputs) and the tables at `csv_path` and `profile_path`
// (write_width_tables). Returns the sweep's totals for its summary.
inline SweepTotals write_sweep_files(const std::string& h5_path, const std::string& csv_path,
                                     const std::string& profile_path,
                                     const std::vector<std::pair<std::string, std::string>>& resolved,
                                     const std::vector<double>& widths, const std::vector<WidthRun>& runs,
                                     bool soft_particles) {
  {
    io::H5mdWriter h5(h5_path, "mesoflow", MESOFLOW_VERSION, "mesoflow hopper");
    for (const auto& [key, value] : resolved) h5.set_parameter(key, value);
    write_width_outputs(h5, widths, runs, soft_particles);
  }
  write_width_tables(csv_path, profile_path, widths, runs);
  SweepTotals t;
  for (std::size_t k = 0; k < widths.size(); ++k) {
    const WidthRun::Scalars& v = runs[k].scalars;
    t.wall += v.seconds;
    t.steps += v.steps;
    if (!v.clogged && v.steady && v.Q > 0 && v.Q_error > 0) {
      t.x.push_back(widths[k]);
      t.Q.push_back(v.Q);
      t.Qe.push_back(v.Q_error);
    }
  }
  return t;
}

}  // namespace mesoflow::hopper
