// capsule_scene.hpp — a microcapsule in SPH fluid, the Discrete Multi-Physics model of the capsule
// paper (sph-microcapsules-constriction §2–§3): composes the SPH system (kernels/sph: eqs. 1–6,
// 11–16) with the membrane's mass-spring network (kernels/msm: eq. 7), owns the state, steps it and
// measures the capsule. Physics stays in kernels/; this header only assembles it.
//
// Scene (§3, Fig. 1): a channel (channel_geometry.hpp: the constriction of §3, the shear cell of
// §4.1, or by default a periodic box of n_x × n_y × n_z sites) on a simple cubic lattice (spacing
// Δx, sites at (i + ½)Δx): SPH fluid on the sites of its fluid region, wall particles (type wall,
// mass ρ0 Δx³, viscosity μ_out, the walls' prescribed velocity; with Morris walls their normal and
// depth, no_slip_walls.hpp) on the solid sites within one kernel support of it, and the capsule's
// two-layer membrane (msm::capsule_membrane: icospheres of radii a and a − h_t, level ℓ, bonds k_b,
// partner k_b and diagonals 2/3 k_b, §3) centred at the given point (default: the domain's
// centre). Walled axes are bounded in the SPH box, which extends over the wall layers. Fluid sites
// in the shell, a − h_t − c < r < a + c with
// the clearance c = clearance·Δx (½Δx: each layer's particles own half a spacing on either side),
// are removed; sites with r ≤ a − h_t − c are inner fluid (particle_type::inner_fluid, viscosity
// μ_in), the others outer fluid (particle_type::fluid, μ_out). Particles are stored outer fluid,
// inner fluid, walls, then the membrane (outer layer, inner layer: capsule_mesh.hpp's numbering) —
// until the first memory sort.
//
// Membrane particles are SPH particles as well (§2.4: "at the same time MSM and SPH particles";
// particle_type::membrane): ρ integrated by eq. (4), pressure by eq. (6), viscous term of eq. (5)
// with μ_m (default μ_out, so that the pair viscosity μ_i + μ_j of eq. 5 is the outer fluid's at
// the outer face; the paper's inner and outer fluids are equal unless stated, and then so are all
// three). Masses: fluid ρ0 Δx³ (the paper's "density and viscosity of inner and outer fluids are
// identical"); each membrane particle an equal share of the mass of the removed fluid sites, so
// the capsule is neutrally buoyant and the mass per volume uniform (the paper gives no membrane
// mass). All particles start at ρ = ρ0; the EOS (ρ0, c0, γ = 7) is shared (SphSystem has one).
//
// Initial shape: the membrane's positions — not its rest lengths — can be stretched by a diagonal
// map S about the centre, e.g. S = (1 + ε, 1/√(1 + ε), 1/√(1 + ε)), a prolate volume-preserving
// ellipsoid that relaxes back to the sphere of the rest lengths. The fluid is classified in the
// same frame (a site p by |S⁻¹(p − c)|), so it fills the stretched capsule and its outside.
// Initial velocities: the membrane and inner fluid can move at a common velocity, and every
// particle can get uniform random noise of a given amplitude per component (host RNG: initial
// conditions only), its net momentum removed.
//
// Step: SphSystem::step_composed with the scene's terms, declared once (declare_terms(),
// scenes/common/term_list.hpp): the SPH pressure (eqs. 5–6), the viscous force (eq. 5) and the body
// force F of eq. (2) (optional; it drives the fluids only, outer and inner, §4, particle_types.hpp)
// in the one SPH pair loop, then the membrane bonds of eq. (7), added to f^{n+1} before the second
// half kick of eq. (15): f_i = (eq. 5)_i + Σ_bonds F_i. The same list gives the NaN watchdog its
// terms alone and the summaries their components.
//
// Memory sorting (SphOptions::sort_every, default 20 rebuilds; 0: never): after each sort the
// bond ends, the bonds' CSR rows and the membrane vertex → particle map are renumbered with the
// sort's new indices (SphSystem::last_sort_new_index), inside extra and so before the bonds are
// evaluated. The bond forces are then bitwise those of the unsorted particles (each row keeps its
// bond order); the SPH sums change order, i.e. trajectories agree to round-off. Renumbering, not
// refusing: sorting keeps the pair loop's memory locality as fluid and capsule move and mix.
//
// Time step: the smallest of the SPH limits (sph_time_step.hpp: viscous C_ν h²/ν, acoustic
// C_c h/c, force C_f √(h/|a|) with the bond forces among the accelerations) and the bond limit
// Δt_bond = C_b min_i √(m_i/K_i) (harmonic_bonds.hpp; K_i the summed stiffness of particle i's
// bonds, C_b = 0.5), at the initial state after the first force evaluation; a given dt above that
// limit is refused. While a run goes on, running_time_step_limits() re-evaluates the state-
// dependent ones, which capsule.cpp's automatic step follows.
//
// c0 of eq. (6): by default 10 U for the expected largest speed U (§2.2: "at least one order of
// magnitude larger than the maximum velocity", for density variations below 1%). The membrane's
// tension adds a pressure jump Δp ~ 2 G_s ε/a across it (strain ε), which that rule ignores: the
// density varies by Δp/(ρ0 c0²); give c0 ≥ √(100 Δp/ρ0) explicitly where that exceeds 10 U
// (tests/sph/test_capsule_scene.cpp: a capsule relaxing from ε = 0.3 at c0 = 10 U varies ρ by 2%
// near the membrane).
//
// Measurements (host, on demand; mirrors made once): the membrane's shape from its outer layer —
// centroid, enclosed volume Σ_triangles x_a · (x_b × x_c)/6 (vertices unwrapped about the first
// one), radii about the centroid, and the Taylor deformation D = (L − B)/(L + B) of §4.1, L and B
// the largest and smallest extent of the outer layer along the principal axes of its gyration
// tensor (the major and minor axes; the undeformed icosphere has D ≈ 0, its extents differing with
// the axis by at most a facet's sag, ~δ²/(8a));
// total momentum Σ m v; largest speed; largest |ρ − ρ0|/ρ0; a finite check.
//
// NaN watchdog (watched(), scenes/common/nan_watchdog.hpp): the state is every per-particle array a
// step reads or a sort permutes (x, v, f, ρ, ρ̇, mass, μ, ū, type, body, Morris wall geometry), the
// bond ends and CSR rows, the membrane slots, the particles' slots (`particle_slot()`: where each
// particle of the build order is stored now, renumbered at every sort like the bonds), the scene's
// step counter and body force. Particles are named by their build-order index and kind ("membrane
// vertex 12 of the outer layer", "outer fluid particle 301"), with the index they are stored at.
// On the host the SPH system's counters (step, rebuilds since the last memory sort, sorts) and, on
// the device, its neighbor list's reference positions are saved too; a restore rebuilds the list
// from them (SphSystem::resume), so the replay rebuilds and sorts at the same steps as the run and
// repeats it bit for bit (tests/capsule/test_capsule_watchdog.cpp).
#pragma once

#include "kernels/common/kernel_launch.hpp"
#include "scenes/capsule/channel_geometry.hpp"
#include "kernels/msm/membrane_moduli.hpp"
#include "scenes/common/nan_watchdog.hpp"
#include "scenes/common/term_list.hpp"
#include "scenes/common/time_step_limit.hpp"
#include "kernels/common/box.hpp"
#include "kernels/common/particle_sort.hpp"
#include "kernels/common/particles.hpp"
#include "kernels/common/reductions.hpp"
#include "kernels/msm/capsule_mesh.hpp"
#include "kernels/msm/harmonic_bonds.hpp"
#include "kernels/sph/particle_types.hpp"
#include "scenes/capsule/sph_system.hpp"
#include "kernels/sph/sph_time_step.hpp"
#include "kernels/sph/tait_equation_of_state.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace mesoflow::capsule {

struct CapsuleSceneParameters {
  // Fluid (§2.2, §4: ρ0, μ of the outer fluid; units Δx = ρ0 = 1 unless set otherwise).
  std::array<int, 3> sites{16, 16, 16};  // lattice sites per axis; the box is periodic, sites·Δx long
  double spacing = 1;                    // Δx
  double support = 3;                    // Lucy kernel support h (the paper's h), in Δx
  double rho0 = 1;                       // ρ0 of eq. (6)
  double mu_outer = 1;                   // dynamic viscosity of the outer fluid
  double mu_inner = 1;                   // of the inner fluid (viscosity ratio μ_in/μ_out)
  std::optional<double> mu_membrane;     // of the membrane particles; default μ_outer
  double u_max = 0.1;                    // expected largest speed U: c0 = 10 U (eq. 6)
  std::optional<double> c0;              // sound speed of eq. (6), overriding 10 U
  std::array<double, 3> body_force{};    // F of eq. (2), per unit mass, on the fluids
  std::optional<ChannelGeometry> channel;  // walls and fluid region; default: the periodic box of `sites`

  // Capsule (§3).
  double radius = 4;                     // a: outer sphere
  double thickness = 1;                  // h_t: the inner sphere has radius a − h_t
  int level = 2;                         // icosphere subdivisions (the paper's 5124 particles: 4)
  double k_b = 1;                        // eq. (7); diagonals 2/3 k_b
  msm::DiagonalBonds diagonals = msm::DiagonalBonds::one_per_quad;
  double clearance = 0.5;                // c/Δx: fluid removed within c of the shell
  std::optional<std::array<double, 3>> centre;  // the capsule's centre; default: the domain's
  std::array<double, 3> stretch{1, 1, 1};  // initial map S of the membrane positions (not rest lengths)

  // Initial velocities.
  std::array<double, 3> capsule_velocity{};  // membrane and inner fluid
  double velocity_noise = 0;             // uniform in [−A, A] per component, net momentum removed
  unsigned seed = 1;

  // Numerics.
  sph::SphOptions sph;                   // neighbor list kind, sorting, walls
  sph::SphTimeStepCoefficients dt_coefficients;
  double bond_dt_coefficient = 0.5;      // C_b of Δt_bond (harmonic_bonds.hpp)
  std::optional<double> dt;              // default: the smallest limit
  bool force_dt = false;                 // run a dt above the limit (a warning instead of an error)

  void validate() const {
    auto require = [](bool ok, const std::string& what) {
      if (!ok) throw std::invalid_argument("capsule scene: " + what);
    };
    auto positive = [](double v) { return std::isfinite(v) && v > 0; };
    for (int d = 0; d < 3; ++d) require(sites[std::size_t(d)] >= 1, "sites must be >= 1 per axis");
    require(positive(spacing), "spacing must be > 0, got " + std::to_string(spacing));
    require(positive(support), "support must be > 0, got " + std::to_string(support));
    require(positive(rho0), "rho0 must be > 0, got " + std::to_string(rho0));
    require(std::isfinite(mu_outer) && mu_outer >= 0, "mu_outer must be >= 0, got " + std::to_string(mu_outer));
    require(std::isfinite(mu_inner) && mu_inner >= 0, "mu_inner must be >= 0, got " + std::to_string(mu_inner));
    if (mu_membrane) require(std::isfinite(*mu_membrane) && *mu_membrane >= 0, "mu_membrane must be >= 0");
    require(positive(u_max), "u_max must be > 0, got " + std::to_string(u_max));
    if (c0) require(positive(*c0), "c0 must be > 0, got " + std::to_string(*c0));
    require(positive(radius), "radius a must be > 0, got " + std::to_string(radius));
    require(positive(thickness) && thickness < radius, "thickness h_t must be in (0, a)");
    require(positive(k_b), "k_b must be > 0, got " + std::to_string(k_b));
    require(std::isfinite(clearance) && clearance >= 0, "clearance must be >= 0");
    require(std::isfinite(velocity_noise) && velocity_noise >= 0, "velocity_noise must be >= 0");
    require(positive(bond_dt_coefficient), "bond_dt_coefficient must be > 0");
    if (dt) require(positive(*dt), "dt must be > 0, got " + std::to_string(*dt));
    for (int d = 0; d < 3; ++d) {
      const std::size_t a = std::size_t(d);
      require(positive(stretch[a]), "stretch must be > 0 per axis");
      require(std::isfinite(body_force[a]) && std::isfinite(capsule_velocity[a]), "non-finite vector");
      if (centre) require(std::isfinite((*centre)[a]), "non-finite capsule centre");
      // The capsule must not reach its periodic image: its extent plus one kernel support.
      const double extent = 2 * (radius * stretch[a] + clearance * spacing) + support * spacing;
      const double edge = channel ? channel->length[a] : sites[a] * spacing;
      require(edge > extent, "box length " + std::to_string(edge) + " along axis " + std::to_string(d) +
                                 " must exceed the capsule's extent + support = " + std::to_string(extent));
    }
  }

  ChannelGeometry geometry() const { return channel ? *channel : periodic_channel(sites, spacing); }
  std::array<double, 3> capsule_centre() const {
    if (centre) return *centre;
    const auto g = geometry();
    return {0.5 * g.length[0], 0.5 * g.length[1], 0.5 * g.length[2]};
  }
};

// The membrane's shape, from its outer layer (see the file comment).
struct MembraneShape {
  std::array<double, 3> centroid{};
  double volume = 0;        // enclosed by the outer-layer triangles
  double mean_radius = 0;   // of the outer vertices about the centroid
  double min_radius = 0, max_radius = 0;
  double length = 0, breadth = 0;  // L, B: extents along the largest and smallest principal axes
  double taylor_deformation = 0;   // D = (L − B)/(L + B)
};

// The stability limits of the scene: the SPH ones and the bonds'.
struct CapsuleTimeStepLimits {
  sph::SphTimeStepLimits sph;
  double bond = std::numeric_limits<double>::infinity();
  double dt() const { return std::min(sph.dt(), bond); }
  const char* binding() const { return bond < sph.dt() ? "bond" : sph.binding(); }
  // The binding limit with its physical term, for error messages.
  std::string term() const {
    const std::string b = binding();
    if (b == "bond") return "membrane bonds k_b (eq. 7)";
    if (b == "viscous") return "viscosity ν (Δt ≤ C_ν h²/ν)";
    if (b == "acoustic") return "largest sound speed c (Δt ≤ C_c h/c; c = c0 at ρ0)";
    if (b == "force") return "largest acceleration |a| (Δt ≤ C_f √(h/|a|))";
    return "acoustic-viscous coupling (Δt ≤ 2ν/c0²)";
  }
};

// Zeroes the pressure (p/ρ²) and/or viscosity columns of packed SPH rows: the pair loop then yields
// one term of eq. (5) alone (the NaN watchdog's term evaluation, CapsuleScene::watched()).
template <int D, class Real, class ExecSpace>
void zero_sph_columns(const sph::SphRows<D, Real, ExecSpace>& rows, bool pressure, bool viscosity) {
  using C = sph::SphColumn<D>;
  mesoflow::launch::parallel_for(
      "mesoflow::capsule::watchdog_zero_columns", Kokkos::RangePolicy<ExecSpace>(0, rows.extent(0)),
      KOKKOS_LAMBDA(int i) {
        if (pressure) rows(i, C::p_over_rho2) = Real(0);
        if (viscosity) rows(i, C::mu) = Real(0);
      });
}

template <class Real, class ExecSpace = Kokkos::DefaultExecutionSpace>
class CapsuleScene {
 public:
  using System = sph::SphSystem<3, Real, ExecSpace>;
  using Bonds = msm::HarmonicBonds<3, Real, ExecSpace>;
  using int_view = Kokkos::View<int*, ExecSpace>;

  explicit CapsuleScene(const CapsuleSceneParameters& par)
      : par_(checked(par)),
        mesh_(msm::capsule_membrane(membrane_parameters(par_))),
        fluid_(fluid_layout(par_)),
        sys_(sph::LucyKernel<3, Real>(Real(par_.support * par_.spacing)),
             sph::TaitEquationOfState<Real>(par_.rho0, par_.c0 ? *par_.c0 : sph::speed_of_sound_for_velocity(par_.u_max)),
             box(par_),
             Real(1), par_.sph),
        bonds_(msm::upload_bonds<Real, ExecSpace>(mesh_, membrane_offset())) {
    build_particles();
    sys_.begin([this](const auto& p) { add_membrane_forces(p); });
    limits_ = time_step_limits();
    const double limit = limits_.dt();
    if (par_.dt) cli::check_time_step("capsule scene", *par_.dt, {limit, limits_.term()}, par_.force_dt);
    sys_.set_dt(Real(par_.dt ? *par_.dt : limit));
  }

  // The term list's launches hold `this`: a scene stays where it was built.
  CapsuleScene(const CapsuleScene&) = delete;
  CapsuleScene& operator=(const CapsuleScene&) = delete;

  // One step of eqs. (11)–(16): the term list's launches (the SPH pair loop, the bonds of eq. 7).
  void step() {
    sys_.step_composed([this] { terms_.evaluate(); });
    ++steps_;
  }
  // F of eq. (2) on the fluids (the constriction's flow control).
  void set_body_force(const sph::BodyForce<3, Real>& body) {
    body_force_ = body;
    sys_.set_body_force(body);
    declare_terms();
  }
  // The scene's terms (see the file comment) and the summary's component lines.
  const scene::TermList<>& terms() const { return terms_; }
  std::vector<std::string> components() const {
    std::vector<std::string> c{std::to_string(num_fluid()) + " fluid, " + std::to_string(num_walls()) + " wall and " +
                               std::to_string(num_membrane()) + " membrane particles"};
    for (auto& line : terms_.components()) c.push_back(std::move(line));
    return c;
  }
  const sph::BodyForce<3, Real>& body_force() const { return body_force_; }
  // Steps run (the SPH system's own counter also counts the steps a NaN-watchdog replay reruns).
  long long steps() const { return steps_; }
  void run(long steps) {
    for (long k = 0; k < steps; ++k) step();
  }

  // The limits at the current state (host reductions: not every step).
  CapsuleTimeStepLimits time_step_limits() const {
    CapsuleTimeStepLimits l;
    l.sph = sys_.time_step_limits(par_.dt_coefficients);
    l.bond = bonds_.time_step_limit(sys_.particles, par_.bond_dt_coefficient);
    return l;
  }
  // The limits at the initial state (after the first force evaluation), which chose dt.
  const CapsuleTimeStepLimits& initial_time_step_limits() const { return limits_; }
  // The limits a running step must keep to (the constriction driver lowers its automatic step to
  // them): the per-step criteria at the current state — viscous with the current ν = μ/ρ, acoustic
  // with the current largest sound speed (the Tait c of eq. 6 grows as (ρ/ρ0)³ where the capsule
  // squeezes the fluid), force with the current accelerations — and, as at the start, the bonds'
  // and the acoustic–viscous limit at c0: a bound on the growth of waves through the bulk,
  // derived and measured for the reference sound speed (sph_time_step.hpp), which a few
  // compressed particles do not move (docs/sph-capsules.md, "Resolution study").
  CapsuleTimeStepLimits running_time_step_limits() const {
    CapsuleTimeStepLimits l = time_step_limits();
    l.sph.acoustic_viscous = limits_.sph.acoustic_viscous;
    return l;
  }
  void set_dt(double dt) { sys_.set_dt(Real(dt)); }

  // The outer layer's vertices (vertex order of the mesh), unwrapped about vertex 0 by the minimum
  // image: one connected surface, possibly reaching past the box on periodic axes (host copy).
  std::vector<Eigen::Vector3d> outer_layer_positions() const {
    Kokkos::deep_copy(x_host_, sys_.particles.x);
    Kokkos::deep_copy(slot_host_, membrane_slot_);
    const int nv = mesh_.vertices_per_layer;
    const auto& b = sys_.box();
    std::vector<Eigen::Vector3d> y(static_cast<std::size_t>(nv));
    auto position = [&](int v) {
      const int i = slot_host_(v);
      return Vec<3, Real>{{x_host_(i, 0), x_host_(i, 1), x_host_(i, 2)}};
    };
    const Vec<3, Real> x0 = position(0);
    for (int v = 0; v < nv; ++v) {
      Vec<3, Real> dr = position(v) - x0;
      b.minimum_image(dr);
      y[std::size_t(v)] = Eigen::Vector3d(double(x0[0]) + double(dr[0]), double(x0[1]) + double(dr[1]),
                                          double(x0[2]) + double(dr[2]));
    }
    return y;
  }

  MembraneShape membrane_shape() const { return membrane_shape(outer_layer_positions()); }

  // The shape of outer-layer positions y (as outer_layer_positions returns them).
  MembraneShape membrane_shape(const std::vector<Eigen::Vector3d>& y) const {
    const int nv = mesh_.vertices_per_layer;
    MembraneShape s;
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (const auto& p : y) c += p;
    c /= double(nv);
    for (int d = 0; d < 3; ++d) s.centroid[std::size_t(d)] = c[d];
    for (const auto& t : mesh_.triangle)
      s.volume += (y[std::size_t(t[0])] - c).dot((y[std::size_t(t[1])] - c).cross(y[std::size_t(t[2])] - c)) / 6;
    Eigen::Matrix3d g = Eigen::Matrix3d::Zero();
    s.min_radius = std::numeric_limits<double>::infinity();
    for (const auto& p : y) {
      const Eigen::Vector3d r = p - c;
      g += r * r.transpose();
      const double len = r.norm();
      s.mean_radius += len / nv;
      s.min_radius = std::min(s.min_radius, len);
      s.max_radius = std::max(s.max_radius, len);
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(g / double(nv));
    auto extent = [&](const Eigen::Vector3d& axis) {
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      for (const auto& p : y) {
        const double q = (p - c).dot(axis);
        lo = std::min(lo, q);
        hi = std::max(hi, q);
      }
      return hi - lo;
    };
    s.length = 0;
    s.breadth = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
      const double e = extent(eig.eigenvectors().col(a));
      s.length = std::max(s.length, e);
      s.breadth = std::min(s.breadth, e);
    }
    s.taylor_deformation = (s.length - s.breadth) / (s.length + s.breadth);
    return s;
  }

  std::array<double, 3> total_momentum() const { return momentum(sys_.particles); }

  double max_speed() const {
    const auto v = sys_.particles.v;
    double v2 = 0;
    mesoflow::launch::parallel_reduce(
        "mesoflow::capsule::max_speed", Kokkos::RangePolicy<ExecSpace>(0, int(sys_.particles.size())),
        KOKKOS_LAMBDA(int i, double& acc) {
          double s = 0;
          for (int d = 0; d < 3; ++d) s += double(v(i, d)) * double(v(i, d));
          if (s > acc) acc = s;
        },
        Kokkos::Max<double>(v2));
    return std::sqrt(v2);
  }

  // max |ρ − ρ0|/ρ0 over all particles.
  double max_density_deviation() const {
    const auto rho = sys_.rho;
    const double rho0 = par_.rho0;
    double dev = 0;
    mesoflow::launch::parallel_reduce(
        "mesoflow::capsule::density_deviation", Kokkos::RangePolicy<ExecSpace>(0, int(sys_.particles.size())),
        KOKKOS_LAMBDA(int i, double& acc) {
          const double e = kmath::fabs(double(rho(i)) / rho0 - 1.0);
          if (e > acc) acc = e;
        },
        Kokkos::Max<double>(dev));
    return dev;
  }

  // Whether every position, velocity, force and density is finite.
  bool all_finite() const {
    const auto x = sys_.particles.x, v = sys_.particles.v, f = sys_.particles.f;
    const auto rho = sys_.rho;
    int bad = 0;
    mesoflow::launch::parallel_reduce(
        "mesoflow::capsule::finite_check", Kokkos::RangePolicy<ExecSpace>(0, int(sys_.particles.size())),
        KOKKOS_LAMBDA(int i, int& acc) {
          bool ok = kmath::isfinite(double(rho(i)));
          for (int d = 0; d < 3; ++d)
            ok = ok && kmath::isfinite(double(x(i, d))) &&
                 kmath::isfinite(double(v(i, d))) && kmath::isfinite(double(f(i, d)));
          acc += ok ? 0 : 1;
        },
        bad);
    return bad == 0;
  }

  // Surface shear modulus G_s = E h_t/(2(1 + ν)) with E = 5 k_b/(√3 δ_ave), ν = 1/4, as §4 quotes
  // it for the spring network (capsule_mesh.hpp: exact for the crossed network at h_t = δ_ave); the
  // capillary number is Ca = μ U a/G_s.
  double surface_shear_modulus() const {
    return msm::surface_shear_modulus(par_.k_b, mesh_.mean_in_layer_bond_length(), par_.thickness);
  }

  // The NaN watchdog's view of the scene (see the file comment). The scene must outlive it.
  watchdog::Watched watched() {
    auto& p = sys_.particles;
    watchdog::Watched w = watchdog::watch_particles(p);
    const auto& b = bonds_.bonds();
    w.state.insert(w.state.end(),
                   {watchdog::Field::of("density", sys_.rho), watchdog::Field::of("density rate", sys_.drho),
                    watchdog::Field::of("mass", p.mass), watchdog::Field::kept("viscosity", sys_.mu),
                    watchdog::Field::kept("extrapolated velocity", sys_.u_bar), watchdog::Field::kept("type", p.type),
                    watchdog::Field::kept("body", p.body), watchdog::Field::kept("bond ends", b.ends),
                    watchdog::Field::kept("bond rows", b.row_particle),
                    watchdog::Field::kept("bond partners", b.incident_partner),
                    watchdog::Field::kept("membrane slots", membrane_slot_),
                    watchdog::Field::kept("particle slots", particle_slot_)});
    if (sys_.wall_geometry.extent(0) > 0) w.state.push_back(watchdog::Field::kept("wall geometry", sys_.wall_geometry));
    w.step = [this] { step(); };
    w.steps = [this] { return steps_; };
    w.set_steps = [this](long long s) { steps_ = s; };
    struct Kept {
      sph::BodyForce<3, Real> body;
      typename System::Counters counters{};
      typename System::vector_view reference;
    };
    auto kept = std::make_shared<Kept>();
    kept->reference = typename System::vector_view(
        Kokkos::view_alloc(Kokkos::WithoutInitializing, "mesoflow::capsule::watchdog_reference"), p.size());
    w.save_host = [this, kept] {
      kept->body = body_force_;
      kept->counters = sys_.counters();
      copy_field(kept->reference, sys_.neighbor_reference_positions(), "mesoflow::watchdog::save");
    };
    w.restore_host = [this, kept] { set_body_force(kept->body); };
    w.after_restore = [this, kept] {
      sys_.resume(kept->counters, kept->reference);
      seen_sorts_ = sys_.num_sorts();
    };
    w.terms = terms_.watchdog_terms();
    const auto slots = particle_slot_;
    const int outer = num_outer_fluid(), fluid = num_fluid(), membrane = membrane_offset(),
              per_layer = mesh_.vertices_per_layer;
    w.particle = [slots, outer, fluid, membrane, per_layer](long long i) {
      const auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), slots);
      std::string name = "particle stored at " + std::to_string(i);
      for (std::size_t k = 0; k < h.extent(0); ++k) {
        if (h(k) != i) continue;
        const int n = int(k);
        if (n < outer)
          name = "outer fluid particle " + std::to_string(n);
        else if (n < fluid)
          name = "inner fluid particle " + std::to_string(n);
        else if (n < membrane)
          name = "wall particle " + std::to_string(n);
        else
          name = "membrane vertex " + std::to_string(n - membrane) +
                 (n - membrane < per_layer ? " of the outer layer" : " of the inner layer");
        name += " (stored at " + std::to_string(i) + ")";
        break;
      }
      return name;
    };
    return w;
  }

  // Scratch of watched(): eq. (5)'s terms alone through a pair loop of their own on packed rows with
  // the other term's column zeroed (the run's kernels, so the same arithmetic).
  struct TermsAlone {
    sph::SphPairInteractions<3, Real, ExecSpace, sph::LucyKernel<3, Real>> pair_loop;
    sph::SphRows<3, Real, ExecSpace> rows;
    Kokkos::View<Real*, ExecSpace> pressure, drho;
    sph::MorrisWallFactor<Real> morris;

    explicit TermsAlone(const CapsuleScene& scene)
        : pair_loop(scene.sys_.kernel(), sph::BodyForce<3, Real>{}),
          rows("mesoflow::capsule::watchdog_rows", scene.sys_.particles.size()),
          pressure("mesoflow::capsule::watchdog_pressure", scene.sys_.particles.size()),
          drho("mesoflow::capsule::watchdog_drho", scene.sys_.particles.size()),
          morris(Real(scene.par_.sph.beta_max)) {}

    // f ← eq. (5) with the pressure and/or viscous part dropped, plus the body force if asked.
    void pair(CapsuleScene& scene, bool drop_pressure, bool drop_viscosity, bool with_body) {
      const auto& sys = scene.sys_;
      const auto& p = sys.particles;
      sph::pack_sph_rows(p, sys.u_bar, sys.rho, sys.mu, sys.equation_of_state(), rows, pressure);
      zero_sph_columns<3, Real, ExecSpace>(rows, drop_pressure, drop_viscosity);
      pair_loop.set_body_force(with_body ? scene.body_force_ : sph::BodyForce<3, Real>{});
      pair_loop.compute(rows, p.type, sys.neighbor_list(), sys.box(), p.f, drho, sys.wall_geometry, morris);
    }
  };

  // particle_slot()(k) = where the particle with build-order index k (outer fluid, inner fluid,
  // walls, membrane) is stored now, kept current through memory sorts.
  const int_view& particle_slot() const { return particle_slot_; }

  const System& system() const { return sys_; }
  const Bonds& bonds() const { return bonds_; }
  const msm::MembraneMesh& mesh() const { return mesh_; }
  const CapsuleSceneParameters& parameters() const { return par_; }
  // membrane_slot()(v) = the particle index of membrane vertex v (0 .. V − 1 outer, V .. 2V − 1
  // inner), kept current through memory sorts.
  const int_view& membrane_slot() const { return membrane_slot_; }
  int num_outer_fluid() const { return fluid_.num_outer; }
  int num_inner_fluid() const { return int(fluid_.position.size()) - fluid_.num_outer; }
  int num_fluid() const { return int(fluid_.position.size()); }
  int num_walls() const { return int(fluid_.walls.wall.size()); }
  int num_membrane() const { return mesh_.num_particles(); }
  int num_particles() const { return membrane_offset() + num_membrane(); }
  // Membrane particles follow the fluid and the walls (until the first memory sort).
  int membrane_offset() const { return num_fluid() + num_walls(); }
  const ChannelGeometry& channel() const { return fluid_.geometry; }
  int num_removed_sites() const { return fluid_.num_removed; }

 private:
  // The fluid sites kept, outer fluid first, then inner fluid.
  struct FluidLayout {
    ChannelGeometry geometry;
    ChannelSites walls;  // its wall sites (its fluid sites are sorted into `position`)
    std::vector<std::array<double, 3>> position;
    int num_outer = 0;
    int num_removed = 0;
  };

  static const CapsuleSceneParameters& checked(const CapsuleSceneParameters& par) {
    par.validate();
    return par;
  }

  // The wall particles reach one kernel support into the solid.
  static double wall_reach(const CapsuleSceneParameters& par) { return par.support * par.spacing; }

  // Periodic axes span the domain; walled ones extend over the wall layers and are bounded.
  static Box<3, Real> box(const CapsuleSceneParameters& par) {
    const auto g = par.geometry();
    Real lo[3], len[3];
    bool periodic[3];
    for (std::size_t d = 0; d < 3; ++d) {
      const double layers = g.walled[d] ? std::ceil(wall_reach(par) / par.spacing - 1e-9) : 0.0;
      lo[d] = Real(-layers * par.spacing);
      len[d] = Real(g.length[d] + 2 * layers * par.spacing);
      periodic[d] = !g.walled[d];
    }
    return Box<3, Real>(lo, len, periodic);
  }

  static msm::CapsuleMembraneParameters membrane_parameters(const CapsuleSceneParameters& par) {
    msm::CapsuleMembraneParameters m;
    m.centre = par.capsule_centre();
    m.radius = par.radius;
    m.thickness = par.thickness;
    m.level = par.level;
    m.bonds.k_b = par.k_b;
    m.bonds.diagonals = par.diagonals;
    return m;
  }

  static FluidLayout fluid_layout(const CapsuleSceneParameters& par) {
    const auto c = par.capsule_centre();
    const double gap = par.clearance * par.spacing;
    const double r_inner = par.radius - par.thickness - gap, r_outer = par.radius + gap;
    FluidLayout all;
    all.geometry = par.geometry();
    ChannelSites sites = channel_sites(all.geometry, par.spacing, wall_reach(par));
    // The capsule with its clearance must lie in the fluid region: test the stretched sphere's
    // extreme points and its diagonals.
    for (int sx = -1; sx <= 1; ++sx)
      for (int sy = -1; sy <= 1; ++sy)
        for (int sz = -1; sz <= 1; ++sz) {
          const double dir[3] = {double(sx), double(sy), double(sz)};
          const double len = std::sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
          if (len == 0) continue;
          std::array<double, 3> p{};
          for (std::size_t d = 0; d < 3; ++d) p[d] = c[d] + dir[d] / len * (par.radius * par.stretch[d] + gap);
          if (!all.geometry.nearest_fluid(p).inside)
            throw std::invalid_argument("capsule scene: the capsule (radius a + clearance) centred at (" +
                                        std::to_string(c[0]) + ", " + std::to_string(c[1]) + ", " +
                                        std::to_string(c[2]) + ") does not fit in the channel's fluid region");
        }
    FluidLayout outer, inner;
    for (const auto& p : sites.fluid) {
      double r2 = 0;  // |S⁻¹(p − c)|², with the minimum image on periodic axes
      for (std::size_t d = 0; d < 3; ++d) {
        double delta = p[d] - c[d];
        if (!all.geometry.walled[d]) delta -= all.geometry.length[d] * std::floor(delta / all.geometry.length[d] + 0.5);
        r2 += std::pow(delta / par.stretch[d], 2);
      }
      const double r = std::sqrt(r2);
      if (r <= r_inner)
        inner.position.push_back(p);
      else if (r >= r_outer)
        outer.position.push_back(p);
      else
        ++outer.num_removed;
    }
    sites.fluid.clear();
    all.walls = std::move(sites);
    all.num_outer = int(outer.position.size());
    all.num_removed = outer.num_removed;
    all.position = std::move(outer.position);
    all.position.insert(all.position.end(), inner.position.begin(), inner.position.end());
    return all;
  }

  void build_particles() {
    const int nf = num_fluid(), nw = num_walls(), nm = num_membrane(), n = nf + nw + nm;
    if (fluid_.num_removed == 0)
      throw std::invalid_argument("capsule scene: no fluid site lies in the membrane shell; the lattice is too coarse");
    sys_.allocate(n);
    auto& p = sys_.particles;
    auto x = Kokkos::create_mirror_view(p.x);
    auto v = Kokkos::create_mirror_view(p.v);
    auto m = Kokkos::create_mirror_view(p.mass);
    auto type = Kokkos::create_mirror_view(p.type);
    auto body = Kokkos::create_mirror_view(p.body);
    auto mu = Kokkos::create_mirror_view(sys_.mu);
    const double dx3 = par_.spacing * par_.spacing * par_.spacing;
    const double m_fluid = par_.rho0 * dx3;
    const double m_membrane = m_fluid * fluid_.num_removed / double(nm);
    const double mu_membrane = par_.mu_membrane ? *par_.mu_membrane : par_.mu_outer;
    const auto c = par_.capsule_centre();
    for (int i = 0; i < nf; ++i) {
      const bool outer = i < fluid_.num_outer;
      for (int d = 0; d < 3; ++d) {
        x(i, d) = Real(fluid_.position[std::size_t(i)][std::size_t(d)]);
        v(i, d) = Real(outer ? 0.0 : par_.capsule_velocity[std::size_t(d)]);
      }
      m(i) = Real(m_fluid);
      type(i) = outer ? sph::particle_type::fluid : sph::particle_type::inner_fluid;
      body(i) = -1;
      mu(i) = Real(outer ? par_.mu_outer : par_.mu_inner);
    }
    const bool morris = sys_.wall_geometry.extent(0) > 0;
    auto geo = Kokkos::create_mirror_view(sys_.wall_geometry);
    for (int k = 0; k < nw; ++k) {
      const int i = nf + k;
      const auto& w = fluid_.walls;
      for (int d = 0; d < 3; ++d) {
        x(i, d) = Real(w.wall[std::size_t(k)][std::size_t(d)]);
        v(i, d) = Real(d == 0 ? w.wall_velocity_x[std::size_t(k)] : 0.0);
        if (morris) geo(i, d) = Real(w.wall_normal[std::size_t(k)][std::size_t(d)]);
      }
      if (morris) geo(i, sph::wall_depth_column<3>) = Real(w.wall_depth[std::size_t(k)]);
      m(i) = Real(m_fluid);
      type(i) = sph::particle_type::wall;
      body(i) = -1;
      mu(i) = Real(par_.mu_outer);
    }
    if (morris) Kokkos::deep_copy(sys_.wall_geometry, geo);
    const int no = membrane_offset();
    for (int k = 0; k < nm; ++k) {
      const int i = no + k;
      for (std::size_t d = 0; d < 3; ++d) {
        const double rest = mesh_.position[std::size_t(k)][d];
        x(i, int(d)) = Real(c[d] + par_.stretch[d] * (rest - c[d]));
        v(i, int(d)) = Real(par_.capsule_velocity[d]);
      }
      m(i) = Real(m_membrane);
      type(i) = sph::particle_type::membrane;
      body(i) = 0;
      mu(i) = Real(mu_membrane);
    }
    if (par_.velocity_noise > 0) {
      std::mt19937 gen(par_.seed);
      std::uniform_real_distribution<double> u(-par_.velocity_noise, par_.velocity_noise);
      double momentum[3] = {}, mass = 0;
      auto moving = [&](int i) { return i < nf || i >= no; };  // walls keep their velocity
      for (int i = 0; i < n; ++i) {
        if (!moving(i)) continue;
        for (int d = 0; d < 3; ++d) {
          v(i, d) += Real(u(gen));
          momentum[d] += double(m(i)) * double(v(i, d));
        }
        mass += double(m(i));
      }
      // Remove the noise's net momentum (keep the capsule's).
      double target[3] = {};
      for (int i = no; i < n; ++i)
        for (int d = 0; d < 3; ++d) target[d] += double(m(i)) * par_.capsule_velocity[std::size_t(d)];
      for (int i = fluid_.num_outer; i < nf; ++i)
        for (int d = 0; d < 3; ++d) target[d] += double(m(i)) * par_.capsule_velocity[std::size_t(d)];
      for (int i = 0; i < n; ++i)
        if (moving(i))
          for (int d = 0; d < 3; ++d) v(i, d) -= Real((momentum[d] - target[d]) / mass);
    }
    Kokkos::deep_copy(p.x, x);
    Kokkos::deep_copy(p.v, v);
    Kokkos::deep_copy(p.mass, m);
    Kokkos::deep_copy(p.type, type);
    Kokkos::deep_copy(p.body, body);
    Kokkos::deep_copy(sys_.mu, mu);

    membrane_slot_ = int_view("mesoflow::capsule::membrane_slot", nm);
    auto slot = Kokkos::create_mirror_view(membrane_slot_);
    for (int k = 0; k < nm; ++k) slot(k) = no + k;
    Kokkos::deep_copy(membrane_slot_, slot);
    particle_slot_ = int_view("mesoflow::capsule::particle_slot", n);
    auto all = Kokkos::create_mirror_view(particle_slot_);
    for (int k = 0; k < n; ++k) all(k) = k;
    Kokkos::deep_copy(particle_slot_, all);
    x_host_ = Kokkos::create_mirror_view(Kokkos::HostSpace(), p.x);
    slot_host_ = Kokkos::create_mirror_view(Kokkos::HostSpace(), membrane_slot_);

    sph::BodyForce<3, Real> body_force;
    for (int d = 0; d < 3; ++d) body_force.g[d] = Real(par_.body_force[std::size_t(d)]);
    set_body_force(body_force);
  }

  // The terms, once (see the file comment); re-declared when the body force changes.
  void declare_terms() {
    terms_ = scene::TermList<>{};
    const auto pair_alone = [this](bool drop_pressure, bool drop_viscosity, bool with_body) {
      return [this, drop_pressure, drop_viscosity, with_body] {
        if (!alone_) alone_ = std::make_shared<TermsAlone>(*this);
        alone_->pair(*this, drop_pressure, drop_viscosity, with_body);
      };
    };
    terms_.term({"SPH pressure", "eqs. 5-6", false, true, pair_alone(false, true, false)});
    terms_.term({"SPH viscous force μ", "eq. 5", true, true, pair_alone(true, false, false)});
    terms_.term({"body force F", "eq. 2", false, body_force_.active(), pair_alone(true, true, true)});
    terms_.term({"membrane bonds k_b", "eq. 7", false, true, [this] {
                   sys_.particles.zero_forces();
                   bonds_.accumulate(sys_.particles, sys_.box());
                 }});
    terms_.launch("SPH pair loop (one kernel: rho rate of eq. 4, force of eq. 5)",
                  {"SPH pressure", "SPH viscous force μ", "body force F"}, [this] { sys_.compute_rates(); });
    terms_.launch("membrane bonds (one kernel)", {"membrane bonds k_b"},
                  [this] { add_membrane_forces(sys_.particles); });
  }

  // The bond forces after the pair loop: follow a memory sort of this step, then eq. (7).
  void add_membrane_forces(const Particles<3, Real, ExecSpace>& p) {
    const int sorts = sys_.num_sorts();
    if (sorts != seen_sorts_) {
      if (sorts != seen_sorts_ + 1)
        throw std::logic_error("capsule scene: " + std::to_string(sorts - seen_sorts_) +
                               " memory sorts since the bonds were last renumbered; step the scene, not its SPH "
                               "system");
      bonds_.renumber(sys_.last_sort_new_index());
      renumber_particle_indices(membrane_slot_, sys_.last_sort_new_index());
      renumber_particle_indices(particle_slot_, sys_.last_sort_new_index());
      seen_sorts_ = sorts;
    }
    bonds_.accumulate(p, sys_.box());
  }

  CapsuleSceneParameters par_;
  msm::MembraneMesh mesh_;
  FluidLayout fluid_;
  System sys_;
  Bonds bonds_;
  int_view membrane_slot_;
  int_view particle_slot_;  // build-order index → storage index
  int seen_sorts_ = 0;
  long long steps_ = 0;
  sph::BodyForce<3, Real> body_force_{};
  CapsuleTimeStepLimits limits_;
  scene::TermList<> terms_;
  std::shared_ptr<TermsAlone> alone_;  // scratch of the terms alone, made at first use
  mutable typename Particles<3, Real, ExecSpace>::vector_view::HostMirror x_host_;
  mutable typename int_view::HostMirror slot_host_;
};

}  // namespace mesoflow::capsule
