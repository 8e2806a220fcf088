// polygons.hpp — deformable polygons (DP model; capillary-droplets §2.2, hopper-flows §2.3):
// which vertices form which body, each body's preferred area a0 and edge length l0, per-body state
// (area, perimeter, centre of mass and its velocity), and the droplet study's shape observables.
//
// Layout: the vertices of body b occupy the contiguous range [offset(b), offset(b+1)) of a
// Particles set, counter-clockwise; N_v may differ between bodies, and a0, l0 are per body (the
// hopper study is bidisperse). The polygons' vertices come first in the particle set; free
// particles may follow them. Positions of one body must be contiguous in space, i.e. unwrapped:
// the shape terms take plain differences of vertex positions, so a periodic scene leaves DP
// vertices unfolded (neighbor and cell lists apply the minimum image and fold on their own).
#pragma once

#include "../common/kernel_launch.hpp"
#include "kernels/common/kokkos_compat.hpp"
#include "kernels/common/particles.hpp"
#include "kernels/common/vec.hpp"

#include <array>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace mesoflow::dp {

constexpr double pi = 3.14159265358979323846;

// The vertex k steps after (next_vertex) or before (prev_vertex) vertex i along the polygon whose
// vertices are [begin, begin + n), wrapping around within the body; 0 ≤ k ≤ n.
KOKKOS_INLINE_FUNCTION int next_vertex(int i, int k, int begin, int n) {
  return begin + (i - begin + k) % n;
}
KOKKOS_INLINE_FUNCTION int prev_vertex(int i, int k, int begin, int n) {
  return begin + (i - begin - k + n) % n;
}

// Edge length of the regular N_v-gon of area a0, the DP model's l0 (capillary-droplets §2.4):
// l0 = sqrt(4 a0 N_v tan(π/N_v)) / N_v.
inline double regular_polygon_edge(double a0, int nv) {
  return std::sqrt(4.0 * a0 * nv * std::tan(pi / nv)) / nv;
}

// Shape parameter 𝒜 = P² / (4π a): 1 for a circle, (N/π) tan(π/N) for a regular N-gon.
// Capillary-droplets §2.2 typesets it garbled, as "(Σ l_i)(N_v)²/(4πa)"; the definition that gives
// 𝒜 = 1 for a circle, and that hopper-flows §2.3 uses for the reference shape
// (𝒜0 = (N_v l0)² / (4π a0)), is P² / (4π a).
template <class Real>
KOKKOS_INLINE_FUNCTION Real shape_parameter(Real perimeter, Real area) {
  return perimeter * perimeter / (Real(4 * pi) * area);
}

template <class Real, class ExecSpace = Kokkos::DefaultExecutionSpace>
struct Polygons {
  using execution_space = ExecSpace;
  using int_view = Kokkos::View<int*, ExecSpace>;
  using scalar_view = Kokkos::View<Real*, ExecSpace>;

  int_view offset;     // n_bodies + 1 entries: body b owns vertices [offset(b), offset(b+1))
  int_view body;       // body of each vertex
  scalar_view a0, l0;  // preferred area and edge length of each body

  Polygons() = default;

  // n_bodies bodies of n_vertices vertices each, all with the same a0 and l0.
  static Polygons uniform(int n_bodies, int n_vertices, Real a0, Real l0) {
    if (n_bodies < 1) throw std::invalid_argument("dp::polygons: need at least one body");
    return from_vertex_counts(std::vector<int>(n_bodies, n_vertices), std::vector<Real>(n_bodies, a0),
                              std::vector<Real>(n_bodies, l0));
  }

  // One body per entry: vertex_counts[b] vertices (≥ 3), preferred area a0[b] and edge l0[b] (> 0).
  static Polygons from_vertex_counts(const std::vector<int>& vertex_counts, const std::vector<Real>& a0,
                                     const std::vector<Real>& l0) {
    const std::size_t nb = vertex_counts.size();
    if (nb == 0) throw std::invalid_argument("dp::polygons: need at least one body");
    if (a0.size() != nb || l0.size() != nb)
      throw std::invalid_argument("dp::polygons: " + std::to_string(nb) + " vertex counts but " +
                                  std::to_string(a0.size()) + " areas and " + std::to_string(l0.size()) +
                                  " edge lengths");
    Polygons p;
    p.offset_host_.assign(nb + 1, 0);
    for (std::size_t b = 0; b < nb; ++b) {
      if (vertex_counts[b] < 3)
        throw std::invalid_argument("dp::polygons: body " + std::to_string(b) + " has " +
                                    std::to_string(vertex_counts[b]) + " vertices, a polygon needs >= 3");
      if (!(a0[b] > Real(0)) || !(l0[b] > Real(0)))
        throw std::invalid_argument("dp::polygons: body " + std::to_string(b) + " needs a0 > 0 and l0 > 0");
      p.offset_host_[b + 1] = p.offset_host_[b] + vertex_counts[b];
    }
    p.a0_host_ = a0;
    p.l0_host_ = l0;

    p.offset = int_view("mesoflow::dp::polygons::offset", nb + 1);
    p.body = int_view("mesoflow::dp::polygons::body", p.offset_host_[nb]);
    p.a0 = scalar_view("mesoflow::dp::polygons::a0", nb);
    p.l0 = scalar_view("mesoflow::dp::polygons::l0", nb);
    auto offset_h = Kokkos::create_mirror_view(p.offset);
    auto body_h = Kokkos::create_mirror_view(p.body);
    auto a0_h = Kokkos::create_mirror_view(p.a0);
    auto l0_h = Kokkos::create_mirror_view(p.l0);
    for (std::size_t b = 0; b < nb; ++b) {
      offset_h(b) = p.offset_host_[b];
      a0_h(b) = a0[b];
      l0_h(b) = l0[b];
      for (int i = p.offset_host_[b]; i < p.offset_host_[b + 1]; ++i) body_h(i) = int(b);
    }
    offset_h(nb) = p.offset_host_[nb];
    Kokkos::deep_copy(p.offset, offset_h);
    Kokkos::deep_copy(p.body, body_h);
    Kokkos::deep_copy(p.a0, a0_h);
    Kokkos::deep_copy(p.l0, l0_h);
    return p;
  }

  int num_bodies() const { return int(offset_host_.size()) - 1; }
  int num_vertices() const { return offset_host_.back(); }

  // Host-side copies of the topology and reference shape.
  int first_vertex(int b) const { return offset_host_[b]; }
  int num_vertices(int b) const { return offset_host_[b + 1] - offset_host_[b]; }
  Real preferred_area(int b) const { return a0_host_[b]; }
  Real preferred_edge(int b) const { return l0_host_[b]; }

 private:
  std::vector<int> offset_host_{0};
  std::vector<Real> a0_host_, l0_host_;
};

// Particles::body ← the body of every polygon vertex (free particles after them are left alone).
template <class Real, class ExecSpace>
void assign_bodies(const Polygons<Real, ExecSpace>& polygons, const Particles<2, Real, ExecSpace>& p) {
  const int nv = polygons.num_vertices();
  if (int(p.size()) < nv)
    throw std::invalid_argument("dp::assign_bodies: the polygons have " + std::to_string(nv) +
                                " vertices but the particle set only " + std::to_string(p.size()));
  Kokkos::deep_copy(Kokkos::subview(p.body, std::make_pair(0, nv)), polygons.body);
}

// Places body b as the regular polygon of area a0(b) centred at `centre`, counter-clockwise, its
// first vertex at polar angle `angle` from the centre. Writes rows of a host (n × 2) View, in its
// precision (a mirror of Particles::x, or a double View to perturb before rounding); the edges
// then have length regular_polygon_edge(a0, N_v).
template <class Real, class ExecSpace, class HostPositions>
void place_regular_polygon(const Polygons<Real, ExecSpace>& polygons, int b, const HostPositions& x,
                           const Vec<2, double>& centre, double angle = 0.0) {
  using T = typename HostPositions::value_type;
  const int n = polygons.num_vertices(b);
  const int begin = polygons.first_vertex(b);
  // Area of a regular n-gon of circumradius R: (n/2) R² sin(2π/n).
  const double radius = std::sqrt(2.0 * double(polygons.preferred_area(b)) / (n * std::sin(2.0 * pi / n)));
  for (int k = 0; k < n; ++k) {
    const double theta = angle + 2.0 * pi * k / n;
    x(begin + k, 0) = T(centre[0] + radius * std::cos(theta));
    x(begin + k, 1) = T(centre[1] + radius * std::sin(theta));
  }
}

// Per-body quantities, refreshed by update_body_state.
template <class Real, class ExecSpace = Kokkos::DefaultExecutionSpace>
struct BodyState {
  using scalar_view = Kokkos::View<Real*, ExecSpace>;
  using vector_view = Kokkos::View<Real* [2], Kokkos::LayoutLeft, ExecSpace>;

  scalar_view area;          // a = ½ Σ (x_i y_{i+1} − x_{i+1} y_i)
  scalar_view perimeter;     // P = Σ l_i
  scalar_view mass;          // M = Σ M_i
  vector_view com;           // Σ M_i r_i / M
  vector_view com_velocity;  // Σ M_i v_i / M
  scalar_view kinetic_energy;  // E_k = Σ ½ M_i |v_i|² (capillary-droplets App. C, the clogging criterion)

  BodyState() = default;
  explicit BodyState(int n_bodies)
      : area("mesoflow::dp::body_state::area", n_bodies),
        perimeter("mesoflow::dp::body_state::perimeter", n_bodies),
        mass("mesoflow::dp::body_state::mass", n_bodies),
        com("mesoflow::dp::body_state::com", n_bodies),
        com_velocity("mesoflow::dp::body_state::com_velocity", n_bodies),
        kinetic_energy("mesoflow::dp::body_state::kinetic_energy", n_bodies) {}

  int num_bodies() const { return int(area.extent(0)); }
};

// Area, perimeter, mass, centre of mass, its velocity and the kinetic energy of every body, in one kernel over bodies:
// each body is summed by one thread in vertex order, in double, so the result is deterministic on
// any backend and thread count. The DP scenes batch many bodies (replicas of a droplet, or the
// hopper's particles) of a few dozen to a few hundred vertices each, so the bodies alone give the
// parallelism. A single huge body on a GPU would want a TeamPolicy variant instead (one team per
// body, a team reduction over its vertices).
// Sums are taken relative to the body's first vertex, so the area and centre keep their precision
// far from the origin.
template <class Real, class ExecSpace>
void update_body_state(const Polygons<Real, ExecSpace>& polygons, const Particles<2, Real, ExecSpace>& p,
                       const BodyState<Real, ExecSpace>& state) {
  if (state.num_bodies() != polygons.num_bodies())
    throw std::invalid_argument("dp::update_body_state: state for " + std::to_string(state.num_bodies()) +
                                " bodies, polygons have " + std::to_string(polygons.num_bodies()));
  if (int(p.size()) < polygons.num_vertices())
    throw std::invalid_argument("dp::update_body_state: the polygons have " +
                                std::to_string(polygons.num_vertices()) + " vertices but the particle set only " +
                                std::to_string(p.size()));
  const auto offset = polygons.offset;
  const auto x = p.x;
  const auto v = p.v;
  const auto m = p.mass;
  const auto area = state.area;
  const auto perimeter = state.perimeter;
  const auto mass = state.mass;
  const auto com = state.com;
  const auto com_velocity = state.com_velocity;
  const auto kinetic_energy = state.kinetic_energy;
  mesoflow::launch::parallel_for(
      "mesoflow::dp::body_state", Kokkos::RangePolicy<ExecSpace>(0, polygons.num_bodies()),
      KOKKOS_LAMBDA(int b) {
        const int begin = offset(b), end = offset(b + 1);
        const double x0 = x(begin, 0), y0 = x(begin, 1);
        double twice_area = 0, length = 0, mb = 0, mr[2] = {0, 0}, mv[2] = {0, 0}, twice_ke = 0;
        for (int i = begin; i < end; ++i) {
          const int j = i + 1 < end ? i + 1 : begin;
          const double xi = double(x(i, 0)) - x0, yi = double(x(i, 1)) - y0;
          const double xj = double(x(j, 0)) - x0, yj = double(x(j, 1)) - y0;
          twice_area += xi * yj - xj * yi;
          length += kmath::sqrt((xj - xi) * (xj - xi) + (yj - yi) * (yj - yi));
          const double mi = m(i);
          mb += mi;
          mr[0] += mi * xi;
          mr[1] += mi * yi;
          mv[0] += mi * double(v(i, 0));
          mv[1] += mi * double(v(i, 1));
          twice_ke += mi * (double(v(i, 0)) * double(v(i, 0)) + double(v(i, 1)) * double(v(i, 1)));
        }
        area(b) = Real(0.5 * twice_area);
        perimeter(b) = Real(length);
        mass(b) = Real(mb);
        com(b, 0) = Real(x0 + mr[0] / mb);
        com(b, 1) = Real(y0 + mr[1] / mb);
        com_velocity(b, 0) = Real(mv[0] / mb);
        com_velocity(b, 1) = Real(mv[1] / mb);
        kinetic_energy(b) = Real(0.5 * twice_ke);
      });
}

// The droplet study's per-body observables, on the host (for output steps): area, perimeter,
// shape parameter 𝒜 = P²/(4πa), centre of mass, its velocity and speed.
struct BodyObservables {
  std::vector<double> area, perimeter, shape_parameter, speed;
  std::vector<std::array<double, 2>> com, com_velocity;
};

template <class Real, class ExecSpace>
BodyObservables body_observables(const BodyState<Real, ExecSpace>& state) {
  const auto area = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), state.area);
  const auto perimeter = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), state.perimeter);
  const auto com = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), state.com);
  const auto vel = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), state.com_velocity);
  const int nb = state.num_bodies();
  BodyObservables o;
  o.area.resize(nb);
  o.perimeter.resize(nb);
  o.shape_parameter.resize(nb);
  o.speed.resize(nb);
  o.com.resize(nb);
  o.com_velocity.resize(nb);
  for (int b = 0; b < nb; ++b) {
    o.area[b] = area(b);
    o.perimeter[b] = perimeter(b);
    o.shape_parameter[b] = shape_parameter(double(perimeter(b)), double(area(b)));
    o.com[b] = {double(com(b, 0)), double(com(b, 1))};
    o.com_velocity[b] = {double(vel(b, 0)), double(vel(b, 1))};
    o.speed[b] = std::hypot(o.com_velocity[b][0], o.com_velocity[b][1]);
  }
  return o;
}

}  // namespace mesoflow::dp
