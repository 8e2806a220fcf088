// pillar_scene.hpp — the MDPD scenes of the pillar study (Hulikal Chakrapani et al., Soft Matter
// 19, 436 (2023), §2.5): a quiescent fluid snapshot from which pillars and walls are carved, and
// the per-sample measurements of the flow (Fig. 2): fluid velocity in the measurement region,
// its elevation profile, and the force of the fluid on the pillars and walls.
//
// Geometry: x is the flow direction (periodic), y periodic, z the elevation. With walls, the box is
// periodic in z too but its top slab z ∈ [H, H + t_w) is solid: the wall below the channel and the
// wall above it are the two faces of one slab of thickness t_w = 3σ, thicker than any interaction
// range (r_A, the WCA cut-off 2^{1/6}σ, and 1.2σ of surface layer), so fluid never meets fluid across
// it. The channel is z ∈ [0, H), its mid-plane at H/2.
#pragma once

#include "scenes/common/nan_watchdog.hpp"
#include "scenes/pillars/pillar_layouts.hpp"
#include "kernels/common/random.hpp"
#include "kernels/common/reductions.hpp"
#include "scenes/pillars/mdpd_system.hpp"

#include <cmath>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace mesoflow::pillars {

constexpr double wall_thickness = 3.0;      // t_w (σ)
constexpr double core_depth = 1.2;          // solid particles deeper than this repel fluid (WCA)
constexpr int max_profile_bins = 64;

struct SceneGeometry {
  int dim = 2;
  double Lx = 0, Ly = 0, Lz = 0;  // box (Lz: 3D only)
  double H = 0;                   // channel height between the walls (0: no walls)
  double diameter = 0;
  std::vector<std::array<double, 2>> centres;  // pillar axes

  bool walls() const { return dim == 3 && H > 0; }
};

// Depth of a point below the nearest solid surface (> 0 inside a solid, ≤ 0 in the fluid), and
// whether that solid is a wall.
struct SolidDepth {
  double depth;
  bool wall;
};

inline SolidDepth solid_depth(const SceneGeometry& g, double x, double y, double z) {
  SolidDepth s{-1e300, false};
  const double radius = 0.5 * g.diameter;
  for (const auto& c : g.centres) {
    double dx = x - c[0], dy = y - c[1];
    dx -= g.Lx * std::round(dx / g.Lx);
    dy -= g.Ly * std::round(dy / g.Ly);
    const double d = radius - std::sqrt(dx * dx + dy * dy);
    if (d > s.depth) s = {d, false};
  }
  if (g.walls()) {
    const double zz = z - g.Lz * std::floor(z / g.Lz);
    const double d = zz >= g.H ? std::min(zz - g.H, g.Lz - zz) : -std::min(zz, g.H - zz);
    if (d > s.depth) s = {d, true};
  }
  return s;
}

inline int nearest_pillar(const SceneGeometry& g, double x, double y) {
  int best = -1;
  double best_d2 = 1e300;
  for (std::size_t k = 0; k < g.centres.size(); ++k) {
    double dx = x - g.centres[k][0], dy = y - g.centres[k][1];
    dx -= g.Lx * std::round(dx / g.Lx);
    dy -= g.Ly * std::round(dy / g.Ly);
    if (dx * dx + dy * dy < best_d2) {
      best_d2 = dx * dx + dy * dy;
      best = int(k);
    }
  }
  return best;
}

// Fills the box with fluid at number density ρ (uniform random positions), at rest.
template <int D, class Real, class Exec>
void fill_fluid(mdpd::MdpdSystem<D, Real, Exec>& sys, const SceneGeometry& g, double density, std::uint64_t seed) {
  const double volume = D == 2 ? g.Lx * g.Ly : g.Lx * g.Ly * g.Lz;
  const int n = int(std::lround(density * volume));
  sys.allocate(n);
  Real lo[D], hi[D];
  const double L[3] = {g.Lx, g.Ly, g.Lz};
  for (int d = 0; d < D; ++d) {
    lo[d] = 0;
    hi[d] = Real(L[d]);
  }
  fill_uniform_counter(sys.particles.x, lo, hi, seed, 0);
}

// Turns the particles inside pillars and walls into tethered solid particles (sites at their
// current positions), those deeper than core_depth into cores; a pillar particle's `body` is the
// index of its pillar (walls: −1), so measurements can take whole pillars. Returns the number of
// solid particles. Host-side, once per run.
template <int D, class Real, class Exec>
int carve_solids(mdpd::MdpdSystem<D, Real, Exec>& sys, const SceneGeometry& g) {
  const auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sys.particles.x);
  auto type = Kokkos::create_mirror_view(sys.particles.type);
  auto site = Kokkos::create_mirror_view(sys.site);
  auto body = Kokkos::create_mirror_view(sys.particles.body);
  int solids = 0;
  for (std::size_t i = 0; i < x.extent(0); ++i) {
    const double z = D == 3 ? double(x(i, D - 1)) : 0.0;
    const auto s = solid_depth(g, double(x(i, 0)), double(x(i, 1)), z);
    type(i) = s.depth <= 0 ? mdpd::particle_type::fluid
                           : (s.depth > core_depth ? mdpd::particle_type::solid_core : mdpd::particle_type::solid);
    solids += s.depth > 0;
    body(i) = s.depth > 0 && !s.wall ? nearest_pillar(g, double(x(i, 0)), double(x(i, 1))) : -1;
    for (int d = 0; d < D; ++d) site(i, d) = x(i, d);
  }
  Kokkos::deep_copy(sys.particles.type, type);
  Kokkos::deep_copy(sys.site, site);
  Kokkos::deep_copy(sys.particles.body, body);
  return solids;
}

// One sample of the flow: sums over the measurement region x ∈ [x_lo, x_hi) (periodic), binned
// in elevation z ∈ [0, H) (3D with walls; one bin otherwise):
//   fluid particles per bin, their Σu_x; the x-force of the fluid on the particles of the pillars
//   whose axes lie in the region (whole pillars: a region edge through a pillar would leave the
//   pressure on its cut half unbalanced), binned by site elevation, and the tether forces on the
//   same particles; the fluid's force on the wall particles below and above the channel in the
//   region. `pillar_x` holds the pillars' axis positions x.
//   Over the whole box as well (issue 28, item 1: the estimators over one and the same volume): the
//   fluid count and Σu_x, and the tether forces on every pillar particle.
struct FlowSample {
  std::vector<double> count, velocity, pillar_force;
  double wall_force_bottom = 0, wall_force_top = 0, pillar_tether = 0;
  double driven_fluid = 0;  // fluid particles in the driving region
  double count_all = 0, velocity_all = 0, pillar_tether_all = 0;  // whole box
};

template <int D, class Real, class Exec>
FlowSample sample_flow(const mdpd::MdpdSystem<D, Real, Exec>& sys, const SceneGeometry& g,
                       const Kokkos::View<double*, Exec>& pillar_x, double x_lo, double x_hi, int bins) {
  const auto region = sys.driving_region();
  if (bins < 1 || bins > max_profile_bins)
    throw std::invalid_argument("profile bins must be in [1, " + std::to_string(max_profile_bins) + "]");
  constexpr int NB = max_profile_bins;
  const auto x = sys.particles.x;
  const auto v = sys.particles.v;
  const auto type = sys.particles.type;
  const auto site = sys.site;
  const auto drag = sys.solid_drag;
  const auto body = sys.particles.body;
  const double Lx = g.Lx, H = g.H, Lz = g.Lz;
  const bool walls = g.walls();
  const double width = x_hi - x_lo;
  const double bin_width = walls ? H / bins : 1.0;
  const double k_tether = sys.has_solids() ? sys.options().k_S : 0.0;
  const auto sums = parallel_sum<3 * NB + 7, Exec>(
      "mesoflow::pillars::sample_flow", int(sys.particles.size()), KOKKOS_LAMBDA(int i, double(&acc)[3 * NB + 7]) {
        const bool fluid = type(i) == mdpd::particle_type::fluid;
        if (fluid && region.contains(x(i, 0), Real(Lx))) acc[3 * NB + 3] += 1.0;
        const bool pillar = !fluid && body(i) >= 0;
        if (fluid) {
          acc[3 * NB + 4] += 1.0;
          acc[3 * NB + 5] += double(v(i, 0));
        } else if (pillar) {
          double stretch = double(site(i, 0)) - double(x(i, 0));
          stretch -= Lx * kmath::floor(stretch / Lx + 0.5);
          acc[3 * NB + 6] += k_tether * stretch;
        }
        const double xi = fluid ? double(x(i, 0)) : (pillar ? pillar_x(body(i)) : double(site(i, 0)));
        double s = xi - x_lo;
        s -= Lx * kmath::floor(s / Lx);
        if (s >= width) return;
        const double z = D == 3 ? double(fluid ? x(i, D - 1) : site(i, D - 1)) : 0.0;
        const double zz = z - Lz * kmath::floor(z / Lz);
        if (walls && zz >= H) {  // wall particle (fluid never sits here for long)
          if (!fluid) acc[3 * NB + (zz - H < Lz - zz ? 0 : 1)] += double(drag(i, 0));
          return;
        }
        int b = walls ? int(zz / bin_width) : 0;
        b = b < 0 ? 0 : (b >= bins ? bins - 1 : b);
        if (fluid) {
          acc[b] += 1.0;
          acc[NB + b] += double(v(i, 0));
        } else {
          acc[2 * NB + b] += double(drag(i, 0));
          double stretch = double(site(i, 0)) - double(x(i, 0));
          stretch -= Lx * kmath::floor(stretch / Lx + 0.5);
          acc[3 * NB + 2] += k_tether * stretch;
        }
      });
  FlowSample out;
  out.count.assign(sums.begin(), sums.begin() + bins);
  out.velocity.assign(sums.begin() + NB, sums.begin() + NB + bins);
  out.pillar_force.assign(sums.begin() + 2 * NB, sums.begin() + 2 * NB + bins);
  out.wall_force_bottom = sums[3 * NB];
  out.wall_force_top = sums[3 * NB + 1];
  out.pillar_tether = sums[3 * NB + 2];
  out.driven_fluid = sums[3 * NB + 3];
  out.count_all = sums[3 * NB + 4];
  out.velocity_all = sums[3 * NB + 5];
  out.pillar_tether_all = sums[3 * NB + 6];
  return out;
}

// ---------------------------------------------------------------------------------------------
// The NaN watchdog's view of an MDPD system (scenes/common/nan_watchdog.hpp): watched(sys).
//
// State: x, v, the forces of the last step (the first half kick's), masses and tether sites
// (checked), types, pillar indices and tags (kept); on the host the system's counters (step, rebuilds
// since the last memory sort, sorts) and, on the device, the neighbor list's reference positions.
// A restore puts all of it back and rebuilds the list from those reference positions
// (MdpdSystem::resume, the path of a bit-identical restart), so the replay has the particles in the
// same memory order, the same list rows, the same rebuilds and sorts at the same steps and the same
// pair noise (keyed on step and tags): it retraces the run bit for bit at a fixed thread count.
// The packed rows and densities are recomputed by every step and are not state.
//
// Terms, each alone: the system's term list (MdpdSystem::terms(), mdpd_system.hpp) — the
// conservative pair force A, B (eq. 9a, with the many-body densities recomputed at the state), the
// dissipative and random pair forces (eqs. 9b–c, at the current velocities and step), the WCA
// repulsion of solid cores (if the scene has cores), the tethers k_S (if it has solids), the driving
// force f_b (if set) and the split Poiseuille force (viscosity mode). Particles are named by tag
// (the index they had before any sort), with their kind and the index they are stored at.

// The view. The system must have begun (or resumed) and must outlive the returned value; its term
// list is read now, so set the driving region or split force first.
template <int D, class Real, class Exec>
watchdog::Watched watched(mdpd::MdpdSystem<D, Real, Exec>& sys) {
  using System = mdpd::MdpdSystem<D, Real, Exec>;
  auto& p = sys.particles;
  watchdog::Watched w = watchdog::watch_particles(p);
  w.state.insert(w.state.end(), {watchdog::Field::of("mass", p.mass), watchdog::Field::of("tether site", sys.site),
                                 watchdog::Field::kept("type", p.type), watchdog::Field::kept("pillar", p.body),
                                 watchdog::Field::kept("tag", sys.tag)});
  w.step = [&sys] { sys.step(); };
  w.steps = [&sys] { return (long long)sys.current_step(); };
  w.set_steps = [](long long) {};  // the counters are restored with the list, in after_restore
  struct Kept {
    typename System::Counters counters{};
    typename System::vector_view reference;
  };
  auto kept = std::make_shared<Kept>();
  kept->reference = typename System::vector_view(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "mesoflow::pillars::watchdog_reference"), p.size());
  w.save_host = [&sys, kept] {
    kept->counters = sys.counters();
    copy_field(kept->reference, sys.neighbor_reference_positions(), "mesoflow::watchdog::save");
  };
  w.after_restore = [&sys, kept] { sys.resume(kept->counters, kept->reference); };
  w.terms = sys.terms().watchdog_terms();
  const auto tag = sys.tag;
  const auto type = p.type, body = p.body;
  w.particle = [tag, type, body](long long i) {
    std::uint32_t t = 0;
    int k = 0, b = -1;
    Kokkos::deep_copy(t, Kokkos::subview(tag, i));
    Kokkos::deep_copy(k, Kokkos::subview(type, i));
    Kokkos::deep_copy(b, Kokkos::subview(body, i));
    const std::string kind = k == mdpd::particle_type::fluid ? "fluid"
                             : std::string(k == mdpd::particle_type::solid_core ? "solid core" : "solid") +
                                   (b >= 0 ? " of pillar " + std::to_string(b) : " of a wall");
    return "particle " + std::to_string(t) + " (" + kind + ", stored at " + std::to_string(i) + ")";
  };
  return w;
}

}  // namespace mesoflow::pillars
