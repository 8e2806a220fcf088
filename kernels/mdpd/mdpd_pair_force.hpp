// mdpd_pair_force.hpp — the one MDPD pair loop: conservative (conservative_force.hpp), dissipative
// and random (dissipative_random_force.hpp) forces of eq. (8), plus the WCA repulsion between fluid
// particles and solid-core particles (paper §2.5.1, particle_types.hpp), in a single pass over a
// neighbor list. The terms share the pair geometry, so fusing them reads each pair once.
//
// An evaluator of the generic pair loop (kernels/common/pair_force.hpp). Model only what the scene
// needs: the thermostat terms are compiled out when D = R = 0; the WCA test (no solid-core
// particles) and the drag record are skipped by uniform run-time flags. Instantiations: 4 (list
// kind × thermostat), were 16 (list kind × thermostat × core × record).
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

#include "../common/kernel_launch.hpp"
#include "conservative_force.hpp"
#include "dissipative_random_force.hpp"
#include "kernels/common/box.hpp"
#include "kernels/common/lennard_jones.hpp"
#include "kernels/common/neighbor_list.hpp"
#include "kernels/common/pair_force.hpp"
#include "kernels/common/particles.hpp"
#include "packed_state.hpp"
#include "particle_types.hpp"

#include <Kokkos_ScatterView.hpp>

#include <cstdint>

namespace mesoflow::mdpd {

// F_ij/r for the pair (i, j) at separation dr = x_i − x_j; false beyond every cut-off. `core`: the
// scene has solid-core particles (the WCA term).
template <bool Thermo, int D, class Real>
KOKKOS_INLINE_FUNCTION bool mdpd_pair(const ConservativeForce<D, Real>& cons, const DissipativeRandomForce<Real>& thermo,
                                      const LennardJones<Real>& wca, Real rA2, bool core, const Vec<D, Real>& dr,
                                      Real r2, int type_i, int type_j, Real rho_i, Real rho_j, const Vec<D, Real>& vij,
                                      std::uint64_t step, std::uint32_t tag_i, std::uint32_t tag_j, Real& force_over_r) {
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
  if (core) {
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

// Eq. (8) + WCA as an evaluator of the generic pair loop. Compile-time switches: the list tag and
// Thermo (the dissipative + random terms); the WCA term (`core`) and the drag record (`record`) are
// uniform run-time flags.
template <bool Thermo, int D, class Real, class ExecSpace>
struct MdpdPairEvaluator : PairEvaluatorTraits {
  static constexpr MinimumImage image = MinimumImage::near;
  using rows_view = PackedRows<Real, ExecSpace>;
  using vector_view = typename Particles<D, Real, ExecSpace>::vector_view;
  using rows_scatter = PairScatter<rows_view>;
  using drag_scatter_type = PairScatter<vector_view>;
  ConservativeForce<D, Real> cons;
  DissipativeRandomForce<Real> thermo;
  LennardJones<Real> wca;
  Real rA2;
  bool core, record;
  // Read-only inputs as pointers into their Views (the closure stays under
  // max_kernel_closure_bytes, kernels/common/kernel_launch.hpp): rows are LayoutRight, packed_width wide.
  PackedRowsRef<Real> xr, vr;
  const int* type;
  const std::uint32_t* tag;
  std::uint64_t step;
  rows_view fr;
  vector_view drag;
  typename rows_scatter::scatter_view fr_scatter;           // half lists only
  typename drag_scatter_type::scatter_view drag_scatter;  // half lists with `record` only

  KOKKOS_INLINE_FUNCTION Vec<D, Real> row_vector(const PackedRowsRef<Real>& rows, int i) const {
    Vec<D, Real> r;
    for (int d = 0; d < D; ++d) r[d] = rows(i, d);
    return r;
  }

  struct FullRow {
    Vec<D, Real> vi;
    int ti;
    Real rho_i;
    std::uint32_t tag_i;
    Vec<D, Real> fi, from_fluid;
  };
  struct HalfRow {
    typename rows_scatter::access_type access;
    Vec<D, Real> vi;
    int ti;
    Real rho_i;
    std::uint32_t tag_i;
    Vec<D, Real> fi;
  };

  KOKKOS_INLINE_FUNCTION FullRow begin(FullList, int i) const {
    return {row_vector(vr, i), core || record ? type[i] : 0, xr(i, rho_column), tag[i], Vec<D, Real>::zero(),
            Vec<D, Real>::zero()};
  }
  KOKKOS_INLINE_FUNCTION void operator()(FullList, FullRow& s, int, int j, const Vec<D, Real>& dr, Real r2,
                                         double&) const {
    const int tj = core || record ? type[j] : 0;
    Real f_over_r;
    if (mdpd_pair<Thermo>(cons, thermo, wca, rA2, core, dr, r2, s.ti, tj, s.rho_i, xr(j, rho_column),
                          Thermo ? s.vi - row_vector(vr, j) : s.vi, step, s.tag_i, tag[j], f_over_r)) {
      s.fi += f_over_r * dr;
      if (record && tj == particle_type::fluid) s.from_fluid += f_over_r * dr;
    }
  }
  KOKKOS_INLINE_FUNCTION void end(FullList, FullRow& s, int i, double&) const {
    for (int d = 0; d < D; ++d) fr(i, d) = s.fi[d];
    if (record)
      for (int d = 0; d < D; ++d) drag(i, d) = is_solid(s.ti) ? s.from_fluid[d] : Real(0);
  }

  KOKKOS_INLINE_FUNCTION HalfRow begin(HalfList, int i) const {
    return {fr_scatter.access(), row_vector(vr, i), core || record ? type[i] : 0, xr(i, rho_column), tag[i],
            Vec<D, Real>::zero()};
  }
  KOKKOS_INLINE_FUNCTION void operator()(HalfList, HalfRow& s, int i, int j, const Vec<D, Real>& dr, Real r2,
                                         double&) const {
    const int tj = core || record ? type[j] : 0;
    Real f_over_r;
    if (mdpd_pair<Thermo>(cons, thermo, wca, rA2, core, dr, r2, s.ti, tj, s.rho_i, xr(j, rho_column),
                          Thermo ? s.vi - row_vector(vr, j) : s.vi, step, s.tag_i, tag[j], f_over_r)) {
      const Vec<D, Real> fij = f_over_r * dr;
      s.fi += fij;
      for (int d = 0; d < D; ++d) s.access(j, d) -= fij[d];
      if (record) {
        auto drag_access = drag_scatter.access();
        if (is_solid(s.ti) && tj == particle_type::fluid)
          for (int d = 0; d < D; ++d) drag_access(i, d) += fij[d];
        if (is_solid(tj) && s.ti == particle_type::fluid)
          for (int d = 0; d < D; ++d) drag_access(j, d) -= fij[d];
      }
    }
  }
  KOKKOS_INLINE_FUNCTION void end(HalfList, HalfRow& s, int i, double&) const {
    for (int d = 0; d < D; ++d) s.access(i, d) += s.fi[d];
  }
};

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
    const bool record = solid_drag.extent(0) > 0;
    const bool full_list = list.kind() == NeighborListKind::full;
    if (thermostat_.active()) {
      auto ev = evaluator<true>(xr, vr, type, tag, step, has_core, fr, solid_drag, record);
      full_list ? full(ev, xr, list, box) : half(ev, xr, list, box);
    } else {
      auto ev = evaluator<false>(xr, vr, type, tag, step, has_core, fr, solid_drag, record);
      full_list ? full(ev, xr, list, box) : half(ev, xr, list, box);
    }
  }

  // evaluator, full and half are implementation details, public only because nvcc rejects a
  // KOKKOS_LAMBDA in a private or protected member function.
  template <bool Thermo>
  MdpdPairEvaluator<Thermo, D, Real, ExecSpace> evaluator(const rows_view& xr, const rows_view& vr,
                                                          const type_view& type, const tag_view& tag,
                                                          std::uint64_t step, bool has_core, const rows_view& fr,
                                                          const vector_view& drag, bool record) const {
    return {{}, conservative_, thermostat_, wca_, rA2_, has_core, record, {xr.data()}, {vr.data()}, type.data(), tag.data(),
            step, fr, drag, {}, {}};
  }

  template <class Evaluator>
  void full(const Evaluator& ev, const rows_view& xr, const NeighborList<D, Real, ExecSpace>& list,
            const Box<D, Real>& box) {
    for_each_pair("mesoflow::mdpd::pair_force_full", FullList{}, list, box, xr, ev);
  }

  template <class Evaluator>
  void half(Evaluator ev, const rows_view& xr, const NeighborList<D, Real, ExecSpace>& list, const Box<D, Real>& box) {
    const auto fr = ev.fr;
    mesoflow::launch::parallel_for(
        "mesoflow::mdpd::zero_pair_forces", Kokkos::RangePolicy<ExecSpace>(0, fr.extent(0)), KOKKOS_LAMBDA(int i) {
          for (int d = 0; d < packed_width; ++d) fr(i, d) = Real(0);
        });
    ev.fr_scatter = scatter_.prepare(fr);
    if (ev.record) {
      const auto drag = ev.drag;
      mesoflow::launch::parallel_for(
          "mesoflow::mdpd::zero_solid_drag", Kokkos::RangePolicy<ExecSpace>(0, drag.extent(0)), KOKKOS_LAMBDA(int i) {
            for (int d = 0; d < D; ++d) drag(i, d) = Real(0);
          });
      ev.drag_scatter = drag_scatter_.prepare(drag);
    }
    for_each_pair("mesoflow::mdpd::pair_force_half", HalfList{}, list, box, xr, ev);
    scatter_.contribute(fr);
    if (ev.record) drag_scatter_.contribute(ev.drag);
  }

 private:
  ConservativeForce<D, Real> conservative_;
  DissipativeRandomForce<Real> thermostat_;
  LennardJones<Real> wca_;
  Real rA2_;
  PairScatter<rows_view> scatter_;
  PairScatter<vector_view> drag_scatter_;
};

}  // namespace mesoflow::mdpd
