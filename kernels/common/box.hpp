// box.hpp — orthorhombic simulation box, periodic or bounded independently along each axis.
#pragma once

#include "kokkos_compat.hpp"
#include "vec.hpp"

#include <stdexcept>
#include <string>

namespace mesoflow {

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
      if (periodic[d]) dr[d] -= length[d] * kmath::floor(dr[d] * inv_length[d] + Real(0.5));
  }

  // The same map for separations known to satisfy |dr| < 1.5 L on the periodic axes (two points
  // each at most L/4 outside the box, as between neighbor-list rebuilds): one conditional shift
  // per axis instead of a floor, for the innermost pair loops. Identical to minimum_image() except
  // for separations within round-off of ±L/2, where both images are equally near.
  KOKKOS_INLINE_FUNCTION void minimum_image_near(Vec<D, Real>& dr) const {
    for (int d = 0; d < D; ++d)
      if (periodic[d]) {
        const Real half = Real(0.5) * length[d];
        dr[d] -= dr[d] >= half ? length[d] : (dr[d] < -half ? -length[d] : Real(0));
      }
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
