// Fast physical validation of the DP droplet scene (capillary-droplets §2): terminal speed,
// energy conservation and its order in Δt, stability at the extremes of Γ, area conservation.
#include "scenes/droplets/droplet_scene.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <vector>

namespace mesoflow::droplets {
namespace {

using Exec = Kokkos::DefaultExecutionSpace;

DropletParameters free_droplet(int vertices, double gamma) {
  DropletParameters par;
  par.vertices = vertices;
  par.line_tension = gamma;
  par.perimeter_stiffness = 5e-4 * gamma;  // K_l/Γ < 10⁻³ (App. B)
  return par;
}

Surfaces<double, Exec> no_surfaces() { return Surfaces<double, Exec>(std::vector<Shape<2, double>>{}); }

bool all_finite(const DropletScene<double, Exec>& scene) {
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), scene.particles().x);
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), scene.particles().v);
  for (std::size_t i = 0; i < x.extent(0); ++i)
    for (int d = 0; d < 2; ++d)
      if (!std::isfinite(x(i, d)) || !std::isfinite(v(i, d))) return false;
  return true;
}

// Far from walls the drag on the droplet is Σ_i (b∞/N_v) v_i = b∞ v_com, so it falls at
// v_t = Mg/b∞ = V_t (eq. 15). Relaxation time M/b∞ = V_t t0: 3 t0 is ~40 relaxation times.
TEST(DropletScene, FreeDropletFallsAtTheTerminalSpeed) {
  for (double vt : {0.08, 0.032}) {
    DropletParameters par = free_droplet(64, 0.16);
    par.terminal_speed = vt;
    DropletScene<double, Exec> scene(par, no_surfaces(), {Vec<2, double>{{0.0, 0.0}}});
    EXPECT_NEAR(scene.far_drag(), droplet_mass / vt, 1e-12);
    for (int s = 0; s < 3000; ++s) scene.step();
    const auto o = scene.observables();
    EXPECT_NEAR(o.com_velocity[0][0], 0.0, 1e-9);
    EXPECT_NEAR(-o.com_velocity[0][1] / vt, 1.0, 0.01) << "V_t = " << vt;
    std::cout << "[ measured ] V_t = " << vt << ": v_com / v_t = " << -o.com_velocity[0][1] / vt << "\n";
  }
}

// Without drag the dynamics is Hamiltonian: velocity Verlet keeps the energy error bounded and
// second order in Δt. A stretched droplet oscillates while it falls.
double max_energy_error(double dt) {
  DropletParameters par = free_droplet(32, 0.16);
  par.drag = false;
  par.dt = dt;
  DropletScene<double, Exec> scene(par, no_surfaces(), {Vec<2, double>{{0.0, 0.0}}});
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), scene.particles().x);
  for (std::size_t i = 0; i < x.extent(0); ++i) {  // stretched at constant area: the shape oscillates
    x(i, 0) *= 1.1;
    x(i, 1) /= 1.1;
  }
  Kokkos::deep_copy(scene.particles().x, x);
  const double e0 = scene.total_energy();
  double worst = 0;
  const int steps = int(std::lround(0.5 / dt));
  for (int s = 0; s < steps; ++s) {
    scene.step();
    if (s % 10 == 9) worst = std::max(worst, std::abs(scene.total_energy() - e0));
  }
  return worst;
}

TEST(DropletScene, EnergyIsConservedWithoutDragAtSecondOrder) {
  const double coarse = max_energy_error(2e-4), fine = max_energy_error(1e-4);
  EXPECT_LT(coarse, 1e-3);
  const double order = std::log2(coarse / fine);
  std::cout << "[ measured ] max |ΔE| over 0.5 t0: " << coarse << " (Δt = 2e-4), " << fine << " (Δt = 1e-4), order "
            << order << "\n";
  EXPECT_NEAR(order, 2.0, 0.3) << "errors " << coarse << " and " << fine;
}

// Equilibrium area of a regular N-gon droplet: line tension squeezes it (Laplace pressure) until
// dU/da = k_a (a − a0) + γ dP/da + k_l N (P/N − l0) dP/da = 0, with P(a) = 2√(N tan(π/N) a).
double laplace_compressed_area(const DropletParameters& par, double l0) {
  const double n = par.vertices, c = n * std::tan(dp::pi / n);
  double a = droplet_area;
  for (int it = 0; it < 50; ++it) {  // Newton on dU/da
    const double P = 2 * std::sqrt(c * a), dP = std::sqrt(c / a), d2P = -0.5 * std::sqrt(c / (a * a * a));
    const double g = par.area_stiffness * (a - droplet_area) + par.line_tension * dP +
                     par.perimeter_stiffness * n * (P / n - l0) * dP;
    const double h = par.area_stiffness + par.line_tension * d2P +
                     par.perimeter_stiffness * (dP * dP + n * (P / n - l0) * d2P);
    a -= g / h;
  }
  return a;
}

// Γ at both ends of the paper's range (10⁻² … 10) integrates without NaN, and the droplet keeps
// the area at which line tension and area elasticity balance (for Γ = 10, K_a = 10⁴ line tension
// compresses it by 2.5·10⁻³; for Γ = 0.01 by 3·10⁻⁶).
TEST(DropletScene, ExtremeLineTensionsStayFiniteAndKeepTheirEquilibriumArea) {
  for (double gamma : {0.01, 10.0}) {
    const DropletParameters par = free_droplet(256, gamma);
    DropletScene<double, Exec> scene(par, no_surfaces(), {Vec<2, double>{{0.0, 0.0}}});
    const int steps = int(std::lround(2.0 / scene.dt()));  // 2 t0 at the automatic Δt
    for (int s = 0; s < steps; ++s) scene.step();
    EXPECT_TRUE(all_finite(scene)) << "Γ = " << gamma;
    const auto o = scene.observables();
    const double expected = laplace_compressed_area(par, scene.edge_length());
    std::cout << "[ measured ] Γ = " << gamma << ": a/a0 = " << o.area[0] / droplet_area << ", equilibrium "
              << expected / droplet_area << "\n";
    EXPECT_NEAR(o.area[0] / expected, 1.0, 1e-4) << "Γ = " << gamma << ", a/a0 = " << o.area[0] / droplet_area;
    EXPECT_NEAR(o.shape_parameter[0], (256 / dp::pi) * std::tan(dp::pi / 256), 1e-3) << "Γ = " << gamma;
  }
}

// Replicas in one scene evolve exactly as the same droplet alone would.
TEST(DropletScene, ReplicasEvolveIndependently) {
  const DropletParameters par = free_droplet(48, 0.5);
  DropletScene<double, Exec> alone(par, no_surfaces(), {Vec<2, double>{{3.0, 1.0}}});
  DropletScene<double, Exec> batch(par, no_surfaces(),
                                   {Vec<2, double>{{0.0, 0.0}}, Vec<2, double>{{3.0, 1.0}}, Vec<2, double>{{-5.0, 2.0}}});
  for (int s = 0; s < 500; ++s) {
    alone.step();
    batch.step();
  }
  const auto a = alone.observables(), b = batch.observables();
  EXPECT_EQ(a.com[0][0], b.com[1][0]);
  EXPECT_EQ(a.com[0][1], b.com[1][1]);
  EXPECT_EQ(a.area[0], b.area[1]);
}

TEST(DropletScene, RejectsBadParametersNamingThem) {
  auto message = [](DropletParameters par) {
    try {
      DropletScene<double, Exec> scene(par, no_surfaces(), {Vec<2, double>{{0.0, 0.0}}});
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  DropletParameters par = free_droplet(32, 0.16);
  par.terminal_speed = 0;
  EXPECT_NE(message(par).find("terminal speed"), std::string::npos) << message(par);
  par = free_droplet(32, 0.16);
  par.dt = -1;
  EXPECT_NE(message(par).find("dt"), std::string::npos) << message(par);
  par = free_droplet(32, 0.16);
  par.line_tension = NAN;
  EXPECT_NE(message(par), "no error");
}

}  // namespace
}  // namespace mesoflow::droplets
