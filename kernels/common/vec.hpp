// vec.hpp — a small fixed-size vector for use inside kernels (loaded from / stored to SoA Views).
#pragma once

#include <Kokkos_Core.hpp>

namespace mesoflow {

template <int D, class Real>
struct Vec {
  static_assert(D == 2 || D == 3, "mesoflow supports 2D and 3D");
  Real c[D];

  KOKKOS_INLINE_FUNCTION Real& operator[](int d) { return c[d]; }
  KOKKOS_INLINE_FUNCTION const Real& operator[](int d) const { return c[d]; }

  KOKKOS_INLINE_FUNCTION static Vec zero() {
    Vec r;
    for (int d = 0; d < D; ++d) r.c[d] = Real(0);
    return r;
  }
  // Row i of an (n × D) View.
  template <class View>
  KOKKOS_INLINE_FUNCTION static Vec load(const View& v, int i) {
    Vec r;
    for (int d = 0; d < D; ++d) r.c[d] = v(i, d);
    return r;
  }
  template <class View>
  KOKKOS_INLINE_FUNCTION void store(const View& v, int i) const {
    for (int d = 0; d < D; ++d) v(i, d) = c[d];
  }
  KOKKOS_INLINE_FUNCTION Vec& operator+=(const Vec& o) {
    for (int d = 0; d < D; ++d) c[d] += o.c[d];
    return *this;
  }
  KOKKOS_INLINE_FUNCTION Vec& operator-=(const Vec& o) {
    for (int d = 0; d < D; ++d) c[d] -= o.c[d];
    return *this;
  }
  KOKKOS_INLINE_FUNCTION Vec& operator*=(Real s) {
    for (int d = 0; d < D; ++d) c[d] *= s;
    return *this;
  }
};

template <int D, class Real>
KOKKOS_INLINE_FUNCTION Vec<D, Real> operator+(Vec<D, Real> a, const Vec<D, Real>& b) {
  return a += b;
}
template <int D, class Real>
KOKKOS_INLINE_FUNCTION Vec<D, Real> operator-(Vec<D, Real> a, const Vec<D, Real>& b) {
  return a -= b;
}
template <int D, class Real>
KOKKOS_INLINE_FUNCTION Vec<D, Real> operator*(Real s, Vec<D, Real> a) {
  return a *= s;
}
template <int D, class Real>
KOKKOS_INLINE_FUNCTION Real dot(const Vec<D, Real>& a, const Vec<D, Real>& b) {
  Real s = 0;
  for (int d = 0; d < D; ++d) s += a.c[d] * b.c[d];
  return s;
}
template <int D, class Real>
KOKKOS_INLINE_FUNCTION Real norm2(const Vec<D, Real>& a) {
  return dot(a, a);
}

}  // namespace mesoflow
