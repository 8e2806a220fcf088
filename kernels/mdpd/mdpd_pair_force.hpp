// mdpd_pair_force.hpp — the one MDPD pair loop: conservative (conservative_force.hpp), dissipative
// and random (dissipative_random_force.hpp) forces of eq. (8), plus the WCA repulsion between fluid
// particles and solid-core particles (paper §2.5.1, particle_types.hpp), in a single pass over a
// neighbor list. The terms share the pair geometry, so fusing them reads each pair once.
//
// Model only what the scene needs: the thermostat terms are compiled out when D = R = 0, and the
// WCA test when the scene has no solid-core particles.
//
// Full list: each row sums the forces on its own particle, deterministic. Half list: each pair
// once (one random number per pair instead of two), the reaction scattered through a ScatterView.
//
// Positions, densities and velocities are read from packed rows (packed_state.hpp) and the pair
// forces written to packed rows `fr`, which the caller adds to the particles' forces.
//
// Optionally records, per solid particle, the force exerted on it by fluid particles (all terms):
// the drag on pillars and walls (paper eq. 3 and Fig. 13).
#pragma once

#include "conservative_force.hpp"
#include "dissipative_random_force.hpp"
#include "kernels/common/box.hpp"
#include "kernels/common/lennard_jones.hpp"
#include "kernels/common/neighbor_list.hpp"
#include "kernels/common/particles.hpp"
#include "packed_state.hpp"
#include "particle_types.hpp"

#include <Kokkos_ScatterView.hpp>

#include <cstdint>

namespace mesoflow::mdpd {

template <int D, class Real, class ExecSpace>
class MdpdPairForce {
 public:
  using vector_view = typename Particles<D, Real, ExecSpace>::vector_view;
  using rows_view = PackedRows<Real, ExecSpace>;
  using tag_view = Kokkos::View<std::uint32_t*, ExecSpace>;
  using type_view = Kokkos::View<int*, ExecSpace>;

  MdpdPairForce(const MdpdParameters& par, std::uint64_t seed, Real wca_epsilon = Real(1), Real wca_sigma = Real(1))
      : conservative_(par),
        thermostat_(par, seed),
        wca_(LennardJones<Real>::wca(wca_epsilon, wca_sigma)),
        rA2_(Real(par.r_A * par.r_A)) {}

  // The reach a neighbor list must cover: r_A, or the WCA cut-off where the scene has cores.
  Real reach(bool has_core) const {
    const Real wca_cut = kmath::sqrt(wca_.cutoff2);
    return has_core && wca_cut > kmath::sqrt(rA2_) ? wca_cut : kmath::sqrt(rA2_);
  }

  // fr(i) ← Σ_j F_ij. xr holds positions and ρ̄ (column rho_column), vr the velocities the
  // dissipative force uses (the integrator's choice), `tag` the identities keying the pair noise.
  // With `solid_drag` non-empty (n × D), solid_drag(i) ← the force of fluid particles on solid i.
  void compute(const rows_view& xr, const rows_view& vr, const type_view& type, const tag_view& tag,
               const NeighborList<D, Real, ExecSpace>& list, const Box<D, Real>& box, std::uint64_t step,
               bool has_core, const rows_view& fr, const vector_view& solid_drag = vector_view()) {
    const bool thermo = thermostat_.active();
    const bool record = solid_drag.extent(0) > 0;
    const Args a{xr, vr, type, tag, list.data(), box, step, fr, solid_drag};
    const bool full_list = list.kind() == NeighborListKind::full;
    const int variant = (full_list ? 8 : 0) + (thermo ? 4 : 0) + (has_core ? 2 : 0) + (record ? 1 : 0);
    switch (variant) {
      case 0: return half<false, false, false>(a);
      case 1: return half<false, false, true>(a);
      case 2: return half<false, true, false>(a);
      case 3: return half<false, true, true>(a);
      case 4: return half<true, false, false>(a);
      case 5: return half<true, false, true>(a);
      case 6: return half<true, true, false>(a);
      case 7: return half<true, true, true>(a);
      case 8: return full<false, false, false>(a);
      case 9: return full<false, false, true>(a);
      case 10: return full<false, true, false>(a);
      case 11: return full<false, true, true>(a);
      case 12: return full<true, false, false>(a);
      case 13: return full<true, false, true>(a);
      case 14: return full<true, true, false>(a);
      default: return full<true, true, true>(a);
    }
  }

  // Args, pair, row_vector, full and half are implementation details, public only because nvcc
  // rejects a KOKKOS_LAMBDA in a private or protected member function, or one capturing a value of a
  // private type.
  struct Args {
    rows_view xr, vr;
    type_view type;
    tag_view tag;
    NeighborData<ExecSpace> nbr;
    Box<D, Real> box;
    std::uint64_t step;
    rows_view fr;
    vector_view drag;
  };

  // F_ij/r for the pair (i, j) at separation dr = x_i − x_j; false beyond every cut-off.
  template <bool Thermo, bool Core>
  KOKKOS_INLINE_FUNCTION static bool pair(const ConservativeForce<D, Real>& cons,
                                          const DissipativeRandomForce<Real>& thermo,
                                          const LennardJones<Real>& wca, Real rA2, const Vec<D, Real>& dr,
                                          Real r2, int type_i, int type_j, Real rho_i, Real rho_j,
                                          const Vec<D, Real>& vij, std::uint64_t step, std::uint32_t tag_i,
                                          std::uint32_t tag_j, Real& force_over_r) {
    Real fr = 0;
    bool hit = false;
    if (r2 < rA2) {
      const Real r = kmath::sqrt(r2);
      const Real inv_r = Real(1) / r;
      Real f = cons.magnitude(r, r2, rho_i, rho_j);
      if constexpr (Thermo) f += thermo.magnitude(r, dot(vij, dr) * inv_r, step, tag_i, tag_j);
      fr = f * inv_r;
      hit = true;
    }
    if constexpr (Core) {
      const bool fluid_core = (type_i == particle_type::fluid && type_j == particle_type::solid_core) ||
                              (type_j == particle_type::fluid && type_i == particle_type::solid_core);
      Real fw, unused;
      if (fluid_core && wca.evaluate(r2, type_i, type_j, fw, unused)) {
        fr += fw;
        hit = true;
      }
    }
    force_over_r = fr;
    return hit;
  }

  KOKKOS_INLINE_FUNCTION static Vec<D, Real> row_vector(const rows_view& rows, int i) {
    Vec<D, Real> r;
    for (int d = 0; d < D; ++d) r[d] = rows(i, d);
    return r;
  }

  template <bool Thermo, bool Core, bool Record>
  void full(const Args& a) const {
    const auto cons = conservative_;
    const auto thermo = thermostat_;
    const auto wca = wca_;
    const Real rA2 = rA2_;
    Kokkos::parallel_for(
        "mesoflow::mdpd::pair_force_full", Kokkos::RangePolicy<ExecSpace>(0, a.xr.extent(0)), KOKKOS_LAMBDA(int row) {
          const int i = a.nbr.particle(row);
          const Vec<D, Real> xi = row_vector(a.xr, i);
          const Vec<D, Real> vi = row_vector(a.vr, i);
          const int ti = Core || Record ? a.type(i) : 0;
          const Real rho_i = a.xr(i, rho_column);
          const std::uint32_t tag_i = a.tag(i);
          Vec<D, Real> fi = Vec<D, Real>::zero(), from_fluid = Vec<D, Real>::zero();
          const int nn = a.nbr.num_neighbors(row);
          for (int k = 0; k < nn; ++k) {
            const int j = a.nbr.neighbor(row, k);
            Vec<D, Real> dr = xi - row_vector(a.xr, j);
            a.box.minimum_image_near(dr);
            const Real r2 = norm2(dr);
            const int tj = Core || Record ? a.type(j) : 0;
            Real f_over_r;
            if (pair<Thermo, Core>(cons, thermo, wca, rA2, dr, r2, ti, tj, rho_i, a.xr(j, rho_column),
                                   Thermo ? vi - row_vector(a.vr, j) : vi, a.step, tag_i, a.tag(j), f_over_r)) {
              fi += f_over_r * dr;
              if constexpr (Record)
                if (tj == particle_type::fluid) from_fluid += f_over_r * dr;
            }
          }
          for (int d = 0; d < D; ++d) a.fr(i, d) = fi[d];
          if constexpr (Record)
            for (int d = 0; d < D; ++d) a.drag(i, d) = is_solid(ti) ? from_fluid[d] : Real(0);
        });
  }

  template <bool Thermo, bool Core, bool Record>
  void half(const Args& a) {
    if (scatter_target_ != a.fr.data()) {
      scatter_ = Kokkos::Experimental::create_scatter_view(a.fr);
      scatter_target_ = a.fr.data();
    }
    const auto fr = a.fr;
    Kokkos::parallel_for(
        "mesoflow::mdpd::zero_pair_forces", Kokkos::RangePolicy<ExecSpace>(0, fr.extent(0)), KOKKOS_LAMBDA(int i) {
          for (int d = 0; d < packed_width; ++d) fr(i, d) = Real(0);
        });
    scatter_.reset_except(fr);
    auto scatter = scatter_;
    if constexpr (Record) {
      if (drag_target_ != a.drag.data()) {
        drag_scatter_ = Kokkos::Experimental::create_scatter_view(a.drag);
        drag_target_ = a.drag.data();
      }
      const auto drag = a.drag;
      Kokkos::parallel_for(
          "mesoflow::mdpd::zero_solid_drag", Kokkos::RangePolicy<ExecSpace>(0, drag.extent(0)), KOKKOS_LAMBDA(int i) {
            for (int d = 0; d < D; ++d) drag(i, d) = Real(0);
          });
      drag_scatter_.reset_except(drag);
    }
    auto drag_scatter = drag_scatter_;
    const auto cons = conservative_;
    const auto thermo = thermostat_;
    const auto wca = wca_;
    const Real rA2 = rA2_;
    Kokkos::parallel_for(
        "mesoflow::mdpd::pair_force_half", Kokkos::RangePolicy<ExecSpace>(0, a.xr.extent(0)), KOKKOS_LAMBDA(int row) {
          auto access = scatter.access();
          const int i = a.nbr.particle(row);
          const Vec<D, Real> xi = row_vector(a.xr, i);
          const Vec<D, Real> vi = row_vector(a.vr, i);
          const int ti = Core || Record ? a.type(i) : 0;
          const Real rho_i = a.xr(i, rho_column);
          const std::uint32_t tag_i = a.tag(i);
          Vec<D, Real> fi = Vec<D, Real>::zero();
          const int nn = a.nbr.num_neighbors(row);
          for (int k = 0; k < nn; ++k) {
            const int j = a.nbr.neighbor(row, k);
            Vec<D, Real> dr = xi - row_vector(a.xr, j);
            a.box.minimum_image_near(dr);
            const Real r2 = norm2(dr);
            const int tj = Core || Record ? a.type(j) : 0;
            Real f_over_r;
            if (pair<Thermo, Core>(cons, thermo, wca, rA2, dr, r2, ti, tj, rho_i, a.xr(j, rho_column),
                                   Thermo ? vi - row_vector(a.vr, j) : vi, a.step, tag_i, a.tag(j), f_over_r)) {
              const Vec<D, Real> fij = f_over_r * dr;
              fi += fij;
              for (int d = 0; d < D; ++d) access(j, d) -= fij[d];
              // `if`, not `if constexpr`: nvcc rejects a KOKKOS_LAMBDA whose first use of a captured
              // variable is inside `if constexpr` (the condition is a compile-time constant all the same).
              if (Record) {
                auto drag_access = drag_scatter.access();
                if (is_solid(ti) && tj == particle_type::fluid)
                  for (int d = 0; d < D; ++d) drag_access(i, d) += fij[d];
                if (is_solid(tj) && ti == particle_type::fluid)
                  for (int d = 0; d < D; ++d) drag_access(j, d) -= fij[d];
              }
            }
          }
          for (int d = 0; d < D; ++d) access(i, d) += fi[d];
        });
    auto fr_target = a.fr;
    Kokkos::Experimental::contribute(fr_target, scatter_);
    if constexpr (Record) {
      auto drag_target = a.drag;
      Kokkos::Experimental::contribute(drag_target, drag_scatter_);
    }
  }

 private:
  ConservativeForce<D, Real> conservative_;
  DissipativeRandomForce<Real> thermostat_;
  LennardJones<Real> wca_;
  Real rA2_;
  decltype(Kokkos::Experimental::create_scatter_view(rows_view())) scatter_;
  Kokkos::Experimental::ScatterView<Real* [D], Kokkos::LayoutLeft, ExecSpace> drag_scatter_;
  const Real* scatter_target_ = nullptr;
  const Real* drag_target_ = nullptr;
};

}  // namespace mesoflow::mdpd
