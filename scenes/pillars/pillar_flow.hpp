// pillar_flow.hpp — the runs of the pillar study (Hulikal Chakrapani et al., Soft Matter 19, 436
// (2023)): the driven flow through a pillar array of Fig. 2 and the periodic Poiseuille flow that
// measures the fluid's viscosity (Backer et al. 2005). Composition and loops only: the MDPD terms
// are kernels/mdpd (composed by mdpd_system.hpp), the carving and sampling kernels pillar_scene.hpp,
// the permeabilities and the viscosity fit analysis/pillars/permeability_estimates.hpp.
//
// Flow (PillarFlow): a quiescent fluid is equilibrated in the periodic box, pillars (and, in 3D with
// H > 0, walls) are carved from it, and a body force f_b drives the fluid in the region
// x ∈ [0, L_d). After the warm-up, every sample_every steps the run samples the fluid velocity in
// the measurement region (the middle half of the rest of the box, away from in- and out-flow; for a
// regular lattice a whole number of unit cells) and the force of the fluid on the solids there
// (sample_flow), summed in a FlowRecord. Every step is watched by the NaN watchdog
// (scenes/common/nan_watchdog.hpp), checked before every sample, the final frame and every checkpoint.
// The state a bit-identical restart needs — the system's (MdpdSystem::checkpoint_fields), the
// samples and the step count — is declared once, in checkpoint_fields().
#pragma once

#include "kernels/mdpd/stability.hpp"
#include "scenes/common/checkpoint_fields.hpp"
#include "scenes/common/nan_watchdog.hpp"
#include "scenes/pillars/pillar_layouts.hpp"
#include "scenes/pillars/pillar_scene.hpp"

#include <cmath>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace mesoflow::pillars {

// The paper's fluid (§2.5.1) with overrides; B < 0 takes the paper's 25 in 3D, 30 in 2D.
inline mdpd::MdpdParameters pillar_fluid(int dim, double A, double B, double r_B, double R, double dt,
                                         const std::string& density_kernel,
                                         const std::string& density_self_term = "off") {
  mdpd::MdpdParameters mp;
  mp.A = A;
  mp.B = B >= 0 ? B : (dim == 2 ? 30.0 : 25.0);
  mp.r_B = r_B;
  mp.R = R;
  mp.dt = dt;
  mp.density_kernel = mdpd::parse_density_kernel(density_kernel);
  mp.density_self_term = mdpd::parse_density_self_term(density_self_term);
  mp.validate();
  return mp;
}

// The MDPD stability limit (kernels/mdpd/stability.hpp) of the fluid at number density ρ; with
// solids, the tethers k_S and the cores' WCA (ε = k_BT, MdpdPairForce's default).
inline StabilityEstimate pillar_stability(const mdpd::MdpdParameters& mp, int dim, double density, bool solids,
                                       double k_S) {
  mdpd::MdpdStiffnessInputs s;
  s.dimension = dim;
  s.density = density;
  s.A = mp.A;
  s.B = mp.B;
  s.r_A = mp.r_A;
  s.r_B = mp.r_B;
  s.dissipation = mp.dissipation();
  s.kT = mp.kT;
  s.tether_stiffness = solids ? k_S : 0.0;
  s.core_wca_epsilon = solids ? 1.0 : 0.0;
  return mdpd::mdpd_stability(s);
}

// The scene's box, periodic on every axis (walls are a solid slab, pillar_scene.hpp).
template <int D>
Box<D, double> periodic_box(const SceneGeometry& g) {
  double lo[D] = {}, len[D];
  bool periodic[D];
  const double edges[3] = {g.Lx, g.Ly, g.Lz};
  for (int d = 0; d < D; ++d) {
    len[d] = edges[d];
    periodic[d] = true;
  }
  return Box<D, double>(lo, len, periodic);
}

// The flow scene as its parameters give it.
struct PillarFlowSettings {
  SceneGeometry geometry;
  double porosity = 1;            // of the layout (1 without pillars)
  bool regular_layout = false;    // a lattice of cells_x unit cells along x
  int cells_x = 1;
  mdpd::MdpdParameters fluid;
  mdpd::MdpdOptions options;
  double density = 6;             // ρ
  double driving_force = 0.2;     // f_b
  double driving_length = 5;      // L_d
  double bin_width = 0.5;         // elevation bins (3D with walls)
  std::uint64_t seed = 2023;
};

// The geometry of a layout: the box of its cells, walls H apart in 3D (H = 0: periodic in z, height lz).
inline SceneGeometry flow_geometry(const PillarLayout& layout, int dim, double height, double lz) {
  SceneGeometry g;
  g.dim = dim;
  g.Lx = layout.length_x;
  g.Ly = layout.length_y;
  g.diameter = layout.diameter;
  g.centres = layout.centres;
  g.H = dim == 3 ? height : 0.0;
  g.Lz = dim == 3 ? (g.H > 0 ? g.H + wall_thickness : lz) : 0.0;
  return g;
}

// The samples of a run, summed (FlowSample per sample, pillar_scene.hpp), kept in checkpoints.
struct FlowRecord {
  std::vector<double> count, velocity, pillar_force;  // per elevation bin
  double wall_bottom = 0, wall_top = 0, tether = 0, sum_u = 0, sum_u2 = 0, driven = 0;
  double count_all = 0, velocity_all = 0, tether_all = 0;  // whole box (fluid count, Σu_x; all pillars' tethers)
  std::vector<double> sample_u, sample_tether, sample_u_box;  // per sample, for block-averaged errors
  // Per sample and bin (sample-major, bins per sample): fluid count and Σu_x, for the Brinkman fit's
  // jackknife error over blocks of samples.
  std::vector<double> sample_count_profile, sample_velocity_profile;
  long long samples = 0;

  explicit FlowRecord(int bins = 0) : count(bins, 0), velocity(bins, 0), pillar_force(bins, 0) {}

  // Adds a sample; returns the mean u_x of its fluid in the measurement region.
  double add(const FlowSample& fs) {
    double c = 0, u = 0;
    for (std::size_t b = 0; b < count.size(); ++b) {
      count[b] += fs.count[b];
      velocity[b] += fs.velocity[b];
      pillar_force[b] += fs.pillar_force[b];
      c += fs.count[b];
      u += fs.velocity[b];
      sample_count_profile.push_back(fs.count[b]);
      sample_velocity_profile.push_back(fs.velocity[b]);
    }
    wall_bottom += fs.wall_force_bottom;
    wall_top += fs.wall_force_top;
    tether += fs.pillar_tether;
    driven += fs.driven_fluid;
    count_all += fs.count_all;
    velocity_all += fs.velocity_all;
    tether_all += fs.pillar_tether_all;
    const double mean_u = c > 0 ? u / c : 0.0;
    sample_u.push_back(mean_u);
    sample_tether.push_back(-fs.pillar_tether);
    sample_u_box.push_back(fs.velocity_all);
    sum_u += mean_u;
    sum_u2 += mean_u * mean_u;
    ++samples;
    return mean_u;
  }

  template <class Archive>
  void checkpoint_fields(Archive& a) {
    a("samples/count", count);
    a("samples/velocity", velocity);
    a("samples/pillar_force", pillar_force);
    a("samples/per_sample_u", sample_u);
    a("samples/per_sample_tether", sample_tether);
    a("samples/per_sample_u_box", sample_u_box);
    a("samples/per_sample_count_profile", sample_count_profile);
    a("samples/per_sample_velocity_profile", sample_velocity_profile);
    std::vector<double> sums{wall_bottom, wall_top, tether, sum_u, sum_u2, driven, count_all, velocity_all, tether_all};
    a("samples/sums", sums);
    if (Archive::loading) {
      if (sums.size() != 9)  // a checkpoint from before the whole-box sums cannot give them
        throw std::invalid_argument("pillars checkpoint: samples/sums has " + std::to_string(sums.size()) +
                                    " entries, expected 9 (written before the whole-box sums; start the run afresh)");
      wall_bottom = sums.at(0);
      wall_top = sums.at(1);
      tether = sums.at(2);
      sum_u = sums.at(3);
      sum_u2 = sums.at(4);
      driven = sums.at(5);
      count_all = sums.at(6);
      velocity_all = sums.at(7);
      tether_all = sums.at(8);
    }
    a("samples/taken", samples);
  }
};

// What a sample shows at once (the run's observables).
struct SampleObservables {
  double mean_velocity_x = 0, pillar_force_x = 0, fluid_temperature = 0;
};

template <int D, class Real = double, class Exec = Kokkos::DefaultExecutionSpace>
class PillarFlow {
 public:
  using System = mdpd::MdpdSystem<D, Real, Exec>;

  explicit PillarFlow(const PillarFlowSettings& s)
      : s_(checked(s)),
        box_(periodic_box<D>(s.geometry)),
        bins_(s.geometry.walls() ? std::max(1, int(std::lround(s.geometry.H / s.bin_width))) : 1),
        sys_(s.fluid, box_, s.seed, s.options),
        record_(bins_),
        pillar_x_("mesoflow::pillars::pillar_x", std::max<std::size_t>(1, s.geometry.centres.size())) {
    if (bins_ > max_profile_bins)
      throw std::invalid_argument("--height / --bin-width gives " + std::to_string(bins_) + " bins, at most " +
                                  std::to_string(max_profile_bins));
    auto h = Kokkos::create_mirror_view(pillar_x_);
    for (std::size_t k = 0; k < s.geometry.centres.size(); ++k) h(k) = s.geometry.centres[k][0];
    Kokkos::deep_copy(pillar_x_, h);
    // Measurement region: the middle half of the box beyond the driving region; for a regular
    // lattice a whole number of unit cells (nearest to half), centred there.
    const auto& g = s.geometry;
    const double rest = g.Lx - s.driving_length;
    double width = 0.5 * rest;
    if (s.regular_layout) {
      const double cell = g.Lx / s.cells_x;
      width = std::max(1.0, std::round(0.5 * rest / cell)) * cell;
      if (width > rest) width = std::floor(rest / cell) * cell;
    }
    x_lo_ = s.driving_length + 0.5 * (rest - width);
    x_hi_ = x_lo_ + width;
    region_.force = Real(s.driving_force);
    region_.x0 = 0;
    region_.length = Real(s.driving_length);
  }

  // A fresh run: the fluid at rest, equilibrated for `steps` (watched every check_every steps),
  // then pillars and walls carved and the driving force switched on.
  void equilibrate_and_carve(long long steps, long long check_every) {
    fill_fluid(sys_, s_.geometry, s_.density, s_.seed);
    sys_.begin();
    {
      watchdog::NanWatchdog watch(watched(sys_), check_every);
      for (long long k = 0; k < steps; ++k) {
        sys_.step();
        watch.after_step();
      }
      watch.check();  // the carving reads the equilibrated positions
    }
    solids_ = carve_solids(sys_, s_.geometry);
    sys_.begin(sys_.current_step());
    sys_.set_driving_region(region_);
  }

  // The state of a bit-identical restart, declared once for writing and reading
  // (scenes/common/checkpoint_fields.hpp). Loading allocates the particles at the stored count.
  template <class Archive>
  void checkpoint_fields(Archive& a) {
    if constexpr (Archive::loading) sys_.allocate(int(a.reader().shape("position").at(0)));
    sys_.checkpoint_fields(a);
    record_.checkpoint_fields(a);
    a("steps_after_carving", done_);
    a("solid_particles", solids_);
    if (Archive::loading) sys_.set_driving_region(region_);
  }

  // Runs the steps after carving up to warmup + steps, sampling every sample_every production
  // steps. `out` receives sample(observables) after each sample, final() at the last step (before
  // its checkpoint), checkpoint() every checkpoint_every steps and at the end, progress(done).
  // Nothing is handed out from a non-finite state.
  template <class Output>
  void run(long long warmup, long long steps, long long sample_every, long long checkpoint_every,
           long long check_every, Output& out) {
    const long long total = warmup + steps;
    watchdog::NanWatchdog watch(watched(sys_), check_every);
    while (done_ < total) {
      const bool production = done_ >= warmup;
      const bool sample = production && (done_ - warmup + 1) % sample_every == 0;
      sys_.step(sample);
      ++done_;
      watch.after_step();
      if (sample || done_ == total || done_ % checkpoint_every == 0) watch.check();
      if (sample) {
        const auto fs = sample_flow(sys_, s_.geometry, pillar_x_, x_lo_, x_hi_, bins_);
        SampleObservables o;
        o.mean_velocity_x = record_.add(fs);
        for (double v : fs.pillar_force) o.pillar_force_x += v;
        o.fluid_temperature = mdpd::kinetic_temperature(sys_.particles, mdpd::particle_type::fluid);
        out.sample(o);
      }
      if (done_ == total) out.final();
      if (done_ % checkpoint_every == 0 || done_ == total) out.checkpoint();
      out.progress(done_);
    }
  }

  std::vector<std::string> components() const {
    std::vector<std::string> c{std::to_string(sys_.particles.size()) + " particles (" + std::to_string(solids_) +
                               " solid), " + std::to_string(s_.geometry.centres.size()) + " pillars" +
                               (s_.geometry.walls() ? ", walls" : "")};
    for (auto& line : sys_.components()) c.push_back(std::move(line));
    return c;
  }

  System& system() { return sys_; }
  const System& system() const { return sys_; }
  const Box<D, double>& box() const { return box_; }
  const PillarFlowSettings& settings() const { return s_; }
  const FlowRecord& record() const { return record_; }
  int bins() const { return bins_; }
  int solid_particles() const { return solids_; }
  long long steps_after_carving() const { return done_; }
  double x_lo() const { return x_lo_; }
  double x_hi() const { return x_hi_; }

 private:
  static const PillarFlowSettings& checked(const PillarFlowSettings& s) {
    const auto& g = s.geometry;
    mdpd::validate_driving_region(s.driving_force, s.driving_length, g.Lx);
    const double reach = 1.0 + 0.2;
    if (g.Lx < 2 * reach || g.Ly < 2 * reach || (D == 3 && g.Lz < 2 * reach))
      throw std::invalid_argument("box edges must be at least 2.4σ (twice the neighbor reach)");
    if (s.regular_layout) {
      const double rest = g.Lx - s.driving_length, cell = g.Lx / s.cells_x;
      double width = std::max(1.0, std::round(0.5 * rest / cell)) * cell;
      if (width > rest) width = std::floor(rest / cell) * cell;
      if (width <= 0)
        throw std::invalid_argument("the driving region leaves no whole unit cell to measure in: raise --cells-x");
    }
    return s;
  }

  PillarFlowSettings s_;
  Box<D, double> box_;
  int bins_;
  System sys_;
  FlowRecord record_;
  Kokkos::View<double*, Exec> pillar_x_;
  mdpd::DrivingRegion<Real> region_;
  double x_lo_ = 0, x_hi_ = 0;
  int solids_ = 0;
  long long done_ = 0;
};

// The periodic Poiseuille flow of the viscosity measurement: force ±g along x, reversing at z = 0
// and L/2 (kernels/mdpd/region_body_force.hpp), in a periodic box (z: the last axis, edge L).
// Returns, per elevation bin, the fluid count and Σ u_x summed over the samples, and the mean
// kinetic temperature of the samples.
struct PoiseuilleSamples {
  std::vector<double> count, velocity;
  double temperature_sum = 0;
  long long samples = 0;
};

template <int D, class Real, class Exec>
PoiseuilleSamples run_poiseuille(mdpd::MdpdSystem<D, Real, Exec>& sys, double force, long long equilibrate,
                                 long long warmup, long long steps, long long sample_every, int bins,
                                 long long check_every, const std::function<void(long long)>& progress) {
  constexpr int NB = max_profile_bins;
  if (bins > NB) throw std::invalid_argument("--lz / --bin-width gives too many bins (at most 64)");
  {
    watchdog::NanWatchdog watch(watched(sys), check_every);
    for (long long s = 0; s < equilibrate; ++s) {
      sys.step();
      watch.after_step();
    }
  }
  sys.set_split_force({Real(force)});
  watchdog::NanWatchdog watch(watched(sys), check_every);
  for (long long s = 0; s < warmup; ++s) {
    sys.step();
    watch.after_step();
    progress(s + 1);
  }
  PoiseuilleSamples out{std::vector<double>(bins, 0), std::vector<double>(bins, 0)};
  const auto x = sys.particles.x;
  const auto v = sys.particles.v;
  const double Lzz = sys.box().length[D - 1];
  for (long long s = 0; s < steps; ++s) {
    sys.step();
    watch.after_step();
    if ((s + 1) % sample_every == 0) {
      watch.check();  // no sample from a non-finite state
      const double bw = Lzz / bins;
      const auto sums = parallel_sum<2 * NB, Exec>(
          "mesoflow::pillars::viscosity_profile", int(sys.particles.size()), KOKKOS_LAMBDA(int i, double(&acc)[2 * NB]) {
            double zz = double(x(i, D - 1));
            zz -= Lzz * kmath::floor(zz / Lzz);
            int b = int(zz / bw);
            b = b >= bins ? bins - 1 : b;
            acc[b] += 1.0;
            acc[NB + b] += double(v(i, 0));
          });
      for (int b = 0; b < bins; ++b) {
        out.count[b] += sums[b];
        out.velocity[b] += sums[NB + b];
      }
      out.temperature_sum += mdpd::kinetic_temperature(sys.particles);
      ++out.samples;
    }
    progress(warmup + s + 1);
  }
  return out;
}

}  // namespace mesoflow::pillars
