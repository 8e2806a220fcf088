// virtual_particles.hpp — virtual particles that extend the collision cells cut by a boundary into
// the boundary (Appendix B; Lamura et al., Europhys. Lett. 56, 319 (2001) for walls; Götze,
// Noguchi & Gompper, PRE 76, 046705 (2007) for bodies). In each collision step the part of the
// cut cells that lies in the boundary is filled with virtual particles at the mean solvent density
// n, with Maxwell–Boltzmann velocities at k_BT plus the boundary velocity; they take part in the
// cell sums of the collision (MpcCollision::collide with xv, vv), which makes the mean velocity of
// a cut cell relax towards the boundary's and removes the slip of bounce-back alone. Their momentum
// change m(v_after − v_before) is what the boundary took up from the solvent.
//
// Walls (WallVirtualParticles, D = 2, 3): the walls of ChannelWalls bound axis 1. With the grid
// shift s = shift_1, the bottom row of cells covers y ∈ [lo − s, lo − s + a), its part
// [lo − s, lo) (width w_b = s) lies in the wall; the row containing the top wall y_t = lo + L
// covers up to y_t + w_t with w_t = (k + 1) a − s − L, k = ⌊(L + s)/a⌋ (w_t = a, a row entirely
// beyond the wall, counts as no cut). Every cell of a cut row receives
//   N_w = ⌊n w/a + u_w⌋
// virtual particles, uniform in the covered part, with one u_w uniform in [0, 1) per wall and
// step: ⟨N_w⟩ = n w/a (the covered volume's share of n), the count is known on the host without a
// transfer, and at most ⌈n⌉ per cell (the fixed capacity 2 ⌈n⌉ × cells per row).
//
// Discs (DiscVirtualParticles, 2D): each disc is filled in the layer R − √2 a < |r − X| < R
// (width √2 a, the cell diagonal: the part of the disc inside every cell its surface cuts), with
//   N_d = ⌊n A/a² + u_d⌋,  A = π(R² − (R − √2 a)²)  (R > √2 a),
// per disc, one u_d per step, positions uniform in the annulus, velocities Maxwell–Boltzmann plus
// the rigid-body velocity U + Ω × (r − X). The momentum change of a disc's virtual particles and
// its moment about X go to RigidDiscs::impulse (each disc sums its own rows in order: deterministic
// for any thread count).
//
// Random numbers (tags reserved for these kernels):
//   counts:    RandomStream(seed, step, virtual_count, 0) → u_w (bottom, top); (…, 1) → u_d
//   walls:     RandomStream(seed, step, wall_virtual, cell, i) for virtual particle i of a cell
//              (cell = index within the row, + cells per row for the top wall)
//   discs:     RandomStream(seed, step, disc_virtual, disc, i)
#pragma once

#include "../common/kernel_launch.hpp"
#include "kernels/common/kokkos_compat.hpp"
#include "kernels/common/random.hpp"
#include "kernels/common/vec.hpp"
#include "kernels/mpc/collision_grid.hpp"
#include "kernels/mpc/rigid_discs.hpp"
#include "kernels/mpc/wall_bounce_back.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace mesoflow::mpc {

namespace boundary_stream_tag {
constexpr std::uint32_t virtual_count = stream_tag::user + 20;
constexpr std::uint32_t wall_virtual = stream_tag::user + 21;
constexpr std::uint32_t disc_virtual = stream_tag::user + 22;
}  // namespace boundary_stream_tag

namespace virtual_detail {
inline void check_common(double density, double kT, double mass) {
  if (!(density > 0) || !std::isfinite(density))
    throw std::invalid_argument("virtual particles: density n must be finite and > 0, got " + std::to_string(density));
  if (!(kT >= 0) || !std::isfinite(kT))
    throw std::invalid_argument("virtual particles: kT must be finite and >= 0, got " + std::to_string(kT));
  if (!(mass > 0) || !std::isfinite(mass))
    throw std::invalid_argument("virtual particles: mass must be finite and > 0, got " + std::to_string(mass));
}
}  // namespace virtual_detail

template <int D, class Real, class ExecSpace>
class WallVirtualParticles {
 public:
  using vector_view = Kokkos::View<Real* [D], Kokkos::LayoutLeft, ExecSpace>;

  // `density`: n, solvent particles per cell (a^D); kT, mass: of the solvent; the walls of
  // ChannelWalls on `grid` (axis 1 walled).
  WallVirtualParticles(const CollisionGrid<D, Real>& grid, Real density, Real kT, Real mass, std::uint64_t seed)
      : density_(density), kT_(kT), mass_(mass), seed_(seed) {
    virtual_detail::check_common(double(density), double(kT), double(mass));
    if (grid.periodic[1]) throw std::invalid_argument("wall virtual particles: axis 1 of the grid must be walled");
    cells_per_row_ = cells_per_row(grid);
    per_cell_capacity_ = std::size_t(std::ceil(double(density)));
    v_before_ = vector_view(Kokkos::ViewAllocateWithoutInitializing("mesoflow::mpc::wall_virtual::v_before"),
                            capacity());
  }

  std::size_t capacity() const { return 2 * cells_per_row_ * per_cell_capacity_; }
  // The same bound before construction (to size the collision's buffers).
  static std::size_t capacity(const CollisionGrid<D, Real>& grid, Real density) {
    return 2 * cells_per_row(grid) * std::size_t(std::ceil(double(density)));
  }
  // Virtual particles per cell of the bottom / top row in the last generate().
  std::size_t per_cell(int wall) const { return wall == 0 ? count_[0] : count_[1]; }
  std::size_t count() const { return cells_per_row_ * (count_[0] + count_[1]); }

  // Fills rows [offset, offset + count()) of xv, vv for the current shift of `grid` and returns
  // count(): bottom-wall particles first, cell by cell.
  std::size_t generate(const CollisionGrid<D, Real>& grid, const vector_view& xv, const vector_view& vv,
                       std::size_t offset, std::uint64_t step) {
    const double a = double(grid.a), L = double(grid.length[1]), s = double(grid.shift[1]);
    const double w_bottom = s;
    const double k_top = std::floor((L + s) / a);
    double w_top = (k_top + 1) * a - s - L;
    if (!(w_top < a)) w_top = 0;
    RandomStream rs(seed_, step, boundary_stream_tag::virtual_count, 0);
    const double u_bottom = 1.0 - rs.uniform<double>(), u_top = 1.0 - rs.uniform<double>();  // [0, 1)
    count_[0] = std::size_t(std::floor(double(density_) * w_bottom / a + u_bottom));
    count_[1] = std::size_t(std::floor(double(density_) * w_top / a + u_top));
    for (int w = 0; w < 2; ++w)
      if (count_[w] > per_cell_capacity_) count_[w] = per_cell_capacity_;  // n w/a + u < n + 1 up to rounding
    const std::size_t n_bottom = cells_per_row_ * count_[0], n_total = count();
    if (offset + n_total > xv.extent(0) || offset + n_total > vv.extent(0))
      throw std::length_error("wall virtual particles: views too short");
    if (n_total == 0) return 0;

    const auto g = grid;
    const auto vb = v_before_;
    const std::size_t cb = count_[0], ct = count_[1], row_cells = cells_per_row_;
    // The covered slabs along y: [lo − s, lo) and [lo + L, lo + L + w_t).
    const Kokkos::Array<Real, 2> slab_lo{Real(double(grid.lo[1]) - s), Real(double(grid.lo[1]) + L)};
    const Kokkos::Array<Real, 2> slab_hi{grid.lo[1], Real(double(grid.lo[1]) + L + w_top)};
    const std::uint64_t seed = seed_;
    const Real speed = Real(std::sqrt(double(kT_) / double(mass_)));
    mesoflow::launch::parallel_for(
        "mesoflow::mpc::wall_virtual::generate", Kokkos::RangePolicy<ExecSpace>(0, n_total),
        KOKKOS_LAMBDA(const std::size_t q) {
          const int wall = q < n_bottom ? 0 : 1;
          const std::size_t local = wall == 0 ? q : q - n_bottom;
          const std::size_t per = wall == 0 ? cb : ct;
          const std::size_t cell = local / per, index = local % per;
          RandomStream rs(seed, step, boundary_stream_tag::wall_virtual,
                          static_cast<std::uint32_t>(cell + std::size_t(wall) * row_cells),
                          static_cast<std::uint32_t>(index));
          std::size_t rest = cell;
          for (int d = 0; d < D; ++d) {
            Real xd;
            if (d == 1) {
              xd = rs.template uniform_in<Real>(slab_lo[wall], slab_hi[wall]);
            } else {
              const std::size_t k = rest % std::size_t(g.n[d]);
              rest /= std::size_t(g.n[d]);
              const Real lower = g.lo[d] - g.shift[d] + Real(k) * g.a;
              xd = rs.template uniform_in<Real>(lower, lower + g.a);
              if (xd < g.lo[d]) xd += g.length[d];
              if (xd >= g.lo[d] + g.length[d]) xd = g.lo[d];
            }
            xv(offset + q, d) = xd;
          }
          for (int d = 0; d < D; ++d) {
            const Real vd = speed * rs.template normal<Real>();
            vv(offset + q, d) = vd;
            vb(q, d) = vd;
          }
        });
    return n_total;
  }

  // After the collision: the momentum change of rows [offset, offset + count()) of vv goes to the
  // walls (ChannelWalls::momentum()).
  void transfer(const vector_view& vv, std::size_t offset, const ChannelWalls<D, Real, ExecSpace>& walls) const {
    const std::size_t n_bottom = cells_per_row_ * count_[0];
    const auto vb = v_before_;
    const double m = double(mass_);
    walls.accumulate("mesoflow::mpc::wall_virtual::transfer", int(count()),
                     KOKKOS_LAMBDA(int q, double(&acc)[2 * D]) {
                       const int wall = std::size_t(q) < n_bottom ? 0 : 1;
                       for (int d = 0; d < D; ++d)
                         acc[wall * D + d] += m * (double(vv(offset + q, d)) - double(vb(q, d)));
                     });
  }

 private:
  static std::size_t cells_per_row(const CollisionGrid<D, Real>& grid) {
    std::size_t cells = 1;
    for (int d = 0; d < D; ++d)
      if (d != 1) cells *= std::size_t(grid.n[d]);
    return cells;
  }

  Real density_, kT_, mass_;
  std::uint64_t seed_;
  std::size_t cells_per_row_ = 0, per_cell_capacity_ = 0;
  std::size_t count_[2] = {0, 0};
  vector_view v_before_;
};

template <class Real, class ExecSpace>
class DiscVirtualParticles {
 public:
  using vector_view = Kokkos::View<Real* [2], Kokkos::LayoutLeft, ExecSpace>;

  // `cell_size`: a; `density`: n per cell; the discs' radius must exceed √2 a.
  DiscVirtualParticles(const RigidDiscs<Real, ExecSpace>& discs, Real cell_size, Real density, Real kT, Real mass,
                       std::uint64_t seed)
      : kT_(kT), mass_(mass), seed_(seed), num_discs_(discs.size()) {
    virtual_detail::check_common(double(density), double(kT), double(mass));
    const double R = double(discs.radius()), a = double(cell_size);
    inner_radius_ = R - std::sqrt(2.0) * a;
    if (!(inner_radius_ > 0))
      throw std::invalid_argument("disc virtual particles: the radius R = " + std::to_string(R) +
                                  " must exceed the layer width sqrt(2) a = " + std::to_string(std::sqrt(2.0) * a));
    mean_per_disc_ = mean_count(discs.radius(), cell_size, density);
    per_disc_capacity_ = std::size_t(std::floor(mean_per_disc_)) + 1;
    v_before_ = vector_view(Kokkos::ViewAllocateWithoutInitializing("mesoflow::mpc::disc_virtual::v_before"),
                            capacity());
  }

  std::size_t capacity() const { return num_discs_ * per_disc_capacity_; }
  // The same bound before construction (to size the collision's buffers).
  static std::size_t capacity(std::size_t num_discs, Real radius, Real cell_size, Real density) {
    return num_discs * (std::size_t(std::floor(mean_count(radius, cell_size, density))) + 1);
  }
  double mean_per_disc() const { return mean_per_disc_; }
  std::size_t per_disc() const { return per_disc_; }
  std::size_t count() const { return num_discs_ * per_disc_; }

  // Fills rows [offset, offset + count()) of xv, vv (disc 0's particles first) and returns count().
  std::size_t generate(const RigidDiscs<Real, ExecSpace>& discs, const vector_view& xv, const vector_view& vv,
                       std::size_t offset, std::uint64_t step) {
    if (discs.size() != num_discs_) throw std::invalid_argument("disc virtual particles: the disc count changed");
    RandomStream rs(seed_, step, boundary_stream_tag::virtual_count, 1);
    per_disc_ = std::size_t(std::floor(mean_per_disc_ + (1.0 - rs.uniform<double>())));
    if (per_disc_ > per_disc_capacity_) per_disc_ = per_disc_capacity_;
    const std::size_t n_total = count();
    if (offset + n_total > xv.extent(0) || offset + n_total > vv.extent(0))
      throw std::length_error("disc virtual particles: views too short");
    if (n_total == 0) return 0;
    const auto X = discs.x;
    const auto U = discs.u;
    const auto W = discs.omega;
    const auto box = discs.box();
    const auto vb = v_before_;
    const std::size_t per = per_disc_;
    const Real r_in2 = Real(inner_radius_ * inner_radius_);
    const Real r_out2 = discs.radius() * discs.radius();
    const std::uint64_t seed = seed_;
    const Real speed = Real(std::sqrt(double(kT_) / double(mass_)));
    mesoflow::launch::parallel_for(
        "mesoflow::mpc::disc_virtual::generate", Kokkos::RangePolicy<ExecSpace>(0, n_total),
        KOKKOS_LAMBDA(const std::size_t q) {
          const std::size_t k = q / per, index = q % per;
          RandomStream rs(seed, step, boundary_stream_tag::disc_virtual, static_cast<std::uint32_t>(k),
                          static_cast<std::uint32_t>(index));
          // Uniform in the annulus: r² uniform in [r_in², R²), angle uniform.
          const Real rho = kmath::sqrt(r_in2 + (r_out2 - r_in2) * (Real(1) - rs.template uniform<Real>()));
          const Real phi = Real(6.283185307179586476925) * rs.template uniform<Real>();
          const Vec<2, Real> r{{rho * kmath::cos(phi), rho * kmath::sin(phi)}};
          Vec<2, Real> p = Vec<2, Real>::load(X, int(k)) + r;
          box.wrap(p);
          p.store(xv, int(offset + q));
          const Real w = W(k);
          const Real vx = U(k, 0) - w * r[1] + speed * rs.template normal<Real>();
          const Real vy = U(k, 1) + w * r[0] + speed * rs.template normal<Real>();
          vv(offset + q, 0) = vb(q, 0) = vx;
          vv(offset + q, 1) = vb(q, 1) = vy;
        });
    return n_total;
  }

  // After the collision: the momentum change of each disc's virtual particles and its moment about
  // the centre are added to discs.impulse.
  void transfer(const vector_view& xv, const vector_view& vv, std::size_t offset,
                const RigidDiscs<Real, ExecSpace>& discs) const {
    const std::size_t per = per_disc_;
    if (per == 0) return;
    const auto X = discs.x;
    const auto J = discs.impulse;
    const auto box = discs.box();
    const auto vb = v_before_;
    const double m = double(mass_);
    mesoflow::launch::parallel_for(
        "mesoflow::mpc::disc_virtual::transfer", Kokkos::RangePolicy<ExecSpace>(0, num_discs_),
        KOKKOS_LAMBDA(const std::size_t k) {
          const Vec<2, Real> centre = Vec<2, Real>::load(X, int(k));
          double jx = 0, jy = 0, l = 0;
          for (std::size_t q = k * per; q < (k + 1) * per; ++q) {
            const double dpx = m * (double(vv(offset + q, 0)) - double(vb(q, 0)));
            const double dpy = m * (double(vv(offset + q, 1)) - double(vb(q, 1)));
            Vec<2, Real> r = Vec<2, Real>::load(xv, int(offset + q)) - centre;
            box.minimum_image(r);
            jx += dpx;
            jy += dpy;
            l += double(r[0]) * dpy - double(r[1]) * dpx;
          }
          J(k, 0) += jx;
          J(k, 1) += jy;
          J(k, 2) += l;
        });
  }

 private:
  // n A / a², A = π(R² − (R − √2 a)²).
  static double mean_count(Real radius, Real cell_size, Real density) {
    const double R = double(radius), a = double(cell_size), r_in = R - std::sqrt(2.0) * a;
    return double(density) * M_PI * (R * R - r_in * r_in) / (a * a);
  }

  Real kT_, mass_;
  std::uint64_t seed_;
  std::size_t num_discs_;
  double inner_radius_ = 0, mean_per_disc_ = 0;
  std::size_t per_disc_capacity_ = 0, per_disc_ = 0;
  vector_view v_before_;
};

}  // namespace mesoflow::mpc
