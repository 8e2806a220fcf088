// mpc_collision.hpp — the MPC collision step (Appendix B): particles binned into the randomly
// shifted cells of a CollisionGrid exchange momentum by one of three rules chosen at run time,
// SRD, MPC-AT−a or MPC-AT+a (eq. B.2), each conserving every cell's mass and momentum.
//
// One generic loop does the binning and the sums; the physics of each rule is a small struct
// (srd_collision.hpp, at_minus_a_collision.hpp, at_plus_a_collision.hpp) with
//   num_sums, num_cell_values, uses_random_velocity, uses_position,
//   add(sums, r, v, v_ran)          — one particle's contribution to its cell's sums (double),
//   cell_values(cell, sums, values) — per-cell quantities from the sums (cells with N_C ≥ 1),
//   apply(values, r, v_ran, v)      — one particle's post-collision velocity,
// r being the particle's offset from its cell's lower corner (CollisionGrid::locate).
//
// Three kernels per collision:
//  1. bin_and_sum: the particles are split into T = concurrency() contiguous chunks; chunk t adds
//     its particles, in index order, into its own copy of the cell sums. It also stores each
//     particle's cell and, for the AT rules, its thermal velocity v^ran. (stream_and_collide
//     streams the particle here as well.)
//  2. cell_values: per cell, the T copies summed in chunk order, then the rule's cell values.
//  3. apply: per particle, the new velocity from its cell's values.
// No atomics: every floating-point sum has a fixed order for a given T, so results are bitwise
// reproducible at a fixed thread count (the last bits change with the thread count). This is the
// duplicated-ScatterView scheme written out, with the zeroing fused into kernel 1 and the
// reduction into kernel 2; a CSR counting sort (count, scan, fill, in-cell sort) would add three
// passes over the particles per step. The chunked copies need host-like concurrency (T copies of
// the cell sums); on device execution spaces (CellSums::automatic) kernel 1 instead adds each
// particle's contribution with atomics into one copy (the ScatterView-on-GPU scheme), which is not
// bitwise reproducible; tests run that path on OpenMP too (CellSums::atomic). CellSums::sorted,
// the deterministic-sum mode (issue 26 item 4), stores each row's contribution in kernel 1, orders
// the rows by cell with kernels/common/segment_order.hpp and sums each cell over its rows in index
// order in kernel 2: bitwise the same on every backend and thread count (the order of one chunk on
// Kokkos::Serial), for a sort per collision. sort_by_cell() reorders anonymous particles by cell every few tens
// of steps, which keeps the scattered sums and cell reads in cache (bench_mpc.cpp).
//
// Random numbers: v^ran of real particle i from particle_stream(seed, step, i); of virtual row j
// from RandomStream(seed, step, mpc_stream_tag::virtual_particle, j); both by thermal_velocity
// (maxwell_boltzmann.hpp), each component normal with variance k_BT/m. Cell noise (SRD axes and
// signs) from cell_stream(seed, step, cell); the grid shift from
// RandomStream(seed, step, mpc_stream_tag::grid_shift, 0).
#pragma once

#include "../common/kernel_launch.hpp"
#include "at_minus_a_collision.hpp"
#include "at_plus_a_collision.hpp"
#include "collision_grid.hpp"
#include "maxwell_boltzmann.hpp"
#include "srd_collision.hpp"
#include "streaming.hpp"

#include "kernels/common/kokkos_compat.hpp"
#include "kernels/common/random.hpp"
#include "kernels/common/segment_order.hpp"

#include <Kokkos_Sort.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace mesoflow::mpc {

enum class CollisionRule { srd, at_minus_a, at_plus_a };

// "srd", "at-a", "at+a".
inline CollisionRule parse_collision_rule(const std::string& name) {
  if (name == "srd") return CollisionRule::srd;
  if (name == "at-a") return CollisionRule::at_minus_a;
  if (name == "at+a") return CollisionRule::at_plus_a;
  throw std::invalid_argument("collision rule '" + name + "': expected one of srd, at-a, at+a");
}

inline std::string to_string(CollisionRule rule) {
  switch (rule) {
    case CollisionRule::srd:
      return "srd";
    case CollisionRule::at_minus_a:
      return "at-a";
    case CollisionRule::at_plus_a:
      return "at+a";
  }
  throw std::invalid_argument("collision rule: unknown value " + std::to_string(int(rule)));
}

// How the cell sums are accumulated: `chunked` (one copy of the sums per thread, summed in chunk
// order: bitwise reproducible at a fixed thread count; host execution spaces), `atomic` (one copy,
// atomic adds: what device backends use; the order of the additions, and so the last bits, vary
// from run to run), `automatic` (chunked on host spaces, atomic on device spaces), `sorted` (the
// deterministic-sum mode, issue 26 item 4: each row's contribution stored, the rows sorted by cell
// with Kokkos::BinSort, each cell's sum taken over its rows in index order — bitwise the same on
// every backend and thread count, at the cost of a sort per collision).
enum class CellSums { automatic, chunked, atomic, sorted };

// "automatic", "chunked", "atomic", "sorted".
inline CellSums parse_cell_sums(const std::string& name) {
  if (name == "automatic") return CellSums::automatic;
  if (name == "chunked") return CellSums::chunked;
  if (name == "atomic") return CellSums::atomic;
  if (name == "sorted") return CellSums::sorted;
  throw std::invalid_argument("cell sums '" + name + "': expected one of automatic, chunked, atomic, sorted");
}

template <class Real>
struct CollisionParameters {
  CollisionRule rule = CollisionRule::at_plus_a;
  Real kT = 1;      // thermostat temperature k_BT (AT rules)
  Real mass = 1;    // particle mass m (real and virtual)
  Real srd_angle = Real(2.2689280275926285);  // SRD rotation angle α, 130°
  std::uint64_t seed = 1;
  CellSums cell_sums = CellSums::automatic;
};

template <int D, class Real, class ExecSpace = Kokkos::DefaultExecutionSpace>
class MpcCollision {
 public:
  using vector_view = Kokkos::View<Real* [D], Kokkos::LayoutLeft, ExecSpace>;
  static constexpr bool host_space =
      Kokkos::SpaceAccessibility<Kokkos::HostSpace, typename ExecSpace::memory_space>::accessible;

  MpcCollision(const CollisionGrid<D, Real>& grid, const CollisionParameters<Real>& p, std::size_t particle_capacity,
               std::size_t virtual_capacity = 0)
      : grid_(grid),
        params_(p),
        particle_capacity_(particle_capacity),
        virtual_capacity_(virtual_capacity),
        atomic_sums_(p.cell_sums == CellSums::atomic || (p.cell_sums == CellSums::automatic && !host_space)),
        sorted_sums_(p.cell_sums == CellSums::sorted),
        num_chunks_(atomic_sums_ || sorted_sums_ ? 1 : (concurrency<ExecSpace>() > 0 ? concurrency<ExecSpace>() : 1)) {
    if (p.cell_sums == CellSums::chunked && !host_space)
      throw std::invalid_argument("MPC collision: chunked cell sums need a host execution space");
    if (!(p.kT >= Real(0)) || !std::isfinite(double(p.kT)))
      throw std::invalid_argument("MPC collision: kT must be finite and >= 0, got " + std::to_string(double(p.kT)));
    if (!(p.mass > Real(0)) || !std::isfinite(double(p.mass)))
      throw std::invalid_argument("MPC collision: mass must be finite and > 0, got " + std::to_string(double(p.mass)));
    if (!std::isfinite(double(p.srd_angle)))
      throw std::invalid_argument("MPC collision: srd_angle must be finite, got " + std::to_string(double(p.srd_angle)));
    const std::size_t rows = particle_capacity + virtual_capacity;
    const std::size_t cells = std::size_t(grid.num_cells());
    const int sums = num_sums(p.rule), values = num_cell_values(p.rule);
    cell_of_ = Kokkos::View<int*, ExecSpace>(Kokkos::ViewAllocateWithoutInitializing("mesoflow::mpc::cell_of"), rows);
    if (p.rule != CollisionRule::srd)
      vran_ = vector_view(Kokkos::ViewAllocateWithoutInitializing("mesoflow::mpc::vran"), rows);
    // Sorted sums: one row of K sums per particle (real and virtual), reduced per cell after the sort.
    partial_sums_ = Kokkos::View<double*, ExecSpace>(Kokkos::ViewAllocateWithoutInitializing("mesoflow::mpc::partial_sums"),
                                                     (sorted_sums_ ? rows : std::size_t(num_chunks_) * cells) * sums);
    if (sorted_sums_) row_order_.emplace(int(rows), int(cells));
    cell_values_ = Kokkos::View<Real*, ExecSpace>(Kokkos::ViewAllocateWithoutInitializing("mesoflow::mpc::cell_values"),
                                                  cells * values);
    x_sorted_ = vector_view(Kokkos::ViewAllocateWithoutInitializing("mesoflow::mpc::x_sorted"), particle_capacity);
    v_sorted_ = vector_view(Kokkos::ViewAllocateWithoutInitializing("mesoflow::mpc::v_sorted"), particle_capacity);
  }

  const CollisionGrid<D, Real>& grid() const { return grid_; }
  const CollisionParameters<Real>& parameters() const { return params_; }
  std::size_t particle_capacity() const { return particle_capacity_; }
  std::size_t virtual_capacity() const { return virtual_capacity_; }

  // Draws the grid shift of this step (grid().shift), from (seed, step).
  void shift_grid(std::uint64_t step) { grid_.draw_shift(params_.seed, step); }

  // One collision with the current shift. x, v: real particles (all rows); xv, vv: the first
  // n_virtual rows are virtual particles, which take part in the cell sums with the same mass;
  // vv receives their post-collision velocities.
  void collide(const vector_view& x, const vector_view& v, const vector_view& xv, const vector_view& vv,
               std::size_t n_virtual, std::uint64_t step) {
    dispatch<false>(x, v, xv, vv, n_virtual, step, Real(0), Kokkos::Array<Real, D>{});
  }

  void collide(const vector_view& x, const vector_view& v, std::uint64_t step) {
    collide(x, v, vector_view(), vector_view(), 0, step);
  }

  // A whole MPC step where nothing happens between streaming and collision (a periodic box: no
  // bounce-back, no virtual particles), fused: stream(x, v, h, g, grid()); shift_grid(step);
  // collide(x, v, step) — bitwise the same result, with the streaming done in the binning kernel
  // (one pass over x and v fewer).
  void stream_and_collide(const vector_view& x, const vector_view& v, Real h, const Kokkos::Array<Real, D>& g,
                          std::uint64_t step) {
    shift_grid(step);
    dispatch<true>(x, v, vector_view(), vector_view(), 0, step, h, g);
  }

  // Reorders the real particles in memory by the cell they had in the last collision (by cell, then
  // by index: Kokkos::BinSort on the device, issue 26 item 5), so that the scattered cell sums and
  // cell reads of the next collisions touch memory in order. A pure permutation of the rows of x and
  // v, the same on every backend and thread count; anything else indexed by particle is not
  // permuted, so call it only where particles are anonymous (the solvent), every few tens of steps
  // (LAMMPS' atom sorting). The scratch storage is allocated with the class and the sorter at the
  // first sort (BinSort's create_permute_vector() allocates nothing; it zeroes its bin counts).
  void sort_by_cell(const vector_view& x, const vector_view& v) {
    const int n = int(x.extent(0));
    if (n != last_num_particles_ || int(v.extent(0)) != n)
      throw std::invalid_argument("MPC sort_by_cell: " + std::to_string(n) + " particles, but the last collision had " +
                                  std::to_string(last_num_particles_));
    const int ncell = grid_.num_cells();
    if (!sorter_ || int(sort_keys_.extent(0)) != n) {  // the first sort, or another particle count
      sort_keys_ = key_view(Kokkos::ViewAllocateWithoutInitializing("mesoflow::mpc::sort_keys"), n);
      sorter_.emplace(sort_keys_, Kokkos::BinOp1D<key_view>(ncell, 0, std::int64_t(ncell) * n), true);
    }
    // Key cell · n + i: unique, so Kokkos::BinSort's binning (bin = cell) followed by its sort within
    // bins gives the stable order (by cell, then by index) on every backend, whatever order its
    // atomic binning filled the bins in.
    const auto cell_of = cell_of_;
    const auto keys = sort_keys_;
    const std::int64_t stride = n;
    mesoflow::launch::parallel_for(
        "mesoflow::mpc::sort::keys", Kokkos::RangePolicy<ExecSpace>(0, n),
        KOKKOS_LAMBDA(const int i) { keys(i) = std::int64_t(cell_of(i)) * stride + i; });
    zero_bin_counts<ExecSpace>(*sorter_);  // create_permute_vector() adds to the last counts
    sorter_->create_permute_vector();
    const auto order = sorter_->get_permute_vector();
    const auto xs = x_sorted_, vs = v_sorted_;
    mesoflow::launch::parallel_for(
        "mesoflow::mpc::sort::gather", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(const int s) {
          const int i = int(order(s));
          for (int d = 0; d < D; ++d) {
            xs(s, d) = x(i, d);
            vs(s, d) = v(i, d);
          }
        });
    mesoflow::launch::parallel_for(
        "mesoflow::mpc::sort::copy_back", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(const int i) {
          for (int d = 0; d < D; ++d) {
            x(i, d) = xs(i, d);
            v(i, d) = vs(i, d);
          }
        });
    last_num_particles_ = -1;  // cell_of no longer matches the rows
  }

 private:
  static int num_sums(CollisionRule rule) {
    switch (rule) {
      case CollisionRule::srd:
        return SrdCollision<D, Real>::num_sums;
      case CollisionRule::at_minus_a:
        return AtMinusACollision<D, Real>::num_sums;
      case CollisionRule::at_plus_a:
        return AtPlusACollision<D, Real>::num_sums;
    }
    throw std::invalid_argument("MPC collision: unknown rule");
  }
  static int num_cell_values(CollisionRule rule) {
    switch (rule) {
      case CollisionRule::srd:
        return SrdCollision<D, Real>::num_cell_values;
      case CollisionRule::at_minus_a:
        return AtMinusACollision<D, Real>::num_cell_values;
      case CollisionRule::at_plus_a:
        return AtPlusACollision<D, Real>::num_cell_values;
    }
    throw std::invalid_argument("MPC collision: unknown rule");
  }

  template <bool Stream>
  void dispatch(const vector_view& x, const vector_view& v, const vector_view& xv, const vector_view& vv,
                std::size_t n_virtual, std::uint64_t step, Real h, const Kokkos::Array<Real, D>& g) {
    if (x.extent(0) > particle_capacity_ || v.extent(0) != x.extent(0))
      throw std::length_error("MPC collision: " + std::to_string(x.extent(0)) + " positions and " +
                              std::to_string(v.extent(0)) + " velocities for a capacity of " +
                              std::to_string(particle_capacity_) + " particles");
    if (n_virtual > virtual_capacity_ || n_virtual > xv.extent(0) || n_virtual > vv.extent(0))
      throw std::length_error("MPC collision: " + std::to_string(n_virtual) + " virtual particles for a capacity of " +
                              std::to_string(virtual_capacity_) + " (views of " + std::to_string(xv.extent(0)) +
                              " and " + std::to_string(vv.extent(0)) + " rows)");
    switch (params_.rule) {
      case CollisionRule::srd:
        run<Stream>(SrdCollision<D, Real>(params_.srd_angle, params_.seed, step), x, v, xv, vv, n_virtual, step, h, g);
        return;
      case CollisionRule::at_minus_a:
        run<Stream>(AtMinusACollision<D, Real>{}, x, v, xv, vv, n_virtual, step, h, g);
        return;
      case CollisionRule::at_plus_a:
        run<Stream>(AtPlusACollision<D, Real>{}, x, v, xv, vv, n_virtual, step, h, g);
        return;
    }
  }

 public:
  // run is an implementation detail, public only because nvcc rejects a KOKKOS_LAMBDA in a private
  // or protected member function.
  template <bool Stream, class Rule>
  void run(const Rule& rule, const vector_view& x, const vector_view& v, const vector_view& xv, const vector_view& vv,
           std::size_t n_virtual, std::uint64_t step, Real h, const Kokkos::Array<Real, D>& g) {
    constexpr int K = Rule::num_sums;
    constexpr int M = Rule::num_cell_values;
    const auto grid = grid_;
    const auto cell_of = cell_of_;
    const auto vran = vran_;
    const auto partial = partial_sums_;
    const auto values = cell_values_;
    const int n = int(x.extent(0));
    const int nv = int(n_virtual);
    const int chunks = num_chunks_;
    const std::size_t ncell = std::size_t(grid.num_cells());
    last_num_particles_ = n;
    const std::uint64_t seed = params_.seed;
    const Real speed = Real(std::sqrt(double(params_.kT) / double(params_.mass)));

    const bool sorted = sorted_sums_;
    if (atomic_sums_ || sorted_sums_) {
      if (!sorted)
        mesoflow::launch::parallel_for(
            "mesoflow::mpc::zero_sums", Kokkos::RangePolicy<ExecSpace>(0, ncell * K),
            KOKKOS_LAMBDA(const std::size_t k) { partial(k) = 0.0; });
      mesoflow::launch::parallel_for(
          sorted ? "mesoflow::mpc::bin_and_store" : "mesoflow::mpc::bin_and_sum_atomic", Kokkos::RangePolicy<ExecSpace>(0, n + nv), KOKKOS_LAMBDA(const int i) {
            const bool real = i < n;
            const int j = real ? i : i - n;
            Real xi[D], vi[D], r[D], vr[D];
            for (int d = 0; d < D; ++d) {
              xi[d] = real ? x(j, d) : xv(j, d);
              vi[d] = real ? v(j, d) : vv(j, d);
            }
            // `if`, not `if constexpr`: nvcc rejects a KOKKOS_LAMBDA whose first use of a captured
            // variable is inside `if constexpr` (the condition is a compile-time constant all the same).
            if (Stream) {
              if (real) {
                stream_particle(xi, vi, h, g, grid);
                for (int d = 0; d < D; ++d) {
                  x(j, d) = xi[d];
                  v(j, d) = vi[d];
                }
              }
            }
            const int c = grid.locate(xi, r);
            cell_of(i) = c;
            if (Rule::uses_random_velocity) {
              RandomStream rs = real ? particle_stream(seed, step, static_cast<std::uint32_t>(j))
                                     : RandomStream(seed, step, mpc_stream_tag::virtual_particle,
                                                    static_cast<std::uint32_t>(j));
              thermal_velocity(rs, speed, vr);
              for (int d = 0; d < D; ++d) vran(i, d) = vr[d];
            } else {
              for (int d = 0; d < D; ++d) vr[d] = Real(0);
            }
            double local[K];
            for (int k = 0; k < K; ++k) local[k] = 0.0;
            rule.add(local, r, vi, vr);
            if (sorted) {
              for (int k = 0; k < K; ++k) partial(std::size_t(i) * K + k) = local[k];
            } else {
              for (int k = 0; k < K; ++k) Kokkos::atomic_add(&partial(std::size_t(c) * K + k), local[k]);
            }
          });
    } else {
      mesoflow::launch::parallel_for(
          "mesoflow::mpc::bin_and_sum", Kokkos::RangePolicy<ExecSpace>(0, chunks), KOKKOS_LAMBDA(const int t) {
            double* sums = partial.data() + std::size_t(t) * ncell * K;
            for (std::size_t k = 0; k < ncell * K; ++k) sums[k] = 0.0;
            const int begin = int(std::int64_t(n) * t / chunks), end = int(std::int64_t(n) * (t + 1) / chunks);
            for (int i = begin; i < end; ++i) {
              Real xi[D], vi[D], r[D], vr[D];
              for (int d = 0; d < D; ++d) {
                xi[d] = x(i, d);
                vi[d] = v(i, d);
              }
              // `if`, not `if constexpr`: nvcc rejects a KOKKOS_LAMBDA whose first use of a captured
              // variable is inside `if constexpr` (the condition is a compile-time constant all the same).
              if (Stream) {
                stream_particle(xi, vi, h, g, grid);
                for (int d = 0; d < D; ++d) {
                  x(i, d) = xi[d];
                  v(i, d) = vi[d];
                }
              }
              const int c = grid.locate(xi, r);
              cell_of(i) = c;
              if (Rule::uses_random_velocity) {
                RandomStream rs = particle_stream(seed, step, static_cast<std::uint32_t>(i));
                thermal_velocity(rs, speed, vr);
                for (int d = 0; d < D; ++d) vran(i, d) = vr[d];
              } else {
                for (int d = 0; d < D; ++d) vr[d] = Real(0);
              }
              rule.add(sums + std::size_t(c) * K, r, vi, vr);
            }
            const int vbegin = int(std::int64_t(nv) * t / chunks), vend = int(std::int64_t(nv) * (t + 1) / chunks);
            for (int j = vbegin; j < vend; ++j) {
              Real xi[D], vi[D], r[D], vr[D];
              for (int d = 0; d < D; ++d) {
                xi[d] = xv(j, d);
                vi[d] = vv(j, d);
              }
              const int c = grid.locate(xi, r);
              cell_of(n + j) = c;
              if constexpr (Rule::uses_random_velocity) {
                RandomStream rs(seed, step, mpc_stream_tag::virtual_particle, static_cast<std::uint32_t>(j));
                thermal_velocity(rs, speed, vr);
                for (int d = 0; d < D; ++d) vran(n + j, d) = vr[d];
              } else {
                for (int d = 0; d < D; ++d) vr[d] = Real(0);
              }
              rule.add(sums + std::size_t(c) * K, r, vi, vr);
            }
          });
    }

    if (sorted) {
      // The rows by cell, then by index (kernels/common/segment_order.hpp), then each cell's sums over
      // its rows in that order.
      const int used = n + nv;
      row_order_->sort(used, cell_of);
      const auto order = row_order_->view();
      mesoflow::launch::parallel_for(
          "mesoflow::mpc::cell_values_sorted", Kokkos::RangePolicy<ExecSpace>(0, ncell), KOKKOS_LAMBDA(const std::size_t c) {
            double s[K];
            for (int k = 0; k < K; ++k) s[k] = 0.0;
            for (int q = order.begin(int(c)); q < order.end(int(c)); ++q) {
              const int i = order.row(q);
              if (i >= used) continue;  // a padding row dealt to this cell
              const double* p = partial.data() + std::size_t(i) * K;
              for (int k = 0; k < K; ++k) s[k] += p[k];
            }
            if (s[0] > 0.0) rule.cell_values(int(c), s, values.data() + c * M);
          });
    } else {
      mesoflow::launch::parallel_for(
          "mesoflow::mpc::cell_values", Kokkos::RangePolicy<ExecSpace>(0, ncell), KOKKOS_LAMBDA(const std::size_t c) {
            double s[K];
            for (int k = 0; k < K; ++k) s[k] = 0.0;
            for (int t = 0; t < chunks; ++t) {
              const double* p = partial.data() + (std::size_t(t) * ncell + c) * K;
              for (int k = 0; k < K; ++k) s[k] += p[k];
            }
            if (s[0] > 0.0) rule.cell_values(int(c), s, values.data() + c * M);
          });
    }

    mesoflow::launch::parallel_for(
        "mesoflow::mpc::apply", Kokkos::RangePolicy<ExecSpace>(0, n + nv), KOKKOS_LAMBDA(const int i) {
          const bool real = i < n;
          const int j = real ? i : i - n;
          const int c = cell_of(i);
          Real r[D], vi[D], vr[D];
          // `if`, not `if constexpr`: nvcc rejects a KOKKOS_LAMBDA whose first use of a captured
          // variable is inside `if constexpr` (the condition is a compile-time constant all the same).
          if (Rule::uses_position) {
            Real xi[D];
            for (int d = 0; d < D; ++d) xi[d] = real ? x(j, d) : xv(j, d);
            grid.locate(xi, r);
          } else {
            for (int d = 0; d < D; ++d) r[d] = Real(0);
          }
          for (int d = 0; d < D; ++d) vi[d] = real ? v(j, d) : vv(j, d);
          if (Rule::uses_random_velocity) {
            for (int d = 0; d < D; ++d) vr[d] = vran(i, d);
          } else {
            for (int d = 0; d < D; ++d) vr[d] = Real(0);
          }
          rule.apply(values.data() + std::size_t(c) * M, r, vr, vi);
          if (real) {
            for (int d = 0; d < D; ++d) v(j, d) = vi[d];
          } else {
            for (int d = 0; d < D; ++d) vv(j, d) = vi[d];
          }
        });
  }

 private:
  CollisionGrid<D, Real> grid_;
  CollisionParameters<Real> params_;
  std::size_t particle_capacity_, virtual_capacity_;
  bool atomic_sums_, sorted_sums_;
  int num_chunks_;
  Kokkos::View<int*, ExecSpace> cell_of_;
  vector_view vran_;
  Kokkos::View<double*, ExecSpace> partial_sums_;
  Kokkos::View<Real*, ExecSpace> cell_values_;
  int last_num_particles_ = -1;
  using key_view = Kokkos::View<std::int64_t*, ExecSpace>;
  key_view sort_keys_;
  std::optional<Kokkos::BinSort<key_view, Kokkos::BinOp1D<key_view>>> sorter_;  // built at the first sort
  std::optional<SegmentOrder<ExecSpace>> row_order_;  // sorted cell sums: the rows by cell
  vector_view x_sorted_, v_sorted_;
};

}  // namespace mesoflow::mpc
