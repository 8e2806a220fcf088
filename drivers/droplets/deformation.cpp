// deformation — the deformation δ_s of a droplet under its own weight on a flat wall
// (capillary-droplets §4.2, Fig. 7b), for the deformable-polygon (DP) model as a function of the
// line tension Γ, or for the soft-particle (SP) model as a function of the wall stiffness E_w
// (eq. 8). This is the axis that maps λ(Γ) and λ(E_w) onto λ(δ_s) in Fig. 7c.
//
// Units (§2.2): length σ (undeformed droplet diameter), acceleration g, areal mass density ρ;
// time t0 = √(σ/g); M = π/4. δ_s is in σ; Γ, E_w, K_a, K_l are the paper's dimensionless numbers.
//
// Method (scenes/droplets/deformation.hpp): the droplet touches the wall y = 0, FIRE relaxes it
// without gravity (§2.4), then with gravity; δ_s is the drop of the centre of mass. SP also gets
// the exact δ_s = π/(16 E_w) for comparison. DP deviates from the paper in E_w (0.05 with δ = l0,
// the explicit stability limit; see droplet_scene.hpp).
//
// Output (<out> = --output without its extension): <out>.csv (one row per swept value: δ_s, the
// area-centroid and top drops, 𝒜, a/a0, edge spread, wall overlap, FIRE iterations, convergence),
// <out>.json (parameters and timing), <out>.png (δ_s against the swept parameter; --no-plot skips it).
#include "drivers/common/cli.hpp"
#include "drivers/common/json_summary.hpp"
#include "drivers/common/output_paths.hpp"
#include "scenes/droplets/deformation.hpp"

#include <chrono>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <stdexcept>
#include <vector>

namespace mesoflow {
namespace {

struct Parameters {
  std::string model = "dp";
  droplets::DropletParameters droplet = [] {
    droplets::DropletParameters d;
    d.vertices = 128;
    d.line_tension = 1.0;
    return d;
  }();
  double gamma_max = 10.0;         // DP sweep: Γ from --gamma to this
  // K_l/Γ. Not the paper's 10⁻³ (App. B): at rest on a wall line tension gives no tangential force,
  // and with K_l/Γ = 10⁻³ gravity slides the vertices down the sides until edges differ 5·10⁴-fold
  // and FIRE does not converge (docs/droplets.md); K_l/Γ = 1 keeps the edges within 8%.
  double perimeter_ratio = 1.0;
  double sp_wall_energy = 1.0;     // SP: E_w of eq. 8
  double sp_wall_energy_max = 100.0;
  int points = 1;                  // swept values, log-spaced; 1: only --gamma / --sp-wall-energy
  droplets::DeformationSettings settings;
  int threads = 0;
  bool no_plot = false;
};

std::vector<double> log_spaced(double lo, double hi, int n) {
  std::vector<double> values;
  for (int k = 0; k < n; ++k) values.push_back(n == 1 ? lo : lo * std::pow(hi / lo, double(k) / (n - 1)));
  return values;
}

void run(const Parameters& par, const cli::DriverApp& app) {
  const bool dp = par.model == "dp";
  const double lo = dp ? par.droplet.line_tension : par.sp_wall_energy;
  const double hi = dp ? par.gamma_max : par.sp_wall_energy_max;
  if (par.points > 1 && !(hi > lo))
    throw std::invalid_argument(std::string(dp ? "--gamma-max" : "--sp-wall-energy-max") + " must be > " +
                                (dp ? "--gamma" : "--sp-wall-energy") + " (" + std::to_string(lo) +
                                ") when --points > 1, got " + std::to_string(hi));
  if (dp) {  // refuse bad DP parameters before any output
    droplets::DropletParameters d = par.droplet;
    d.perimeter_stiffness = par.perimeter_ratio * d.line_tension;
    d.validate();
    if (d.vertices % 4 != 0)
      throw std::invalid_argument("--vertices must be a multiple of 4, got " + std::to_string(d.vertices));
    droplets::resolve_time_step(d, true);
  }
  const driver::OutputPaths out(app.output());
  const auto wall_start = std::chrono::steady_clock::now();
  std::ofstream csv(out.csv);
  if (!csv) throw std::runtime_error("cannot write " + out.csv);
  csv << std::setprecision(10);
  csv << (dp ? "line_tension" : "sp_wall_energy")
      << ",sinking_depth,centroid_sinking,top_sinking,shape_parameter,area_over_a0,edge_ratio,wall_overlap,stored_energy_ratio,"
         "iterations_free,iterations_gravity,max_force,converged"
      << (dp ? "" : ",sinking_depth_exact") << '\n';
  bool all_converged = true;
  for (const double value : log_spaced(lo, hi, par.points)) {
    droplets::DeformationResult r;
    if (dp) {
      droplets::DropletParameters d = par.droplet;
      d.line_tension = value;
      d.perimeter_stiffness = par.perimeter_ratio * value;
      r = droplets::dp_deformation(d, par.settings);
    } else {
      r = droplets::sp_deformation(value, par.settings);
    }
    all_converged = all_converged && r.converged;
    csv << value << ',' << r.sinking_depth << ',' << r.centroid_sinking << ',' << r.top_sinking << ','
        << r.shape_parameter << ',' << r.area << ',' << r.edge_ratio << ',' << r.wall_overlap << ',' << r.stored_energy_ratio << ','
        << r.iterations_free << ',' << r.iterations_gravity << ',' << r.max_force << ',' << int(r.converged);
    if (!dp) csv << ',' << droplets::sp_sinking_depth_exact(value);
    csv << '\n' << std::flush;
    if (!app.quiet())
      std::cout << "deformation: " << (dp ? "Γ = " : "E_w = ") << value << ": δ_s/σ = " << r.sinking_depth
                << (dp ? " (centroid " + std::to_string(r.centroid_sinking) + ", 𝒜 = " + std::to_string(r.shape_parameter) +
                             ", edges " + std::to_string(r.edge_ratio) + ":1)"
                       : " (exact " + std::to_string(droplets::sp_sinking_depth_exact(value)) + ")")
                << ", FIRE " << r.iterations_free << " + " << r.iterations_gravity << " iterations, max |F| "
                << r.max_force << (r.converged ? "" : " NOT CONVERGED") << "\n";
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  cli::Json parameters = cli::Json::object();
  for (const auto& [key, value] : app.resolved_parameters()) parameters[key] = value;
  cli::write_summary(out.summary, cli::Json{{"driver", "deformation"},
                                             {"model", par.model},
                                             {"points", par.points},
                                             {"all_converged", all_converged},
                                             {"wall_seconds", wall},
                                             {"parameters", parameters},
                                             {"kokkos", kokkos_configuration()}});
  if (!par.no_plot) {
    const std::string png = out.csv.substr(0, out.csv.size() - 4) + ".png";
    driver::plot_with_matplotlib("deformation", "plot_deformation.py", {out.csv, png}, png, app.quiet());
  }
  if (!all_converged) throw std::runtime_error("FIRE did not reach --force-tolerance for every value (see " + out.csv + ")");
}

}  // namespace
}  // namespace mesoflow

int main(int argc, char** argv) {
  using mesoflow::cli::Bounds;
  mesoflow::Parameters par;
  auto& d = par.droplet;
  mesoflow::cli::DriverApp app(
      "Deformation delta_s of a droplet under its own weight on a flat wall (capillary-droplets paper, Fig. 7b): "
      "DP against line tension, SP against wall stiffness; units sigma, g, rho",
      "deformation.csv");
  app.add_choice("--model", par.model, "droplet model: deformable polygon or soft particle", {"dp", "sp"});
  app.add_real("--gamma", d.line_tension, "DP: line tension Γ (first value of a sweep)", 0.0, 1000.0,
               Bounds::left_open);
  app.add_real("--gamma-max", par.gamma_max, "DP: last Γ of a sweep (--points > 1)", 0.0, 1000.0, Bounds::left_open);
  app.add_real("--sp-wall-energy", par.sp_wall_energy, "SP: wall stiffness E_w of eq. 8 (first value of a sweep)", 0.0,
               1e8, Bounds::left_open);
  app.add_real("--sp-wall-energy-max", par.sp_wall_energy_max, "SP: last E_w of a sweep (--points > 1)", 0.0, 1e8,
               Bounds::left_open);
  app.add_int("--points", par.points, "values in the sweep, log-spaced (1: the first value only)", 1, 1000);
  app.add_int("--vertices", d.vertices, "DP: vertices per droplet N_v (a multiple of 4)", 8, 65536);
  app.add_real("--area-stiffness", d.area_stiffness, "DP: area compressibility K_a", 0.0, 1e9);
  app.add_real("--perimeter-ratio", par.perimeter_ratio, "DP: perimeter elasticity over line tension K_l/Γ", 0.0, 10.0);
  app.add_real("--wall-energy", d.wall_energy, "DP: vertex-wall repulsion E_w (eq. 3)", 0.0, 1e8, Bounds::left_open);
  app.add_real("--vertex-diameter", d.vertex_diameter, "DP: vertex diameter δ/l0 (eq. 3)", 0.0, 10.0, Bounds::left_open);
  app.add_int("--max-iterations", par.settings.max_iterations, "FIRE iterations per minimization", 1, 100000000);
  app.add_real("--force-tolerance", par.settings.force_tolerance, "FIRE stops at max |F_i| below this [ρσ²g]", 0.0, 1.0,
               Bounds::left_open);
  app.add_int("--threads", par.threads, "host threads (0: OMP_NUM_THREADS or all cores)", 0, 4096);
  app.add_flag("--no-plot", par.no_plot, "do not write the PNG plot");
  return app.run(argc, argv, [&] {
    mesoflow::KokkosScope kokkos(par.threads);
    mesoflow::run(par, app);
  });
}
