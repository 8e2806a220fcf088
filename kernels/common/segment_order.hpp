// segment_order.hpp — the deterministic-sum mode's one tool (issue 26 item 4): rows grouped by
// segment (a cell, a disc) in index order, so that each segment's sum is taken by one thread over its
// rows in a fixed order — bitwise the same on every backend and thread count, where float atomics
// (ScatterView on GPUs) add in whatever order the hardware schedules.
//
//   SegmentOrder<ExecSpace> order(rows, segments);   // once: the sorter and its buffers
//   order.sort(used, seg_of);                        // per step: seg_of(i) ∈ [0, segments) or −1
//   ... in a kernel over segments s, with the handle order.view():
//       for (int q = h.begin(s); q < h.end(s); ++q) { const int i = h.row(q); if (i is none) continue; ... }
//
// Rows are sorted by the unique key segment · rows + row with Kokkos::BinSort (bins = rows, sort within
// bins), so the order is by segment, then by row, whatever order BinSort's atomic binning filled the
// bins in. Rows that contribute to no segment (seg_of = −1) and the padding rows ≥ `used` are dealt to
// the segments round-robin (their keys still sort after every contributing row of the segment they
// are dealt to only where their index is larger; the loop skips them either way), which keeps every bin
// small: BinSort sorts within a bin serially. Segment ranges come from per-segment counts (integer
// atomics: exact) and an exclusive scan. Nothing is allocated after construction.
#pragma once

#include "kernel_launch.hpp"
#include "kokkos_compat.hpp"

#include <Kokkos_Core.hpp>
#include <Kokkos_Sort.hpp>

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace mesoflow {

// A Kokkos::BinSort bin operator on keys bin · stride + index (0 ≤ index < stride): the bin is the
// integer quotient, exact — unlike Kokkos::BinOp1D, whose floating-point ⌊key · nbins/range⌋ can put
// the key k·stride into bin k − 1 — so BinSort's bin offsets are the offsets of the bins. Ordering
// within a bin by key orders it by index.
template <class Key = std::int64_t>
struct ExactBinOp {
  int bins;
  Key stride;
  KOKKOS_INLINE_FUNCTION int max_bins() const { return bins; }
  template <class ViewType, class IndexType>
  KOKKOS_INLINE_FUNCTION int bin(ViewType& keys, const IndexType& i) const {
    return int(keys(i) / stride);
  }
  template <class ViewType, class I1, class I2>
  KOKKOS_INLINE_FUNCTION bool operator()(ViewType& keys, I1& i1, I2& i2) const {
    return keys(i1) < keys(i2);
  }
};

// Zeroes the bin counts of `sorter` before create_permute_vector(), which adds to the counts its
// last binning left (Kokkos 3.4 and 4.x zero them only in the constructor): through a writable alias
// of get_bin_count() (the same allocation). Every reused BinSort in mesoflow calls this first.
template <class ExecSpace, class Sorter>
void zero_bin_counts(const Sorter& sorter) {
  const auto bin_count = sorter.get_bin_count();
  using count_type = std::remove_const_t<typename decltype(bin_count)::value_type>;
  const Kokkos::View<count_type*, ExecSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>> counts(
      const_cast<count_type*>(bin_count.data()), bin_count.extent(0));
  mesoflow::launch::parallel_for(
      "mesoflow::binsort::zero_bins", Kokkos::RangePolicy<ExecSpace>(0, int(counts.extent(0))),
      KOKKOS_LAMBDA(const int b) { counts(b) = 0; });
}

// The device side of a SegmentOrder (raw pointers, small): the rows of segment s are
// row(begin(s)) … row(end(s) − 1), in index order, with the skipped rows among them.
template <class SizeType>
struct SegmentOrderView {
  const int* start;       // segment offsets, segments + 1
  const SizeType* perm;   // BinSort's permutation (positions → rows); rows entries
  KOKKOS_INLINE_FUNCTION int begin(int s) const { return start[s]; }
  KOKKOS_INLINE_FUNCTION int end(int s) const { return start[s + 1]; }
  KOKKOS_INLINE_FUNCTION int row(int q) const { return int(perm[q]); }
};

template <class ExecSpace = Kokkos::DefaultExecutionSpace>
class SegmentOrder {
 public:
  using key_view = Kokkos::View<std::int64_t*, ExecSpace>;
  using sorter_type = Kokkos::BinSort<key_view, Kokkos::BinOp1D<key_view>>;
  using view_type = SegmentOrderView<typename sorter_type::size_type>;

  SegmentOrder(int rows, int segments)
      : rows_(rows),
        segments_(segments),
        keys_(Kokkos::ViewAllocateWithoutInitializing("mesoflow::segment_order::keys"), std::size_t(rows > 0 ? rows : 1)),
        start_("mesoflow::segment_order::start", std::size_t(segments) + 1),
        count_("mesoflow::segment_order::count", std::size_t(segments)) {
    if (rows < 1) throw std::invalid_argument("segment order: rows must be >= 1, got " + std::to_string(rows));
    if (segments < 1) throw std::invalid_argument("segment order: segments must be >= 1, got " + std::to_string(segments));
    sorter_.emplace(keys_, Kokkos::BinOp1D<key_view>(rows, 0, std::int64_t(segments) * std::int64_t(rows)), true);
  }

  // Sorts rows [0, rows) by segment: seg_of(i) (a device functor, i < used) is row i's segment or
  // −1; rows ≥ used are padding. Afterwards view() gives each segment's rows in index order.
  template <class SegOf>
  void sort(int used, const SegOf& seg_of) {
    if (used < 0 || used > rows_)
      throw std::invalid_argument("segment order: " + std::to_string(used) + " rows used of " + std::to_string(rows_));
    const auto keys = keys_;
    const auto count = count_;
    const std::int64_t rows = rows_;
    const int segments = segments_;
    mesoflow::launch::parallel_for(
        "mesoflow::segment_order::zero", Kokkos::RangePolicy<ExecSpace>(0, segments),
        KOKKOS_LAMBDA(const int s) { count(s) = 0; });
    mesoflow::launch::parallel_for(
        "mesoflow::segment_order::keys", Kokkos::RangePolicy<ExecSpace>(0, int(rows)), KOKKOS_LAMBDA(const int i) {
          int s = i < used ? int(seg_of(i)) : -1;
          if (s < 0 || s >= segments) s = i % segments;  // skipped rows, dealt round-robin
          keys(i) = std::int64_t(s) * rows + i;
          Kokkos::atomic_add(&count(s), 1);
        });
    const auto start = start_;
    mesoflow::launch::parallel_scan(
        "mesoflow::segment_order::offsets", Kokkos::RangePolicy<ExecSpace>(0, segments + 1),
        KOKKOS_LAMBDA(const int s, int& partial, const bool final) {
          if (final) start(s) = partial;
          if (s < segments) partial += count(s);
        });
    zero_bin_counts<ExecSpace>(*sorter_);
    sorter_->create_permute_vector();
  }

  view_type view() const { return {start_.data(), sorter_->get_permute_vector().data()}; }
  int rows() const { return rows_; }
  int segments() const { return segments_; }

 private:
  int rows_, segments_;
  key_view keys_;
  Kokkos::View<int*, ExecSpace> start_, count_;
  std::optional<sorter_type> sorter_;
};

}  // namespace mesoflow
