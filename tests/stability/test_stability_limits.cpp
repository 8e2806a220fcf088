// The Δt stability limits of the models that had none (kernels/mdpd/stability.hpp,
// kernels/mpc/stability.hpp, kernels/common/lennard_jones_stability.hpp) and the refusal rule the
// drivers share (scenes/common/time_step_limit.hpp): each limit reproduces its derivation at the
// paper's parameters, a run just below it stays bounded and, where cheap, a run well above it
// blows up — so the limit is an estimate with a margin, not a number chosen to pass.
#include "scenes/common/time_step_limit.hpp"
#include "scenes/droplets/deformation.hpp"
#include "scenes/droplets/droplet_scene.hpp"
#include "scenes/hopper/hopper_scene.hpp"
#include "kernels/common/fire.hpp"
#include "kernels/common/lennard_jones.hpp"
#include "kernels/common/lennard_jones_stability.hpp"
#include "kernels/common/neighbor_list.hpp"
#include "kernels/common/pair_force.hpp"
#include "kernels/common/random.hpp"
#include "kernels/common/reductions.hpp"
#include "kernels/common/velocity_verlet.hpp"
#include "kernels/dp/polygons.hpp"
#include "kernels/dp/shape_stiffness.hpp"
#include "kernels/dp/stability.hpp"
#include "scenes/pillars/mdpd_system.hpp"
#include "kernels/mdpd/stability.hpp"
#include "scenes/crystal/channel_flow.hpp"
#include "kernels/mpc/stability.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <iostream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace mesoflow {
namespace {

using Exec = Kokkos::DefaultExecutionSpace;

template <class View>
bool all_finite(const View& a) {
  const auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), a);
  for (std::size_t i = 0; i < h.extent(0); ++i)
    for (std::size_t d = 0; d < h.extent(1); ++d)
      if (!std::isfinite(double(h(i, d)))) return false;
  return true;
}

// ---------------------------------------------------------------------------------------------
// The shared rule

TEST(TimeStepLimit, RefusesAboveTheLimitNamingTheTermAndTheLimitUnlessForced) {
  const cli::TimeStepLimit limit{0.0125, "dissipation D (rate 113.1/τ)"};
  std::ostringstream warn;
  EXPECT_NO_THROW(cli::check_time_step("test", 0.0125, limit, false, warn));  // at the limit: accepted
  EXPECT_TRUE(warn.str().empty());
  try {
    cli::check_time_step("test", 0.02, limit, false, warn);
    ADD_FAILURE() << "dt above the limit accepted";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("dissipation D"), std::string::npos) << what;
    EXPECT_NE(what.find("0.0125"), std::string::npos) << what;
    EXPECT_NE(what.find("got 0.02"), std::string::npos) << what;
    EXPECT_NE(what.find("--force-dt"), std::string::npos) << what;
  }
  EXPECT_NO_THROW(cli::check_time_step("test", 0.02, limit, true, warn));
  EXPECT_NE(warn.str().find("warning: "), std::string::npos) << warn.str();
  EXPECT_NE(warn.str().find("dissipation D"), std::string::npos) << warn.str();
  EXPECT_NE(warn.str().find("0.0125"), std::string::npos) << warn.str();
}

TEST(StabilityEstimate, SumsModesAndRatesAndNamesTheBindingTerm) {
  StabilityEstimate e;
  e.add_mode("spring a", 30);
  e.add_mode("spring b", 40);
  EXPECT_DOUBLE_EQ(e.omega(), 50);
  EXPECT_DOUBLE_EQ(e.edge(), 2.0 / 50);  // Verlet: ω Δt < 2
  EXPECT_DOUBLE_EQ(e.max_dt(), 0.02);    // safety ½: ω Δt ≤ 1
  EXPECT_NE(e.limiting_term("τ").find("spring b"), std::string::npos);
  e.add_rate("friction", 150);  // ν Δt + (ω Δt)²/2 = 2 at the edge; the friction takes most of it
  const double edge = e.edge();
  EXPECT_NEAR(150 * edge + 0.5 * 2500 * edge * edge, 2.0, 1e-12);
  EXPECT_DOUBLE_EQ(e.max_dt(), 0.5 * edge);
  EXPECT_NE(e.limiting_term("τ").find("friction"), std::string::npos);
  StabilityEstimate friction_only;
  friction_only.add_rate("drag", 40);
  EXPECT_DOUBLE_EQ(friction_only.edge(), 2.0 / 40);  // explicit Euler: ν Δt < 2
  e.add_bound("geometry", 1e-3);
  EXPECT_DOUBLE_EQ(e.max_dt(), 1e-3);
  EXPECT_NE(e.limiting_term("τ").find("geometry"), std::string::npos);
  EXPECT_EQ(StabilityEstimate().max_dt(), HUGE_VAL);
}

// ---------------------------------------------------------------------------------------------
// MDPD

mdpd::MdpdStiffnessInputs paper_fluid(int dim) {
  mdpd::MdpdStiffnessInputs s;
  s.dimension = dim;
  s.B = dim == 2 ? 30 : 25;
  return s;
}

// The numbers of the file comment of kernels/mdpd/stability.hpp; the paper's dt = 0.01 is inside.
TEST(MdpdStability, PaperFluidsMatchTheDerivation) {
  const auto f2 = mdpd::mdpd_stability(paper_fluid(2)), f3 = mdpd::mdpd_stability(paper_fluid(3));
  EXPECT_NEAR(f2.omega(), 72.77, 0.01);
  EXPECT_NEAR(f3.omega(), 51.87, 0.01);
  EXPECT_NEAR(f2.rate(), 113.10, 0.01);  // docs/mdpd.md: 113/τ
  EXPECT_NEAR(f3.rate(), 60.32, 0.01);   // 60/τ
  EXPECT_NEAR(f2.edge(), 0.013449, 1e-6);
  EXPECT_NEAR(f2.max_dt(), 0.011432, 1e-6);  // 0.85 of the edge
  EXPECT_NEAR(f3.max_dt(), 0.018855, 1e-6);
  auto with_cores = paper_fluid(2);
  with_cores.tether_stiffness = 12.5;
  with_cores.core_wca_epsilon = 1;
  const auto c2 = mdpd::mdpd_stability(with_cores);
  EXPECT_NEAR(c2.max_dt(), 0.010385, 1e-6);
  EXPECT_GT(c2.max_dt(), 0.01);  // the paper's dt
  EXPECT_NE(f2.limiting_term("τ").find("dissipation D"), std::string::npos) << f2.limiting_term("τ");
}

struct MdpdRun {
  double max_temperature = 0, late_max_temperature = 0, mean_temperature = 0, max_momentum = 0;
  bool finite = true;
};

// A 2D fluid of the paper (ρ = 6, B = 30), L = 8 (384 particles), from random positions.
MdpdRun run_mdpd_2d(double dt, int steps) {
  mdpd::MdpdParameters par;
  par.B = 30;
  par.dt = dt;
  const double L = 8;
  mdpd::MdpdSystem<2, double, Exec> sys(par, Box<2, double>::cube(L, true), 77);
  sys.allocate(int(6 * L * L));
  const double lo[2] = {0, 0}, hi[2] = {L, L};
  fill_uniform_counter(sys.particles.x, lo, hi, 5, 0);
  sys.begin();
  MdpdRun r;
  int samples = 0;
  for (int s = 1; s <= steps; ++s) {
    sys.step();
    if (s % 10 == 0) {
      const double t = mdpd::kinetic_temperature(sys.particles);
      if (!std::isfinite(t) || t > 1e6) {
        r.finite = false;
        r.max_temperature = HUGE_VAL;
        break;
      }
      r.max_temperature = std::max(r.max_temperature, t);
      if (s > steps / 2) {  // after the release of the random start's overlaps
        r.late_max_temperature = std::max(r.late_max_temperature, t);
        r.mean_temperature += t;
        ++samples;
      }
      for (double p : momentum(sys.particles)) r.max_momentum = std::max(r.max_momentum, std::abs(p));
    }
  }
  if (r.finite) r.finite = all_finite(sys.particles.x) && all_finite(sys.particles.v);
  if (samples) r.mean_temperature /= samples;
  return r;
}

// Just below the estimate (0.95 × 0.01143) the fluid holds k_BT within 5% over the second half of
// 1000 steps from a random start (measured +2.3%, the start's overlaps still cooling) and conserves
// momentum;
// just beyond the edge (1.05 × 0.01345) and at 0.05 (the pillars driver's largest --dt) it blows up.
TEST(MdpdStability, BoundedJustBelowTheLimitAndBlowsUpWellAbove) {
  const double limit = mdpd::mdpd_stability(paper_fluid(2)).max_dt();
  const double edge = mdpd::mdpd_stability(paper_fluid(2)).edge();
  const auto below = run_mdpd_2d(0.95 * limit, 1000);
  const auto beyond = run_mdpd_2d(1.05 * edge, 1000);
  const auto above = run_mdpd_2d(0.05, 200);
  std::cout << "[ mdpd ] 2D at dt = " << 0.95 * limit << ": mean k_BT " << below.mean_temperature << " (max "
            << below.late_max_temperature << " over the second half), max |P| " << below.max_momentum << "; at dt = " << 1.05 * edge
            << ": max k_BT " << beyond.max_temperature << (beyond.finite ? "" : " (not finite)")
            << "; at dt = 0.05: max k_BT " << above.max_temperature << (above.finite ? "" : " (not finite)") << "\n";
  ASSERT_TRUE(below.finite);
  EXPECT_NEAR(below.mean_temperature, 1.0, 0.05);
  EXPECT_LT(below.max_momentum, 1e-9);
  EXPECT_TRUE(!beyond.finite || beyond.max_temperature > 10);
  EXPECT_TRUE(!above.finite || above.max_temperature > 10);
}

// ---------------------------------------------------------------------------------------------
// Lennard-Jones

TEST(LennardJonesStability, ContactAtNineTenthsOfSigmaInTheBenchLiquid) {
  const auto c = lennard_jones_contact(1, 1, 1.44);
  EXPECT_NEAR(c.distance, 0.900, 1e-3);
  EXPECT_NEAR(c.stiffness, 2334, 5);
  const auto e = lennard_jones_stability(1, 1, 1, 1.44, 0);
  EXPECT_NEAR(e.max_dt(), 0.01464, 1e-4);
  EXPECT_NE(e.limiting_term("τ").find("r = 0.900σ"), std::string::npos) << e.limiting_term("τ");
  EXPECT_LT(lennard_jones_stability(1, 1, 1, 5.0, 0).max_dt(), e.max_dt());  // hotter: closer contacts
  const double w = e.omega(), gamma = 500;  // a strong thermostat: the damped mode's edge
  EXPECT_NEAR(lennard_jones_stability(1, 1, 1, 1.44, gamma).max_dt(),
              0.5 * (std::sqrt(gamma * gamma + 4 * w * w) - gamma) / (w * w), 1e-12);
}

// Largest |E(t) − E(0)|/N of an NVE LJ liquid (3D, 343 particles at ρ = 0.8442, k_BT = 1.44 from a
// quenched simple cubic lattice) over `time` τ; infinity if it blew up.
double lj_energy_drift(double dt, double time) {
  const int side = 7, n = side * side * side;
  const double L = std::cbrt(n / 0.8442), a = L / side;
  const auto box = Box<3, double>::cube(L, true);
  const LennardJones<double> lj(1, 1, 2.5);
  Particles<3, double, Exec> p(n, "lj");
  NeighborList<3, double, Exec> list(2.5, 0.3);
  PairForce<3, double, Exec> pair;
  auto forces = [&] {
    list.update(p, box);
    p.zero_forces();
    return pair.accumulate(lj, p, list, box);
  };
  auto x = Kokkos::create_mirror_view(p.x);
  auto v = Kokkos::create_mirror_view(p.v);
  std::mt19937 gen(11);
  std::normal_distribution<double> g(0, std::sqrt(1.44));
  double mean[3] = {0, 0, 0};
  for (int i = 0; i < n; ++i) {
    const int c[3] = {i % side, (i / side) % side, i / (side * side)};
    for (int d = 0; d < 3; ++d) {
      x(i, d) = (c[d] + 0.5) * a;
      v(i, d) = g(gen);
      mean[d] += v(i, d) / n;
    }
  }
  for (int i = 0; i < n; ++i)
    for (int d = 0; d < 3; ++d) v(i, d) -= mean[d];
  Kokkos::deep_copy(p.x, x);
  Kokkos::deep_copy(p.v, v);
  VelocityVerlet<3, double, Exec> vv(dt);
  double potential = forces();
  const double e0 = potential + kinetic_energy(p);
  double worst = 0;
  const int steps = int(std::lround(time / dt));
  for (int s = 1; s <= steps; ++s) {
    vv.first_half(p);
    potential = forces();
    vv.second_half(p);
    if (s % 5 == 0) {
      const double e = potential + kinetic_energy(p);
      if (!std::isfinite(e)) return HUGE_VAL;
      worst = std::max(worst, std::abs(e - e0) / n);
    }
  }
  return worst;
}

// At 0.9 × the estimate the energy per particle wanders by less than 0.05ε over 3τ (the energy
// shift at the cutoff makes it jump a little at every crossing); at 0.04τ (2.7 × the estimate)
// the liquid heats up by more than 1ε per particle or blows up.
TEST(LennardJonesStability, NveBoundedBelowTheLimitAndRunsAwayWellAbove) {
  const double limit = lennard_jones_stability(1, 1, 1, 1.44, 0).max_dt();
  const double below = lj_energy_drift(0.9 * limit, 3), above = lj_energy_drift(0.04, 3);
  std::cout << "[ lj ] max |ΔE|/N over 3τ: " << below << " at dt = " << 0.9 * limit << ", " << above
            << " at dt = 0.04\n";
  EXPECT_LT(below, 0.05);
  EXPECT_GT(above, 1.0);
}

// ---------------------------------------------------------------------------------------------
// MPC discs

TEST(MpcDiscStability, PaperSceneMatchesTheDerivation) {
  const mpc::DiscStiffnessInputs paper;  // R = 5, n = 40, g = 0.1, ε = k_BT, r0 = Δx
  const auto e = mpc::disc_stability(paper);
  EXPECT_NEAR(mpc::disc_mass(paper), 3141.59, 0.01);
  EXPECT_NEAR(e.omega(), 2.909, 0.005);
  EXPECT_NEAR(e.max_dt(), 0.3437, 5e-4);
  EXPECT_GT(e.max_dt(), 0.005);  // the paper's h
  EXPECT_NE(e.limiting_term("τ").find("disc WCA"), std::string::npos) << e.limiting_term("τ");
  mpc::DiscStiffnessInputs solvent_only;
  solvent_only.discs = false;
  EXPECT_EQ(mpc::disc_stability(solvent_only).max_dt(), HUGE_VAL);
  mpc::DiscStiffnessInputs big_steps = paper;
  big_steps.wca_epsilon = 0;  // no contacts: the solvent crossing a disc binds (h ≤ R/4)
  EXPECT_NEAR(mpc::disc_stability(big_steps).max_dt(), 1.25, 1e-12);
}

// Two discs (R = 3, n = 8, periodic box, no friction, no body force) approach each other with a
// relative kinetic energy of 5 k_BT, at 0.9 × the estimate: positions stay finite, the discs never
// overlap (the WCA gap stays > 0.7 r0), the disc kinetic energy stays bounded, and solvent + discs
// conserve momentum.
TEST(MpcDiscStability, ApproachingDiscsStayBoundedJustBelowTheLimit) {
  mpc::ChannelFlowParameters<double> p;
  p.length = 30;
  p.width = 20;
  p.walls = false;
  p.density = 8;
  p.body_acceleration = 0;
  p.friction = 0;
  p.disc_radius = 3;
  p.seed = 5;
  mpc::DiscStiffnessInputs s;
  s.density = 8;
  s.disc_radius = 3;
  s.body_acceleration = 0;
  p.h = 0.9 * mpc::disc_stability(s).max_dt();
  mpc::ChannelFlow<double, Exec> flow(p, {{8.0, 10.0}, {15.2, 10.0}});
  const double M = mpc::disc_mass(s), u = std::sqrt(5.0 / M);  // ½ (M/2) (2u)² = M u² = 5 k_BT
  {
    auto U = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), flow.discs().u);
    U(0, 0) = u;
    U(1, 0) = -u;
    Kokkos::deep_copy(flow.discs().u, U);
  }
  const auto p0 = flow.total_momentum();
  double min_gap = HUGE_VAL, max_ke = 0, drift = 0;
  for (int step = 0; step < 200; ++step) {
    flow.step();
    const auto X = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), flow.discs().x);
    const auto U = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), flow.discs().u);
    double dx = X(1, 0) - X(0, 0);
    dx -= p.length * std::round(dx / p.length);
    min_gap = std::min(min_gap, std::hypot(dx, X(1, 1) - X(0, 1)) - 2 * p.disc_radius);
    double ke = 0;
    for (int k = 0; k < 2; ++k) ke += 0.5 * M * (U(k, 0) * U(k, 0) + U(k, 1) * U(k, 1));
    max_ke = std::max(max_ke, ke);
    const auto P = flow.total_momentum();
    drift = std::max({drift, std::abs(P[0] - p0[0]), std::abs(P[1] - p0[1])});
  }
  std::cout << "[ mpc ] h = " << p.h << ": min WCA gap " << min_gap << " r0, max disc E_k " << max_ke
            << " k_BT (start " << M * u * u << "), max |ΔP| " << drift << "\n";
  ASSERT_TRUE(all_finite(flow.positions()));
  EXPECT_LT(min_gap, std::pow(2.0, 1.0 / 6.0));  // they met
  EXPECT_GT(min_gap, 0.7);
  EXPECT_LT(max_ke, 20.0);  // 5 k_BT at the start, k_BT per degree of freedom in equilibrium
  EXPECT_LT(drift, 1e-9);
}

// ---------------------------------------------------------------------------------------------
// Named terms of the SP hopper (the message of HopperCli.TimeStepAboveStabilityLimit)

TEST(HopperStability, NamesThePairWallFrictionOrDragTerm) {
  hopper::HopperParameters par;
  par.pair_energy = 1e4;
  par.wall_energy = 1e2;
  EXPECT_NE(par.stability_limit(2).term.find("pair repulsion E_sp"), std::string::npos);
  par.pair_energy = 10;
  par.wall_energy = 1e4;
  EXPECT_NE(par.stability_limit(2).term.find("wall repulsion E_w"), std::string::npos);
  par.friction = 1e3;
  EXPECT_NE(par.stability_limit(2).term.find("friction μ"), std::string::npos);
  par.friction = 0;
  par.drag = 1e4;
  EXPECT_NE(par.stability_limit(2).term.find("drag ζ"), std::string::npos);
  EXPECT_DOUBLE_EQ(par.stability_limit(2).max_dt, 2e-4);
}

// ---------------------------------------------------------------------------------------------
// DP droplets: the limit of the current shape (kernels/dp/shape_stiffness.hpp) and the scene's
// check of it (DropletScene::check_shape_time_step).

// Shoelace area of the polygon `xs` (host).
double polygon_area(const std::vector<std::array<double, 2>>& xs) {
  double a = 0;
  for (std::size_t i = 0; i < xs.size(); ++i) {
    const auto& p = xs[i];
    const auto& q = xs[(i + 1) % xs.size()];
    a += p[0] * q[1] - q[0] * p[1];
  }
  return 0.5 * a;
}

// Two bodies (N_v = 12 and 40), each a circle of radius 0.5 with vertices at random angles and
// radii: Σ_i |∇_i a|² of each body by central differences of the shoelace area (step 10⁻⁶), the
// largest over the bodies, against measure_area_gradient_squared.
TEST(DpShapeStability, MeasuredStiffnessMatchesFiniteDifferencesOfTheArea) {
  const std::vector<int> counts{12, 40};
  auto polygons = dp::Polygons<double, Exec>::from_vertex_counts(counts, {0.785, 0.785}, {0.26, 0.08});
  Particles<2, double, Exec> p(52);
  auto x = Kokkos::create_mirror_view(p.x);
  std::mt19937 gen(5);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  std::vector<std::vector<std::array<double, 2>>> bodies;
  int row = 0;
  for (const int n : counts) {
    std::vector<std::array<double, 2>> xs;
    for (int k = 0; k < n; ++k) {
      const double angle = 2 * dp::pi * (k + jitter(gen)) / n, radius = 0.5 * (1 + jitter(gen));
      xs.push_back({radius * std::cos(angle) + 3.0 * row, radius * std::sin(angle)});
      x(row == 0 ? k : counts[0] + k, 0) = xs.back()[0];
      x(row == 0 ? k : counts[0] + k, 1) = xs.back()[1];
    }
    bodies.push_back(xs);
    ++row;
  }
  Kokkos::deep_copy(p.x, x);
  double largest = 0;
  for (auto xs : bodies) {
    double sum = 0;
    for (std::size_t i = 0; i < xs.size(); ++i) {
      for (int d = 0; d < 2; ++d) {
        const double h = 1e-6, keep = xs[i][d];
        xs[i][d] = keep + h;
        const double up = polygon_area(xs);
        xs[i][d] = keep - h;
        const double down = polygon_area(xs);
        xs[i][d] = keep;
        sum += std::pow((up - down) / (2 * h), 2);
      }
    }
    largest = std::max(largest, sum);
  }
  EXPECT_NEAR(dp::measure_area_gradient_squared(polygons, p), largest, 1e-6 * largest);
}

// The shape's limit equals the static one for the regular polygon and shrinks as derived when the
// measured Σ|∇a|² exceeds P l0 (ω_area ∝ √Σ|∇a|²); it never exceeds the static limit.
TEST(DpShapeStability, LimitForShapeFollowsTheAreaGradient) {
  dp::StiffnessInputs s{};
  s.vertex_mass = 0.785 / 64;
  s.edge_length = 0.049;
  s.perimeter = 64 * s.edge_length;
  s.vertices = 64;
  s.line_tension = 0.16;
  s.area_stiffness = 1e6;
  s.wall_energy = 0.05;
  s.vertex_diameter = s.edge_length;
  const auto fixed = dp::stability_limit(s);
  const double p_l0 = s.perimeter * s.edge_length;
  const auto regular = dp::stability_limit_for_shape(s, 0.998 * p_l0);
  EXPECT_DOUBLE_EQ(regular.max_dt(), fixed.max_dt());
  const auto stretched = dp::stability_limit_for_shape(s, 4 * p_l0);
  EXPECT_NEAR(stretched.omega_area, 2 * fixed.omega_area, 1e-9 * fixed.omega_area);
  EXPECT_LT(stretched.max_dt(), 0.51 * fixed.max_dt());
  EXPECT_NE(stretched.limiting_term().find("area elasticity K_a"), std::string::npos);
}

// The K_a = 10⁶ corner of tests/stability/test_extremes.cpp (N_v = 64, Γ = 0.16, K_l/Γ = 10⁻³, no
// drag, resting on a wall at the static limit's Δt): its vertices slide down the interface and
// Σ|∇a|² grows, 2.3 P l0 after 1.5 t0, 3.9 P l0 at 2.4 t0 where the run blows up. The scene stops it
// at the first check where Δt exceeds 1.8 × the shape's limit, naming the area term, while the
// energy is still conserved; forced on (--force-dt), the same run loses energy conservation —
// the check stops a run that would have gone wrong.
double stiff_area_droplet_drift(bool force, std::string& stopped) {
  droplets::DropletParameters par;
  par.vertices = 64;
  par.line_tension = 0.16;
  par.perimeter_stiffness = 1.6e-4;
  par.area_stiffness = 1e6;
  par.drag = false;
  par.force_dt = force;
  const double l0 = dp::regular_polygon_edge(droplets::droplet_area, par.vertices);
  droplets::DropletScene<double, Exec> scene(par, droplets::deformation_detail::flat_wall(),
                                             {Vec<2, double>{{0.0, 0.5 + 0.5 * l0 + 0.02}}});
  const double e0 = scene.total_energy();
  double drift = 0;
  const long long steps = std::lround(3.0 / scene.dt());
  try {
    for (long long s = 1; s <= steps; ++s) {
      scene.step();
      if (s % 50 == 0) drift = std::max(drift, std::abs(scene.total_energy() - e0) / droplets::droplet_mass);
    }
  } catch (const droplets::ShapeTimeStepExceeded& e) {
    stopped = e.what();
    drift = std::max(drift, std::abs(scene.total_energy() - e0) / droplets::droplet_mass);
  }
  return drift;
}

TEST(DropletShapeCheck, StopsAFlatteningStiffDropletBeforeItsAreaModeTurnsUnstable) {
  std::string stopped;
  const double drift = stiff_area_droplet_drift(false, stopped);
  std::cout << "[ stopped ] max |ΔE|/Mgσ = " << drift << ": " << stopped << "\n";
  ASSERT_FALSE(stopped.empty());
  EXPECT_NE(stopped.find("area elasticity K_a"), std::string::npos) << stopped;
  EXPECT_NE(stopped.find("--force-dt"), std::string::npos) << stopped;
  EXPECT_LT(drift, 1e-5);
  std::string forced_stop;
  const double forced = stiff_area_droplet_drift(true, forced_stop);
  std::cout << "[ forced ] max |ΔE|/Mgσ = " << forced << "\n";
  EXPECT_TRUE(forced_stop.empty());
  EXPECT_GT(forced, 1.0);
}

}  // namespace
}  // namespace mesoflow
