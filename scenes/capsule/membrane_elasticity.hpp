// membrane_elasticity.hpp — the in-plane elastic moduli of the capsule's two-layer spring network,
// measured rather than quoted (issue 29 item 1). The capsule paper (§4) writes G_s = E h_t/(2(1 + ν))
// with E = 5 k_b/(√3 δ_ave) and ν = 1/4; that formula is exact for one network only (both diagonals
// per quad at h_t = δ_ave, tests/msm/test_msm_membrane.cpp), and G_s ∝ h_t in it, while a spring
// network's stretching moduli do not scale with the thickness. So the moduli are measured here on a
// flat periodic patch of the same network (same diagonals, same h_t/δ): the box strained in-plane,
// the particles relaxed by FIRE, the moduli from the energy per unit area W(ε):
//   area (2D bulk) modulus K_A:  ε_xx = ε_yy = ±ε,   W = 2 K_A ε²
//   shear modulus G_s:           ε_xx = −ε_yy = ±ε,  W = 2 G_s ε²
//   Young's modulus E_2D, ν:     ε_xx = ±ε, ε_yy relaxed (σ_yy = 0): W = ½ E_2D ε², ν = −ε_yy/ε_xx
// (averages of +ε and −ε cancel the odd orders). For an isotropic sheet E_2D = 4 K_A G_s/(K_A + G_s)
// and ν = (K_A − G_s)/(K_A + G_s); the paper's one-diagonal network is slightly anisotropic (the
// diagonals all lean one way per lattice direction), so these are its moduli along the lattice axes.
// Host-side setup: the patch is small (6 × 6 sites, 72 particles) and runs on the host.
#pragma once

#include "kernels/common/box.hpp"
#include "kernels/common/fire.hpp"
#include "kernels/common/particles.hpp"
#include "kernels/msm/capsule_mesh.hpp"
#include "kernels/msm/harmonic_bonds.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace mesoflow::capsule {

// Moduli of the network per unit k_b (2D moduli: force per length, k_b being a force per length too).
struct MembraneModuli {
  double area = 0;     // K_A / k_b
  double shear = 0;    // G_s / k_b
  double young = 0;    // E_2D / k_b (uniaxial stress along x, σ_yy = 0)
  double poisson = 0;  // ν = −ε_yy/ε_xx under that stress
};

// The moduli of the two-layer network with layer gap h_t = thickness_over_spacing · δ.
inline MembraneModuli measure_membrane_moduli(double thickness_over_spacing, msm::DiagonalBonds diagonals,
                                              double strain = 0.01) {
  if (!(thickness_over_spacing > 0 && thickness_over_spacing < 100))
    throw std::invalid_argument("measure_membrane_moduli: h_t/δ must be in (0, 100), got " +
                                std::to_string(thickness_over_spacing));
  if (!(strain > 0 && strain <= 0.05))
    throw std::invalid_argument("measure_membrane_moduli: strain must be in (0, 0.05], got " + std::to_string(strain));
  using Exec = Kokkos::DefaultHostExecutionSpace;
  msm::FlatMembraneParameters fp;
  fp.nx = 6;
  fp.ny = 6;
  fp.spacing = 1;
  fp.thickness = thickness_over_spacing;
  fp.bonds.k_b = 1;
  fp.bonds.diagonals = diagonals;
  const auto mesh = msm::flat_membrane(fp);
  const msm::HarmonicBonds<3, double, Exec> bonds(msm::upload_bonds<double, Exec>(mesh));
  Particles<3, double, Exec> p(std::size_t(mesh.num_particles()), "membrane_patch");
  const double area0 = mesh.period[0] * mesh.period[1];

  // U/A₀ with the box strained by (ε_xx, ε_yy), the particles relaxed from the affine positions.
  auto energy_density = [&](double exx, double eyy) {
    const double lo[3] = {0, 0, -10 - 2 * thickness_over_spacing};
    const double length[3] = {mesh.period[0] * (1 + exx), mesh.period[1] * (1 + eyy),
                              20 + 4 * thickness_over_spacing};
    const bool periodic[3] = {true, true, false};
    const Box<3, double> box(lo, length, periodic);
    for (int i = 0; i < mesh.num_particles(); ++i) {
      const auto& r = mesh.position[std::size_t(i)];
      p.x(i, 0) = (1 + exx) * r[0];
      p.x(i, 1) = (1 + eyy) * r[1];
      p.x(i, 2) = r[2];
    }
    FireParameters fire;
    fire.dt_start = 0.01;
    fire.dt_max = 0.2;
    fire.force_tolerance = 1e-12;
    auto forces = [&] {
      p.zero_forces();
      bonds.accumulate(p, box);
      return bonds.energy(p, box);
    };
    const auto result = fire_minimize(p, forces, fire);
    if (!result.converged)
      throw std::runtime_error("measure_membrane_moduli: FIRE did not relax the patch at strain (" +
                               std::to_string(exx) + ", " + std::to_string(eyy) + "): max |F| " +
                               std::to_string(result.max_force));
    return result.energy / area0;
  };
  // ε_yy at σ_yy = 0 for a given ε_xx: the minimum of the parabola through three relaxed energies.
  auto uniaxial = [&](double exx, double& eyy_out) {
    const double step = -0.25 * exx;
    const double w0 = energy_density(exx, 0), w1 = energy_density(exx, step), w2 = energy_density(exx, 2 * step);
    const double c = (w0 - 2 * w1 + w2) / (2 * step * step), b = (w1 - w0) / step - c * step;
    eyy_out = -b / (2 * c);
    const double w = energy_density(exx, eyy_out);
    if (!(w <= std::min({w0, w1, w2}) * (1 + 1e-9)))
      throw std::runtime_error("measure_membrane_moduli: the transverse strain at ε_xx = " + std::to_string(exx) +
                               " is not at the energy's minimum");
    return w;
  };

  const double e = strain, e2 = strain * strain;
  MembraneModuli m;
  m.area = (energy_density(e, e) + energy_density(-e, -e)) / (4 * e2);
  m.shear = (energy_density(e, -e) + energy_density(-e, e)) / (4 * e2);
  double eyy_plus = 0, eyy_minus = 0;
  const double w_plus = uniaxial(e, eyy_plus), w_minus = uniaxial(-e, eyy_minus);
  m.young = (w_plus + w_minus) / e2;
  m.poisson = -(eyy_plus - eyy_minus) / (2 * e);
  return m;
}

}  // namespace mesoflow::capsule
