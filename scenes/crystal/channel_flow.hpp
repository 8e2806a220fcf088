// channel_flow.hpp — the 2D scene of the paper's simulations (Appendix B): an MPC solvent in a
// channel, periodic along x, between no-slip walls at y = 0 and y = W (or periodic in y), driven
// by a body acceleration g along x, with rigid discs (the droplets) coupled to it by bounce-back
// and virtual particles, repelling each other and the walls by eq. (B.4), and slowed by the
// friction with the top and bottom plates of the Hele-Shaw cell, F = −γ U.
//
// One MPC step (step()):
//   1. discs move, X ← X + h U, and are binned                       (rigid_discs.hpp)
//   2. the solvent streams, v ← v + g h, x ← x + h v, eq. (B.1)       (streaming.hpp)
//   3. bounce-back on the walls                                      (wall_bounce_back.hpp)
//   4. bounce-back on the moving discs, impulses to the discs          (disc_bounce_back.hpp)
//   5. the collision grid is shifted at random
//   6. virtual particles fill the wall part of the cut wall cells — mirror images of the fluid
//      next to the wall (wall_mirror_particles.hpp, the default) or Appendix B's Maxwell–Boltzmann
//      particles at rest (virtual_particles.hpp; ChannelFlowParameters::wall_virtual) — and a
//      √2 a layer inside each disc                                   (virtual_particles.hpp)
//   7. collision (SRD, AT−a or AT+a, eq. B.2) of solvent + virtual particles (mpc_collision.hpp)
//   8. the virtual particles' momentum change goes to the walls and discs
//   9. WCA forces (eq. B.4, disc_wca.hpp) and the disc velocity update
//      U ← [U + J/M + h F/M]/(1 + γh/M), Ω ← Ω + L/I                 (rigid_discs.hpp)
//  10. every sort_interval steps the solvent is reordered in memory by collision cell
//      (MpcCollision::sort_by_cell: solvent particles are anonymous), for cache locality
// With no walls, γ = 0 and g = 0 the momentum of solvent + discs is conserved to round-off.
//
// The stages are the scene's terms, declared once (declare_terms(), scenes/common/term_list.hpp):
// step() runs the list's launches in order, components() names them, and the NaN watchdog
// (watched()) takes the one force term, the discs' WCA (eq. B.4), alone; the solvent moves by
// streaming and collisions only. checkpoint_fields() declares the state of a restart once.
//
// Units: cell size a = Δx, solvent mass m, k_BT; τ = Δx √(m/k_BT). Disc mass M = ρ π R² with the
// solvent's mass density ρ = n m / a² (Appendix B). Initial state: solvent particles uniform at
// density n in the channel outside the discs (N = round(n (L W − N_d π R²)/a²)), drawn from the
// counter-based stream (seed, 0, initial_condition, i, 0) by rejection, with Maxwell–Boltzmann
// velocities from (seed, 0, initial_condition, i, 1) less their mean (zero solvent momentum);
// discs at rest.
#pragma once

#include "kernels/common/kernel_launch.hpp"
#include "kernels/common/kokkos_compat.hpp"
#include "kernels/common/random.hpp"
#include "kernels/common/reductions.hpp"
#include "kernels/common/vec.hpp"
#include "kernels/mpc/collision_grid.hpp"
#include "kernels/mpc/disc_bounce_back.hpp"
#include "kernels/mpc/disc_wca.hpp"
#include "kernels/mpc/maxwell_boltzmann.hpp"
#include "kernels/mpc/mpc_collision.hpp"
#include "kernels/mpc/rigid_discs.hpp"
#include "kernels/mpc/stability.hpp"
#include "kernels/mpc/streaming.hpp"
#include "kernels/mpc/virtual_particles.hpp"
#include "kernels/mpc/wall_bounce_back.hpp"
#include "kernels/mpc/wall_mirror_particles.hpp"
#include "scenes/common/nan_watchdog.hpp"
#include "scenes/common/term_list.hpp"

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace mesoflow::mpc {

// How the wall part of the cut wall cells is filled: `mirror`, the images of the adjacent fluid
// (wall_mirror_particles.hpp; in the plane Poiseuille test of tests/mpc/test_mpc_walls.cpp a slip
// of −0.03 … +0.42% of u_max over five seeds), or `maxwell`, Appendix B's Maxwell–Boltzmann
// particles at the wall velocity (Lamura et al. 2001; a slip of 3.7–4.1% of u_max, slip length
// ≈ 0.1a, in the same test).
enum class WallVirtualRule { mirror, maxwell };

inline WallVirtualRule parse_wall_virtual_rule(const std::string& name) {
  if (name == "mirror") return WallVirtualRule::mirror;
  if (name == "maxwell") return WallVirtualRule::maxwell;
  throw std::invalid_argument("wall virtual particles '" + name + "': expected one of mirror, maxwell");
}

inline std::string to_string(WallVirtualRule rule) { return rule == WallVirtualRule::mirror ? "mirror" : "maxwell"; }

template <class Real>
struct ChannelFlowParameters {
  Real length = 1000;  // L, along x (periodic), a multiple of the cell size
  Real width = 15;     // W, along y
  bool walls = true;   // no-slip walls at y = 0 and y = W; false: periodic in y (a multiple of a)
  WallVirtualRule wall_virtual = WallVirtualRule::mirror;  // how the walls' cut cells are filled
  Real cell_size = 1;  // a = Δx
  Real density = 40;   // n, solvent particles per cell
  Real kT = 1;
  Real mass = 1;       // m, solvent particle mass
  Real h = Real(0.005);  // MPC time step
  CollisionRule rule = CollisionRule::at_plus_a;
  Real srd_angle = Real(2.2689280275926285);  // SRD rotation angle, 130°
  Real body_acceleration = Real(0.1);          // g, along x, on the solvent
  Real disc_radius = 5;                        // R
  Real friction = Real(2e4);                   // γ of F = −γ U
  Real wca_epsilon = 1;                        // ε of eq. (B.4)
  Real wca_r0 = 1;                             // r0 of eq. (B.4)
  std::uint64_t seed = 1;
  int sort_interval = 25;  // steps between reorderings of the solvent by collision cell; 0: never
  // The deterministic-sum mode (issue 26 item 4, docs/design.md): MPC cell sums and disc impulses
  // summed over index-ordered segments (CellSums::sorted, DiscBounceBack's sorted impulses) instead
  // of per-thread copies or float atomics: bitwise the same on every backend and thread count.
  bool deterministic = false;
};

// The parameters at another precision.
template <class To, class From>
ChannelFlowParameters<To> converted(const ChannelFlowParameters<From>& p) {
  ChannelFlowParameters<To> q;
  q.length = To(p.length);
  q.width = To(p.width);
  q.walls = p.walls;
  q.wall_virtual = p.wall_virtual;
  q.cell_size = To(p.cell_size);
  q.density = To(p.density);
  q.kT = To(p.kT);
  q.mass = To(p.mass);
  q.h = To(p.h);
  q.rule = p.rule;
  q.srd_angle = To(p.srd_angle);
  q.body_acceleration = To(p.body_acceleration);
  q.disc_radius = To(p.disc_radius);
  q.friction = To(p.friction);
  q.wca_epsilon = To(p.wca_epsilon);
  q.wca_r0 = To(p.wca_r0);
  q.seed = p.seed;
  q.sort_interval = p.sort_interval;
  q.deterministic = p.deterministic;
  return q;
}

// The explicit limit of the discs' WCA contacts and the solvent's bounce-back (kernels/mpc/stability.hpp).
inline DiscStiffnessInputs disc_stiffness_inputs(const ChannelFlowParameters<double>& f, bool discs) {
  DiscStiffnessInputs s;
  s.cell_size = f.cell_size;
  s.density = f.density;
  s.mass = f.mass;
  s.kT = f.kT;
  s.disc_radius = f.disc_radius;
  s.body_acceleration = f.body_acceleration;
  s.wca_epsilon = f.wca_epsilon;
  s.wca_r0 = f.wca_r0;
  s.discs = discs;
  return s;
}
inline StabilityEstimate channel_flow_stability(const ChannelFlowParameters<double>& f, bool discs) {
  return disc_stability(disc_stiffness_inputs(f, discs));
}

template <class Real, class ExecSpace = Kokkos::DefaultExecutionSpace>
class ChannelFlow {
 public:
  using vector_view = Kokkos::View<Real* [2], Kokkos::LayoutLeft, ExecSpace>;

  // Discs at the given centres (inside the channel, not touching each other or the walls: the
  // WCA potential is defined for positive gaps), at rest.
  explicit ChannelFlow(const ChannelFlowParameters<Real>& p, const std::vector<std::array<Real, 2>>& disc_centres = {})
      : p_(checked(p)),
        collision_(make_grid(p), collision_parameters(p), num_solvent(p, disc_centres.size()),
                   virtual_capacity(p, disc_centres.size())),
        discs_(disc_centres.size(), p.disc_radius, disc_mass(p), box_of(collision_.grid()),
               Real(2) * p.disc_radius + WcaPotential<Real>(p.wca_epsilon, p.wca_r0).cutoff),
        disc_bounce_back_(discs_, p.mass, p.deterministic),
        wca_(p.wca_epsilon, p.wca_r0),
        g_{p.body_acceleration, Real(0)} {
    check_disc_centres(disc_centres);
    if (!disc_centres.empty()) discs_.set_positions(disc_centres);
    if (p.walls) {
      walls_.emplace(collision_.grid(), p.mass);
      if (p.wall_virtual == WallVirtualRule::mirror)
        wall_mirror_.emplace(collision_.grid(), p.density, p.mass);
      else
        wall_virtual_.emplace(collision_.grid(), p.density, p.kT, p.mass, p.seed);
    }
    if (!disc_centres.empty())
      disc_virtual_.emplace(discs_, p.cell_size, p.density, p.kT, p.mass, p.seed);
    const std::size_t nv = collision_.virtual_capacity();
    xv_ = vector_view(Kokkos::ViewAllocateWithoutInitializing("mesoflow::mpc::channel::xv"), nv);
    vv_ = vector_view(Kokkos::ViewAllocateWithoutInitializing("mesoflow::mpc::channel::vv"), nv);
    x_ = vector_view(Kokkos::ViewAllocateWithoutInitializing("mesoflow::mpc::channel::x"),
                     collision_.particle_capacity());
    v_ = vector_view(Kokkos::ViewAllocateWithoutInitializing("mesoflow::mpc::channel::v"),
                     collision_.particle_capacity());
    initialise_solvent();
    declare_terms();
  }

  // The term list's launches hold `this`: a scene stays where it was built.
  ChannelFlow(const ChannelFlow&) = delete;
  ChannelFlow& operator=(const ChannelFlow&) = delete;

  // One MPC step (see the file comment): the term list's launches; no allocation. The mirror wall
  // rule returns one count to the host per step; otherwise there is no host transfer.
  void step() {
    terms_.evaluate();
    ++step_;
    if (p_.sort_interval > 0 && step_ % std::uint64_t(p_.sort_interval) == 0) collision_.sort_by_cell(x_, v_);
  }

  const scene::TermList<>& terms() const { return terms_; }
  std::vector<std::string> components() const {
    std::vector<std::string> c{std::to_string(num_solvent()) + " solvent particles, " +
                               std::to_string(discs_.size()) + " discs"};
    for (auto& line : terms_.components()) c.push_back(std::move(line));
    return c;
  }

  // The NaN watchdog's view (scenes/common/nan_watchdog.hpp): solvent and disc state, the one force
  // term (the discs' WCA), particles named by index. The scene must outlive it.
  watchdog::Watched watched() {
    watchdog::Watched w;
    w.state = {watchdog::Field::of("solvent position", x_), watchdog::Field::of("solvent velocity", v_),
               watchdog::Field::of("disc position", discs_.x), watchdog::Field::of("disc velocity", discs_.u),
               watchdog::Field::of("disc angular velocity", discs_.omega)};
    w.step = [this] { step(); };
    w.steps = [this] { return (long long)step_; };
    w.set_steps = [this](long long s) { restore(std::uint64_t(s)); };
    w.terms = terms_.watchdog_terms();
    const auto disc_force = discs_.force;
    w.first_bad_force = [disc_force] { return first_non_finite(disc_force, "mesoflow::watchdog::term_check"); };
    w.max_force = [disc_force] { return max_norm(disc_force, "mesoflow::watchdog::term_max"); };
    w.particle = [](long long i) { return "particle/disc " + std::to_string(i); };
    return w;
  }

  // The state of a restart, declared once for writing and reading (scenes/common/checkpoint_fields.hpp):
  // solvent and disc state and the step count; a load continues from it (restore()).
  template <class Archive>
  void checkpoint_fields(Archive& a) {
    a("solvent/x", x_);
    a("solvent/v", v_);
    a("discs/x", discs_.x);
    a("discs/u", discs_.u);
    a("discs/omega", discs_.omega);
    std::int64_t s = std::int64_t(step_);
    a("step", s);
    if (Archive::loading) restore(std::uint64_t(s));
  }

  // After the solvent and disc state were overwritten (a restart from a checkpoint): continue as
  // step `steps_done` of the run, with the disc bins rebuilt for the restored centres.
  void restore(std::uint64_t steps_done) {
    step_ = steps_done;
    discs_.build_bins();
  }

  const ChannelFlowParameters<Real>& parameters() const { return p_; }
  std::uint64_t steps_done() const { return step_; }
  double time() const { return double(step_) * double(p_.h); }
  const CollisionGrid<2, Real>& grid() const { return collision_.grid(); }

  // Solvent particles (positions folded into the channel) and velocities.
  std::size_t num_solvent() const { return x_.extent(0); }
  vector_view positions() const { return x_; }
  vector_view velocities() const { return v_; }

  // The discs: centres x, velocities u, angular velocities omega, last step's WCA force and
  // solvent impulse. Non-const access to set an initial state.
  const RigidDiscs<Real, ExecSpace>& discs() const { return discs_; }
  RigidDiscs<Real, ExecSpace>& discs() { return discs_; }
  const WcaPotential<Real>& wca() const { return wca_; }

  // Momentum taken up by the bottom (row 0) and top (row 1) wall since the start (host copy).
  std::array<std::array<double, 2>, 2> wall_momentum() const {
    if (!walls_) throw std::logic_error("channel flow: no walls");
    return walls_->momentum();
  }

  // Σ m v over the solvent (host value, a reduction).
  std::array<double, 2> solvent_momentum() const {
    const auto v = v_;
    const auto sum = parallel_sum<2, ExecSpace>("mesoflow::mpc::channel::solvent_momentum", int(num_solvent()),
                                                KOKKOS_LAMBDA(int i, double(&acc)[2]) {
                                                  acc[0] += double(v(i, 0));
                                                  acc[1] += double(v(i, 1));
                                                });
    return {double(p_.mass) * sum[0], double(p_.mass) * sum[1]};
  }

  // Σ m v + Σ M U.
  std::array<double, 2> total_momentum() const {
    const auto s = solvent_momentum();
    const auto d = discs_.momentum();
    return {s[0] + d[0], s[1] + d[1]};
  }

  static Real disc_mass(const ChannelFlowParameters<Real>& p) {
    return Real(double(p.density) * double(p.mass) * M_PI * double(p.disc_radius) * double(p.disc_radius) /
                (double(p.cell_size) * double(p.cell_size)));
  }

 private:
  static const ChannelFlowParameters<Real>& checked(const ChannelFlowParameters<Real>& p) {
    const auto positive = [](double value, const char* name) {
      if (!(value > 0) || !std::isfinite(value))
        throw std::invalid_argument(std::string("channel flow: ") + name + " must be finite and > 0, got " +
                                    std::to_string(value));
    };
    positive(double(p.length), "length");
    positive(double(p.width), "width");
    positive(double(p.cell_size), "cell_size");
    positive(double(p.density), "density");
    positive(double(p.mass), "mass");
    positive(double(p.h), "h");
    positive(double(p.disc_radius), "disc_radius");
    if (!(p.kT >= Real(0)) || !(p.friction >= Real(0)) || !std::isfinite(double(p.body_acceleration)))
      throw std::invalid_argument("channel flow: kT and friction must be >= 0, body_acceleration finite");
    return p;
  }

  static CollisionGrid<2, Real> make_grid(const ChannelFlowParameters<Real>& p) {
    return make_collision_grid<2, Real>(p.cell_size, {Real(0), Real(0)}, {p.length, p.width},
                                        {1, p.walls ? 0 : 1});
  }

  static CollisionParameters<Real> collision_parameters(const ChannelFlowParameters<Real>& p) {
    CollisionParameters<Real> c;
    c.rule = p.rule;
    c.kT = p.kT;
    c.mass = p.mass;
    c.srd_angle = p.srd_angle;
    c.seed = p.seed;
    c.cell_sums = p.deterministic ? CellSums::sorted : CellSums::automatic;
    return c;
  }

  static std::size_t num_solvent(const ChannelFlowParameters<Real>& p, std::size_t discs) {
    const double area = double(p.length) * double(p.width) -
                        double(discs) * M_PI * double(p.disc_radius) * double(p.disc_radius);
    if (!(area > 0)) throw std::invalid_argument("channel flow: the discs cover the channel");
    return std::size_t(std::llround(double(p.density) * area / (double(p.cell_size) * double(p.cell_size))));
  }

  // Upper bound of the virtual particle count (walls, then discs).
  static std::size_t virtual_capacity(const ChannelFlowParameters<Real>& p, std::size_t discs) {
    std::size_t total = 0;
    if (p.walls)
      total += p.wall_virtual == WallVirtualRule::mirror
                   ? WallMirrorParticles<2, Real, ExecSpace>::capacity(make_grid(p), p.density)
                   : WallVirtualParticles<2, Real, ExecSpace>::capacity(make_grid(p), p.density);
    if (discs > 0)
      total += DiscVirtualParticles<Real, ExecSpace>::capacity(discs, p.disc_radius, p.cell_size, p.density);
    return total;
  }

  // The step's stages, once, in the order of the file comment; a launch runs when one of its terms
  // acts. The WCA term alone (for the watchdog) leaves the discs' force in discs().force.
  void declare_terms() {
    const bool discs = discs_.size() > 0, walls = walls_.has_value();
    terms_.term({"disc drift", "", false, discs, {}});
    terms_.term({"streaming", "eq. B.1", false, true, {}});
    terms_.term({"body acceleration g", "eq. B.1", false, g_[0] != Real(0) || g_[1] != Real(0), {}});
    terms_.term({"wall bounce-back", "", true, walls, {}});
    terms_.term({"disc bounce-back", "", true, discs, {}});
    terms_.term({"MPC collision", "eq. B.2", true, true, {}});
    terms_.term({"wall virtual particles", "", true, walls, {}});
    terms_.term({"disc virtual particles", "", true, discs, {}});
    terms_.term({"disc–disc and disc–wall WCA", "eq. B.4", false, discs, [this] {
                   discs_.clear_accumulators();
                   accumulate_disc_wca(wca_, discs_);
                 }});
    terms_.term({"plate friction γ", "", true, discs && p_.friction != Real(0), {}});
    terms_.term({"disc kick", "", false, discs, {}});
    terms_.launch("disc drift (rigid_discs.hpp)", {"disc drift"}, [this] {
      discs_.clear_accumulators();
      discs_.move(p_.h);
    });
    terms_.launch("streaming (one kernel)", {"streaming", "body acceleration g"},
                  [this] { stream(x_, v_, p_.h, g_, collision_.grid()); });
    terms_.launch("wall bounce-back (one kernel)", {"wall bounce-back"}, [this] { walls_->bounce_back(x_, v_, p_.h); });
    terms_.launch("disc bounce-back (one kernel)", {"disc bounce-back"},
                  [this] { disc_bounce_back_.apply(x_, v_, p_.h, discs_); });
    terms_.launch("collision (grid shift, virtual particles, collision, transfer)",
                  {"MPC collision", "wall virtual particles", "disc virtual particles"}, [this] { collide(); });
    terms_.launch("disc forces and kick", {"disc–disc and disc–wall WCA", "plate friction γ", "disc kick"}, [this] {
      accumulate_disc_wca(wca_, discs_);
      discs_.update_velocities(p_.h, p_.friction);
    });
  }

  // Steps 5–8 of the file comment.
  void collide() {
    const std::uint64_t s = step_;
    collision_.shift_grid(s);
    std::size_t nv = 0;
    if (wall_virtual_) nv += wall_virtual_->generate(collision_.grid(), xv_, vv_, 0, s);
    if (wall_mirror_) nv += wall_mirror_->generate(collision_.grid(), x_, v_, num_solvent(), xv_, vv_, 0);
    const std::size_t disc_offset = nv;
    if (disc_virtual_) nv += disc_virtual_->generate(discs_, xv_, vv_, disc_offset, s);
    collision_.collide(x_, v_, xv_, vv_, nv, s);
    if (wall_virtual_) wall_virtual_->transfer(vv_, 0, *walls_);
    if (wall_mirror_) wall_mirror_->transfer(xv_, vv_, 0, *walls_);
    if (disc_virtual_) disc_virtual_->transfer(xv_, vv_, disc_offset, discs_);
  }

  // Discs must not touch each other or a wall, and their surfaces must start at least the closest
  // approach the step limit assumes apart (disc_closest_approach, kernels/mpc/stability.hpp): a pair
  // placed 0.01 r0 apart otherwise meets a WCA force ~10¹³ times the driving force in its first step.
  void check_disc_centres(const std::vector<std::array<Real, 2>>& c) const {
    const double R = double(p_.disc_radius), L = double(p_.length), W = double(p_.width);
    const double gap = c.empty() ? 0.0 : disc_closest_approach(disc_stiffness_inputs(converted<double>(p_), true));
    const auto too_close = [&](const std::string& what, double r) {
      throw std::invalid_argument("channel flow: " + what + " " + std::to_string(r) +
                                  " apart at their surfaces, closer than the " + std::to_string(gap) +
                                  " the step limit assumes (WCA force M g or energy 10 k_BT); place them further apart");
    };
    for (std::size_t k = 0; k < c.size(); ++k) {
      const double y = double(c[k][1]);
      if (p_.walls && !(y > R && y < W - R))
        throw std::invalid_argument("channel flow: disc " + std::to_string(k) + " at y = " + std::to_string(y) +
                                    " touches a wall (needs R < y < W - R)");
      if (p_.walls && std::min(y - R, W - R - y) < gap) too_close("disc " + std::to_string(k) + " and a wall are", std::min(y - R, W - R - y));
      for (std::size_t j = 0; j < k; ++j) {
        double dx = double(c[k][0]) - double(c[j][0]), dy = double(c[k][1]) - double(c[j][1]);
        dx -= L * std::floor(dx / L + 0.5);
        if (!p_.walls) dy -= W * std::floor(dy / W + 0.5);
        if (!(dx * dx + dy * dy > 4 * R * R))
          throw std::invalid_argument("channel flow: discs " + std::to_string(j) + " and " + std::to_string(k) +
                                      " touch or overlap");
        const double r = std::sqrt(dx * dx + dy * dy) - 2 * R;
        if (r < gap) too_close("discs " + std::to_string(j) + " and " + std::to_string(k) + " are", r);
      }
    }
  }

 public:
  // initialise_solvent is an implementation detail, public only because nvcc rejects a
  // KOKKOS_LAMBDA in a private or protected member function.
  void initialise_solvent() {
    const auto x = x_;
    const auto bins = discs_.bins();
    const auto X = discs_.x;
    const Real R = discs_.radius(), L = p_.length, W = p_.width;
    const std::uint64_t seed = p_.seed;
    constexpr int max_attempts = 10000;
    int failures = 0;
    mesoflow::launch::parallel_reduce(
        "mesoflow::mpc::channel::initialise", Kokkos::RangePolicy<ExecSpace>(0, num_solvent()),
        KOKKOS_LAMBDA(int i, int& failed) {
          RandomStream rs(seed, 0, stream_tag::initial_condition, std::uint32_t(i), 0);
          bool placed = false;
          Vec<2, Real> p;
          for (int attempt = 0; attempt < max_attempts && !placed; ++attempt) {
            p[0] = rs.uniform_in<Real>(Real(0), L);
            p[1] = rs.uniform_in<Real>(Real(0), W);
            bool inside = false;
            bins.for_each_near(p, [&](int k) {
              inside = inside || norm2(bins.separation(p, Vec<2, Real>::load(X, k))) < R * R;
            });
            placed = !inside;
          }
          failed += placed ? 0 : 1;
          p.store(x, i);
        },
        failures);
    if (failures > 0)
      throw std::runtime_error("channel flow: " + std::to_string(failures) +
                               " solvent particles found no place outside the discs");
    fill_maxwell_boltzmann<2, Real, ExecSpace>(v_, p_.kT, p_.mass, p_.seed, 1, p_.deterministic);
  }

 private:
  ChannelFlowParameters<Real> p_;
  MpcCollision<2, Real, ExecSpace> collision_;
  RigidDiscs<Real, ExecSpace> discs_;
  DiscBounceBack<Real, ExecSpace> disc_bounce_back_;
  WcaPotential<Real> wca_;
  Kokkos::Array<Real, 2> g_;
  std::optional<ChannelWalls<2, Real, ExecSpace>> walls_;
  std::optional<WallVirtualParticles<2, Real, ExecSpace>> wall_virtual_;
  std::optional<WallMirrorParticles<2, Real, ExecSpace>> wall_mirror_;
  std::optional<DiscVirtualParticles<Real, ExecSpace>> disc_virtual_;
  vector_view x_, v_, xv_, vv_;
  std::uint64_t step_ = 0;
  scene::TermList<> terms_;
};

}  // namespace mesoflow::mpc
