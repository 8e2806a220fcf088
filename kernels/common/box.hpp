// box.hpp — orthorhombic simulation box, periodic or bounded independently along each axis.
#pragma once

#include "kokkos_compat.hpp"
#include "vec.hpp"

#include <stdexcept>
#include <string>

namespace mesoflow {

namespace box_detail {
// dr mapped into [−L/2, L/2): the nearest image by a floor, then the last rounding folded back.
// With fused multiply-add (nvcc contracts dr·(1/L) + ½ into one FMA by default) the floor can land
// one image off for |dr| within round-off of L/2, (k + ½)L; the comparisons make the half-open
// interval exact on every backend, whatever the compiler contracts.
template <class Real>
KOKKOS_INLINE_FUNCTION Real minimum_image_axis(Real dr, Real length, Real inv_length) {
  dr -= length * kmath::floor(dr * inv_length + Real(0.5));
  const Real half = Real(0.5) * length;
  return dr >= half ? dr - length : (dr < -half ? dr + length : dr);
}

// The nearest image without the tie-break at ±L/2 (which image a separation of exactly L/2 gets
// may depend on FMA contraction): for pair loops, whose cutoff is below L/2, so that no pair within
// it is anywhere near the tie, and whose innermost loop the two comparisons would slow (by 10% in
// the Lennard-Jones loop, BM_PairForceLJ).
template <class Real>
KOKKOS_INLINE_FUNCTION Real nearest_image_axis(Real dr, Real length, Real inv_length) {
  return dr - length * kmath::floor(dr * inv_length + Real(0.5));
}

// The same for |dr| < 1.5 L: one conditional shift, no floor (exact by construction).
template <class Real>
KOKKOS_INLINE_FUNCTION Real minimum_image_near_axis(Real dr, Real length) {
  const Real half = Real(0.5) * length;
  return dr - (dr >= half ? length : (dr < -half ? -length : Real(0)));
}
}  // namespace box_detail

// What the minimum-image convention needs of a Box (per-axis length, 1/length, periodicity): the
// pair loops capture this (56 bytes in 3D double) rather than the whole Box. Its minimum_image()
// leaves the tie at ±L/2 unresolved (see nearest_image_axis); minimum_image_near() resolves it.
template <int D, class Real>
struct PeriodicImages {
  Real length[D];
  Real inv_length[D];
  bool periodic[D];

  // The nearest image, ties at ±L/2 unresolved (box_detail::nearest_image_axis): pair loops only.
  KOKKOS_INLINE_FUNCTION void minimum_image(Vec<D, Real>& dr) const {
    for (int d = 0; d < D; ++d)
      if (periodic[d]) dr[d] = box_detail::nearest_image_axis(dr[d], length[d], inv_length[d]);
  }
  KOKKOS_INLINE_FUNCTION void minimum_image_near(Vec<D, Real>& dr) const {
    for (int d = 0; d < D; ++d)
      if (periodic[d]) dr[d] = box_detail::minimum_image_near_axis(dr[d], length[d]);
  }
};

template <int D, class Real>
struct Box {
  Real lo[D];
  Real length[D];
  Real inv_length[D];
  bool periodic[D];

  Box() = default;

  // Box [lo, lo + length) per axis; `periodic[d]` false means the axis is bounded (by walls) and
  // no image convention applies along it.
  Box(const Real (&lo_)[D], const Real (&length_)[D], const bool (&periodic_)[D]) {
    for (int d = 0; d < D; ++d) {
      if (!(length_[d] > Real(0)))
        throw std::invalid_argument("box: edge length along axis " + std::to_string(d) +
                                    " must be > 0, got " + std::to_string(length_[d]));
      lo[d] = lo_[d];
      length[d] = length_[d];
      inv_length[d] = Real(1) / length_[d];
      periodic[d] = periodic_[d];
    }
  }

  // Cube/square [0, L)^D, periodic or not on all axes.
  static Box cube(Real L, bool is_periodic) {
    Real lo_[D], len[D];
    bool per[D];
    for (int d = 0; d < D; ++d) {
      lo_[d] = 0;
      len[d] = L;
      per[d] = is_periodic;
    }
    return Box(lo_, len, per);
  }

  Real volume() const {
    Real v = 1;
    for (int d = 0; d < D; ++d) v *= length[d];
    return v;
  }

  // Minimum-image convention on the periodic axes: maps a separation into [-L/2, L/2).
  KOKKOS_INLINE_FUNCTION void minimum_image(Vec<D, Real>& dr) const {
    for (int d = 0; d < D; ++d)
      if (periodic[d]) dr[d] = box_detail::minimum_image_axis(dr[d], length[d], inv_length[d]);
  }

  // The same map for separations known to satisfy |dr| < 1.5 L on the periodic axes (two points
  // each at most L/4 outside the box, as between neighbor-list rebuilds): one conditional shift
  // per axis instead of a floor, for the innermost pair loops. Picks the same image as minimum_image().
  KOKKOS_INLINE_FUNCTION void minimum_image_near(Vec<D, Real>& dr) const {
    for (int d = 0; d < D; ++d)
      if (periodic[d]) dr[d] = box_detail::minimum_image_near_axis(dr[d], length[d]);
  }

  PeriodicImages<D, Real> images() const {
    PeriodicImages<D, Real> m;
    for (int d = 0; d < D; ++d) {
      m.length[d] = length[d];
      m.inv_length[d] = inv_length[d];
      m.periodic[d] = periodic[d];
    }
    return m;
  }

  // Position folded into [lo, lo + L) on the periodic axes; bounded axes are left alone.
  KOKKOS_INLINE_FUNCTION void wrap(Vec<D, Real>& x) const {
    for (int d = 0; d < D; ++d)
      if (periodic[d]) {
        x[d] -= length[d] * kmath::floor((x[d] - lo[d]) * inv_length[d]);
        if (x[d] >= lo[d] + length[d]) x[d] = lo[d];  // x just below lo rounds up to lo + L
      }
  }
};

}  // namespace mesoflow
