// pillars — MDPD flow through pillar arrays (Hulikal Chakrapani, Bazyar, Lammertink, Luding &
// den Otter, Soft Matter 19, 436 (2023)), and the viscosity of any MDPD fluid.
//
// Units (paper §2.5.1): length σ = r_A, mass m, energy ε = k_BT, time τ = σ√(m/ε). Defaults are
// the paper's: ρ = 6, A = −40, B = 25 (3D) / 30 (2D), r_B = 0.75, R = 12 (D = 72), dt = 0.01,
// tethers k_S = 12.5, pillar diameter d = 5, L_d = 5, bins of 0.5σ in elevation.
//
// --mode flow (Fig. 2): a quiescent fluid is equilibrated in the periodic box, pillars (and, in 3D
// with --height H > 0, walls) are carved from it (pillar_scene.hpp), and a body force f_b drives
// the fluid in the region x ∈ [0, L_d). After --warmup-steps, every --sample-every steps over
// --steps the driver samples the fluid velocity in the measurement region (the middle half of the
// rest of the box, away from in- and out-flow) and the force of the fluid on the solids there.
//   Darcy (eqs. 1-2): U_s = ε⟨u_x⟩ and κ = μ U_s L_x / Δp (κ_p without walls, κ_eff with walls)
//     with the paper's Δp = f_b ρ L_d (kappa_darcy). It agrees with eq. (3) to 1-2% in the
//     documented runs. Also reported: Δp from the force balance f_b N_d / (ε A_⊥), N_d the fluid
//     particles actually in the driving region (kappa_darcy_force_balance), which differs by up to
//     15% where the driving slab cuts pillars unevenly and does not match eq. (3).
//   Drag (eq. 3): F_d per pillar and unit length, κ_p = π μ U_s d² / (4 φ F_d), F_d = F_m/(n_m h)
//     with F_m the x-force of the fluid on the n_m pillars whose axes lie in the measurement region
//     (height h) — from the pair forces (the paper's estimator) and from the pillars' tethers,
//     which balance it on average with far less noise.
//   Walls (3D): the superficial velocity u_s(z) = ε⟨u_x⟩_z, fitted with Brinkman's eq. (5) for B
//     and α; with --kappa-p (from the matching 2D run), μ_eff/μ = 1/(κ_p α²), eq. (7)'s κ_eff and
//     B's theory value κ_p Δp/(μ L_x). Without pillars (--layout none) the run checks κ_w = H²/12.
// --mode theory: the square- and hexagonal-array permeability curves over ε (<out>_theory.csv) and
//   Sangani & Acrivos' exact square-array values (<out>_sangani_acrivos_table.csv).
// --mode viscosity: periodic Poiseuille (region_body_force.hpp) in a periodic box; the two
//   parabolas of u_x(z) give η (Backer et al. 2005).
//
// Checkpoints (flow mode): every --checkpoint-every steps after carving, <out>.ckpt.h5 is replaced
// atomically by the whole state (particles, tags, tether sites, the list's reference positions and
// the accumulated samples); --restart continues from it bit-identically at the same thread count.
// Only --steps, --checkpoint-every, --check-every and --threads may differ from the interrupted run.
//
// NaN watchdog (scenes/common/nan_watchdog.hpp, pillars::watched in pillar_scene.hpp): every
// --check-every steps, and before every sample, the final frame and every checkpoint, positions,
// velocities, forces, masses and tether sites are checked; a non-finite value stops the run with
// exit status 1 and a message naming the particle (by tag), the force term and the step, before
// anything is written from the bad state (the checkpoint on disk stays the last good one). The
// equilibration and the viscosity mode are watched the same way.
//
// Output (<out> = --output without extension): <out>.h5 (H5MD: final frame with particle types,
// observables per sample, parameters), <out>.xdmf, <out>_profile.csv (per bin: z, fluid count,
// ⟨u_x⟩, u_s, pillar force density, Brinkman fit), <out>_layout.csv (pillar centres), <out>.json
// (summary with the theory values), <out>.png (profile and fit).
#include "drivers/common/cli.hpp"
#include "drivers/common/output_paths.hpp"
#include "drivers/common/particle_io.hpp"
#include "drivers/common/progress.hpp"
#include "scenes/common/time_step_limit.hpp"
#include "analysis/pillars/permeability_theory.hpp"
#include "scenes/pillars/pillar_layouts.hpp"
#include "scenes/pillars/pillar_scene.hpp"

#include "io/checkpoint.hpp"
#include "kernels/mdpd/stability.hpp"

#include <chrono>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <optional>
#include <set>

namespace mesoflow {
namespace {

struct Parameters {
  std::string mode = "flow";
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
  long long seed = 2023;
  int threads = 0;
  long long checkpoint_every = 10000;
  long long check_every = 100;  // steps between NaN-watchdog checks
  bool restart = false;
  bool force_dt = false;  // --force-dt
};

// The parameters a restart must share with the run it continues, as a string kept in the
// checkpoint: all but the run length, the checkpoint interval, the threads and the output options.
std::string scene_signature(const cli::DriverApp& app) {
  const std::set<std::string> may_change = {"steps",   "checkpoint-every", "check-every", "threads",
                                            "restart", "quiet",            "output"};
  std::string s;
  for (const auto& [key, value] : app.resolved_parameters())
    if (may_change.count(key) == 0) s += key + "=" + value + " ";
  return s;
}

constexpr double pi = 3.14159265358979323846;

// The paper's fluid (§2.5.1) with the command line's overrides; B defaults to 25 in 3D, 30 in 2D.
mdpd::MdpdParameters fluid_parameters(const Parameters& par, int dim) {
  mdpd::MdpdParameters mp;
  mp.A = par.A;
  mp.B = par.B >= 0 ? par.B : (dim == 2 ? 30.0 : 25.0);
  mp.r_B = par.r_B;
  mp.R = par.R;
  mp.dt = par.dt;
  mp.density_kernel = mdpd::parse_density_kernel(par.density_kernel);
  mp.validate();
  return mp;
}

// Refuses a --dt above the MDPD limit (kernels/mdpd/stability.hpp) unless --force-dt: the flow mode
// has tethered solids and WCA cores, the viscosity mode only fluid.
void check_time_step(const Parameters& par) {
  const auto mp = fluid_parameters(par, par.dimension);
  mdpd::MdpdStiffnessInputs s;
  s.dimension = par.dimension;
  s.density = par.density;
  s.A = mp.A;
  s.B = mp.B;
  s.r_A = mp.r_A;
  s.r_B = mp.r_B;
  s.dissipation = mp.dissipation();
  s.kT = mp.kT;
  const bool solids = par.mode == "flow";
  s.tether_stiffness = solids ? par.k_S : 0.0;
  s.core_wca_epsilon = solids ? 1.0 : 0.0;  // MdpdPairForce's default WCA, ε = k_BT
  const auto limit = mdpd::mdpd_stability(s);
  cli::check_time_step("pillars", par.dt, {limit.max_dt(), limit.limiting_term("τ")}, par.force_dt);
}

// The scene's box, periodic on every axis (walls are a solid slab, pillar_scene.hpp).
template <int D>
Box<D, double> periodic_box(const pillars::SceneGeometry& g) {
  double lo[D] = {}, len[D];
  bool periodic[D];
  const double edges[3] = {g.Lx, g.Ly, g.Lz};
  for (int d = 0; d < D; ++d) {
    len[d] = edges[d];
    periodic[d] = true;
  }
  return Box<D, double>(lo, len, periodic);
}

pillars::PillarLayout make_layout(const Parameters& par) {
  if (par.layout == "none") return {0, 0, par.diameter, {}};
  if (par.layout == "file") {
    if (par.layout_file.empty()) throw std::invalid_argument("--layout file needs --layout-file");
    return pillars::read_csv(par.layout_file);
  }
  if (par.layout == "irregular")
    return pillars::irregular_array(par.pillars, par.porosity, par.diameter, par.aspect, par.exclusion, par.mc_sweeps,
                                    std::uint64_t(par.seed));
  return pillars::regular_lattice(pillars::parse_lattice(par.layout), par.porosity, par.diameter, par.cells_x,
                                  par.cells_y);
}

template <int D>
void run_flow(const Parameters& par, const cli::DriverApp& app) {
  using Real = double;
  using Exec = Kokkos::DefaultExecutionSpace;
  const driver::OutputPaths out(app.output());
  const std::string stem = out.trajectory.substr(0, out.trajectory.size() - 3);
  const bool quiet = app.quiet();

  const mdpd::MdpdParameters mp = fluid_parameters(par, D);
  const double mu = par.viscosity > 0 ? par.viscosity : (D == 2 ? 26.1 : 17.5);
  const double fb = par.fb >= 0 ? par.fb : (D == 2 ? 0.2 : 0.3);

  pillars::PillarLayout layout = make_layout(par);
  pillars::SceneGeometry g;
  g.dim = D;
  if (par.layout == "none") {
    layout.length_x = par.box;
    layout.length_y = par.box;
  }
  g.Lx = layout.length_x;
  g.Ly = layout.length_y;
  g.diameter = layout.diameter;
  g.centres = layout.centres;
  g.H = D == 3 ? par.height : 0.0;
  g.Lz = D == 3 ? (g.H > 0 ? g.H + pillars::wall_thickness : par.lz) : 0.0;
  const double porosity = par.layout == "none" ? 1.0 : layout.porosity();
  if (par.layout != "none") pillars::write_csv(layout, stem + "_layout.csv");
  mdpd::validate_driving_region(fb, par.driving_length, g.Lx);
  const double reach = 1.0 + 0.2;
  if (g.Lx < 2 * reach || g.Ly < 2 * reach || (D == 3 && g.Lz < 2 * reach))
    throw std::invalid_argument("box edges must be at least 2.4σ (twice the neighbor reach)");

  const auto box = periodic_box<D>(g);
  const int bins = g.walls() ? std::max(1, int(std::lround(g.H / par.bin_width))) : 1;
  if (bins > pillars::max_profile_bins)
    throw std::invalid_argument("--height / --bin-width gives " + std::to_string(bins) + " bins, at most " +
                                std::to_string(pillars::max_profile_bins));
  mdpd::MdpdOptions opt;
  opt.k_S = par.k_S;
  opt.list_kind = par.list == "full" ? NeighborListKind::full : NeighborListKind::half;
  mdpd::MdpdSystem<D, Real, Exec> sys(mp, box, std::uint64_t(par.seed), opt);

  // Samples accumulated over the production run (and kept in checkpoints).
  std::vector<double> count(bins, 0), velocity(bins, 0), pillar_force(bins, 0);
  double wall_bottom = 0, wall_top = 0, tether = 0, sum_u = 0, sum_u2 = 0, driven = 0;
  std::vector<double> sample_u, sample_tether;  // per sample, for block-averaged errors
  long long samples = 0, done = 0;              // samples taken; steps run after carving
  int solids = 0;
  std::optional<io::H5mdWriter> h5;
  std::int64_t resumed_from_step = 0;  // the checkpoint's step after --restart
  const auto t0 = std::chrono::steady_clock::now();
  if (par.restart) {
    if (!io::checkpoint_exists(out.checkpoint))
      throw std::invalid_argument("--restart: no checkpoint " + out.checkpoint + " to resume from");
    io::CheckpointReader ck(out.checkpoint);
    const std::string stored = ck.get_string("scene");
    if (stored != scene_signature(app))
      throw std::invalid_argument("--restart: " + out.checkpoint + " was written by another scene (" + stored +
                                  "); only --steps, --checkpoint-every, --check-every and --threads may change");
    std::vector<Real> data;
    std::vector<int> ints;
    std::vector<std::int64_t> tags;
    ck.get("position", data);
    sys.allocate(int(data.size() / D));
    driver::from_row_major(sys.particles.x, data);
    ck.get("velocity", data);
    driver::from_row_major(sys.particles.v, data);
    ck.get("force", data);
    driver::from_row_major(sys.particles.f, data);
    ck.get("mass", data);
    driver::from_host_vector(sys.particles.mass, data);
    ck.get("site", data);
    driver::from_row_major(sys.site, data);
    ck.get("type", ints);
    driver::from_host_vector(sys.particles.type, ints);
    ck.get("body", ints);
    driver::from_host_vector(sys.particles.body, ints);
    ck.get("tag", tags);
    {
      auto h = Kokkos::create_mirror_view(sys.tag);
      for (std::size_t i = 0; i < tags.size(); ++i) h(i) = std::uint32_t(tags[i]);
      Kokkos::deep_copy(sys.tag, h);
    }
    ck.get("neighbor_reference_position", data);
    typename mdpd::MdpdSystem<D, Real, Exec>::vector_view reference("mesoflow::pillars::x_ref", sys.particles.size());
    driver::from_row_major(reference, data);
    sys.resume({std::uint64_t(ck.get_scalar_int64("step")), int(ck.get_scalar_int64("builds_since_sort")),
                int(ck.get_scalar_int64("num_sorts"))},
               reference);
    ck.get("samples/count", count);
    ck.get("samples/velocity", velocity);
    ck.get("samples/pillar_force", pillar_force);
    ck.get("samples/per_sample_u", sample_u);
    ck.get("samples/per_sample_tether", sample_tether);
    std::vector<double> sums;
    ck.get("samples/sums", sums);
    wall_bottom = sums.at(0);
    wall_top = sums.at(1);
    tether = sums.at(2);
    sum_u = sums.at(3);
    sum_u2 = sums.at(4);
    driven = sums.at(5);
    samples = ck.get_scalar_int64("samples/taken");
    done = ck.get_scalar_int64("steps_after_carving");
    solids = int(ck.get_scalar_int64("solid_particles"));
    resumed_from_step = std::int64_t(sys.current_step());
    h5.emplace(io::H5mdWriter::resume(out.trajectory, resumed_from_step));
    if (!quiet) std::cerr << "pillars: resumed from " << out.checkpoint << " at step " << sys.current_step() << "\n";
  } else {
    pillars::fill_fluid(sys, g, par.density, std::uint64_t(par.seed));
    sys.begin();
    {
      watchdog::NanWatchdog watch(pillars::watched(sys, std::uint64_t(par.seed)), par.check_every);
      for (long long s = 0; s < par.equilibrate_steps; ++s) {
        sys.step();
        watch.after_step();
      }
      watch.check();  // the carving reads the equilibrated positions
    }
    solids = pillars::carve_solids(sys, g);
    sys.begin(sys.current_step());
    h5.emplace(out.trajectory, "mesoflow", MESOFLOW_VERSION, "mesoflow pillars");
    for (const auto& [key, value] : app.resolved_parameters()) h5->set_parameter(key, value);
    h5->set_parameter("porosity_actual", porosity);
    h5->set_parameter("box_x", g.Lx);
    h5->set_parameter("box_y", g.Ly);
    h5->set_parameter("box_z", g.Lz);
  }
  mdpd::DrivingRegion<Real> region;
  region.force = Real(fb);
  region.x0 = 0;
  region.length = Real(par.driving_length);
  sys.set_driving_region(region);
  if (!quiet)
    std::cerr << "pillars: " << D << "D, " << sys.particles.size() << " particles (" << solids << " solid), box "
              << g.Lx << " x " << g.Ly << (D == 3 ? " x " + std::to_string(g.Lz) : std::string()) << ", porosity "
              << porosity << ", f_b = " << fb << "\n";

  const auto checkpoint = [&] {
    h5->flush();
    io::CheckpointWriter ck(out.checkpoint);
    const std::size_t n = sys.particles.size();
    const std::vector<std::size_t> vec_shape{n, std::size_t(D)}, scalar_shape{n};
    const auto put = [&](const std::string& name, const std::vector<double>& v) { ck.put(name, v.data(), {v.size()}); };
    ck.put_string("scene", scene_signature(app));
    const auto c = sys.counters();
    ck.put_scalar("step", std::int64_t(c.step));
    ck.put_scalar("builds_since_sort", c.builds_since_sort);
    ck.put_scalar("num_sorts", c.num_sorts);
    ck.put_scalar("steps_after_carving", done);
    ck.put_scalar("solid_particles", solids);
    ck.put("position", driver::to_row_major(sys.particles.x).data(), vec_shape);
    ck.put("velocity", driver::to_row_major(sys.particles.v).data(), vec_shape);
    ck.put("force", driver::to_row_major(sys.particles.f).data(), vec_shape);
    ck.put("mass", driver::to_host_vector(sys.particles.mass).data(), scalar_shape);
    ck.put("site", driver::to_row_major(sys.site).data(), vec_shape);
    ck.put("type", driver::to_host_vector(sys.particles.type).data(), scalar_shape);
    ck.put("body", driver::to_host_vector(sys.particles.body).data(), scalar_shape);
    {
      const auto t = driver::to_host_vector(sys.tag);
      const std::vector<std::int64_t> tags(t.begin(), t.end());
      ck.put("tag", tags.data(), scalar_shape);
    }
    ck.put("neighbor_reference_position", driver::to_row_major(sys.neighbor_reference_positions()).data(), vec_shape);
    put("samples/count", count);
    put("samples/velocity", velocity);
    put("samples/pillar_force", pillar_force);
    put("samples/per_sample_u", sample_u);
    put("samples/per_sample_tether", sample_tether);
    put("samples/sums", {wall_bottom, wall_top, tether, sum_u, sum_u2, driven});
    ck.put_scalar("samples/taken", samples);
    ck.commit();
  };

  // Measurement region: the middle half of the box beyond the driving region; for a regular
  // lattice a whole number of unit cells (nearest to half), centred there, so the average covers
  // complete cells.
  const double rest = g.Lx - par.driving_length;
  double width = 0.5 * rest;
  const bool regular = par.layout == "square" || par.layout == "rotated-square" || par.layout == "hexagonal";
  if (regular) {
    const double cell = g.Lx / par.cells_x;
    width = std::max(1.0, std::round(0.5 * rest / cell)) * cell;
    if (width > rest) width = std::floor(rest / cell) * cell;
    if (width <= 0) throw std::invalid_argument("the driving region leaves no whole unit cell to measure in: raise --cells-x");
  }
  const double x_lo = par.driving_length + 0.5 * (rest - width), x_hi = x_lo + width;
  Kokkos::View<double*, Exec> pillar_x("mesoflow::pillars::pillar_x", std::max<std::size_t>(1, g.centres.size()));
  {
    auto h = Kokkos::create_mirror_view(pillar_x);
    for (std::size_t k = 0; k < g.centres.size(); ++k) h(k) = g.centres[k][0];
    Kokkos::deep_copy(pillar_x, h);
  }

  const long long total = par.warmup_steps + par.steps;
  const long long first = done;
  // Checked every --check-every steps and before every sample, the final frame and every
  // checkpoint: nothing is written from a non-finite state.
  watchdog::NanWatchdog watch(pillars::watched(sys, std::uint64_t(par.seed)), par.check_every);
  cli::ProgressLine progress(total - first, int(sys.particles.size()), !quiet);
  while (done < total) {
    const bool production = done >= par.warmup_steps;
    const bool sample = production && (done - par.warmup_steps + 1) % par.sample_every == 0;
    sys.step(sample);
    ++done;
    watch.after_step();
    if (sample || done == total || done % par.checkpoint_every == 0) watch.check();
    if (sample) {
      const auto fs = pillars::sample_flow(sys, g, pillar_x, x_lo, x_hi, bins);
      double c = 0, u = 0;
      for (int b = 0; b < bins; ++b) {
        count[b] += fs.count[b];
        velocity[b] += fs.velocity[b];
        pillar_force[b] += fs.pillar_force[b];
        c += fs.count[b];
        u += fs.velocity[b];
      }
      wall_bottom += fs.wall_force_bottom;
      wall_top += fs.wall_force_top;
      tether += fs.pillar_tether;
      driven += fs.driven_fluid;
      const double mean_u = c > 0 ? u / c : 0.0;
      sample_u.push_back(mean_u);
      sample_tether.push_back(-fs.pillar_tether);
      sum_u += mean_u;
      sum_u2 += mean_u * mean_u;
      ++samples;
      h5->append_observable("mean_velocity_x", std::int64_t(sys.current_step()), sys.time(), mean_u);
      double f = 0;
      for (double v : fs.pillar_force) f += v;
      h5->append_observable("pillar_force_x", std::int64_t(sys.current_step()), sys.time(), f);
      h5->append_observable("temperature_fluid", std::int64_t(sys.current_step()), sys.time(),
                            mdpd::kinetic_temperature(sys.particles, mdpd::particle_type::fluid));
    }
    if (done == total) {  // the final frame, before the last checkpoint
      if (!h5->has_particles_group("all")) driver::add_particles_group(*h5, "all", sys.particles.size(), box);
      driver::write_frame(*h5, "all", std::int64_t(sys.current_step()), sys.time(), sys.particles);
      const auto type = driver::to_host_vector(sys.particles.type);
      h5->append_int("all", "species", std::int64_t(sys.current_step()), sys.time(), type.data(), type.size(), 1);
    }
    if (done % par.checkpoint_every == 0 || done == total) checkpoint();
    progress.update(done - first);
  }
  progress.finish();
  const double wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (samples == 0) throw std::invalid_argument("--steps must cover at least one --sample-every interval");

  // Darcy and drag permeabilities (eqs. 1-3).
  double n_fluid = 0, u_sum = 0, f_sum = 0;
  for (int b = 0; b < bins; ++b) {
    n_fluid += count[b];
    u_sum += velocity[b];
    f_sum += pillar_force[b];
  }
  const double mean_u = u_sum / n_fluid;
  // Standard error from 10 block means (samples within a block are correlated; blocks of ≥ 100τ
  // in the documented runs are not).
  auto block_error = [](const std::vector<double>& x) {
    const int blocks = 10;
    const std::size_t per = x.size() / blocks;
    if (per == 0) return 0.0;
    double m = 0, m2 = 0;
    for (int b = 0; b < blocks; ++b) {
      double s = 0;
      for (std::size_t k = 0; k < per; ++k) s += x[b * per + k];
      s /= double(per);
      m += s;
      m2 += s * s;
    }
    m /= blocks;
    return std::sqrt(std::max(0.0, m2 / blocks - m * m) / (blocks - 1));
  };
  const double mean_u_block_error = block_error(sample_u);
  const double tether_block_error = block_error(sample_tether);
  const double mean_u_error = std::sqrt(std::max(0.0, sum_u2 / samples - (sum_u / samples) * (sum_u / samples)) /
                                        double(samples));  // naive: samples treated as independent
  const double U_s = porosity * mean_u;
  // Δp: the paper's nominal f_b ρ L_d, and the one the applied force actually imposes, f_b N_d over
  // the fluid's share ε A_⊥ of the cross-section (N_d: fluid particles in the driving region, fewer
  // than ρ ε V_d where the fluid thins next to walls and pillars). κ uses the latter.
  const double height = D == 3 ? (g.walls() ? g.H : g.Lz) : 1.0;
  const double delta_p = fb * par.density * par.driving_length;
  const double delta_p_force_balance = fb * (driven / double(samples)) / (porosity * g.Ly * height);
  const double kappa_darcy = mu * U_s * g.Lx / delta_p;
  const double F_pair = f_sum / double(samples), F_tether = -tether / double(samples);
  const bool has_pillars = !g.centres.empty();
  // Eq. (3) per pillar: F_d = F_m / (n_m × height), n_m the pillars with axes in the region.
  int n_m = 0;
  for (const auto& c : g.centres) {
    double s = c[0] - x_lo;
    s -= g.Lx * std::floor(s / g.Lx);
    n_m += s < x_hi - x_lo;
  }
  const double phi = 1 - porosity;
  auto kappa_eq3 = [&](double F_m) {
    return has_pillars && n_m > 0 && F_m != 0 ? pi * mu * U_s * g.diameter * g.diameter / (4 * phi * F_m / (n_m * height))
                                             : 0.0;
  };
  const double kappa_drag_pair = kappa_eq3(F_pair);
  const double kappa_drag_tether = kappa_eq3(F_tether);

  // Elevation profile and Brinkman fit (3D with walls).
  std::vector<double> z(bins), u_s(bins), fp(bins);
  const double bw = g.walls() ? g.H / bins : 1.0;
  for (int b = 0; b < bins; ++b) {
    z[b] = g.walls() ? (b + 0.5) * bw - 0.5 * g.H : 0.0;
    u_s[b] = count[b] > 0 ? porosity * velocity[b] / count[b] : 0.0;
    fp[b] = pillar_force[b] / double(samples) / ((x_hi - x_lo) * g.Ly * bw);
  }
  std::optional<pillars::BrinkmanFit> fit;
  if (g.walls() && has_pillars && bins >= 3) fit = pillars::fit_brinkman(z, u_s, g.H);

  std::ofstream csv(stem + "_profile.csv");
  csv << "z,fluid_samples,mean_ux,u_s,pillar_force_density,brinkman_fit\n" << std::setprecision(10);
  for (int b = 0; b < bins; ++b)
    csv << z[b] << "," << count[b] << "," << (count[b] > 0 ? velocity[b] / count[b] : 0.0) << "," << u_s[b] << ","
        << fp[b] << "," << (fit ? pillars::brinkman_profile(z[b], fit->B, fit->alpha, g.H) : 0.0) << "\n";
  csv.close();

  h5->write_xdmf(out.xdmf);

  std::ofstream json(out.summary);
  json << std::setprecision(8) << "{\n  \"driver\": \"pillars\",\n  \"mode\": \"flow\",\n  \"dimension\": " << D
       << ",\n  \"layout\": \"" << par.layout << "\",\n  \"porosity\": " << porosity
       << ",\n  \"diameter\": " << g.diameter << ",\n  \"box\": [" << g.Lx << ", " << g.Ly << ", " << g.Lz
       << "],\n  \"walls_height\": " << g.H << ",\n  \"particles\": " << sys.particles.size()
       << ",\n  \"solid_particles\": " << solids << ",\n  \"driving_force\": " << fb
       << ",\n  \"pressure_difference\": " << delta_p << ",\n  \"pressure_difference_force_balance\": " << delta_p_force_balance
       << ",\n  \"kappa_darcy_force_balance\": " << mu * U_s * g.Lx / delta_p_force_balance << ",\n  \"viscosity_used\": " << mu
       << ",\n  \"samples\": " << samples << ",\n  \"mean_ux\": " << mean_u
       << ",\n  \"mean_ux_naive_error\": " << mean_u_error << ",\n  \"mean_ux_block_error\": " << mean_u_block_error
       << ",\n  \"kappa_darcy_relative_error\": " << mean_u_block_error / std::abs(mean_u)
       << ",\n  \"kappa_drag_tether_relative_error\": "
       << std::sqrt(std::pow(mean_u_block_error / mean_u, 2) + std::pow(tether_block_error / F_tether, 2)) << ",\n  \"superficial_velocity\": " << U_s
       << ",\n  \"kappa_darcy\": " << kappa_darcy << ",\n  \"kappa_darcy_over_d2\": "
       << kappa_darcy / (g.diameter * g.diameter) << ",\n  \"kappa_drag_pair\": " << kappa_drag_pair
       << ",\n  \"kappa_drag_tether\": " << kappa_drag_tether << ",\n  \"wall_force_bottom\": "
       << wall_bottom / std::max<long long>(samples, 1) << ",\n  \"wall_force_top\": "
       << wall_top / std::max<long long>(samples, 1);
  if (has_pillars && porosity < 1) {
    json << ",\n  \"theory_over_d2\": {\"gebart_square\": " << pillars::kappa_gebart_square(porosity)
         << ", \"drummond_tahir_square\": " << pillars::kappa_drummond_tahir_square(porosity)
         << ", \"sangani_acrivos_dense\": " << pillars::kappa_sangani_acrivos_dense(porosity)
         << ", \"tsay_weinbaum_fit\": " << pillars::kappa_tsay_weinbaum_fit(porosity) << "}";
  }
  if (g.walls()) json << ",\n  \"kappa_walls_theory\": " << pillars::kappa_walls(g.H);
  if (fit) {
    json << ",\n  \"brinkman\": {\"B\": " << fit->B << ", \"alpha\": " << fit->alpha
         << ", \"rms_residual\": " << fit->rms_residual << ", \"alpha_at_bound\": "
         << (fit->alpha_at_lower_bound || fit->alpha_at_upper_bound ? "true" : "false");
    if (par.kappa_p > 0) {
      json << ", \"kappa_p\": " << par.kappa_p << ", \"mu_eff_over_mu\": " << pillars::mu_eff_ratio(par.kappa_p, fit->alpha)
           << ", \"kappa_eff_eq7\": " << pillars::kappa_eff_brinkman(par.kappa_p, fit->alpha, g.H)
           << ", \"B_theory\": " << par.kappa_p * delta_p / (mu * g.Lx);
    }
    json << "}";
  }
  json << ",\n  \"resumed_from_step\": " << resumed_from_step
       << ",\n  \"steps_run\": " << std::int64_t(sys.current_step()) - resumed_from_step  // equilibration included
       << ",\n  \"wall_seconds\": " << wall_seconds << ",\n  \"particle_steps_per_second\": "
       << double(sys.particles.size()) * double((par.restart ? 0 : par.equilibrate_steps) + total - first) / wall_seconds
       << ",\n  \"kokkos\": \"" << kokkos_configuration() << "\"\n}\n";
  json.close();
  if (!quiet)
    std::cerr << "pillars: U_s = " << U_s << " ± " << porosity * mean_u_block_error << ", kappa_darcy/d^2 = "
              << kappa_darcy / (g.diameter * g.diameter) << ", kappa_drag (pair, tether)/d^2 = "
              << kappa_drag_pair / (g.diameter * g.diameter) << ", " << kappa_drag_tether / (g.diameter * g.diameter)
              << "\n";
  if (g.walls())
    driver::plot_with_matplotlib("pillars", "plot_pillars.py", {stem + "_profile.csv", out.summary, stem + ".png"}, stem + ".png",
                                 quiet);
}

// The square-array theory curves of Fig. 7(b) (and the hexagonal ones) over ε, as CSV.
void write_theory_table(const cli::DriverApp& app) {
  const driver::OutputPaths out(app.output());
  const std::string path = out.trajectory.substr(0, out.trajectory.size() - 3) + "_theory.csv";
  std::ofstream csv(path);
  csv << "porosity,gebart_square,drummond_tahir_square,sangani_acrivos_dilute,sangani_acrivos_dense,"
         "tsay_weinbaum_fit,gebart_hexagonal,drummond_tahir_hexagonal\n"
      << std::setprecision(8);
  for (int k = 0; k <= 118; ++k) {  // ε = 0.40 … 0.99
    const double eps = 0.4 + 0.005 * k;
    csv << eps << "," << pillars::kappa_gebart_square(eps) << "," << pillars::kappa_drummond_tahir_square(eps) << ","
        << pillars::kappa_sangani_acrivos_dilute(eps) << "," << pillars::kappa_sangani_acrivos_dense(eps) << ","
        << pillars::kappa_tsay_weinbaum_fit(eps) << "," << pillars::kappa_gebart_hexagonal(eps) << ","
        << pillars::kappa_drummond_tahir_hexagonal(eps) << "\n";
  }
  std::ofstream table(out.trajectory.substr(0, out.trajectory.size() - 3) + "_sangani_acrivos_table.csv");
  table << "porosity,kappa_over_d2\n" << std::setprecision(8);
  for (const auto& row : pillars::sangani_acrivos_square_table()) table << row[0] << "," << row[1] << "\n";
  if (!app.quiet()) std::cerr << "pillars: wrote " << path << "\n";
}

// Periodic Poiseuille viscosity (Backer et al. 2005) in a fully periodic box.
template <int D>
void run_viscosity(const Parameters& par, const cli::DriverApp& app) {
  using Real = double;
  using Exec = Kokkos::DefaultExecutionSpace;
  const driver::OutputPaths out(app.output());
  const std::string stem = out.trajectory.substr(0, out.trajectory.size() - 3);
  const mdpd::MdpdParameters mp = fluid_parameters(par, D);
  const double g_force = par.fb >= 0 ? par.fb : 0.5;
  pillars::SceneGeometry geometry;
  geometry.dim = D;
  geometry.Lx = par.box;
  geometry.Ly = D == 3 ? par.box : par.lz;
  geometry.Lz = D == 3 ? par.lz : 0.0;
  const double Lzz = D == 3 ? geometry.Lz : geometry.Ly;

  if (par.box < 2.4 || Lzz < 4.8) throw std::invalid_argument("--box must be >= 2.4 and --lz >= 4.8 (σ)");
  const auto box = periodic_box<D>(geometry);
  mdpd::MdpdOptions opt;
  opt.list_kind = par.list == "full" ? NeighborListKind::full : NeighborListKind::half;
  mdpd::MdpdSystem<D, Real, Exec> sys(mp, box, std::uint64_t(par.seed), opt);
  pillars::fill_fluid(sys, geometry, par.density, std::uint64_t(par.seed));
  sys.begin();
  {
    watchdog::NanWatchdog watch(pillars::watched(sys, std::uint64_t(par.seed)), par.check_every);
    for (long long s = 0; s < par.equilibrate_steps; ++s) {
      sys.step();
      watch.after_step();
    }
  }
  sys.set_split_force({Real(g_force)});
  watchdog::NanWatchdog watch(pillars::watched(sys, std::uint64_t(par.seed), {Real(g_force)}), par.check_every);
  const int bins = std::max(4, int(std::lround(Lzz / par.bin_width)) / 2 * 2);
  constexpr int NB = pillars::max_profile_bins;
  if (bins > NB) throw std::invalid_argument("--lz / --bin-width gives too many bins (at most 64)");
  cli::ProgressLine progress(par.warmup_steps + par.steps, int(sys.particles.size()), !app.quiet());
  for (long long s = 0; s < par.warmup_steps; ++s) {
    sys.step();
    watch.after_step();
    progress.update(s + 1);
  }
  std::vector<double> count(bins, 0), velocity(bins, 0);
  double t_sum = 0;
  long long samples = 0;
  const auto x = sys.particles.x;
  const auto v = sys.particles.v;
  for (long long s = 0; s < par.steps; ++s) {
    sys.step();
    watch.after_step();
    if ((s + 1) % par.sample_every == 0) {
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
        count[b] += sums[b];
        velocity[b] += sums[NB + b];
      }
      t_sum += mdpd::kinetic_temperature(sys.particles);
      ++samples;
    }
    progress.update(par.warmup_steps + s + 1);
  }
  progress.finish();
  if (samples == 0) throw std::invalid_argument("--steps must cover at least one --sample-every interval");
  // u(z) = s(z) a q(z) + c, q = z'(L/2 − z'), s = ±1 by half: linear least squares for a and c.
  const double half = 0.5 * Lzz;
  double sqq = 0, sq = 0, s1 = 0, squ = 0, su = 0;
  std::vector<double> zc(bins), u(bins), model_q(bins);
  int fitted = 0;
  for (int b = 0; b < bins; ++b) {
    zc[b] = (b + 0.5) * Lzz / bins;
    const double zp = zc[b] < half ? zc[b] : zc[b] - half;
    const double sign = zc[b] < half ? 1.0 : -1.0;
    model_q[b] = sign * zp * (half - zp);
    u[b] = velocity[b] / count[b];
    // The force reverses at z = 0 and L/2; within r_A of those planes the finite interaction
    // range rounds the profile's cusp, so those bins are left out of the fit.
    if (zp < 1.0 || half - zp < 1.0) continue;
    ++fitted;
    sqq += model_q[b] * model_q[b];
    sq += model_q[b];
    s1 += 1;
    squ += model_q[b] * u[b];
    su += u[b];
  }
  const double det = sqq * s1 - sq * sq;
  const double a = (squ * s1 - sq * su) / det, c = (sqq * su - sq * squ) / det;
  const double volume = D == 3 ? geometry.Lx * geometry.Ly * geometry.Lz : geometry.Lx * geometry.Ly;
  const double rho = double(sys.particles.size()) / volume;
  const double eta = rho * g_force / (2 * a);
  double rss = 0;
  for (int b = 0; b < bins; ++b) {
    const double zp = zc[b] < half ? zc[b] : zc[b] - half;
    if (zp >= 1.0 && half - zp >= 1.0) rss += std::pow(u[b] - (a * model_q[b] + c), 2);
  }
  // Thermal temperature: the kinetic temperature less the streaming profile's share.
  double stream2 = 0, total_count = 0;
  for (int b = 0; b < bins; ++b) {
    stream2 += count[b] * u[b] * u[b];
    total_count += count[b];
  }
  const double thermal_temperature = t_sum / samples - stream2 / total_count / D;
  // Standard error of a from the residuals (bins independent) → relative error of η.
  const double sigma2 = rss / std::max(1, fitted - 2);
  const double a_error = std::sqrt(sigma2 * s1 / det);
  std::ofstream csv(stem + "_profile.csv");
  csv << "z,mean_ux,fit\n" << std::setprecision(10);
  for (int b = 0; b < bins; ++b) csv << zc[b] << "," << u[b] << "," << a * model_q[b] + c << "\n";
  std::ofstream json(out.summary);
  json << std::setprecision(8) << "{\n  \"driver\": \"pillars\",\n  \"mode\": \"viscosity\",\n  \"dimension\": " << D
       << ",\n  \"A\": " << mp.A << ",\n  \"B\": " << mp.B << ",\n  \"r_B\": " << mp.r_B << ",\n  \"R\": " << mp.R
       << ",\n  \"dt\": " << mp.dt << ",\n  \"density\": " << rho << ",\n  \"force\": " << g_force
       << ",\n  \"viscosity\": " << eta << ",\n  \"viscosity_error\": " << eta * a_error / a
       << ",\n  \"max_velocity\": " << a * half * half / 4 << ",\n  \"temperature\": " << thermal_temperature
       << ",\n  \"samples\": " << samples << "\n}\n";
  if (!app.quiet())
    std::cerr << "pillars: viscosity " << eta << " ± " << eta * a_error / a << " (ρ = " << rho << ", k_BT = "
              << thermal_temperature << ")\n";
}

}  // namespace
}  // namespace mesoflow

int main(int argc, char** argv) {
  using mesoflow::cli::Bounds;
  mesoflow::Parameters par;
  mesoflow::cli::DriverApp app("MDPD flow through pillar arrays: permeability, Brinkman fits, viscosity (Soft Matter 19, 436)",
                               "pillars.h5");
  app.add_choice("--mode", par.mode,
                 "flow through pillars, the fluid's viscosity (periodic Poiseuille), or the theory curves (CSV)",
                 {"flow", "viscosity", "theory"});
  app.add_int("--dimension", par.dimension, "2 (pillars only) or 3", 2, 3);
  app.add_choice("--layout", par.layout, "pillar arrangement",
                 {"square", "rotated-square", "hexagonal", "irregular", "file", "none"});
  app.add_string("--layout-file", par.layout_file, "pillar centres (CSV of pillar_layouts.hpp) for --layout file");
  app.add_real("--porosity", par.porosity, "porosity ε (regular and irregular layouts)", 0.0, 1.0, Bounds::open);
  app.add_real("--diameter", par.diameter, "pillar diameter d/σ", 1.0, 100.0);
  app.add_int("--cells-x", par.cells_x, "unit cells of a regular layout along the flow", 1, 1000);
  app.add_int("--cells-y", par.cells_y, "unit cells of a regular layout across the flow", 1, 1000);
  app.add_int("--pillars", par.pillars, "pillars of an irregular layout", 1, 100000);
  app.add_real("--aspect", par.aspect, "L_y/L_x of an irregular layout", 0.1, 10.0);
  app.add_real("--exclusion", par.exclusion, "Monte Carlo disc diameter / d (paper: 1.2)", 1.0, 2.0);
  app.add_int("--mc-sweeps", par.mc_sweeps, "hard-disc Monte Carlo sweeps of an irregular layout", 0, 1000000000LL);
  app.add_real("--height", par.height, "3D: wall separation H/σ (0: periodic in z)", 0.0, 100.0);
  app.add_real("--lz", par.lz, "3D box height without walls; viscosity mode: box edge along the gradient", 2.4, 1000.0);
  app.add_real("--box", par.box, "viscosity mode and --layout none: box edge L_x = L_y", 2.4, 1000.0);
  app.add_real("--fb", par.fb, "driving body force f_b (−1: 0.2 in 2D, 0.3 in 3D; viscosity mode: 0.5)", -1.0, 10.0);
  app.add_real("--driving-length", par.driving_length, "length L_d of the driving region", 0.0, 1000.0, Bounds::left_open);
  app.add_real("--viscosity", par.viscosity, "μ used for κ (−1: paper's 17.5 in 3D, 26.1 in 2D)", -1.0, 1000.0);
  app.add_real("--kappa-p", par.kappa_p, "pillar permeability κ_p (σ²) for Brinkman's μ_eff (0: none)", 0.0, 1e6);
  app.add_real("--bin-width", par.bin_width, "elevation bin width", 0.05, 10.0);
  app.add_int("--equilibrate-steps", par.equilibrate_steps, "steps of the quiescent fluid before carving", 0, 100000000LL);
  app.add_int("--warmup-steps", par.warmup_steps, "steps of driven flow before sampling", 0, 1000000000LL);
  app.add_int("--steps", par.steps, "production steps", 1, 1000000000LL);
  app.add_positive("--sample-every", par.sample_every, "steps between samples");
  app.add_real("--density", par.density, "number density ρ", 0.5, 20.0);
  app.add_real("--A", par.A, "attraction A (ε/σ)", -1000.0, 1000.0);
  app.add_real("--B", par.B, "repulsion B (−1: 25 in 3D, 30 in 2D)", -1.0, 1000.0);
  app.add_real("--r-B", par.r_B, "density cut-off r_B/σ", 0.1, 1.0);
  app.add_real("--R", par.R, "random-force strength R", 0.0, 1000.0);
  app.add_real("--dt", par.dt, "time step dt/τ (refused above the stability limit)", 0.0, 0.05, Bounds::left_open);
  app.add_flag(mesoflow::cli::force_dt_flag, par.force_dt, mesoflow::cli::force_dt_help);
  app.add_real("--k-S", par.k_S, "tether stiffness of solid particles", 0.0, 1e4);
  app.add_choice("--density-kernel", par.density_kernel, "many-body density weight", {"normalized", "lucy"});
  app.add_choice("--list", par.list, "neighbor list", {"half", "full"});
  app.add_int("--seed", par.seed, "random seed", 0, 4294967295LL);
  app.add_int("--threads", par.threads, "host threads (0: OMP_NUM_THREADS or all cores)", 0, 4096);
  app.add_int("--checkpoint-every", par.checkpoint_every, "flow mode: steps between checkpoints (<out>.ckpt.h5)", 1,
              1000000000LL);
  app.add_flag("--restart", par.restart, "flow mode: continue the interrupted run from <out>.ckpt.h5");
  app.add_int("--check-every", par.check_every,
              "steps between NaN-watchdog checks (a non-finite state stops the run, naming particle, term and step)",
              1, 1000000);
  return app.run(argc, argv, [&] {
    if (par.mode != "theory") mesoflow::check_time_step(par);
    mesoflow::KokkosScope kokkos(par.threads);
    if (par.mode == "theory")
      mesoflow::write_theory_table(app);
    else if (par.mode == "viscosity")
      par.dimension == 2 ? mesoflow::run_viscosity<2>(par, app) : mesoflow::run_viscosity<3>(par, app);
    else
      par.dimension == 2 ? mesoflow::run_flow<2>(par, app) : mesoflow::run_flow<3>(par, app);
  });
}
