// disc_bounce_back.hpp — no-slip coupling of the MPC solvent to moving rigid discs in the streaming
// step: bounce-back on the moving surface, v' = −v + 2 v_b (Appendix B; Padding & Louis, PRE 74,
// 031402 (2006), for moving bodies), with the surface velocity v_b = U + Ω × (r_c − X).
//
// Runs after the discs moved (RigidDiscs::move, bins rebuilt) and the solvent streamed
// (mpc::stream, then the wall bounce-back). A particle now inside disc k (|x − X_k| < R, minimum
// image; candidates from the disc bins, never all discs) is treated relative to the disc's new
// centre, along its straight path from the old position x − h v:
//  * old position outside: the crossing point r_c on the segment (the first root of
//    |r_old + t v| = R), v' = −v + 2 v_b(r_c), and the particle streams from r_c with v' for the
//    remaining time;
//  * old position inside (swept by the moving disc): it is put on the surface, r_c = R r/|r| (the
//    radial projection of its position), with the same velocity rule and no further streaming.
// Where the remaining streaming leaves it inside (a disc moving or spinning faster than the
// particle leaves), it is projected radially onto the surface. Points on the surface are put at
// R (1 + 8ε) so that rounding does not leave them inside.
//
// The momentum change Δp = m(v' − v) is taken from the disc: impulse −Δp and angular impulse
// −(r_c − X) × Δp, added to RigidDiscs::impulse through a ScatterView (thread-duplicated on
// OpenMP, where the static RangePolicy gives every duplicate a fixed set of particles in a fixed
// order, so the sums are reproducible at a fixed thread count; atomic on GPUs, not reproducible).
// With `deterministic` (the deterministic-sum mode, issue 26 item 4) each particle's Δp is stored
// instead, the particles are ordered by the disc they hit (kernels/common/segment_order.hpp) and each
// disc sums its particles' impulses in index order: bitwise the same on every backend and thread
// count, for a sort of the particles per step.
// Particles that cross a disc entirely within one step, or that a bounce moves into another disc or
// through a wall, are not treated (the step moves particles by h|v| ≪ R and ≪ the gaps).
#pragma once

#include "../common/kernel_launch.hpp"
#include "kernels/common/kokkos_compat.hpp"
#include "kernels/common/segment_order.hpp"
#include "kernels/common/vec.hpp"
#include "kernels/mpc/rigid_discs.hpp"

#include <Kokkos_ScatterView.hpp>

#include <algorithm>
#include <optional>
#include <stdexcept>
#include <type_traits>

namespace mesoflow::mpc {

// The bounce-back of one particle on one disc, in the disc's frame (r = x − X). Returns the
// contact point r_c; r and v are replaced by the new relative position and velocity.
template <class Real>
KOKKOS_INLINE_FUNCTION Vec<2, Real> bounce_on_disc(Vec<2, Real>& r, Vec<2, Real>& v, Real h, Real radius,
                                                   const Vec<2, Real>& disc_velocity, Real disc_omega) {
  constexpr Real epsilon = std::is_same<Real, float>::value ? Real(1.1920928955078125e-07) : Real(2.220446049250313e-16);
  const Real outward = Real(1) + Real(8) * epsilon;
  const Real r2 = radius * radius;
  const Vec<2, Real> r_old = r - h * v;
  Vec<2, Real> rc;
  Real t_rest = Real(0);
  const Real c = norm2(r_old) - r2;
  if (c >= Real(0)) {
    // |r_old + t v|² = R²: a t² + 2 b t + c = 0, c ≥ 0, the smaller root.
    const Real a = norm2(v), b = dot(r_old, v);
    const Real disc = b * b - a * c;
    Real t = a > Real(0) ? (-b - kmath::sqrt(disc > Real(0) ? disc : Real(0))) / a : h;
    t = t < Real(0) ? Real(0) : (t > h ? h : t);
    rc = r_old + t * v;
    t_rest = h - t;
  } else {
    const Real len = kmath::sqrt(norm2(r));
    rc = len > Real(0) ? (radius / len) * r : Vec<2, Real>{{radius, Real(0)}};
  }
  const Vec<2, Real> vb{{disc_velocity[0] - disc_omega * rc[1], disc_velocity[1] + disc_omega * rc[0]}};
  v = Real(2) * vb - v;
  r = rc + t_rest * v;
  const Real len2 = norm2(r);
  if (len2 < r2 * outward * outward) {
    const Real len = kmath::sqrt(len2);
    r = len > Real(0) ? (radius * outward / len) * r : Vec<2, Real>{{radius * outward, Real(0)}};
  }
  return rc;
}

// Particle i of (x, v) after a streaming step h: if it is inside a disc (candidates from the disc
// bins), bounces it (bounce_on_disc), stores its new x and v and returns the disc with the particle's
// Δp = m (v' − v) and angular Δp (r_c × Δp) in dp[3]; −1 (and x, v untouched) otherwise. The one
// per-particle body of both DiscBounceBack paths.
template <class Real, class ExecSpace, class VectorView, class DiscVectors, class DiscScalars>
KOKKOS_INLINE_FUNCTION int bounce_particle(int i, const VectorView& x, const VectorView& v, Real h,
                                           const DiscBinsView<Real, ExecSpace>& bins, const DiscVectors& X,
                                           const DiscVectors& U, const DiscScalars& W, Real radius, Real m,
                                           double (&dp)[3]) {
  const Vec<2, Real> xi = Vec<2, Real>::load(x, i);
  int hit = -1;
  Vec<2, Real> r;
  bins.for_each_near(xi, [&](int k) {
    if (hit >= 0) return;
    const Vec<2, Real> dr = bins.separation(xi, Vec<2, Real>::load(X, k));
    if (norm2(dr) < radius * radius) {
      hit = k;
      r = dr;
    }
  });
  if (hit < 0) return -1;
  const Vec<2, Real> v_old = Vec<2, Real>::load(v, i);
  Vec<2, Real> vi = v_old;
  const Vec<2, Real> rc = bounce_on_disc(r, vi, h, radius, Vec<2, Real>::load(U, hit), W(hit));
  Vec<2, Real> xn = Vec<2, Real>::load(X, hit) + r;
  bins.box.wrap(xn);
  xn.store(x, i);
  vi.store(v, i);
  dp[0] = double(m) * (double(vi[0]) - double(v_old[0]));
  dp[1] = double(m) * (double(vi[1]) - double(v_old[1]));
  dp[2] = double(rc[0]) * dp[1] - double(rc[1]) * dp[0];
  return hit;
}

template <class Real, class ExecSpace>
class DiscBounceBack {
 public:
  using vector_view = Kokkos::View<Real* [2], Kokkos::LayoutLeft, ExecSpace>;

  // `mass`: the solvent particle mass m. The scatter view is created here, once; with
  // `deterministic`, the per-particle buffers and the sorter at the first apply().
  DiscBounceBack(const RigidDiscs<Real, ExecSpace>& discs, Real mass, bool deterministic = false)
      : mass_(mass),
        deterministic_(deterministic),
        scatter_(Kokkos::Experimental::create_scatter_view(discs.impulse)),
        target_(discs.impulse.data()) {
    if (!(mass > Real(0))) throw std::invalid_argument("disc bounce-back: mass must be > 0");
  }

  bool deterministic() const { return deterministic_; }

  // Bounce-back of every row of (x, v) after a streaming step of length h (see the file comment);
  // adds the discs' impulses to discs.impulse (which must be the view given to the constructor).
  void apply(const vector_view& x, const vector_view& v, Real h, const RigidDiscs<Real, ExecSpace>& discs) {
    if (discs.size() == 0) return;
    if (discs.impulse.data() != target_)
      throw std::invalid_argument("disc bounce-back: not the discs given to the constructor");
    if (deterministic_) {
      apply_sorted(x, v, h, discs);
      return;
    }
    scatter_.reset_except(discs.impulse);
    auto scatter = scatter_;
    const auto bins = discs.bins();
    const auto X = discs.x;
    const auto U = discs.u;
    const auto W = discs.omega;
    const Real radius = discs.radius(), m = mass_;
    mesoflow::launch::parallel_for(
        "mesoflow::mpc::disc_bounce_back", Kokkos::RangePolicy<ExecSpace>(0, x.extent(0)), KOKKOS_LAMBDA(int i) {
          double dp[3];
          const int hit = bounce_particle<Real, ExecSpace>(i, x, v, h, bins, X, U, W, radius, m, dp);
          if (hit < 0) return;
          auto access = scatter.access();
          for (int c = 0; c < 3; ++c) access(hit, c) -= dp[c];
        });
    auto impulse = discs.impulse;
    Kokkos::Experimental::contribute(impulse, scatter_);
  }

  // apply() in the deterministic-sum mode; public only because nvcc rejects a KOKKOS_LAMBDA in a
  // private member function.
  void apply_sorted(const vector_view& x, const vector_view& v, Real h, const RigidDiscs<Real, ExecSpace>& discs) {
    const int n = int(x.extent(0)), nd = int(discs.size());
    if (!order_ || order_->rows() != std::max(n, 1) || order_->segments() != nd) {  // first use, or resized
      order_.emplace(std::max(n, 1), nd);
      hit_ = Kokkos::View<int*, ExecSpace>(Kokkos::ViewAllocateWithoutInitializing("mesoflow::mpc::disc_hit"),
                                           std::size_t(std::max(n, 1)));
      dp_ = Kokkos::View<double* [3], Kokkos::LayoutRight, ExecSpace>(
          Kokkos::ViewAllocateWithoutInitializing("mesoflow::mpc::disc_dp"), std::size_t(std::max(n, 1)));
    }
    const auto hit_of = hit_;
    const auto dp = dp_;
    const auto bins = discs.bins();
    const auto X = discs.x;
    const auto U = discs.u;
    const auto W = discs.omega;
    const Real radius = discs.radius(), m = mass_;
    mesoflow::launch::parallel_for(
        "mesoflow::mpc::disc_bounce_back_store", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) {
          double d[3];
          const int hit = bounce_particle<Real, ExecSpace>(i, x, v, h, bins, X, U, W, radius, m, d);
          hit_of(i) = hit;
          if (hit >= 0)
            for (int c = 0; c < 3; ++c) dp(i, c) = d[c];
        });
    order_->sort(n, hit_of);
    const auto order = order_->view();
    const auto impulse = discs.impulse;
    mesoflow::launch::parallel_for(
        "mesoflow::mpc::disc_impulse_sums", Kokkos::RangePolicy<ExecSpace>(0, nd), KOKKOS_LAMBDA(int k) {
          double s[3] = {0.0, 0.0, 0.0};
          for (int q = order.begin(k); q < order.end(k); ++q) {
            const int i = order.row(q);
            if (i >= n || hit_of(i) != k) continue;  // rows of no disc, dealt to this one
            for (int c = 0; c < 3; ++c) s[c] -= dp(i, c);
          }
          for (int c = 0; c < 3; ++c) impulse(k, c) += s[c];
        });
  }

 private:
  Real mass_;
  bool deterministic_;
  Kokkos::Experimental::ScatterView<double* [3], Kokkos::LayoutRight, ExecSpace> scatter_;
  const double* target_;
  std::optional<SegmentOrder<ExecSpace>> order_;  // the deterministic mode's: particles by disc
  Kokkos::View<int*, ExecSpace> hit_;             // disc hit by each particle this step, or −1
  Kokkos::View<double* [3], Kokkos::LayoutRight, ExecSpace> dp_;  // its Δp and angular Δp
};

}  // namespace mesoflow::mpc
