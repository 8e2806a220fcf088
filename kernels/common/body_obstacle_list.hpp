// body_obstacle_list.hpp — for each body (a group of particles: a droplet's vertices), the
// obstacles near it, so that each particle finds its nearest obstacle among a handful of
// candidates instead of searching the obstacle grid: a Verlet list per body.
//
// At a build, body b gets a reference centre c_b (mean of its particles), its radius R_b (largest
// distance of a particle from c_b), and the periodic images of every obstacle centre within
// ρ_b = R_b + skin + D of c_b, D being a distance within which every point has an obstacle centre
// (the cell width of a maximal Poisson-disk array). While every particle stays within R_b + skin
// of c_b, its nearest centre is within D of it and so among the candidates. Queries check this
// (the nearest candidate must be nearer than ρ_b − |x − c_b|) and fall back to the grid search
// otherwise, so the result is always exact; `update()` rebuilds when some particle has left the
// R_b + skin disk.
//
// Each body may live in its own obstacle array of a multi-array ObstacleArray (`body_array`: one
// replica of an ensemble per array); its candidates and fallback come from that array only. An
// update moves the reference disks of the bodies that left theirs and keeps the others, so a body's
// candidates (and hence its forces, to the bit) never depend on what the other bodies do.
#pragma once

#include "kernel_launch.hpp"
#include "kokkos_compat.hpp"
#include "obstacle_array.hpp"
#include "particles.hpp"
#include "vec.hpp"

#include <array>
#include <stdexcept>
#include <string>
#include <vector>

namespace mesoflow {

// The device part of a BodyObstacleList: the obstacle array's query handle and raw pointers into the
// list's Views (row-major), about 200 bytes in double — what kernels capture (BodyObstacleList::query(),
// kernels/common/kernel_launch.hpp). Valid until the list's next update().
template <class Real, class ExecSpace = Kokkos::DefaultExecutionSpace>
struct BodyObstacleQuery {
  ObstacleArrayQuery<Real, ExecSpace> obstacles;
  const int* body_array;   // obstacle array of each body
  const Real* reference;   // c_b (x, y) and R_b per body: [3 b + k]
  const int* count;        // CSR offsets of the candidates, per body
  const Real* candidates;  // candidate centre images: [2 k + d]
  Real skin;

  // Nearest obstacle surface to x, a particle of body b: exact (see the file comment).
  KOKKOS_INLINE_FUNCTION SurfacePoint<2, Real> nearest(int b, const Vec<2, Real>& x) const {
    const Real cx = x[0] - reference[3 * b], cy = x[1] - reference[3 * b + 1];
    const Real trusted = reference[3 * b + 2] + skin + obstacles.cell_width() - kmath::sqrt(cx * cx + cy * cy);
    Real best_r2 = Kokkos::reduction_identity<Real>::min();
    Vec<2, Real> best_dr = Vec<2, Real>::zero();
    for (int k = count[b]; k < count[b + 1]; ++k) {
      const Vec<2, Real> dr{{x[0] - candidates[2 * k], x[1] - candidates[2 * k + 1]}};
      const Real r2 = norm2(dr);
      if (r2 < best_r2) {
        best_r2 = r2;
        best_dr = dr;
      }
    }
    if (!(trusted > Real(0) && best_r2 <= trusted * trusted)) return obstacles.nearest(body_array[b], x);
    const Real rho = kmath::sqrt(best_r2);
    const Vec<2, Real> outward = rho > Real(0) ? (Real(1) / rho) * best_dr : Vec<2, Real>{{Real(1), Real(0)}};
    const Real distance = rho - obstacles.radius();
    return {distance, x - distance * outward, outward};
  }

  // nearest(b, x), also calling visit(s) for the surface s of every obstacle at signed distance
  // < reach from x, exact like nearest: one pass over the candidates when every obstacle centre
  // within max(nearest, radius + reach) of x is certainly a candidate, the grid otherwise.
  template <class Visit>
  KOKKOS_INLINE_FUNCTION SurfacePoint<2, Real> nearest_within(int b, const Vec<2, Real>& x, Real reach,
                                                              Visit&& visit) const {
    const Real cx = x[0] - reference[3 * b], cy = x[1] - reference[3 * b + 1];
    const Real trusted = reference[3 * b + 2] + skin + obstacles.cell_width() - kmath::sqrt(cx * cx + cy * cy);
    const Real contact = obstacles.radius() + reach;  // centre distance below which visit is called
    if (!(trusted >= contact)) return obstacles.nearest_within(body_array[b], x, reach, visit);
    const Real contact2 = contact * contact;
    Real best_r2 = Kokkos::reduction_identity<Real>::min();
    Vec<2, Real> best_dr = Vec<2, Real>::zero();
    for (int k = count[b]; k < count[b + 1]; ++k) {
      const Vec<2, Real> dr{{x[0] - candidates[2 * k], x[1] - candidates[2 * k + 1]}};
      const Real r2 = norm2(dr);
      if (r2 < best_r2) {
        best_r2 = r2;
        best_dr = dr;
      }
      if (r2 < contact2) {
        const SurfacePoint<2, Real> s = obstacles.surface_of(x, dr);
        if (s.distance < reach) visit(s);
      }
    }
    if (!(best_r2 <= trusted * trusted)) return obstacles.nearest(body_array[b], x);
    const Real rho = kmath::sqrt(best_r2);
    const Vec<2, Real> outward = rho > Real(0) ? (Real(1) / rho) * best_dr : Vec<2, Real>{{Real(1), Real(0)}};
    const Real distance = rho - obstacles.radius();
    return {distance, x - distance * outward, outward};
  }

  // Calls visit(dr), dr = x − c, for the image c of every obstacle centre of body b's array within
  // `radius` of x (any point, e.g. the middle of an edge of body b): exact like nearest, from the
  // candidates when the disk of that radius around x lies inside the candidates' disk, from the grid
  // otherwise.
  template <class Visit>
  KOKKOS_INLINE_FUNCTION void for_each_centre_within(int b, const Vec<2, Real>& x, Real radius, Visit&& visit) const {
    const Real cx = x[0] - reference[3 * b], cy = x[1] - reference[3 * b + 1];
    const Real trusted = reference[3 * b + 2] + skin + obstacles.cell_width() - kmath::sqrt(cx * cx + cy * cy);
    if (!(trusted >= radius)) {
      obstacles.for_each_within(body_array[b], x, radius, [&](const Vec<2, Real>& image) { visit(x - image); });
      return;
    }
    const Real radius2 = radius * radius;
    for (int k = count[b]; k < count[b + 1]; ++k) {
      const Vec<2, Real> dr{{x[0] - candidates[2 * k], x[1] - candidates[2 * k + 1]}};
      if (norm2(dr) < radius2) visit(dr);
    }
  }
};

template <class Real, class ExecSpace = Kokkos::DefaultExecutionSpace>
class BodyObstacleList {
 public:
  using int_view = Kokkos::View<int*, ExecSpace>;

  // `body_offset`: body b owns particles [body_offset(b), body_offset(b+1)), e.g. dp::Polygons::offset.
  // Every body in array 0.
  BodyObstacleList(const ObstacleArray<Real, ExecSpace>& obstacles, const int_view& body_offset, Real skin)
      : BodyObstacleList(obstacles, body_offset, int_view("mesoflow::body_obstacle_list::body_array",
                                                          body_offset.extent(0) > 0 ? body_offset.extent(0) - 1 : 0),
                         skin) {}

  // `body_array`: the obstacle array of each body, in [0, obstacles.num_arrays()).
  BodyObstacleList(const ObstacleArray<Real, ExecSpace>& obstacles, const int_view& body_offset,
                   const int_view& body_array, Real skin)
      : obstacles_(obstacles), body_offset_(body_offset), body_array_(body_array), skin_(skin) {
    if (!(skin > Real(0))) throw std::invalid_argument("body obstacle list: skin must be > 0, got " + std::to_string(skin));
    const int nb = int(body_offset.extent(0)) - 1;
    if (nb < 1) throw std::invalid_argument("body obstacle list: no bodies");
    if (int(body_array.extent(0)) != nb)
      throw std::invalid_argument("body obstacle list: " + std::to_string(body_array.extent(0)) +
                                  " body arrays for " + std::to_string(nb) + " bodies");
    const int num_arrays = obstacles.num_arrays();
    if (count_bodies_outside(body_array, num_arrays) > 0)
      throw std::invalid_argument("body obstacle list: a body's obstacle array is outside [0, " +
                                  std::to_string(num_arrays) + ")");
    reference_ = Kokkos::View<Real* [3], Kokkos::LayoutRight, ExecSpace>("mesoflow::body_obstacle_list::reference", nb);
    count_ = int_view("mesoflow::body_obstacle_list::count", nb + 1);
    stale_ = int_view("mesoflow::body_obstacle_list::stale", nb);
    forced_ = int_view("mesoflow::body_obstacle_list::forced", nb);
  }

  // Bodies whose obstacle array is outside [0, num_arrays). (A function of its own: nvcc rejects a
  // KOKKOS_LAMBDA in a constructor.)
  static int count_bodies_outside(const int_view& body_array, int num_arrays) {
    int bad = 0;
    mesoflow::launch::parallel_reduce(
        "mesoflow::body_obstacle_list::check_arrays", Kokkos::RangePolicy<ExecSpace>(0, body_array.extent(0)),
        KOKKOS_LAMBDA(int b, int& acc) { acc += body_array(b) < 0 || body_array(b) >= num_arrays ? 1 : 0; }, bad);
    return bad;
  }

  // Rebuilds if some particle left its body's disk of radius R_b + skin (or before the first
  // build); returns whether it did.
  template <class PositionView>
  bool update(const PositionView& x) {
    if (builds_ == 0) {
      build(x);
      return true;
    }
    if (!mark_stale(x)) return false;
    rebuild(x);
    return true;
  }

  // Moves every body's reference disk to its current particles and rebuilds.
  template <class PositionView>
  void build(const PositionView& x) {
    Kokkos::deep_copy(stale_, 1);
    rebuild(x);
  }

  // Puts body b in obstacle array `array` (a batch refilling a slot with a new replica): its reference
  // disk moves and its candidates are rebuilt at the next update(). Host setup.
  void reassign(int b, int array) {
    if (b < 0 || b >= num_bodies())
      throw std::invalid_argument("body obstacle list: body " + std::to_string(b) + " outside [0, " +
                                  std::to_string(num_bodies()) + ")");
    if (array < 0 || array >= obstacles_.num_arrays())
      throw std::invalid_argument("body obstacle list: obstacle array " + std::to_string(array) + " outside [0, " +
                                  std::to_string(obstacles_.num_arrays()) + ")");
    Kokkos::deep_copy(Kokkos::subview(body_array_, b), array);
    Kokkos::deep_copy(Kokkos::subview(forced_, b), 1);
  }

  // The reference disks (c_b, R_b) of every body, host copy: with the body arrays, what fixes each
  // body's candidates (a body moved to another list with build_at() gets the same candidates).
  std::vector<std::array<double, 3>> references() const {
    const auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), reference_);
    std::vector<std::array<double, 3>> out(h.extent(0));
    for (std::size_t b = 0; b < h.extent(0); ++b) out[b] = {double(h(b, 0)), double(h(b, 1)), double(h(b, 2))};
    return out;
  }

  // Builds every body's candidates from the given reference disks (instead of moving them to the
  // current particles): the list then equals, body for body, the one the disks came from.
  template <class PositionView>
  void build_at(const std::vector<std::array<double, 3>>& disks, const PositionView& x) {
    if (int(disks.size()) != num_bodies())
      throw std::invalid_argument("body obstacle list: " + std::to_string(disks.size()) + " reference disks for " +
                                  std::to_string(num_bodies()) + " bodies");
    const auto h = Kokkos::create_mirror_view(reference_);
    for (std::size_t b = 0; b < disks.size(); ++b)
      for (int k = 0; k < 3; ++k) h(b, k) = Real(disks[b][std::size_t(k)]);
    Kokkos::deep_copy(reference_, h);
    Kokkos::deep_copy(stale_, 0);
    Kokkos::deep_copy(forced_, 0);
    rebuild(x);
  }

  // rebuild, mark_stale and max_reach_bound are implementation details, public only because nvcc
  // rejects a KOKKOS_LAMBDA in a private or protected member function.

  // Moves the reference disks of the stale bodies, then recounts and refills every body's candidates
  // (those of the other bodies come out identical: same disk, same array, same order).
  template <class PositionView>
  void rebuild(const PositionView& x) {
    const int nb = num_bodies();
    const auto offset = body_offset_;
    const auto reference = reference_;
    const auto count = count_;
    const auto stale = stale_;
    const auto body_array = body_array_;
    const auto obstacles = obstacles_.query();
    const Real coverage = obstacles_.cell_width(), skin = skin_;
    for (int d = 0; d < 2; ++d)
      if (obstacles_.size() > 0 && obstacles_.box_length(d) < Real(2) * max_reach_bound(x))
        throw std::invalid_argument("body obstacle list: a body's candidate disk is wider than half the box");
    mesoflow::launch::parallel_for(
        "mesoflow::body_obstacle_list::reference", Kokkos::RangePolicy<ExecSpace>(0, nb), KOKKOS_LAMBDA(int b) {
          if (stale(b)) {
            const int begin = offset(b), end = offset(b + 1);
            Real c[2] = {0, 0};
            for (int i = begin; i < end; ++i)
              for (int d = 0; d < 2; ++d) c[d] += x(i, d);
            for (int d = 0; d < 2; ++d) c[d] /= Real(end - begin);
            Real r2 = 0;
            for (int i = begin; i < end; ++i) {
              const Real dx = x(i, 0) - c[0], dy = x(i, 1) - c[1];
              r2 = dx * dx + dy * dy > r2 ? dx * dx + dy * dy : r2;
            }
            reference(b, 0) = c[0];
            reference(b, 1) = c[1];
            reference(b, 2) = kmath::sqrt(r2);
            stale(b) = 0;
          }
          int n = 0;
          obstacles.for_each_within(body_array(b), Vec<2, Real>{{reference(b, 0), reference(b, 1)}},
                                    reference(b, 2) + skin + coverage, [&](const Vec<2, Real>&) { ++n; });
          count(b + 1) = n;
        });
    mesoflow::launch::parallel_scan(
        "mesoflow::body_obstacle_list::offsets", Kokkos::RangePolicy<ExecSpace>(0, nb + 1),
        KOKKOS_LAMBDA(int k, int& partial, bool final) {
          partial += k == 0 ? 0 : count(k);
          if (final) count(k) = partial;
        });
    int total = 0;  // the scan's last entry, read back as a reduction (one scalar per rebuild)
    mesoflow::launch::parallel_reduce(
        "mesoflow::body_obstacle_list::total", Kokkos::RangePolicy<ExecSpace>(nb, nb + 1),
        KOKKOS_LAMBDA(int k, int& acc) { acc += count(k); }, total);
    if (int(candidates_.extent(0)) < total)
      candidates_ = Kokkos::View<Real* [2], Kokkos::LayoutRight, ExecSpace>(
          Kokkos::ViewAllocateWithoutInitializing("mesoflow::body_obstacle_list::candidates"), total + total / 4 + 1);
    const auto candidates = candidates_;
    mesoflow::launch::parallel_for(
        "mesoflow::body_obstacle_list::fill", Kokkos::RangePolicy<ExecSpace>(0, nb), KOKKOS_LAMBDA(int b) {
          int slot = count(b);
          const Vec<2, Real> c{{reference(b, 0), reference(b, 1)}};
          obstacles.for_each_within(body_array(b), c, reference(b, 2) + skin + coverage, [&](const Vec<2, Real>& image) {
            candidates(slot, 0) = image[0];
            candidates(slot, 1) = image[1];
            ++slot;
          });
        });
    ++builds_;
  }

 public:
  using Query = BodyObstacleQuery<Real, ExecSpace>;

  // The small handle kernels capture; valid until the next update().
  KOKKOS_INLINE_FUNCTION Query query() const {
    return {obstacles_.query(), body_array_.data(), reference_.data(), count_.data(), candidates_.data(), skin_};
  }

  // Nearest obstacle surface to x, a particle of body b: exact (see the file comment).
  KOKKOS_INLINE_FUNCTION SurfacePoint<2, Real> nearest(int b, const Vec<2, Real>& x) const {
    return query().nearest(b, x);
  }

  // nearest(b, x), also calling visit(s) for the surface of every obstacle at signed distance < reach.
  template <class Visit>
  KOKKOS_INLINE_FUNCTION SurfacePoint<2, Real> nearest_within(int b, const Vec<2, Real>& x, Real reach,
                                                              Visit&& visit) const {
    return query().nearest_within(b, x, reach, visit);
  }

  int num_bodies() const { return int(body_offset_.extent(0)) - 1; }
  int num_builds() const { return builds_; }
  const ObstacleArray<Real, ExecSpace>& obstacles() const { return obstacles_; }
  const int_view& body_array() const { return body_array_; }

  // Marks the bodies some particle of which has left the disk of radius R_b + skin around c_b;
  // returns whether there is one.
  template <class PositionView>
  bool mark_stale(const PositionView& x) const {
    const auto offset = body_offset_;
    const auto reference = reference_;
    const auto stale = stale_;
    const auto forced = forced_;
    const Real skin = skin_;
    int outside = 0;
    mesoflow::launch::parallel_reduce(
        "mesoflow::body_obstacle_list::check", Kokkos::RangePolicy<ExecSpace>(0, num_bodies()),
        KOKKOS_LAMBDA(int b, int& acc) {
          const Real limit = reference(b, 2) + skin;
          int left = forced(b);
          forced(b) = 0;
          if (!left)
          for (int i = offset(b); i < offset(b + 1); ++i) {
            const Real dx = x(i, 0) - reference(b, 0), dy = x(i, 1) - reference(b, 1);
            if (dx * dx + dy * dy > limit * limit) {
              left = 1;
              break;
            }
          }
          stale(b) = left;
          acc += left;
        },
        outside);
    return outside > 0;
  }

  // Upper bound of every body's candidate radius, for the box-size check (host, at builds only).
  template <class PositionView>
  Real max_reach_bound(const PositionView& x) const {
    const auto offset = body_offset_;
    Real extent = 0;
    mesoflow::launch::parallel_reduce(
        "mesoflow::body_obstacle_list::extent", Kokkos::RangePolicy<ExecSpace>(0, num_bodies()),
        KOKKOS_LAMBDA(int b, Real& acc) {
          Real lo[2] = {x(offset(b), 0), x(offset(b), 1)}, hi[2] = {lo[0], lo[1]};
          for (int i = offset(b); i < offset(b + 1); ++i)
            for (int d = 0; d < 2; ++d) {
              lo[d] = x(i, d) < lo[d] ? x(i, d) : lo[d];
              hi[d] = x(i, d) > hi[d] ? x(i, d) : hi[d];
            }
          const Real size = (hi[0] - lo[0]) + (hi[1] - lo[1]);
          acc = size > acc ? size : acc;
        },
        Kokkos::Max<Real>(extent));
    return extent + skin_ + obstacles_.cell_width();
  }

 private:
  ObstacleArray<Real, ExecSpace> obstacles_;
  int_view body_offset_;
  int_view body_array_;  // obstacle array of each body
  Real skin_;
  Kokkos::View<Real* [3], Kokkos::LayoutRight, ExecSpace> reference_;  // c_b (x, y) and R_b per body
  int_view count_;                                 // CSR offsets of the candidates, per body
  int_view stale_;                                 // 1: the body's reference disk moves at the next rebuild
  int_view forced_;                                // 1: stale at the next update whatever its particles do
  Kokkos::View<Real* [2], Kokkos::LayoutRight, ExecSpace> candidates_;
  int builds_ = 0;
};

// Surface query for the surface-force loop: the walls of a scene and, through a BodyObstacleList's
// query handle, the obstacles near each particle's body. A small handle (raw pointers into the
// scene's Views, about 220 bytes in double): build it after the list's update() and pass it to one
// launch (kernels/common/kernel_launch.hpp).
template <class Real, class ExecSpace = Kokkos::DefaultExecutionSpace>
struct BodySurfaces {
  const Shape<2, Real>* walls;
  int num_walls;
  BodyObstacleQuery<Real, ExecSpace> obstacles;
  const int* body;  // body of each particle
  // false: pairwise terms see the walls only (the obstacles' repulsion is evaluated elsewhere, on
  // edges: dp/edge_obstacle_repulsion.hpp); nearest() still sees the obstacles (drag).
  bool visit_obstacles = true;

  BodySurfaces(const typename Surfaces<Real, ExecSpace>::shape_view& wall_shapes, int wall_count,
               const BodyObstacleList<Real, ExecSpace>& list, const Kokkos::View<int*, ExecSpace>& body_of,
               bool visit_obstacles_ = true)
      : walls(wall_shapes.data()),
        num_walls(wall_count),
        obstacles(list.query()),
        body(body_of.data()),
        visit_obstacles(visit_obstacles_) {}

  KOKKOS_INLINE_FUNCTION SurfacePoint<2, Real> nearest(int i, const Vec<2, Real>& x) const {
    const SurfacePoint<2, Real> wall = nearest_surface(walls, num_walls, x);
    const SurfacePoint<2, Real> obstacle = obstacles.nearest(body[i], x);
    return obstacle.distance < wall.distance ? obstacle : wall;
  }

  // The form of the surface-force loop for pairwise terms (surface_force.hpp): walls, then obstacles.
  template <class Visit>
  KOKKOS_INLINE_FUNCTION SurfacePoint<2, Real> nearest_within(int i, const Vec<2, Real>& x, Real reach,
                                                              Visit&& visit) const {
    const SurfacePoint<2, Real> wall = walls_nearest_within(walls, num_walls, x, reach, visit);
    const SurfacePoint<2, Real> obstacle =
        visit_obstacles ? obstacles.nearest_within(body[i], x, reach, visit) : obstacles.nearest(body[i], x);
    return obstacle.distance < wall.distance ? obstacle : wall;
  }
};

}  // namespace mesoflow
