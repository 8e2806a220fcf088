// Energy balance of a whole SP hopper run (hopper-flows paper eqs. 2–6; issue 27, item 2):
//   W_g = ΔE_k + ΔU + D,
// the work of gravity equals the change of kinetic energy, the change of elastic energy (pair and
// wall contacts, eqs. 2–3) and the energy dissipated by kinetic friction (eq. 6) and drag (eq. 5).
//
// The accounting is the test's own and reads nothing but the particle state the scene exposes
// (positions, velocities, masses, types, ids): W_g = Σ M_m g (h_m(0) − h_m(T)); E_k = Σ ½ M_m |v_m|²;
// D from its own brute-force evaluation of eqs. 5 and 6 at the states the integrator used. Only U
// comes from the scene (conservative_forces, whose potentials have their own finite-difference
// gradient tests in tests/sp/).
//
// Which states: velocity Verlet with velocity-dependent forces at the half-step velocity
// (kernels/common/velocity_verlet.hpp, λ = ½) evaluates F_d at (x_{n+1}, v_{n+1/2}), with
// v_{n+1/2} = (x_{n+1} − x_n)/Δt exactly. Its kicks give, exactly,
//   E_k(n+1) − E_k(n) = ½(F_n + F_{n+1})·(x_{n+1} − x_n) + (Δt²/8) Σ_m (|F_{n+1}|² − |F_n|²)/M_m,
// whose last term telescopes to (Δt²/8) Σ (|F_N|² − |F_0|²)/M — below 10⁻⁹ of W_g here, left out. So
// the dissipated energy of the discrete run is D = −Σ_n ½(F_d,n + F_d,n+1)·(x_{n+1} − x_n), and the
// balance misses only the trapezoidal rule's error on the elastic work, O((ωΔt)²): the test checks
// that the residual falls as Δt² between two time steps and is below 10⁻⁶ of W_g at the smaller.
//
// The scene: 40 particles in a flat-bottomed box (θ_w = 90°, W = 8σ_avg) whose orifice (0.5σ_avg)
// is narrower than a small particle, so nothing leaves and nothing is re-inserted; they fall from
// the random initial packing, collide, rub and settle for T = 6 t0 with E_sp = E_w = 100, μ/μ0 = 1
// (eq. 6 as printed) and ζ/ζ0 = 0.1.
#include "scenes/hopper/hopper_scene.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <vector>

namespace mesoflow::hopper {
namespace {

using Exec = Kokkos::DefaultExecutionSpace;
using Scene2 = HopperScene<2, double, Exec>;

struct Balance {
  double gravity_work = 0, kinetic = 0, elastic = 0, dissipated = 0;
  double residual() const { return std::abs(gravity_work - kinetic - elastic - dissipated) / gravity_work; }
};

// The particle state by id (a cell sort permutes the arrays).
struct State {
  std::vector<double> x, y, vx, vy, m;
  std::vector<int> type;
};

State read_state(const Scene2& s) {
  const auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.particles().x);
  const auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.particles().v);
  const auto m = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.particles().mass);
  const auto t = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.particles().type);
  const auto id = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.ids());
  const std::size_t n = x.extent(0);
  State st{std::vector<double>(n), std::vector<double>(n), std::vector<double>(n), std::vector<double>(n),
           std::vector<double>(n), std::vector<int>(n)};
  for (std::size_t i = 0; i < n; ++i) {
    const auto k = std::size_t(id(i));
    st.x[k] = x(i, 0);
    st.y[k] = x(i, 1);
    st.vx[k] = v(i, 0);
    st.vy[k] = v(i, 1);
    st.m[k] = m(i);
    st.type[k] = t(i);
  }
  return st;
}

// Eqs. 5 and 6 (full relative velocity), brute force over all pairs: F_d at positions `at` and
// velocities (ux, uy).
void dissipative_forces(const HopperParameters& par, const State& at, const std::vector<double>& ux,
                        const std::vector<double>& uy, std::vector<double>& fx, std::vector<double>& fy) {
  const std::size_t n = at.x.size();
  for (std::size_t i = 0; i < n; ++i) {
    fx[i] = -par.drag * at.m[i] * ux[i];
    fy[i] = -par.drag * at.m[i] * uy[i];
  }
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      const double sij = 0.5 * (particle_diameter(at.type[i]) + particle_diameter(at.type[j]));
      const double dx = at.x[i] - at.x[j], dy = at.y[i] - at.y[j];
      if (!(dx * dx + dy * dy < sij * sij)) continue;
      const double gx = -par.friction * (ux[i] - ux[j]), gy = -par.friction * (uy[i] - uy[j]);
      fx[i] += gx;
      fy[i] += gy;
      fx[j] -= gx;
      fy[j] -= gy;
    }
}

double kinetic_energy(const State& s) {
  double e = 0;
  for (std::size_t i = 0; i < s.x.size(); ++i) e += 0.5 * s.m[i] * (s.vx[i] * s.vx[i] + s.vy[i] * s.vy[i]);
  return e;
}

HopperParameters closed_box(double dt) {
  HopperParameters par;
  par.particles = 40;
  par.hopper_width = 8;
  par.orifice = 0.5;  // narrower than a small particle (σ_s = 0.83σ_avg): closed
  par.wall_angle = 90;
  par.pair_energy = 100;
  par.wall_energy = 100;
  par.friction = 1;
  par.drag = 0.1;
  par.dt = dt;
  par.seed = 11;
  return par;
}

Balance run_balance(double dt, double duration, int* contacts_seen = nullptr) {
  const HopperParameters par = closed_box(dt);
  Scene2 scene(par);
  scene.relax();
  Balance b;
  const double u0 = scene.conservative_forces(false);  // the relaxed state's forces, as relax left them
  State prev = read_state(scene);
  const State first = prev;
  const std::size_t n = prev.x.size();
  std::vector<double> ux(n, 0), uy(n, 0), fx_prev(n, 0), fy_prev(n, 0), fx(n), fy(n);  // F_d,0 = 0 (at rest)
  const long long steps = std::llround(duration / dt);
  int contacts = 0;
  for (long long k = 0; k < steps; ++k) {
    scene.step();
    const State now = read_state(scene);
    for (std::size_t i = 0; i < n; ++i) {
      ux[i] = (now.x[i] - prev.x[i]) / dt;  // v_{n+1/2}, the velocity the step's F_d used
      uy[i] = (now.y[i] - prev.y[i]) / dt;
    }
    dissipative_forces(par, now, ux, uy, fx, fy);
    double work = 0;
    for (std::size_t i = 0; i < n; ++i)
      work += 0.5 * ((fx_prev[i] + fx[i]) * (now.x[i] - prev.x[i]) + (fy_prev[i] + fy[i]) * (now.y[i] - prev.y[i]));
    b.dissipated -= work;
    if (k % 1000 == 0)
      for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j) {
          const double sij = 0.5 * (particle_diameter(now.type[i]) + particle_diameter(now.type[j]));
          contacts += std::hypot(now.x[i] - now.x[j], now.y[i] - now.y[j]) < sij;
        }
    fx_prev.swap(fx);
    fy_prev.swap(fy);
    prev = now;
  }
  EXPECT_EQ(scene.insertions(), 0);
  for (std::size_t i = 0; i < n; ++i) b.gravity_work += first.m[i] * (first.y[i] - prev.y[i]);  // g = 1
  b.kinetic = kinetic_energy(prev) - kinetic_energy(first);
  b.elastic = scene.conservative_forces(false) - u0;
  if (contacts_seen != nullptr) *contacts_seen = contacts;
  return b;
}

TEST(HopperEnergyBalance, GravityWorkIsKineticElasticAndDissipatedEnergy) {
  const double duration = 6.0;
  int contacts = 0;
  const Balance coarse = run_balance(4e-4, duration);
  const Balance fine = run_balance(1e-4, duration, &contacts);
  for (const auto& [dt, b] : {std::pair{4e-4, coarse}, std::pair{1e-4, fine}})
    std::cout << "dt = " << dt << ": W_g = " << b.gravity_work << ", ΔE_k = " << b.kinetic
              << ", ΔU = " << b.elastic << ", D = " << b.dissipated << ", residual/W_g = " << b.residual() << "\n";
  std::cout << "contacts sampled every 1000 steps at dt = 1e-4: " << contacts << "\n";
  // The run does what the balance needs: particles fall, touch, and lose energy to both terms.
  EXPECT_GT(fine.gravity_work, 10.0);
  EXPECT_GT(contacts, 100);
  EXPECT_GT(fine.dissipated, 0.1 * fine.gravity_work);
  EXPECT_LT(fine.kinetic, 0.5 * fine.gravity_work);
  // Second order in Δt: a quarter of the step leaves at most a tenth of the residual (1/16 ideal).
  EXPECT_LT(fine.residual(), 0.1 * coarse.residual());
  EXPECT_LT(fine.residual(), 1e-6);
}

}  // namespace
}  // namespace mesoflow::hopper
