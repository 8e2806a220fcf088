// recycling.hpp — the continuous flow of the hoppers (hopper-flows §2.4), one implementation for
// the soft-particle (hopper_scene.hpp) and deformable-polygon (dp_hopper_scene.hpp) scenes.
//
// Every `detect_every` steps one parallel_reduce over the bodies (particles or polygons) marks
// those whose height (centre, or centroid) first passes below the orifice plane (height 0: they
// leave the hopper, adding their area/volume to the crossed total) and counts those more than
// `recycle_depth` below it (count_crossings). Only when that count is nonzero does the scene copy
// its state to the host and call Recycler::reinsert with the bodies to re-insert. For each, in
// index order: a lateral target is drawn uniformly in the hopper's cross-section (host RNG keyed on
// the seed); the bulk bodies (inside the hopper, not awaiting re-insertion) are ordered as anchors:
// those held in the packing first (the SP scene: touching at least min_anchor_contacts particles or
// walls, so never a particle in free flight above the pile; the others only while nothing is held,
// as in the free fall at the start), within that those within σ_avg of the target laterally first,
// each group highest first; the body is put in contact with the first anchor in the first
// direction — straight up, then tilting away by 15° steps (3D: 8 azimuths per tilt) — where the
// scene's placement test finds no overlap beyond `contact_tolerance`, and takes the mean velocity of
// the anchor and its bulk neighbours within 2σ_avg (not the anchor's own: copying one body's
// agitation at every re-insertion heated a weakly damped pile without bound, issue 27). What "in
// contact" and "overlap" mean is the scene's (a disk or sphere at σ_mn from the anchor's centre; a
// polygon translated rigidly to R_m + R_n + δ_mn from the anchor's centroid): the scene passes it as
// try_place. The body count never changes.
#pragma once

#include "kernels/common/reductions.hpp"
#include "kernels/common/vec.hpp"

#include <Kokkos_Core.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace mesoflow::hopper {

constexpr double recycle_depth = 2.0;       // σ_avg below the orifice before re-insertion (§2.4)
constexpr double contact_tolerance = 1e-9;  // largest relative overlap of a re-inserted body
constexpr int detect_every = 10;            // steps between crossing/recycling checks
constexpr int min_anchor_contacts = 2;      // SP: an anchor touches at least this many particles or walls

// One parallel_reduce over n bodies: body.height(i) (Real) below 0 for the first time marks
// outside(i) and adds body.measure(i) (double) to sums[0] and 1 to sums[1]; sums[2] counts the
// bodies more than recycle_depth below the orifice. Body: a device-copyable functor.
template <class Real, class ExecSpace, class Body>
std::array<double, 3> count_crossings(const std::string& label, int n, const Kokkos::View<int*, ExecSpace>& outside_,
                                      const Body& body) {
  const auto outside = outside_;
  const Real depth = Real(-recycle_depth);
  return parallel_sum<3, ExecSpace>(label, n, KOKKOS_LAMBDA(int i, double(&acc)[3]) {
    const Real h = body.height(i);
    if (outside(i) == 0 && h < Real(0)) {
      outside(i) = 1;
      acc[0] += body.measure(i);
      acc[1] += 1;
    }
    if (h < depth) acc[2] += 1;
  });
}

// Directions to try around an anchor: straight up, then tilting by 15° steps (2D: to either side;
// 3D: 8 azimuths per tilt).
template <int D>
std::vector<Vec<D, double>> contact_directions() {
  constexpr double pi = 3.14159265358979323846;
  std::vector<Vec<D, double>> dirs;
  for (int tilt = 0; tilt <= 6; ++tilt) {
    const double a = tilt * pi / 12;
    if constexpr (D == 2) {
      dirs.push_back(Vec<2, double>{{std::sin(a), std::cos(a)}});
      if (tilt > 0) dirs.push_back(Vec<2, double>{{-std::sin(a), std::cos(a)}});
    } else {
      const int azimuths = tilt == 0 ? 1 : 8;
      for (int k = 0; k < azimuths; ++k) {
        const double b = 2 * pi * k / azimuths;
        dirs.push_back(Vec<3, double>{{std::sin(a) * std::cos(b), std::sin(a) * std::sin(b), std::cos(a)}});
      }
    }
  }
  return dirs;
}

// The host side of the continuous flow: the counters, the re-insertion RNG and the re-insertion.
class Recycler {
 public:
  // The counters and RNG, as the NaN watchdog saves and restores them.
  struct State {
    std::mt19937_64 rng;
    long long crossings = 0, insertions = 0, last_recycling_step = -1;
    double crossed = 0, last_crossing_time = 0, max_insertion_overlap = 0;
    std::vector<int> last_inserted;
  };

  // A body as an anchor candidate: its lateral coordinates (D − 1 of them) and height, and whether
  // it is in the bulk (inside the hopper and not awaiting re-insertion).
  struct Anchor {
    bool bulk;
    double lateral[2];
    double height;
    bool held = true;  // part of the packing (SP: touching ≥ min_anchor_contacts surfaces); held anchors go first
  };

  explicit Recycler(unsigned long long seed) { s_.rng.seed(seed ^ 0x9e3779b97f4a7c15ULL); }

  // Adds the sums of count_crossings at time t; returns whether bodies wait for re-insertion.
  bool record_crossings(const std::array<double, 3>& sums, double t) {
    if (sums[1] > 0) {
      s_.crossed += sums[0];
      s_.crossings += (long long)(sums[1]);
      s_.last_crossing_time = t;
    }
    return sums[2] > 0;
  }

  // Re-inserts `bodies` (see the file comment) at step `step`, targets within `radius` of the axis.
  // anchor_of(k) describes body k of n as it is now (bodies placed before it included);
  // try_place(i, j, dir) puts body i in contact with anchor j in direction dir if nothing overlaps
  // it beyond contact_tolerance, and then returns its overlap (else std::nullopt, leaving it).
  // Throws std::runtime_error `what` + the body's index where no place is found.
  template <int D, class AnchorOf, class TryPlace>
  void reinsert(const std::vector<int>& bodies, double radius, int n, AnchorOf&& anchor_of, TryPlace&& try_place,
                const std::string& what, long long step) {
    s_.last_inserted = bodies;
    const auto dirs = contact_directions<D>();
    std::uniform_real_distribution<double> u(-1, 1);
    for (const int i : bodies) {
      double target[2] = {0, 0};
      do {
        for (int d = 0; d < D - 1; ++d) target[d] = radius * u(s_.rng);
      } while (target[0] * target[0] + target[1] * target[1] > radius * radius);
      std::vector<std::pair<double, int>> order;
      for (int k = 0; k < n; ++k) {
        const Anchor a = anchor_of(k);
        if (!a.bulk) continue;
        double lateral2 = 0;
        for (int d = 0; d < D - 1; ++d) lateral2 += std::pow(a.lateral[d] - target[d], 2);
        order.emplace_back((a.held ? 2e9 : 0) + (lateral2 < 1 ? 1e9 : 0) + a.height, k);
      }
      std::sort(order.begin(), order.end(), [](const auto& a, const auto& b) {
        return a.first != b.first ? a.first > b.first : a.second < b.second;
      });
      bool placed = false;
      for (const auto& [key, j] : order) {
        for (const auto& dir : dirs) {
          const std::optional<double> overlap = try_place(i, j, dir);
          if (!overlap) continue;
          s_.max_insertion_overlap = std::max(s_.max_insertion_overlap, *overlap);
          placed = true;
          break;
        }
        if (placed) break;
      }
      if (!placed) throw std::runtime_error(what + std::to_string(i));
      ++s_.insertions;
    }
    s_.last_recycling_step = step;
  }

  const State& state() const { return s_; }
  void restore(const State& s) { s_ = s; }

 private:
  State s_;
};

}  // namespace mesoflow::hopper
