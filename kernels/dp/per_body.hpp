// per_body.hpp — per-body coefficients for the DP terms: every droplet of a batch carries its own
// Γ, K_l, b∞ and b0 (issue 25 item 3: all the points of a sweep advance in the same launches).
//
// No physics of its own: PerBody<Term> holds one evaluator of a shape term (line_tension.hpp,
// segment_spring_force.hpp, ...) per body and hands vertex i's stencil to its body's, so the
// arithmetic of each body is exactly that of the uniform term with the body's coefficient (a
// droplet gives bitwise the same forces in a mixed batch as alone). PerBodySurfaceTerm<Term> does the
// same for a surface term (near_wall_drag.hpp, vertex_wall_repulsion.hpp) through the particle's body.
#pragma once

#include "vertex_stencil.hpp"

#include "kernels/common/kokkos_compat.hpp"
#include "kernels/common/surface_force.hpp"

#include <stdexcept>
#include <string>
#include <vector>

namespace mesoflow::dp {

// A shape term with one evaluator per body: terms(b) acts on the vertices of body b.
template <class Term, class ExecSpace = Kokkos::DefaultExecutionSpace>
struct PerBody {
  Kokkos::View<const Term*, ExecSpace> terms;

  template <class Real>
  KOKKOS_INLINE_FUNCTION ForceEnergy<Real> evaluate(const VertexStencil<Real>& s, const BodyShape<Real>& body) const {
    return terms(body.index).evaluate(s, body);
  }
};

// A surface term (nearest-surface or pairwise, surface_force.hpp) with one evaluator per body:
// particle i uses terms(body(i)).
template <class Term, class Real, class ExecSpace = Kokkos::DefaultExecutionSpace>
struct PerBodySurfaceTerm {
  static constexpr bool per_particle = true;
  static constexpr bool pairwise = surface_force_detail::IsPairwise<Term>::value;

  Kokkos::View<const int*, ExecSpace> body;  // body of each particle
  Kokkos::View<const Term*, ExecSpace> terms;
  Real largest_reach = 0;                    // max over the bodies of terms(b).reach() (pairwise terms)

  Real reach() const { return largest_reach; }

  KOKKOS_INLINE_FUNCTION void evaluate(int i, const SurfacePoint<2, Real>& s, const Vec<2, Real>& v,
                                       Vec<2, Real>& force, double& energy) const {
    terms(body(i)).evaluate(s, v, force, energy);
  }
  KOKKOS_INLINE_FUNCTION void evaluate_pair(int i, const SurfacePoint<2, Real>& s, Vec<2, Real>& force,
                                            double& energy) const {
    terms(body(i)).evaluate_pair(s, force, energy);
  }
};

// Host: a device View holding `terms` (one per body).
template <class Term, class ExecSpace = Kokkos::DefaultExecutionSpace>
Kokkos::View<Term*, ExecSpace> per_body_view(const std::string& label, const std::vector<Term>& terms) {
  if (terms.empty()) throw std::invalid_argument(label + ": no bodies");
  Kokkos::View<Term*, ExecSpace> view(label, terms.size());
  const auto host = Kokkos::create_mirror_view(view);
  for (std::size_t b = 0; b < terms.size(); ++b) host(b) = terms[b];
  Kokkos::deep_copy(view, host);
  return view;
}

}  // namespace mesoflow::dp
