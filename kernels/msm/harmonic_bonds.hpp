// harmonic_bonds.hpp — the Hookean bonds of the mass-spring model (MSM), paper §2.3, eq. (7):
//
//   F_i = k_b (r_ij − r_0) r̂_ij,   r̂_ij = (x_j − x_i)/r_ij (minimum image),   U = ½ k_b (r_ij − r_0)²
//
// summed over a fixed bond list, each bond with its own k_b and r_0 (the membrane's in-layer,
// partner and diagonal bonds differ in both: capsule_mesh.hpp). A stretched bond (r > r_0) pulls
// its two particles together.
//
// Layout: the bonds (ends, k, r0) and, built from them once on the host, a CSR incidence list with
// one row per bonded particle: row r belongs to particle row_particle(r) and lists its bonds in
// increasing bond order, with the particle at the other end. Each row sums its own particle's
// force (the full-list style of pair_force.hpp): no atomics, and the same bits on every backend
// and thread count. Every bond is evaluated twice, once from each end; at 10–13 bonds a particle
// that is cheaper than a scatter. Sums accumulate in double whatever Real is. The energy is one
// parallel_reduce over the bonds (reproducible at a fixed thread count).
//
// Coupling to SPH (paper §2.4): membrane particles are at the same time MSM and SPH particles
// ("ghost" SPH particles). They live in the SPH scene's Particles (kernels/sph/particle_types.hpp:
// particle_type::membrane — moving, with mass, density, pressure and viscosity like fluid
// particles, so the fluid sees no-penetration through the pressure term of eq. 5 and no-slip
// through its viscous term), and the bond forces simply add to the same Particles::f:
//   f_i = (SPH pressure + viscous + body force of eq. 5)_i + Σ_bonds F_i (eq. 7).
// The SPH pair loop assigns f (sph_pair_interactions.hpp), so accumulate() must run after it and
// before the second half kick of eq. (15) — SphSystem::step(extra) calls it there. Bonds index
// particles: with SphOptions::sort_every > 0 the SPH system reorders particles in memory, and
// renumber() maps the bond ends (and the CSR rows) through that sort's new indices
// (SphSystem::last_sort_new_index()). Each row keeps its bonds in the same order, so the force on
// every particle is bitwise the one it had before the sort. Inner and outer fluid: the SPH system stores
// the dynamic viscosity per particle (SphSystem::mu, packed per row into eq. 5 as μ_i + μ_j) and
// the mass per particle, so the two fluids can differ in μ and m by setting those views per type;
// the reference density ρ0 and c0 belong to the one TaitEquationOfState of a SphSystem (eq. 6),
// i.e. are shared (the paper's inner and outer fluids have the same ρ and μ unless stated).
//
// Time step (the SPH limits of sph_time_step.hpp know nothing of bonds): velocity Verlet is stable
// for ω_max Δt < 2. For the linearised network, Gershgorin's bound on M^{-1/2} K M^{-1/2} (K the
// stiffness matrix, a block k n̂n̂ᵀ per bond) gives ω_max² ≤ max_i Σ_{bonds b of i} k_b (1/m_i +
// 1/√(m_i m_j)), which for equal masses is 2 K_i/m_i with K_i = Σ_{b ∋ i} k_b. time_step_limit()
// returns C_b min_i √(m_i/K_i); the stability edge is then C_b = √2 (equal masses), and the default
// C_b = 0.5 keeps ω_max Δt ≤ 0.71, at least ~9 steps per period of the fastest mode. The bound
// is conservative: a stiff capsule in SPH fluid (tests/sph/test_capsule_scene.cpp) stays bounded
// up to C_b = 2.0 and blows up from 2.4, so the default keeps a factor ~4. For the
// paper's capsule (one diagonal per quad, k_d = 2/3 k_b) K_i = 7 k_b + n_d 2/3 k_b: ≤ 6 in-layer
// bonds, the partner and 0–6 diagonals, so K_i ≤ 11 k_b and Δt_bond ≥ 0.15 √(m/k_b) at C_b = 0.5.
#pragma once

#include "../common/kernel_launch.hpp"
#include "kernels/common/box.hpp"
#include "kernels/common/kokkos_compat.hpp"
#include "kernels/common/particle_sort.hpp"
#include "kernels/common/particles.hpp"
#include "kernels/common/vec.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace mesoflow::msm {

// Eq. (7) for one bond: the force on i along (x_j − x_i), divided by r, and the bond energy.
template <class Real>
struct HarmonicBondLaw {
  // k (r − r0)/r: F_i = force_over_r · (x_j − x_i). Zero for coincident ends (no direction).
  KOKKOS_INLINE_FUNCTION static Real force_over_r(Real r, Real k, Real r0) {
    return r > Real(0) ? k * (r - r0) / r : Real(0);
  }
  KOKKOS_INLINE_FUNCTION static double energy(double r, double k, double r0) {
    return 0.5 * k * (r - r0) * (r - r0);
  }
};

// A bond list in Views: bond b joins ends(b, 0) and ends(b, 1) with stiffness k(b) and rest
// length r0(b); the CSR rows (one per particle that has bonds) list, for row r, the bonds of
// particle row_particle(r) in entries offset(r) .. offset(r + 1) − 1: incident_bond(e) and the
// particle at its other end, incident_partner(e).
template <class Real, class ExecSpace>
struct HarmonicBondList {
  Kokkos::View<int* [2], Kokkos::LayoutRight, ExecSpace> ends;
  Kokkos::View<Real*, ExecSpace> k, r0;
  Kokkos::View<int*, ExecSpace> row_particle, offset, incident_bond, incident_partner;
  int max_particle = -1;  // the largest particle index a bond names

  int num_bonds() const { return int(ends.extent(0)); }
  int num_rows() const { return int(row_particle.extent(0)); }
};

// Builds the bond list on the host (setup, not a step) and copies it to ExecSpace. Bond b joins
// particles first_particle + ends[b][0] and first_particle + ends[b][1] (first_particle: where the
// bonded particles start in the scene's Particles).
template <class Real, class ExecSpace>
HarmonicBondList<Real, ExecSpace> make_harmonic_bond_list(const std::vector<std::array<int, 2>>& ends,
                                                          const std::vector<double>& k,
                                                          const std::vector<double>& r0, int first_particle = 0) {
  const std::size_t nb = ends.size();
  if (k.size() != nb || r0.size() != nb)
    throw std::invalid_argument("harmonic bonds: " + std::to_string(nb) + " bonds but " + std::to_string(k.size()) +
                                " stiffnesses and " + std::to_string(r0.size()) + " rest lengths");
  if (first_particle < 0)
    throw std::invalid_argument("harmonic bonds: first_particle must be >= 0, got " + std::to_string(first_particle));
  int max_end = -1;
  for (std::size_t b = 0; b < nb; ++b) {
    const auto& e = ends[b];
    if (e[0] < 0 || e[1] < 0 || e[0] == e[1])
      throw std::invalid_argument("harmonic bonds: bond " + std::to_string(b) + " joins particles " +
                                  std::to_string(e[0]) + " and " + std::to_string(e[1]));
    if (!(std::isfinite(k[b]) && k[b] >= 0))
      throw std::invalid_argument("harmonic bonds: bond " + std::to_string(b) + " has stiffness k = " +
                                  std::to_string(k[b]) + ", must be >= 0");
    if (!(std::isfinite(r0[b]) && r0[b] >= 0))
      throw std::invalid_argument("harmonic bonds: bond " + std::to_string(b) + " has rest length r0 = " +
                                  std::to_string(r0[b]) + ", must be >= 0");
    max_end = std::max(max_end, std::max(e[0], e[1]));
  }

  // CSR by counting: degree per particle → rows of the particles with bonds (ascending) → offsets
  // → fill in bond order, so each row lists its bonds in increasing bond index.
  std::vector<int> degree(std::size_t(max_end + 1), 0);
  for (const auto& e : ends) {
    ++degree[std::size_t(e[0])];
    ++degree[std::size_t(e[1])];
  }
  std::vector<int> row_of(degree.size(), -1), rows, offsets{0};
  for (std::size_t i = 0; i < degree.size(); ++i)
    if (degree[i] > 0) {
      row_of[i] = int(rows.size());
      rows.push_back(first_particle + int(i));
      offsets.push_back(offsets.back() + degree[i]);
    }
  std::vector<int> bond_of(2 * nb), partner_of(2 * nb), cursor(offsets.begin(), offsets.end() - 1);
  for (std::size_t b = 0; b < nb; ++b)
    for (int end = 0; end < 2; ++end) {
      const int r = row_of[std::size_t(ends[b][end])];
      const int e = cursor[std::size_t(r)]++;
      bond_of[std::size_t(e)] = int(b);
      partner_of[std::size_t(e)] = first_particle + ends[b][1 - end];
    }

  HarmonicBondList<Real, ExecSpace> list;
  const std::string p = "mesoflow::msm::bonds::";
  list.ends = decltype(list.ends)(p + "ends", nb);
  list.k = decltype(list.k)(p + "k", nb);
  list.r0 = decltype(list.r0)(p + "r0", nb);
  list.row_particle = decltype(list.row_particle)(p + "row_particle", rows.size());
  list.offset = decltype(list.offset)(p + "offset", offsets.size());
  list.incident_bond = decltype(list.incident_bond)(p + "incident_bond", 2 * nb);
  list.incident_partner = decltype(list.incident_partner)(p + "incident_partner", 2 * nb);
  list.max_particle = max_end < 0 ? -1 : first_particle + max_end;

  auto h_ends = Kokkos::create_mirror_view(list.ends);
  auto h_k = Kokkos::create_mirror_view(list.k);
  auto h_r0 = Kokkos::create_mirror_view(list.r0);
  for (std::size_t b = 0; b < nb; ++b) {
    h_ends(b, 0) = first_particle + ends[b][0];
    h_ends(b, 1) = first_particle + ends[b][1];
    h_k(b) = Real(k[b]);
    h_r0(b) = Real(r0[b]);
  }
  auto copy = [](const auto& view, const std::vector<int>& values) {
    auto h = Kokkos::create_mirror_view(view);
    for (std::size_t i = 0; i < values.size(); ++i) h(i) = values[i];
    Kokkos::deep_copy(view, h);
  };
  Kokkos::deep_copy(list.ends, h_ends);
  Kokkos::deep_copy(list.k, h_k);
  Kokkos::deep_copy(list.r0, h_r0);
  copy(list.row_particle, rows);
  copy(list.offset, offsets);
  copy(list.incident_bond, bond_of);
  copy(list.incident_partner, partner_of);
  return list;
}

// The bond forces of eq. (7) over one bond list.
template <int D, class Real, class ExecSpace>
class HarmonicBonds {
 public:
  explicit HarmonicBonds(const HarmonicBondList<Real, ExecSpace>& bonds) : bonds_(bonds) {}

  const HarmonicBondList<Real, ExecSpace>& bonds() const { return bonds_; }

  // After a memory sort of the particles: every particle index the bonds hold (ends, rows,
  // partners) i ← new_index(i) (kernels/common/particle_sort.hpp). Shared with every copy of the
  // list (the Views are shared).
  void renumber(const Kokkos::View<int*, ExecSpace>& new_index) {
    if (bonds_.max_particle >= int(new_index.extent(0)))
      throw std::invalid_argument("harmonic bonds: renumbering " + std::to_string(new_index.extent(0)) +
                                  " particles, but a bond names particle " + std::to_string(bonds_.max_particle));
    renumber_particle_indices(bonds_.ends, new_index);
    renumber_particle_indices(bonds_.row_particle, new_index);
    renumber_particle_indices(bonds_.incident_partner, new_index);
    // Still an upper bound of the indices named (a permutation of 0 .. n − 1), all check_size needs.
    bonds_.max_particle = int(new_index.extent(0)) - 1;
  }

  // Δt_bond = C_b min_i √(m_i/K_i), K_i the summed stiffness of particle i's bonds (see the file
  // comment; C_b = 0.5 by default). A reduction to the host: call it when choosing Δt.
  double time_step_limit(const Particles<D, Real, ExecSpace>& p, double coefficient = 0.5) const {
    check_size(p);
    if (!(std::isfinite(coefficient) && coefficient > 0))
      throw std::invalid_argument("harmonic bonds: time-step coefficient must be > 0, got " +
                                  std::to_string(coefficient));
    const auto m = p.mass;
    const auto rows = bonds_.row_particle, offset = bonds_.offset, bond = bonds_.incident_bond;
    const auto k = bonds_.k;
    double max_ratio = 0;  // max_i K_i/m_i
    mesoflow::launch::parallel_reduce(
        "mesoflow::msm::bond_time_step", Kokkos::RangePolicy<ExecSpace>(0, bonds_.num_rows()),
        KOKKOS_LAMBDA(int row, double& acc) {
          double sum_k = 0;
          for (int e = offset(row); e < offset(row + 1); ++e) sum_k += double(k(bond(e)));
          const double ratio = sum_k / double(m(rows(row)));
          if (ratio > acc) acc = ratio;
        },
        Kokkos::Max<double>(max_ratio));
    return max_ratio > 0 ? coefficient / std::sqrt(max_ratio) : std::numeric_limits<double>::infinity();
  }

  // p.f += the bond forces of eq. (7) (each bonded particle's row summed by one thread, in bond
  // order; particles without bonds untouched).
  void accumulate(const Particles<D, Real, ExecSpace>& p, const Box<D, Real>& box) const {
    check_size(p);
    const auto x = p.x, f = p.f;
    const auto rows = bonds_.row_particle, offset = bonds_.offset;
    const auto bond = bonds_.incident_bond, partner = bonds_.incident_partner;
    const auto k = bonds_.k, r0 = bonds_.r0;
    mesoflow::launch::parallel_for(
        "mesoflow::msm::harmonic_bonds", Kokkos::RangePolicy<ExecSpace>(0, bonds_.num_rows()),
        KOKKOS_LAMBDA(int row) {
          const int i = rows(row);
          const Vec<D, Real> xi = Vec<D, Real>::load(x, i);
          double fi[D] = {};
          for (int e = offset(row); e < offset(row + 1); ++e) {
            const int b = bond(e);
            Vec<D, Real> dr = Vec<D, Real>::load(x, partner(e)) - xi;
            box.minimum_image(dr);
            const Real s = HarmonicBondLaw<Real>::force_over_r(kmath::sqrt(norm2(dr)), k(b), r0(b));
            for (int d = 0; d < D; ++d) fi[d] += double(s * dr[d]);
          }
          for (int d = 0; d < D; ++d) f(i, d) += Real(fi[d]);
        });
  }

  // Σ_bonds ½ k (r − r0)² (eq. 7's potential), in double.
  double energy(const Particles<D, Real, ExecSpace>& p, const Box<D, Real>& box) const {
    check_size(p);
    const auto x = p.x;
    const auto ends = bonds_.ends;
    const auto k = bonds_.k, r0 = bonds_.r0;
    double u = 0;
    mesoflow::launch::parallel_reduce(
        "mesoflow::msm::harmonic_bond_energy", Kokkos::RangePolicy<ExecSpace>(0, bonds_.num_bonds()),
        KOKKOS_LAMBDA(int b, double& acc) {
          Vec<D, Real> dr = Vec<D, Real>::load(x, ends(b, 1)) - Vec<D, Real>::load(x, ends(b, 0));
          box.minimum_image(dr);
          acc += HarmonicBondLaw<Real>::energy(kmath::sqrt(double(norm2(dr))), double(k(b)), double(r0(b)));
        },
        u);
    return u;
  }

 private:
  void check_size(const Particles<D, Real, ExecSpace>& p) const {
    if (bonds_.max_particle >= int(p.size()))
      throw std::invalid_argument("harmonic bonds: a bond names particle " + std::to_string(bonds_.max_particle) +
                                  " but there are " + std::to_string(p.size()) + " particles");
  }

  HarmonicBondList<Real, ExecSpace> bonds_;
};

}  // namespace mesoflow::msm
