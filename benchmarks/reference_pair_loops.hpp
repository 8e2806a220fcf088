// reference_pair_loops.hpp — the model-specific neighbor loops as they were before issue 24, item 3
// (commit 8798b78), kept only to time the generic loop of kernels/common/pair_force.hpp against them
// in the same run (bench_sp, bench_mdpd, bench_sph). Not used by any kernel, scene or driver.
#pragma once

#include "kernels/common/box.hpp"
#include "kernels/common/lennard_jones.hpp"
#include "kernels/common/neighbor_list.hpp"
#include "kernels/common/particles.hpp"
#include "kernels/dp/smooth_vertex_contacts.hpp"
#include "kernels/mdpd/conservative_force.hpp"
#include "kernels/mdpd/density_weight.hpp"
#include "kernels/mdpd/dissipative_random_force.hpp"
#include "kernels/mdpd/packed_state.hpp"
#include "kernels/mdpd/particle_types.hpp"
#include "kernels/sp/kinetic_friction.hpp"
#include "kernels/sph/sph_pair_interactions.hpp"

#include <Kokkos_ScatterView.hpp>

#include <cstdint>
#include <limits>
#include <stdexcept>

namespace mesoflow {

template <int D, class Real, class ExecSpace>
class ReferencePairForce {
 public:
  using vector_view = typename Particles<D, Real, ExecSpace>::vector_view;

  // Adds the pair forces to p.f and returns the total pair energy.
  template <class Evaluator>
  double accumulate(const Evaluator& eval, const Particles<D, Real, ExecSpace>& p,
                    const NeighborList<D, Real, ExecSpace>& list, const Box<D, Real>& box) {
    return list.kind() == NeighborListKind::full ? accumulate_full(eval, p, list, box)
                                                 : accumulate_half(eval, p, list, box);
  }

  // Adds the pair forces to p.f, without the energy (see the file comment).
  template <class Evaluator>
  void accumulate_forces(const Evaluator& eval, const Particles<D, Real, ExecSpace>& p,
                         const NeighborList<D, Real, ExecSpace>& list, const Box<D, Real>& box) {
    if (list.kind() != NeighborListKind::full) {
      accumulate_half(eval, p, list, box);
      return;
    }
    const auto x = p.x;
    const auto f = p.f;
    const auto type = p.type;
    const auto nbr = list.data();
    Kokkos::parallel_for(
        "mesoflow::pair_force::full_forces",
        Kokkos::RangePolicy<ExecSpace, Kokkos::Schedule<Kokkos::Dynamic>>(0, p.size()).set_chunk_size(64),
        KOKKOS_LAMBDA(int row) {
          const int i = nbr.particle(row);
          double unused = 0;
          const Vec<D, Real> fi = full_row_force(eval, nbr, x, type, box, row, i, unused);
          for (int d = 0; d < D; ++d) f(i, d) += fi[d];
        });
  }

  // full_row_force, accumulate_full and accumulate_half are implementation details, public only
  // because nvcc rejects a KOKKOS_LAMBDA in a private or protected member function.

  // Σ_j F_ij over row `row` (particle i) of a full list, in list order; adds the pair energies to e_sum.
  template <class Evaluator, class Neighbors, class Positions, class Types>
  KOKKOS_INLINE_FUNCTION static Vec<D, Real> full_row_force(const Evaluator& eval, const Neighbors& nbr,
                                                            const Positions& x, const Types& type,
                                                            const Box<D, Real>& box, int row, int i, double& e_sum) {
    const Vec<D, Real> xi = Vec<D, Real>::load(x, i);
    const int ti = type(i);
    Vec<D, Real> fi = Vec<D, Real>::zero();
    const int nn = nbr.num_neighbors(row);
    for (int k = 0; k < nn; ++k) {
      const int j = nbr.neighbor(row, k);
      Vec<D, Real> dr = xi - Vec<D, Real>::load(x, j);
      box.minimum_image(dr);
      Real force_over_r, e;
      if (eval.evaluate(norm2(dr), ti, type(j), force_over_r, e)) {
        fi += force_over_r * dr;
        e_sum += e;
      }
    }
    return fi;
  }

  template <class Evaluator>
  double accumulate_full(const Evaluator& eval, const Particles<D, Real, ExecSpace>& p,
                         const NeighborList<D, Real, ExecSpace>& list, const Box<D, Real>& box) {
    const auto x = p.x;
    const auto f = p.f;
    const auto type = p.type;
    const auto nbr = list.data();
    double energy = 0;
    Kokkos::parallel_reduce(
        "mesoflow::pair_force::full", Kokkos::RangePolicy<ExecSpace>(0, p.size()),
        KOKKOS_LAMBDA(int row, double& e_acc) {
          const int i = nbr.particle(row);
          double ei = 0;
          const Vec<D, Real> fi = full_row_force(eval, nbr, x, type, box, row, i, ei);
          for (int d = 0; d < D; ++d) f(i, d) += fi[d];
          e_acc += 0.5 * ei;
        },
        energy);
    return energy;
  }

  template <class Evaluator>
  double accumulate_half(const Evaluator& eval, const Particles<D, Real, ExecSpace>& p,
                         const NeighborList<D, Real, ExecSpace>& list, const Box<D, Real>& box) {
    // Created once per force array. On backends where the ScatterView aliases p.f (Serial, GPUs)
    // reset_except leaves the forces other terms already added; duplicates are zeroed.
    if (scatter_target_ != p.f.data()) {
      scatter_ = Kokkos::Experimental::create_scatter_view(p.f);
      scatter_target_ = p.f.data();
    }
    scatter_.reset_except(p.f);
    auto scatter = scatter_;
    const auto x = p.x;
    const auto type = p.type;
    const auto nbr = list.data();
    double energy = 0;
    Kokkos::parallel_reduce(
        "mesoflow::pair_force::half", Kokkos::RangePolicy<ExecSpace>(0, p.size()),
        KOKKOS_LAMBDA(int row, double& e_acc) {
          auto access = scatter.access();
          const int i = nbr.particle(row);
          const Vec<D, Real> xi = Vec<D, Real>::load(x, i);
          const int ti = type(i);
          Vec<D, Real> fi = Vec<D, Real>::zero();
          const int nn = nbr.num_neighbors(row);
          for (int k = 0; k < nn; ++k) {
            const int j = nbr.neighbor(row, k);
            Vec<D, Real> dr = xi - Vec<D, Real>::load(x, j);
            box.minimum_image(dr);
            Real force_over_r, e;
            if (eval.evaluate(norm2(dr), ti, type(j), force_over_r, e)) {
              const Vec<D, Real> fij = force_over_r * dr;
              fi += fij;
              for (int d = 0; d < D; ++d) access(j, d) -= fij[d];
              e_acc += e;
            }
          }
          for (int d = 0; d < D; ++d) access(i, d) += fi[d];
        },
        energy);
    auto f = p.f;
    Kokkos::Experimental::contribute(f, scatter_);
    return energy;
  }

 private:
  Kokkos::Experimental::ScatterView<Real* [D], Kokkos::LayoutLeft, ExecSpace> scatter_;
  const Real* scatter_target_ = nullptr;
};

}  // namespace mesoflow

namespace mesoflow::sp {

template <int D, class Real, class ExecSpace>
void reference_kinetic_friction(Real mu, const SoftSphereRepulsion<Real>& contacts,
                                 const Particles<D, Real, ExecSpace>& p,
                                 const typename Particles<D, Real, ExecSpace>::vector_view& velocity,
                                 const NeighborList<D, Real, ExecSpace>& list, const Box<D, Real>& box,
                                 FrictionComponent component = FrictionComponent::full) {
  if (!(mu >= Real(0)) || !std::isfinite(double(mu)))
    throw std::invalid_argument("kinetic_friction: mu must be finite and >= 0, got " + std::to_string(double(mu)));
  if (list.kind() != NeighborListKind::full)
    throw std::invalid_argument("kinetic_friction: needs a full neighbor list");
  if (mu == Real(0)) return;  // a term whose coefficient is zero costs nothing
  const auto x = p.x;
  const auto v = velocity;
  const auto f = p.f;
  const auto type = p.type;
  const auto nbr = list.data();
  const bool tangential = component == FrictionComponent::tangential;
  Kokkos::parallel_for(
      "mesoflow::sp::kinetic_friction", Kokkos::RangePolicy<ExecSpace, Kokkos::Schedule<Kokkos::Dynamic>>(0, p.size()).set_chunk_size(64),
      KOKKOS_LAMBDA(int row) {
        const int i = nbr.particle(row);
        const Vec<D, Real> xi = Vec<D, Real>::load(x, i);
        const Vec<D, Real> vi = Vec<D, Real>::load(v, i);
        const int ti = type(i);
        Vec<D, Real> fi = Vec<D, Real>::zero();
        const int nn = nbr.num_neighbors(row);
        for (int k = 0; k < nn; ++k) {
          const int j = nbr.neighbor(row, k);
          Vec<D, Real> dr = xi - Vec<D, Real>::load(x, j);
          box.minimum_image(dr);
          const Real s = contacts.contact[ti][type(j)];
          const Real r2 = norm2(dr);
          if (!(r2 < s * s)) continue;
          Vec<D, Real> dv = vi - Vec<D, Real>::load(v, j);
          if (tangential && r2 > Real(0)) dv -= (dot(dv, dr) / r2) * dr;
          fi += (-mu) * dv;
        }
        for (int d = 0; d < D; ++d) f(i, d) += fi[d];
      });
}

}  // namespace mesoflow::sp

namespace mesoflow::dp {

// Adds the contact forces to p.f and returns the energy. `widths`: ε_c and δ of each vertex type
// (the particle's size class), as a SoftSphereRepulsion. Throws if the list does not exclude pairs of
// the same body or its cutoff (plus skin) is shorter than smooth_contact_reach.
template <class Real, class ExecSpace>
double reference_smooth_vertex_contacts(const sp::SoftSphereRepulsion<Real>& widths,
                                         const Polygons<Real, ExecSpace>& polygons,
                                         const Particles<2, Real, ExecSpace>& p,
                                         const NeighborList<2, Real, ExecSpace>& list, const Box<2, Real>& box) {
  if (list.exclusion() != BodyExclusion::same_body)
    throw std::invalid_argument("dp smooth contacts: the neighbor list must exclude pairs of the same body");
  if (list.kind() != NeighborListKind::full)
    throw std::invalid_argument("dp smooth contacts: needs a full neighbor list");
  const Real reach = smooth_contact_reach(polygons, p, box, widths);
  if (reach > list.cutoff())
    throw std::invalid_argument("dp smooth contacts: an edge plus the contact width (" + std::to_string(double(reach)) +
                                ") exceeds the neighbor-list cutoff " + std::to_string(double(list.cutoff())));
  const auto offset = polygons.offset;
  const auto body = polygons.body;
  const auto x = p.x;
  const auto f = p.f;
  const auto type = p.type;
  const auto nbr = list.data();
  double energy = 0;
  Kokkos::parallel_reduce(
      "mesoflow::dp::smooth_vertex_contacts", Kokkos::RangePolicy<ExecSpace>(0, p.size()),
      KOKKOS_LAMBDA(int row, double& acc) {
        using smooth_contact_detail::contact;
        const int i = nbr.particle(row);
        const int bi = body(i), begin_i = offset(bi), n_i = offset(bi + 1) - begin_i;
        const Vec<2, Real> xi = Vec<2, Real>::load(x, i);
        const Vec<2, Real> x_next = Vec<2, Real>::load(x, next_vertex(i, 1, begin_i, n_i));
        const Vec<2, Real> x_prev = Vec<2, Real>::load(x, prev_vertex(i, 1, begin_i, n_i));
        const int ti = type(i);
        Vec<2, Real> fi = Vec<2, Real>::zero();
        const int nn = nbr.num_neighbors(row);
        for (int k = 0; k < nn; ++k) {
          const int j = nbr.neighbor(row, k);
          const Real width = widths.contact[ti][type(j)];
          const Vec<2, Real> xj = Vec<2, Real>::load(x, j);
          Real fm, t, e;
          Vec<2, Real> u;
          // (a) i the point, against the edge j → next(j) of the other particle.
          const int bj = body(j), begin_j = offset(bj), n_j = offset(bj + 1) - begin_j;
          if (contact(xi, xj, Vec<2, Real>::load(x, next_vertex(j, 1, begin_j, n_j)), box, width, widths.epsilon, fm,
                      u, t, e)) {
            fi += fm * u;
            acc += double(e);
          }
          // (b) i the first vertex of its edge i → next(i), against the point j.
          if (contact(xj, xi, x_next, box, width, widths.epsilon, fm, u, t, e)) fi += (-(Real(1) - t) * fm) * u;
          // (c) i the second vertex of its edge prev(i) → i, against the point j (no share at a cap).
          if (contact(xj, x_prev, xi, box, width, widths.epsilon, fm, u, t, e)) fi += (-t * fm) * u;
        }
        for (int d = 0; d < 2; ++d) f(i, d) += fi[d];
      },
      energy);
  return energy;
}

}  // namespace mesoflow::dp

namespace mesoflow::mdpd {

template <int D, class Real, class ExecSpace>
class ReferenceLocalDensity {
 public:
  using scalar_view = Kokkos::View<Real*, ExecSpace>;

  explicit ReferenceLocalDensity(const DensityWeight<D, Real>& weight) : weight_(weight) {}

  // rho(i) ← ρ̄_i for every particle, from the positions packed in rows xr (packed_state.hpp).
  void compute(const PackedRows<Real, ExecSpace>& xr, const NeighborList<D, Real, ExecSpace>& list,
               const Box<D, Real>& box, const scalar_view& rho) {
    use_inner_ = list.inner_cutoff() >= weight_.h;
    if (list.kind() == NeighborListKind::full)
      compute_full(xr, list, box, rho);
    else
      compute_half(xr, list, box, rho);
  }

  const DensityWeight<D, Real>& weight() const { return weight_; }

  // compute_full, compute_half and row_vector are implementation details, public only because nvcc
  // rejects a KOKKOS_LAMBDA in a private or protected member function.
  void compute_full(const PackedRows<Real, ExecSpace>& x, const NeighborList<D, Real, ExecSpace>& list,
                    const Box<D, Real>& box, const scalar_view& rho) const {
    const auto nbr = list.data();
    const auto w = weight_;
    const bool use_inner = use_inner_;
    Kokkos::parallel_for(
        "mesoflow::mdpd::density_full", Kokkos::RangePolicy<ExecSpace>(0, x.extent(0)), KOKKOS_LAMBDA(int row) {
          const int i = nbr.particle(row);
          const Vec<D, Real> xi = row_vector(x, i);
          Real sum = w.self;
          const int nn = use_inner ? nbr.num_inner_neighbors(row) : nbr.num_neighbors(row);
          for (int k = 0; k < nn; ++k) {
            Vec<D, Real> dr = xi - row_vector(x, nbr.neighbor(row, k));
            box.minimum_image_near(dr);
            const Real r2 = norm2(dr);
            if (r2 < w.h2) sum += w(kmath::sqrt(r2));
          }
          rho(i) = sum;
        });
  }

  void compute_half(const PackedRows<Real, ExecSpace>& x, const NeighborList<D, Real, ExecSpace>& list,
                    const Box<D, Real>& box, const scalar_view& rho) {
    const auto w = weight_;
    Kokkos::parallel_for(
        "mesoflow::mdpd::density_self", Kokkos::RangePolicy<ExecSpace>(0, x.extent(0)),
        KOKKOS_LAMBDA(int i) { rho(i) = w.self; });
    if (scatter_target_ != rho.data()) {
      scatter_ = Kokkos::Experimental::create_scatter_view(rho);
      scatter_target_ = rho.data();
    }
    scatter_.reset_except(rho);
    auto scatter = scatter_;
    const auto nbr = list.data();
    const bool use_inner = use_inner_;
    Kokkos::parallel_for(
        "mesoflow::mdpd::density_half", Kokkos::RangePolicy<ExecSpace>(0, x.extent(0)), KOKKOS_LAMBDA(int row) {
          auto access = scatter.access();
          const int i = nbr.particle(row);
          const Vec<D, Real> xi = row_vector(x, i);
          Real sum = 0;
          const int nn = use_inner ? nbr.num_inner_neighbors(row) : nbr.num_neighbors(row);
          for (int k = 0; k < nn; ++k) {
            const int j = nbr.neighbor(row, k);
            Vec<D, Real> dr = xi - row_vector(x, j);
            box.minimum_image_near(dr);
            const Real r2 = norm2(dr);
            if (r2 < w.h2) {
              const Real wij = w(kmath::sqrt(r2));
              sum += wij;
              access(j) += wij;
            }
          }
          access(i) += sum;
        });
    auto target = rho;
    Kokkos::Experimental::contribute(target, scatter_);
  }

  KOKKOS_INLINE_FUNCTION static Vec<D, Real> row_vector(const PackedRows<Real, ExecSpace>& rows, int i) {
    Vec<D, Real> r;
    for (int d = 0; d < D; ++d) r[d] = rows(i, d);
    return r;
  }

 private:
  DensityWeight<D, Real> weight_;
  bool use_inner_ = false;
  decltype(Kokkos::Experimental::create_scatter_view(scalar_view())) scatter_;
  const Real* scatter_target_ = nullptr;
};

}  // namespace mesoflow::mdpd

namespace mesoflow::mdpd {

template <int D, class Real, class ExecSpace>
class ReferenceMdpdPairForce {
 public:
  using vector_view = typename Particles<D, Real, ExecSpace>::vector_view;
  using rows_view = PackedRows<Real, ExecSpace>;
  using tag_view = Kokkos::View<std::uint32_t*, ExecSpace>;
  using type_view = Kokkos::View<int*, ExecSpace>;

  ReferenceMdpdPairForce(const MdpdParameters& par, std::uint64_t seed, Real wca_epsilon = Real(1), Real wca_sigma = Real(1))
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

namespace mesoflow::sph {

template <int D, class Real, class ExecSpace, class Kernel>
class ReferenceSphPairInteractions {
 public:
  using vector_view = typename Particles<D, Real, ExecSpace>::vector_view;
  using scalar_view = Kokkos::View<Real*, ExecSpace>;
  using int_view = Kokkos::View<int*, ExecSpace>;

  ReferenceSphPairInteractions(const Kernel& kernel, const BodyForce<D, Real>& body) : kernel_(kernel), body_(body) {}

  const Kernel& kernel() const { return kernel_; }
  const BodyForce<D, Real>& body_force() const { return body_; }
  void set_body_force(const BodyForce<D, Real>& body) { body_ = body; }

  // f(i) ← f_i of eq. (5) and drho(i) ← dρ_i/dt of eq. (4) for every particle, from the packed
  // rows; `list` must be a neighbor list (full or half) of reach ≥ the kernel's support. With `walls`
  // non-empty the viscous term of fluid–wall pairs uses Morris' extrapolated wall velocity with
  // factor `morris`.
  void compute(const SphRows<D, Real, ExecSpace>& rows, const int_view& type,
               const NeighborList<D, Real, ExecSpace>& list, const Box<D, Real>& box, const vector_view& f,
               const scalar_view& drho, const WallGeometry<D, Real, ExecSpace>& walls = {},
               const MorrisWallFactor<Real>& morris = MorrisWallFactor<Real>()) {
    if (list.cutoff() < kernel_.support)
      throw std::invalid_argument("sph: the neighbor list's cutoff is below the kernel support");
    const bool half = list.kind() == NeighborListKind::half;
    const ImageFreeRegion<D, Real, ExecSpace> region = image_free_region(rows, box);
    if (walls.extent(0) > 0)
      half ? run_half<true>(rows, type, list, box, region, f, drho, walls, morris)
           : run<true>(rows, type, list, box, region, f, drho, walls, morris);
    else
      half ? run_half<false>(rows, type, list, box, region, f, drho, walls, morris)
           : run<false>(rows, type, list, box, region, f, drho, walls, morris);
  }

  // The ImageFreeRegion of the particles in `rows`: one reduction for the largest overhang, into a
  // device scalar (asynchronous: the pair loop reads it).
  ImageFreeRegion<D, Real, ExecSpace> image_free_region(const SphRows<D, Real, ExecSpace>& rows,
                                                        const Box<D, Real>& box) {
    using C = SphColumn<D>;
    if (overhang_.data() == nullptr) overhang_ = Kokkos::View<Real, ExecSpace>("mesoflow::sph::overhang");
    Kokkos::parallel_reduce(
        "mesoflow::sph::overhang", Kokkos::RangePolicy<ExecSpace>(0, rows.extent(0)),
        KOKKOS_LAMBDA(int i, Real& out) {
          for (int d = 0; d < D; ++d)
            if (box.periodic[d]) {
              const Real below = box.lo[d] - rows(i, C::x + d);
              const Real above = rows(i, C::x + d) - (box.lo[d] + box.length[d]);
              out = below > out ? below : out;
              out = above > out ? above : out;
            }
        },
        Kokkos::Max<Real, ExecSpace>(overhang_));
    ImageFreeRegion<D, Real, ExecSpace> inner;
    inner.overhang = overhang_;
    for (int d = 0; d < D; ++d) {
      if (!box.periodic[d]) {
        inner.lo[d] = std::numeric_limits<Real>::lowest() / 2;
        inner.hi[d] = std::numeric_limits<Real>::max() / 2;
        continue;
      }
      // Round-off of the positions and of these bounds stays far below the slack.
      const double lo = double(box.lo[d]), length = double(box.length[d]);
      const double margin =
          double(kernel_.support) + 64 * double(std::numeric_limits<Real>::epsilon()) * (std::fabs(lo) + length);
      inner.lo[d] = Real(lo + margin);
      inner.hi[d] = Real(lo + length - margin);
    }
    return inner;
  }

  // run, run_half, screen and wall_factor are implementation details, public only because nvcc
  // rejects a KOKKOS_LAMBDA in a private or protected member function.

  // List entries screened at a time (the file comment): a half list of skin 10% holds about 44 per
  // row. An enumerator, not a static constexpr int: nvcc has no device copy of a host variable.
  enum : int { chunk = 32 };

  // The entries k ∈ [k0, k1) (k1 − k0 ≤ chunk) of `row` with |x_i − x_j| < support: j_in, dr_in
  // (x_i − x_j, minimum image) and r2_in (|dr|²) receive them; returns how many there are. Without
  // Image, x_i lies in the ImageFreeRegion and dr is taken as it is (the same bits: the minimum image
  // would not change it).
  template <bool Image>
  KOKKOS_INLINE_FUNCTION static int screen(const SphRows<D, Real, ExecSpace>& rows,
                                           const NeighborData<ExecSpace>& nbr, const Box<D, Real>& box, int row,
                                           int k0, int k1, const Vec<D, Real>& xi, Real support2, int* j_in,
                                           Vec<D, Real>* dr_in, Real* r2_in) {
    using C = SphColumn<D>;
    int kept = 0;
    for (int k = k0; k < k1; ++k) {
      const int j = nbr.neighbor(row, k);
      Vec<D, Real> dr;
      for (int d = 0; d < D; ++d) dr[d] = xi[d] - rows(j, C::x + d);
      if (Image) box.minimum_image_near(dr);
      const Real r2 = norm2(dr);
      j_in[kept] = j;
      dr_in[kept] = dr;
      r2_in[kept] = r2;
      kept += r2 < support2;
    }
    return kept;
  }

  template <bool Morris>
  void run(const SphRows<D, Real, ExecSpace>& rows, const int_view& type, const NeighborList<D, Real, ExecSpace>& list,
           const Box<D, Real>& box, const ImageFreeRegion<D, Real, ExecSpace>& region, const vector_view& f,
           const scalar_view& drho, const WallGeometry<D, Real, ExecSpace>& walls,
           const MorrisWallFactor<Real>& morris) const {
    using C = SphColumn<D>;
    const auto kernel = kernel_;
    const auto body = body_;
    const auto nbr = list.data();
    const Real support2 = kernel_.support2;
    Kokkos::parallel_for(
        "mesoflow::sph::pair_interactions", Kokkos::RangePolicy<ExecSpace>(0, rows.extent(0)),
        KOKKOS_LAMBDA(int row) {
          const int i = nbr.particle(row);
          Vec<D, Real> xi, ui;
          for (int d = 0; d < D; ++d) {
            xi[d] = rows(i, C::x + d);
            ui[d] = rows(i, C::u + d);
          }
          const Real inv_rho_i = rows(i, C::inv_rho);
          const Real p_rho2_i = rows(i, C::p_over_rho2);
          const Real mu_i = rows(i, C::mu);
          const int ti = type(i);
          [[maybe_unused]] const bool wall_i = is_fixed(ti);
          double rate = 0;
          double fi[D] = {};
          int j_in[chunk];
          Vec<D, Real> dr_in[chunk];
          Real r2_in[chunk];
          const int nn = nbr.num_neighbors(row);
          const bool image_free = region.contains(xi);
          for (int k0 = 0; k0 < nn; k0 += chunk) {
            const int k1 = nn - k0 < chunk ? nn : k0 + chunk;
            const int kept = image_free ? screen<false>(rows, nbr, box, row, k0, k1, xi, support2, j_in, dr_in, r2_in)
                                        : screen<true>(rows, nbr, box, row, k0, k1, xi, support2, j_in, dr_in, r2_in);
            for (int q = 0; q < kept; ++q) {
              const int j = j_in[q];
              const Vec<D, Real> dr = dr_in[q];
              const Real dW_over_r = kernel.derivative_over_r(kmath::sqrt(r2_in[q]));
              Vec<D, Real> uij;
              for (int d = 0; d < D; ++d) uij[d] = ui[d] - rows(j, C::u + d);
              const Real m_j = rows(j, C::mass);
              rate += double(ContinuityDensity<D, Real>::rate(m_j, dW_over_r, dr, uij));
              Vec<D, Real> vij = uij;
              // `if`, not `if constexpr`: nvcc rejects a KOKKOS_LAMBDA whose first use of a captured
              // variable is inside `if constexpr` (the condition is a compile-time constant all the same).
              if (Morris) {
                if (wall_i != is_fixed(type(j))) vij *= wall_factor(wall_i, i, j, dr, walls, morris);
              }
              const Vec<D, Real> fij = PressureViscousForce<D, Real>::pair(
                  m_j, p_rho2_i, rows(j, C::p_over_rho2), mu_i, rows(j, C::mu), inv_rho_i, rows(j, C::inv_rho),
                  dW_over_r, dr, vij);
              for (int d = 0; d < D; ++d) fi[d] += double(fij[d]);
            }
          }
          const double m_i = double(rows(i, C::mass));
          for (int d = 0; d < D; ++d) f(i, d) = Real(m_i * (fi[d] + double(body.component(ti, d))));
          drho(i) = Real(rate);
        });
  }

  // Half list: per pair T_ij = (pressure + viscous term of eq. 5)/m_j, antisymmetric, and the
  // symmetric rate factor of eq. (4); i gains m_j T_ij and m_j R_ij, j loses m_i T_ij and gains
  // m_i R_ij. acc(i) holds Σ_j f_ij/m_i (D columns) and ρ̇_i (column D).
  template <bool Morris>
  void run_half(const SphRows<D, Real, ExecSpace>& rows, const int_view& type,
                const NeighborList<D, Real, ExecSpace>& list, const Box<D, Real>& box,
                const ImageFreeRegion<D, Real, ExecSpace>& region, const vector_view& f, const scalar_view& drho,
                const WallGeometry<D, Real, ExecSpace>& walls,
                const MorrisWallFactor<Real>& morris) {
    using C = SphColumn<D>;
    const int n = int(rows.extent(0));
    if (int(acc_.extent(0)) != n) {
      acc_ = Kokkos::View<double* [D + 1], ExecSpace>("mesoflow::sph::pair_sums", n);
      scatter_ = Kokkos::Experimental::create_scatter_view(acc_);
    }
    const auto acc = acc_;
    Kokkos::parallel_for(
        "mesoflow::sph::zero_pair_sums", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) {
          for (int d = 0; d <= D; ++d) acc(i, d) = 0.0;
        });
    scatter_.reset_except(acc_);
    auto scatter = scatter_;
    const auto kernel = kernel_;
    const auto nbr = list.data();
    const Real support2 = kernel_.support2;
    Kokkos::parallel_for(
        "mesoflow::sph::pair_interactions_half", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int row) {
          auto access = scatter.access();
          const int i = nbr.particle(row);
          Vec<D, Real> xi, ui;
          for (int d = 0; d < D; ++d) {
            xi[d] = rows(i, C::x + d);
            ui[d] = rows(i, C::u + d);
          }
          const Real m_i = rows(i, C::mass);
          const Real inv_rho_i = rows(i, C::inv_rho);
          const Real p_rho2_i = rows(i, C::p_over_rho2);
          const Real mu_i = rows(i, C::mu);
          [[maybe_unused]] const bool wall_i = Morris ? is_fixed(type(i)) : false;
          double rate = 0;
          double fi[D] = {};
          int j_in[chunk];
          Vec<D, Real> dr_in[chunk];
          Real r2_in[chunk];
          const int nn = nbr.num_neighbors(row);
          const bool image_free = region.contains(xi);
          for (int k0 = 0; k0 < nn; k0 += chunk) {
            const int k1 = nn - k0 < chunk ? nn : k0 + chunk;
            const int kept = image_free ? screen<false>(rows, nbr, box, row, k0, k1, xi, support2, j_in, dr_in, r2_in)
                                        : screen<true>(rows, nbr, box, row, k0, k1, xi, support2, j_in, dr_in, r2_in);
            for (int q = 0; q < kept; ++q) {
              const int j = j_in[q];
              const Vec<D, Real> dr = dr_in[q];
              const Real dW_over_r = kernel.derivative_over_r(kmath::sqrt(r2_in[q]));
              Vec<D, Real> uij;
              for (int d = 0; d < D; ++d) uij[d] = ui[d] - rows(j, C::u + d);
              const Real m_j = rows(j, C::mass);
              const Real r_ij = ContinuityDensity<D, Real>::rate(Real(1), dW_over_r, dr, uij);
              rate += double(m_j * r_ij);
              Vec<D, Real> vij = uij;
              // `if`, not `if constexpr`: nvcc rejects a KOKKOS_LAMBDA whose first use of a captured
              // variable is inside `if constexpr` (the condition is a compile-time constant all the same).
              if (Morris) {
                if (wall_i != is_fixed(type(j))) vij *= wall_factor(wall_i, i, j, dr, walls, morris);
              }
              const Vec<D, Real> t_ij = PressureViscousForce<D, Real>::pair(
                  Real(1), p_rho2_i, rows(j, C::p_over_rho2), mu_i, rows(j, C::mu), inv_rho_i, rows(j, C::inv_rho),
                  dW_over_r, dr, vij);
              for (int d = 0; d < D; ++d) {
                fi[d] += double(m_j * t_ij[d]);
                access(j, d) -= double(m_i * t_ij[d]);
              }
              access(j, D) += double(m_i * r_ij);
            }
          }
          for (int d = 0; d < D; ++d) access(i, d) += fi[d];
          access(i, D) += rate;
        });
    Kokkos::Experimental::contribute(acc_, scatter_);
    const auto body = body_;
    const auto m = Kokkos::subview(rows, Kokkos::ALL, int(C::mass));
    Kokkos::parallel_for(
        "mesoflow::sph::unpack_pair_sums", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) {
          const int ti = type(i);
          for (int d = 0; d < D; ++d) f(i, d) = Real(double(m(i)) * (acc(i, d) + double(body.component(ti, d))));
          drho(i) = Real(acc(i, D));
        });
  }

  // Morris' β for the viscous term of a fluid–wall pair (i, j), dr = x_i − x_j: the wall particle's
  // normal and depth give the fluid particle's distance from the wall surface (no_slip_walls.hpp).
  KOKKOS_INLINE_FUNCTION static Real wall_factor(bool wall_i, int i, int j, const Vec<D, Real>& dr,
                                                 const WallGeometry<D, Real, ExecSpace>& walls,
                                                 const MorrisWallFactor<Real>& morris) {
    const int w = wall_i ? i : j;
    Real offset = 0;  // (x_fluid − x_wall)·n_wall
    for (int d = 0; d < D; ++d) offset += dr[d] * walls(w, d);
    return morris(wall_i ? -offset : offset, walls(w, int(wall_depth_column<D>)));  // a copy: not odr-used on the device
  }

 private:
  Kernel kernel_;
  BodyForce<D, Real> body_;
  Kokkos::View<double* [D + 1], ExecSpace> acc_;
  Kokkos::View<Real, ExecSpace> overhang_;  // largest distance of a particle outside the box (ImageFreeRegion)
  decltype(Kokkos::Experimental::create_scatter_view(Kokkos::View<double* [D + 1], ExecSpace>())) scatter_;
};

}  // namespace mesoflow::sph
