// rigid_discs.hpp — rigid discs in the 2D MPC solvent (the flattened droplets of Appendix B;
// Götze & Gompper, PRE 84, 031404 (2011)): storage, the coarse bin grid used to find the discs
// near a point, and Newton's equations for their translation and rotation.
//
// Monodisperse discs of radius R, mass M and moment of inertia I = M R²/2 (uniform disc). Per disc:
// centre X (folded into the box on its periodic axes), velocity U, angular velocity Ω (scalar,
// about the z axis), the force F of the steric terms (eq. B.4, disc_wca.hpp), and `impulse`
// = (J_x, J_y, L_z): the momentum and angular momentum about X the disc received from the solvent
// during the current MPC step (bounce-back, disc_bounce_back.hpp, and virtual particles after the
// collision, virtual_particles.hpp), summed in double.
//
// One MPC step of a disc (the scheme of ChannelFlow::step):
//   X ← X + h U                                          (before the solvent streams)
//   U ← [U + J/M + h F(X)/M] / (1 + γ h / M)             (after the collision)
//   Ω ← Ω + L/I
// The wall friction F_friction = −γ U (Appendix B) is taken implicitly (backward Euler), which is
// stable for any γ h/M (γ h/M = 0.03 in the paper's scene but > 1 in small test systems); with
// γ = 0 the update is U + (J + h F)/M, so solvent + discs conserve momentum exactly when the
// steric forces are pairwise equal and opposite (no walls). No torque acts besides the solvent's.
#pragma once

#include "../common/kernel_launch.hpp"
#include "kernels/common/box.hpp"
#include "kernels/common/cell_list.hpp"
#include "kernels/common/kokkos_compat.hpp"
#include "kernels/common/reductions.hpp"
#include "kernels/common/vec.hpp"
#include "kernels/mpc/collision_grid.hpp"

#include <array>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace mesoflow::mpc {

// The box of a 2D collision grid, for the minimum image and wrapping of disc positions.
template <class Real>
Box<2, Real> box_of(const CollisionGrid<2, Real>& grid) {
  const Real lo[2] = {grid.lo[0], grid.lo[1]}, length[2] = {grid.length[0], grid.length[1]};
  const bool periodic[2] = {grid.periodic[0] != 0, grid.periodic[1] != 0};
  return Box<2, Real>(lo, length, periodic);
}

// Device-copyable view of the disc bins: calls f(k) for every disc k whose bin is the bin of a
// point or one of its (up to 8) neighbours, each bin once, in a fixed order. Every disc whose
// centre is within one bin width of the point (minimum image) is visited. Points are expected in
// the box (folded on periodic axes, as mpc::stream and RigidDiscs::move leave them); a point
// slightly outside is binned into the nearest edge bin, which keeps the search exact. Bins and
// images are found without floor(): a cast and a comparison, this being the inner loop of the
// disc bounce-back.
template <class Real, class ExecSpace>
struct DiscBinsView {
  CellGrid<2, Real> grid;
  Box<2, Real> box;
  Kokkos::View<int*, ExecSpace> offset, slots;

  // Minimum image of a − b for two points in the box: |a − b| < 1.5 L on a periodic axis, folded
  // into [−L/2, L/2] (exactly antisymmetric in a and b).
  KOKKOS_INLINE_FUNCTION Vec<2, Real> separation(const Vec<2, Real>& a, const Vec<2, Real>& b) const {
    Vec<2, Real> d = a - b;
    for (int k = 0; k < 2; ++k)
      if (box.periodic[k]) {
        const Real half = Real(0.5) * box.length[k];
        d[k] = d[k] > half ? d[k] - box.length[k] : (d[k] < -half ? d[k] + box.length[k] : d[k]);
      }
    return d;
  }

  template <class F>
  KOKKOS_INLINE_FUNCTION void for_each_near(const Vec<2, Real>& p, F&& f) const {
    int c[2], first[2], last[2];
    for (int d = 0; d < 2; ++d) {
      const Real t = (p[d] - grid.lo[d]) * grid.inv_width[d];
      c[d] = t < Real(0) ? 0 : (t >= Real(grid.n[d]) ? grid.n[d] - 1 : int(t));
      if (box.periodic[d] && grid.n[d] < 3) {  // every bin along this axis, once
        first[d] = 0;
        last[d] = grid.n[d] - 1;
        c[d] = 0;
      } else {
        first[d] = -1;
        last[d] = 1;
      }
    }
    for (int oy = first[1]; oy <= last[1]; ++oy)
      for (int ox = first[0]; ox <= last[0]; ++ox) {
        int b[2] = {c[0] + ox, c[1] + oy};
        bool inside = true;
        for (int d = 0; d < 2; ++d) {
          if (box.periodic[d]) {
            b[d] = b[d] < 0 ? b[d] + grid.n[d] : (b[d] >= grid.n[d] ? b[d] - grid.n[d] : b[d]);
          } else if (b[d] < 0 || b[d] >= grid.n[d]) {
            inside = false;
          }
        }
        if (!inside) continue;
        const int bin = grid.index(b);
        for (int s = offset(bin); s < offset(bin + 1); ++s) f(slots(s));
      }
  }
};

template <class Real, class ExecSpace>
class RigidDiscs {
 public:
  using vector_view = Kokkos::View<Real* [2], Kokkos::LayoutLeft, ExecSpace>;
  using scalar_view = Kokkos::View<Real*, ExecSpace>;
  using impulse_view = Kokkos::View<double* [3], Kokkos::LayoutRight, ExecSpace>;

  // n discs of radius R and mass M in `box`, at rest at the origin; bins of width ≥ bin_width
  // (≥ 2R, and ≥ the range of any pair term that uses the bins).
  RigidDiscs(std::size_t n, Real radius, Real mass, const Box<2, Real>& box, Real bin_width)
      : x("mesoflow::mpc::discs::x", n),
        u("mesoflow::mpc::discs::u", n),
        omega("mesoflow::mpc::discs::omega", n),
        force("mesoflow::mpc::discs::force", n),
        impulse("mesoflow::mpc::discs::impulse", n),
        radius_(radius),
        mass_(mass),
        inertia_(Real(0.5) * mass * radius * radius),
        box_(box),
        bin_width_(bin_width) {
    if (!(radius > Real(0)) || !std::isfinite(double(radius)))
      throw std::invalid_argument("rigid discs: radius must be finite and > 0, got " + std::to_string(double(radius)));
    if (!(mass > Real(0)) || !std::isfinite(double(mass)))
      throw std::invalid_argument("rigid discs: mass must be finite and > 0, got " + std::to_string(double(mass)));
    if (!(bin_width >= Real(2) * radius))
      throw std::invalid_argument("rigid discs: bin width " + std::to_string(double(bin_width)) +
                                  " must be >= 2R = " + std::to_string(double(2 * radius)));
    build_bins();
  }

  std::size_t size() const { return x.extent(0); }
  Real radius() const { return radius_; }
  Real mass() const { return mass_; }
  Real inertia() const { return inertia_; }
  Real bin_width() const { return bin_width_; }
  const Box<2, Real>& box() const { return box_; }

  // Sets the centres (host values, folded into the box) and rebuilds the bins; velocities and
  // angular velocities are left as they are.
  void set_positions(const std::vector<std::array<Real, 2>>& centres) {
    if (centres.size() != size())
      throw std::invalid_argument("rigid discs: " + std::to_string(centres.size()) + " centres for " +
                                  std::to_string(size()) + " discs");
    const auto h = Kokkos::create_mirror_view(x);
    for (std::size_t k = 0; k < size(); ++k) {
      Vec<2, Real> c{{centres[k][0], centres[k][1]}};
      box_.wrap(c);
      h(k, 0) = c[0];
      h(k, 1) = c[1];
    }
    Kokkos::deep_copy(x, h);
    build_bins();
  }

  // Bins the current centres (a counting sort, no allocation at a fixed disc count).
  void build_bins() { bins_.build(x, box_, bin_width_); }
  DiscBinsView<Real, ExecSpace> bins() const {
    return DiscBinsView<Real, ExecSpace>{bins_.grid(), box_, bins_.cell_offset(), bins_.cell_particles()};
  }

  // X ← X + h U, folded into the box, then the bins are rebuilt.
  void move(Real h) {
    const auto X = x;
    const auto U = u;
    const auto box = box_;
    mesoflow::launch::parallel_for(
        "mesoflow::mpc::discs::move", Kokkos::RangePolicy<ExecSpace>(0, size()), KOKKOS_LAMBDA(int k) {
          Vec<2, Real> c{{X(k, 0) + h * U(k, 0), X(k, 1) + h * U(k, 1)}};
          box.wrap(c);
          c.store(X, k);
        });
    build_bins();
  }

  // force ← 0 and impulse ← 0: the start of a step's accumulation.
  void clear_accumulators() const {
    const auto F = force;
    const auto J = impulse;
    mesoflow::launch::parallel_for(
        "mesoflow::mpc::discs::clear", Kokkos::RangePolicy<ExecSpace>(0, size()), KOKKOS_LAMBDA(int k) {
          F(k, 0) = F(k, 1) = Real(0);
          J(k, 0) = J(k, 1) = J(k, 2) = 0.0;
        });
  }

  // U ← [U + J/M + h F/M] / (1 + γ h/M), Ω ← Ω + L/I (see the file comment), γ ≥ 0 the wall
  // friction coefficient.
  void update_velocities(Real h, Real gamma) const {
    if (!(gamma >= Real(0))) throw std::invalid_argument("rigid discs: friction gamma must be >= 0");
    const auto U = u;
    const auto W = omega;
    const auto F = force;
    const auto J = impulse;
    const double inv_m = 1.0 / double(mass_), inv_i = 1.0 / double(inertia_);
    const double damping = 1.0 / (1.0 + double(gamma) * double(h) * inv_m);
    const double dt = double(h);
    mesoflow::launch::parallel_for(
        "mesoflow::mpc::discs::update_velocities", Kokkos::RangePolicy<ExecSpace>(0, size()),
        KOKKOS_LAMBDA(int k) {
          for (int d = 0; d < 2; ++d)
            U(k, d) = Real((double(U(k, d)) + (J(k, d) + dt * double(F(k, d))) * inv_m) * damping);
          W(k) = Real(double(W(k)) + J(k, 2) * inv_i);
        });
  }

  // Σ M U (host value, a reduction).
  std::array<double, 2> momentum() const {
    const auto U = u;
    const auto sum = parallel_sum<2, ExecSpace>("mesoflow::mpc::discs::momentum", int(size()),
                                                KOKKOS_LAMBDA(int k, double(&acc)[2]) {
                                                  acc[0] += double(U(k, 0));
                                                  acc[1] += double(U(k, 1));
                                                });
    return {double(mass_) * sum[0], double(mass_) * sum[1]};
  }

  vector_view x, u;
  scalar_view omega;
  vector_view force;
  impulse_view impulse;

 private:
  Real radius_, mass_, inertia_;
  Box<2, Real> box_;
  Real bin_width_;
  CellList<2, Real, ExecSpace> bins_;
};

}  // namespace mesoflow::mpc
