// sph_pair_interactions.hpp — the SPH pair interactions, one evaluator of the generic pair loop
// (kernels/common/pair_force.hpp): the density rate of eq. (4)
// (continuity_density.hpp) and the pressure + viscous force of eq. (5) (pressure_viscous_force.hpp),
// plus the body force, in a single pass over a full neighbor list. Both sums need the same pairs at
// the same positions and extrapolated velocities (sph_integrator.hpp), so fusing them reads each
// pair once and evaluates the kernel gradient once.
//
// Full list: each row sums its own particle's ρ̇ and force in list order — deterministic for any
// thread count, no atomics. Half list: each pair once — one kernel gradient and one pair term for
// both ends, the pair terms being antisymmetric (pressure and viscous) or symmetric (density rate)
// in i ↔ j — with j's share scattered through a ScatterView (duplicated per thread on OpenMP, so
// reproducible at a fixed thread count, atomic on GPUs). Sums accumulate in double whatever Real
// is (the pressure terms of a nearly uniform fluid cancel to a small remainder).
//
// Walls (particle_types.hpp) show their own velocity in the viscous term, or, with a wall geometry,
// the fluid velocity extrapolated through their surface (Morris et al. 1997, no_slip_walls.hpp);
// only that variant reads the particle types per pair.
//
// Every particle's per-pair data is gathered from one packed row (LayoutRight, as the MDPD pair
// loop does, packed_state.hpp there): position, extrapolated velocity ū, mass, 1/ρ, p/ρ² and
// dynamic viscosity μ; pack_sph_rows() fills them once per step and evaluates the equation of
// state, eq. (6), on the way.
//
// A row is read a chunk of list entries at a time: a branch-free screen keeps the entries within
// the kernel support (a quarter of a list of skin 10% lies beyond it), and the pair terms run over
// the kept ones only, so no branch depends on a distance (a mispredicted one per dropped entry
// cost more than the pair terms' arithmetic). Rows of particles in the ImageFreeRegion, away from
// the periodic faces, skip the minimum image. Neither changes a bit of the sums.
#pragma once

#include "../common/kernel_launch.hpp"
#include "continuity_density.hpp"
#include "no_slip_walls.hpp"
#include "kernels/common/box.hpp"
#include "kernels/common/neighbor_list.hpp"
#include "kernels/common/pair_force.hpp"
#include "kernels/common/particles.hpp"
#include "particle_types.hpp"
#include "pressure_viscous_force.hpp"
#include "tait_equation_of_state.hpp"

#include <Kokkos_ScatterView.hpp>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace mesoflow::sph {

// Columns of a packed row.
template <int D>
struct SphColumn {
  // Enumerators, not static constexpr ints: Kokkos 3's View takes indices by reference, and nvcc has
  // no device copy of a host variable to refer to.
  enum : int {
    x = 0,            // position, D columns
    u = D,            // extrapolated velocity ū, D columns
    mass = 2 * D,
    inv_rho = 2 * D + 1,
    p_over_rho2 = 2 * D + 2,
    mu = 2 * D + 3,   // dynamic viscosity
    width = 2 * D + 4
  };
};

template <int D, class Real, class ExecSpace>
using SphRows = Kokkos::View<Real* [SphColumn<D>::width], Kokkos::LayoutRight, ExecSpace>;

// Per wall particle: the unit normal into the fluid and the depth below the wall surface
// (no_slip_walls.hpp); rows of fluid particles are not read.
template <int D, class Real, class ExecSpace>
using WallGeometry = Kokkos::View<Real* [D + 1], Kokkos::LayoutRight, ExecSpace>;

// The part of the box at least (kernel support + overhang) inside every periodic face, where the
// overhang is the largest distance of any particle outside the box (SphSystem wraps positions at
// each list rebuild, so it stays below half the skin): a particle j within the support of a
// particle i in it lies within the box extended by the overhang only at its nearest image, so
// x_i − x_j needs no minimum image. Unbounded along the other axes. lo and hi hold the bounds
// without the overhang, which stays on the device (reduced there each step, no host sync).
template <int D, class Real, class ExecSpace>
struct ImageFreeRegion {
  Real lo[D], hi[D];
  Kokkos::View<const Real, ExecSpace> overhang;
  KOKKOS_INLINE_FUNCTION bool contains(const Vec<D, Real>& x) const {
    const Real margin = overhang() > Real(0) ? overhang() : Real(0);
    bool inside = true;
    for (int d = 0; d < D; ++d) inside = inside && x[d] >= lo[d] + margin && x[d] <= hi[d] - margin;
    return inside;
  }
};

// rows(i) ← (x_i, ū_i, m_i, 1/ρ_i, p_i/ρ_i², μ_i) and pressure(i) ← p(ρ_i) (eq. 6).
template <int D, class Real, class ExecSpace>
void pack_sph_rows(const Particles<D, Real, ExecSpace>& p,
                   const typename Particles<D, Real, ExecSpace>::vector_view& u_bar,
                   const Kokkos::View<Real*, ExecSpace>& rho, const Kokkos::View<Real*, ExecSpace>& mu,
                   const TaitEquationOfState<Real>& eos, const SphRows<D, Real, ExecSpace>& rows,
                   const Kokkos::View<Real*, ExecSpace>& pressure) {
  using C = SphColumn<D>;
  const auto x = p.x;
  const auto m = p.mass;
  mesoflow::launch::parallel_for(
      "mesoflow::sph::pack_rows", Kokkos::RangePolicy<ExecSpace>(0, p.size()), KOKKOS_LAMBDA(int i) {
        const Real rho_i = rho(i);
        const Real inv_rho = Real(1) / rho_i;
        const Real p_i = eos.pressure(rho_i);
        for (int d = 0; d < D; ++d) {
          rows(i, C::x + d) = x(i, d);
          rows(i, C::u + d) = u_bar(i, d);
        }
        rows(i, C::mass) = m(i);
        rows(i, C::inv_rho) = inv_rho;
        rows(i, C::p_over_rho2) = p_i * inv_rho * inv_rho;
        rows(i, C::mu) = mu(i);
        pressure(i) = p_i;
      });
}

// Eqs. (4)–(5) as an evaluator of the generic pair loop: the loop screens chunks of entries at the
// kernel support and skips the minimum image in ImageFreeRegion rows. Compile-time switches: the
// list tag and Morris (wall geometry present).
//
// Full rows sum ρ̇_i and f_i/m_i in double and write f_i (with the body force) and ρ̇_i. Half rows:
// per pair T_ij = (pressure + viscous term of eq. 5)/m_j, antisymmetric, and the symmetric rate
// factor of eq. (4); i gains m_j T_ij and m_j R_ij, j loses m_i T_ij and gains m_i R_ij, through
// `acc` (Σ_j f_ij/m_i in D columns, ρ̇_i in column D), unpacked after the loop.
template <bool Morris, int D, class Real, class ExecSpace, class Kernel>
struct SphPairEvaluator : PairEvaluatorTraits {
  static constexpr MinimumImage image = MinimumImage::near;
  static constexpr PairScreen screen = PairScreen::chunked;
  static constexpr bool image_free_rows = true;
  using C = SphColumn<D>;
  using vector_view = typename Particles<D, Real, ExecSpace>::vector_view;
  using acc_view = Kokkos::View<double* [D + 1], ExecSpace>;
  using acc_scatter = PairScatter<acc_view>;
  Kernel kernel;
  BodyForce<D, Real> body;
  Real cutoff2;  // the kernel support²
  ImageFreeRegion<D, Real, ExecSpace> region;
  SphRows<D, Real, ExecSpace> rows;
  Kokkos::View<int*, ExecSpace> type;
  WallGeometry<D, Real, ExecSpace> walls;
  MorrisWallFactor<Real> morris;
  vector_view f;                              // full lists
  Kokkos::View<Real*, ExecSpace> drho;        // full lists
  typename acc_scatter::scatter_view scatter;  // half lists

  KOKKOS_INLINE_FUNCTION bool image_free(const Vec<D, Real>& xi) const { return region.contains(xi); }

  // Morris' β for the viscous term of a fluid–wall pair (i, j), dr = x_i − x_j: the wall particle's
  // normal and depth give the fluid particle's distance from the wall surface (no_slip_walls.hpp).
  KOKKOS_INLINE_FUNCTION Real wall_factor(bool wall_i, int i, int j, const Vec<D, Real>& dr) const {
    const int w = wall_i ? i : j;
    Real offset = 0;  // (x_fluid − x_wall)·n_wall
    for (int d = 0; d < D; ++d) offset += dr[d] * walls(w, d);
    return morris(wall_i ? -offset : offset, walls(w, int(wall_depth_column<D>)));  // a copy: not odr-used on the device
  }

  struct FullRow {
    Vec<D, Real> ui;
    Real inv_rho_i, p_rho2_i, mu_i;
    int ti;
    bool wall_i;
    double rate;
    double fi[D];
  };
  struct HalfRow {
    typename acc_scatter::access_type access;
    Vec<D, Real> ui;
    Real m_i, inv_rho_i, p_rho2_i, mu_i;
    bool wall_i;
    double rate;
    double fi[D];
  };

  KOKKOS_INLINE_FUNCTION Vec<D, Real> velocity(int i) const {
    Vec<D, Real> u;
    for (int d = 0; d < D; ++d) u[d] = rows(i, C::u + d);
    return u;
  }

  KOKKOS_INLINE_FUNCTION FullRow begin(FullList, int i) const {
    const int ti = type(i);
    FullRow s{velocity(i), rows(i, C::inv_rho), rows(i, C::p_over_rho2), rows(i, C::mu), ti, is_fixed(ti), 0.0, {}};
    for (int d = 0; d < D; ++d) s.fi[d] = 0.0;
    return s;
  }
  KOKKOS_INLINE_FUNCTION void operator()(FullList, FullRow& s, int i, int j, const Vec<D, Real>& dr, Real r2,
                                         double&) const {
    const Real dW_over_r = kernel.derivative_over_r(kmath::sqrt(r2));
    Vec<D, Real> uij;
    for (int d = 0; d < D; ++d) uij[d] = s.ui[d] - rows(j, C::u + d);
    const Real m_j = rows(j, C::mass);
    s.rate += double(ContinuityDensity<D, Real>::rate(m_j, dW_over_r, dr, uij));
    Vec<D, Real> vij = uij;
    if (Morris) {
      if (s.wall_i != is_fixed(type(j))) vij *= wall_factor(s.wall_i, i, j, dr);
    }
    const Vec<D, Real> fij =
        PressureViscousForce<D, Real>::pair(m_j, s.p_rho2_i, rows(j, C::p_over_rho2), s.mu_i, rows(j, C::mu),
                                            s.inv_rho_i, rows(j, C::inv_rho), dW_over_r, dr, vij);
    for (int d = 0; d < D; ++d) s.fi[d] += double(fij[d]);
  }
  KOKKOS_INLINE_FUNCTION void end(FullList, FullRow& s, int i, double&) const {
    const double m_i = double(rows(i, C::mass));
    for (int d = 0; d < D; ++d) f(i, d) = Real(m_i * (s.fi[d] + double(body.component(s.ti, d))));
    drho(i) = Real(s.rate);
  }

  KOKKOS_INLINE_FUNCTION HalfRow begin(HalfList, int i) const {
    HalfRow s{scatter.access(), velocity(i), rows(i, C::mass), rows(i, C::inv_rho), rows(i, C::p_over_rho2),
              rows(i, C::mu), Morris ? is_fixed(type(i)) : false, 0.0, {}};
    for (int d = 0; d < D; ++d) s.fi[d] = 0.0;
    return s;
  }
  KOKKOS_INLINE_FUNCTION void operator()(HalfList, HalfRow& s, int i, int j, const Vec<D, Real>& dr, Real r2,
                                         double&) const {
    const Real dW_over_r = kernel.derivative_over_r(kmath::sqrt(r2));
    Vec<D, Real> uij;
    for (int d = 0; d < D; ++d) uij[d] = s.ui[d] - rows(j, C::u + d);
    const Real m_j = rows(j, C::mass);
    const Real r_ij = ContinuityDensity<D, Real>::rate(Real(1), dW_over_r, dr, uij);
    s.rate += double(m_j * r_ij);
    Vec<D, Real> vij = uij;
    if (Morris) {
      if (s.wall_i != is_fixed(type(j))) vij *= wall_factor(s.wall_i, i, j, dr);
    }
    const Vec<D, Real> t_ij =
        PressureViscousForce<D, Real>::pair(Real(1), s.p_rho2_i, rows(j, C::p_over_rho2), s.mu_i, rows(j, C::mu),
                                            s.inv_rho_i, rows(j, C::inv_rho), dW_over_r, dr, vij);
    for (int d = 0; d < D; ++d) {
      s.fi[d] += double(m_j * t_ij[d]);
      s.access(j, d) -= double(s.m_i * t_ij[d]);
    }
    s.access(j, D) += double(s.m_i * r_ij);
  }
  KOKKOS_INLINE_FUNCTION void end(HalfList, HalfRow& s, int i, double&) const {
    for (int d = 0; d < D; ++d) s.access(i, d) += s.fi[d];
    s.access(i, D) += s.rate;
  }
};

template <int D, class Real, class ExecSpace, class Kernel>
class SphPairInteractions {
 public:
  using vector_view = typename Particles<D, Real, ExecSpace>::vector_view;
  using scalar_view = Kokkos::View<Real*, ExecSpace>;
  using int_view = Kokkos::View<int*, ExecSpace>;

  SphPairInteractions(const Kernel& kernel, const BodyForce<D, Real>& body) : kernel_(kernel), body_(body) {}

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
    mesoflow::launch::parallel_reduce(
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

  // run and run_half are implementation details, public only because nvcc rejects a KOKKOS_LAMBDA
  // in a private or protected member function.
  template <bool Morris>
  SphPairEvaluator<Morris, D, Real, ExecSpace, Kernel> evaluator(
      const SphRows<D, Real, ExecSpace>& rows, const int_view& type, const ImageFreeRegion<D, Real, ExecSpace>& region,
      const WallGeometry<D, Real, ExecSpace>& walls, const MorrisWallFactor<Real>& morris) const {
    return {{}, kernel_, body_, kernel_.support2, region, rows, type, walls, morris, {}, {}, {}};
  }

  template <bool Morris>
  void run(const SphRows<D, Real, ExecSpace>& rows, const int_view& type, const NeighborList<D, Real, ExecSpace>& list,
           const Box<D, Real>& box, const ImageFreeRegion<D, Real, ExecSpace>& region, const vector_view& f,
           const scalar_view& drho, const WallGeometry<D, Real, ExecSpace>& walls,
           const MorrisWallFactor<Real>& morris) const {
    auto ev = evaluator<Morris>(rows, type, region, walls, morris);
    ev.f = f;
    ev.drho = drho;
    for_each_pair("mesoflow::sph::pair_interactions", FullList{}, list, box, rows, ev);
  }

  template <bool Morris>
  void run_half(const SphRows<D, Real, ExecSpace>& rows, const int_view& type,
                const NeighborList<D, Real, ExecSpace>& list, const Box<D, Real>& box,
                const ImageFreeRegion<D, Real, ExecSpace>& region, const vector_view& f, const scalar_view& drho,
                const WallGeometry<D, Real, ExecSpace>& walls, const MorrisWallFactor<Real>& morris) {
    using C = SphColumn<D>;
    const int n = int(rows.extent(0));
    if (int(acc_.extent(0)) != n) acc_ = Kokkos::View<double* [D + 1], ExecSpace>("mesoflow::sph::pair_sums", n);
    const auto acc = acc_;
    mesoflow::launch::parallel_for(
        "mesoflow::sph::zero_pair_sums", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) {
          for (int d = 0; d <= D; ++d) acc(i, d) = 0.0;
        });
    auto ev = evaluator<Morris>(rows, type, region, walls, morris);
    ev.scatter = scatter_.prepare(acc_);
    for_each_pair("mesoflow::sph::pair_interactions_half", HalfList{}, list, box, rows, ev);
    scatter_.contribute(acc_);
    const auto body = body_;
    const auto m = Kokkos::subview(rows, Kokkos::ALL, int(C::mass));
    mesoflow::launch::parallel_for(
        "mesoflow::sph::unpack_pair_sums", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) {
          const int ti = type(i);
          for (int d = 0; d < D; ++d) f(i, d) = Real(double(m(i)) * (acc(i, d) + double(body.component(ti, d))));
          drho(i) = Real(acc(i, D));
        });
  }

 private:
  Kernel kernel_;
  BodyForce<D, Real> body_;
  Kokkos::View<double* [D + 1], ExecSpace> acc_;
  Kokkos::View<Real, ExecSpace> overhang_;  // largest distance of a particle outside the box (ImageFreeRegion)
  PairScatter<Kokkos::View<double* [D + 1], ExecSpace>> scatter_;
};

}  // namespace mesoflow::sph
