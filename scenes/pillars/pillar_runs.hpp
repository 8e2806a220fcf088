// pillar_runs.hpp — the runs of the `pillars` driver (Hulikal Chakrapani et al., Soft Matter 19, 436
// (2023)) as its parameters give them: the study's parameters with the paper's defaults, the fluid
// and the pillar layout they name, the flow scene's settings (scenes/pillars/pillar_flow.hpp), the
// flow run with its record in the results file and the checkpoints (FlowRecording), and the
// periodic Poiseuille run of the viscosity measurement (ViscosityRun). Composition and recording only: the estimates
// and the viscosity fit are analysis/pillars/permeability_estimates.hpp.
//
// Units (paper §2.5.1): length σ = r_A, mass m, energy ε = k_BT, time τ = σ√(m/ε).
#pragma once

#include "io/checkpoint.hpp"
#include "io/h5md_writer.hpp"
#include "scenes/common/checkpoint_fields.hpp"
#include "scenes/common/particle_frames.hpp"
#include "scenes/pillars/pillar_flow.hpp"

#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace mesoflow::pillars {

// The study's parameters (defaults: the paper's, as the driver's options give them).
struct PillarRunParameters {
  int dimension = 2;
  std::string layout = "square";
  std::string layout_file;
  double porosity = 0.7, diameter = 5.0;
  int cells_x = 4, cells_y = 2, pillars = 30;
  double aspect = 1.0, exclusion = 1.2;
  long long mc_sweeps = 20000;
  double height = 7.5;       // 3D: wall separation H (0: periodic in z)
  double lz = 5.0;           // 3D without walls, and the viscosity box
  double box = 10.0;         // viscosity mode: Lx = Ly
  double fb = -1;            // driving force (−1: 0.2 in 2D, 0.3 in 3D)
  double driving_length = 5.0;
  double viscosity = -1;     // μ for κ (−1: the paper's 17.5 in 3D, 26.1 in 2D)
  double kappa_p = 0;        // pillar permeability for Brinkman's μ_eff (0: not given)
  double bin_width = 0.5;
  long long equilibrate_steps = 1000, warmup_steps = 5000, steps = 20000, sample_every = 10;
  double density = 6.0, A = -40, B = -1, r_B = 0.75, R = 12, dt = 0.01, k_S = 12.5;
  std::string density_kernel = "normalized", list = "half";
  std::string density_self_term = "off";  // off: LAMMPS' mdpd/rhosum (no w_ρ(0) in ρ̄_i)
  long long seed = 2023;
  long long checkpoint_every = 10000;
  long long check_every = 100;  // steps between NaN-watchdog checks

  // μ used for κ in `dim` dimensions.
  double viscosity_for_kappa(int dim) const { return viscosity > 0 ? viscosity : (dim == 2 ? 26.1 : 17.5); }
};

inline mdpd::MdpdParameters pillar_fluid(const PillarRunParameters& par, int dim) {
  return pillar_fluid(dim, par.A, par.B, par.r_B, par.R, par.dt, par.density_kernel, par.density_self_term);
}

// The stability limit of the fluid of `par` (pillar_stability), with the solids' tethers and cores.
inline StabilityEstimate pillar_stability(const PillarRunParameters& par, int dim, bool solids) {
  return pillar_stability(pillar_fluid(par, dim), dim, par.density, solids, par.k_S);
}

inline PillarLayout make_layout(const PillarRunParameters& par) {
  if (par.layout == "none") return {par.box, par.box, par.diameter, {}};
  if (par.layout == "file") {
    if (par.layout_file.empty()) throw std::invalid_argument("--layout file needs --layout-file");
    return read_csv(par.layout_file);
  }
  if (par.layout == "irregular")
    return irregular_array(par.pillars, par.porosity, par.diameter, par.aspect, par.exclusion, par.mc_sweeps,
                           std::uint64_t(par.seed));
  return regular_lattice(parse_lattice(par.layout), par.porosity, par.diameter, par.cells_x, par.cells_y);
}

// The flow scene of `layout` in `dim` dimensions.
inline PillarFlowSettings flow_settings(const PillarRunParameters& par, const PillarLayout& layout, int dim) {
  PillarFlowSettings s;
  s.geometry = flow_geometry(layout, dim, par.height, par.lz);
  s.porosity = par.layout == "none" ? 1.0 : layout.porosity();
  s.regular_layout = par.layout == "square" || par.layout == "rotated-square" || par.layout == "hexagonal";
  s.cells_x = par.cells_x;
  s.fluid = pillar_fluid(par, dim);
  s.options.k_S = par.k_S;
  s.options.list_kind = par.list == "full" ? NeighborListKind::full : NeighborListKind::half;
  s.density = par.density;
  s.driving_force = par.fb >= 0 ? par.fb : (dim == 2 ? 0.2 : 0.3);
  s.driving_length = par.driving_length;
  s.bin_width = par.bin_width;
  s.seed = std::uint64_t(par.seed);
  return s;
}

// The flow run (PillarFlow::run) and its record: a fresh run (start: equilibrated and carved, a
// new results file with the resolved parameters (key, value), the layout's actual porosity and the
// box) or a restart (resume: the state of a checkpoint, the results file resumed at its step); then
// the observables of every sample and the final frame (particle types as species) in the results
// file, and the checkpoints, each with the scene's signature.
template <int D>
class FlowRecording {
 public:
  FlowRecording(PillarFlow<D>& flow, std::string checkpoint_path, std::string signature)
      : flow_(flow), checkpoint_path_(std::move(checkpoint_path)), signature_(std::move(signature)) {}

  void start(long long equilibrate_steps, long long check_every, const std::string& path,
             const std::vector<std::pair<std::string, std::string>>& resolved) {
    flow_.equilibrate_and_carve(equilibrate_steps, check_every);
    h5_.emplace(path, "mesoflow", MESOFLOW_VERSION, "mesoflow pillars");
    for (const auto& [key, value] : resolved) h5_->set_parameter(key, value);
    const PillarFlowSettings& s = flow_.settings();
    h5_->set_parameter("porosity_actual", s.porosity);
    h5_->set_parameter("box_x", s.geometry.Lx);
    h5_->set_parameter("box_y", s.geometry.Ly);
    h5_->set_parameter("box_z", s.geometry.Lz);
  }
  // Returns the checkpoint's step.
  std::int64_t resume(const io::CheckpointReader& ck, const std::string& path) {
    scene::LoadFields load(ck);
    flow_.checkpoint_fields(load);
    const std::int64_t step = std::int64_t(flow_.system().current_step());
    h5_.emplace(io::H5mdWriter::resume(path, step));
    return step;
  }

  // Runs the flow up to warmup + steps (PillarFlow::run), recording it; progress(done) after every step.
  void run(long long warmup, long long steps, long long sample_every, long long checkpoint_every,
           long long check_every, std::function<void(long long)> progress) {
    progress_ = std::move(progress);
    flow_.run(warmup, steps, sample_every, checkpoint_every, check_every, *this);
  }
  void write_xdmf(const std::string& path) { h5_->write_xdmf(path); }

  // What PillarFlow::run hands out.
  void sample(const SampleObservables& o) {
    const auto& sys = flow_.system();
    const std::int64_t step = std::int64_t(sys.current_step());
    h5_->append_observable("mean_velocity_x", step, sys.time(), o.mean_velocity_x);
    h5_->append_observable("pillar_force_x", step, sys.time(), o.pillar_force_x);
    h5_->append_observable("temperature_fluid", step, sys.time(), o.fluid_temperature);
  }
  void final() {
    const auto& sys = flow_.system();
    const std::int64_t step = std::int64_t(sys.current_step());
    if (!h5_->has_particles_group("all")) scene::add_particles_group(*h5_, "all", sys.particles.size(), flow_.box());
    scene::write_frame(*h5_, "all", step, sys.time(), sys.particles);
    const auto type = scene::to_host_vector(sys.particles.type);
    h5_->append_int("all", "species", step, sys.time(), type.data(), type.size(), 1);
  }
  void checkpoint() {
    h5_->flush();
    io::CheckpointWriter ck(checkpoint_path_);
    ck.put_string("scene", signature_);
    scene::SaveFields save(ck);
    flow_.checkpoint_fields(save);
    ck.commit();
  }
  void progress(long long done) { progress_(done); }

 private:
  PillarFlow<D>& flow_;
  const std::string checkpoint_path_, signature_;
  std::optional<io::H5mdWriter> h5_;
  std::function<void(long long)> progress_;
};

// The fully periodic box of the viscosity and bulk runs: edges --box along x (and y in 3D) and --lz
// along the last axis; refused (naming both) below 2.4σ, or the last edge below `min_last_edge`.
template <int D>
SceneGeometry periodic_run_geometry(const PillarRunParameters& par, double min_last_edge) {
  SceneGeometry geometry;
  geometry.dim = D;
  geometry.Lx = par.box;
  geometry.Ly = D == 3 ? par.box : par.lz;
  geometry.Lz = D == 3 ? par.lz : 0.0;
  if (par.box < 2.4 || par.lz < min_last_edge) {
    std::ostringstream m;
    m << "--box must be >= 2.4 and --lz >= " << min_last_edge << " (σ), got " << par.box << " and " << par.lz;
    throw std::invalid_argument(m.str());
  }
  return geometry;
}

// The pair-loop options of those runs: the neighbor list kind of --list.
inline mdpd::MdpdOptions periodic_run_options(const PillarRunParameters& par) {
  mdpd::MdpdOptions opt;
  opt.list_kind = par.list == "full" ? NeighborListKind::full : NeighborListKind::half;
  return opt;
}

// Periodic Poiseuille viscosity (Backer et al. 2005) in a fully periodic box: the fluid of `par`,
// edges --box along x (and y in 3D) and --lz along the gradient (the last axis), force ±f_b
// (0.5 by default), the fluid filled at --density and started.
template <int D>
class ViscosityRun {
 public:
  using System = mdpd::MdpdSystem<D, double, Kokkos::DefaultExecutionSpace>;

  explicit ViscosityRun(const PillarRunParameters& par)
      : mp_(pillar_fluid(par, D)),
        force_(par.fb >= 0 ? par.fb : 0.5),
        geometry_(periodic_run_geometry<D>(par, 4.8)),
        sys_(mp_, periodic_box<D>(geometry_), std::uint64_t(par.seed), periodic_run_options(par)) {
    fill_fluid(sys_, geometry_, par.density, std::uint64_t(par.seed));
    sys_.begin();
    bins_ = std::max(4, int(std::lround(gradient_length() / par.bin_width)) / 2 * 2);
  }

  // run_poiseuille (pillar_flow.hpp) on this box, in bins_ bins along the gradient.
  PoiseuilleSamples run(long long equilibrate, long long warmup, long long steps, long long sample_every,
                        long long check_every, const std::function<void(long long)>& progress) {
    return run_poiseuille(sys_, force_, equilibrate, warmup, steps, sample_every, bins_, check_every, progress);
  }

  const System& system() const { return sys_; }
  const mdpd::MdpdParameters& fluid() const { return mp_; }
  double force() const { return force_; }
  int bins() const { return bins_; }
  // The box edge along the gradient (z in 3D, y in 2D).
  double gradient_length() const { return D == 3 ? geometry_.Lz : geometry_.Ly; }
  double number_density() const {
    const double volume = D == 3 ? geometry_.Lx * geometry_.Ly * geometry_.Lz : geometry_.Lx * geometry_.Ly;
    return double(sys_.particles.size()) / volume;
  }

 private:

  mdpd::MdpdParameters mp_;
  double force_;
  SceneGeometry geometry_;
  System sys_;
  int bins_ = 4;
};

}  // namespace mesoflow::pillars
