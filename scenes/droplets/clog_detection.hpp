// clog_detection.hpp — per-replica clog detection and displacement tracking for droplets in
// obstacle arrays (capillary-droplets §4.2, Appendices C and D), on the device.
//
// A replica clogs when E_k/E_t falls below a threshold (10⁻¹⁷ in App. C), E_k the droplet's kinetic
// energy (Σ ½ m_i v_i² over a DP droplet's vertices, ½ M v² for an SP droplet) and E_t = ½ M v_t²
// its kinetic energy at the terminal speed. A replica that reaches the time limit first is
// right-censored. Either way the tracker records the displacement along g, r = (x_com − x_com(0))·ĝ,
// the time, and the final centre of mass.
//
// For continuous flow (App. D) the steady-state speed v_g is the least-squares slope of r(t); the
// tracker accumulates the sums of that fit over the samples in the second half of the run
// (t ≥ T/2), relative to t = T/2 for precision, while the replica is running.
//
// Early clog test (issue 25): E_k/E_t < 10⁻¹⁷ stays the definition, but at K_l/Γ ≤ 10⁻² the last
// decades of an arrest's exponential decay take 10²–10³ t0. Every Δt_s (sample_interval) each
// replica stores (t, ln E_k/E_t, x_com, y_com) in a device ring buffer of W = window/Δt_s samples;
// with the buffer full, a replica is declared clogged early when, over the window,
//   (1) its centre of mass stayed within `tolerance` of where it is now;
//   (2) ln(E_k/E_t) decays as an exponential: the least-squares slopes over the whole window and
//       over each half are all < −min_rate and the residual scatter (rms) of the whole-window fit is
//       below max_scatter (natural-log units);
//   (3) the travel left under that decay is below `tolerance`: |v_com| ≤ √(2E_k/M) = v_t √(E_k/E_t)
//       and E_k ∝ e^{−k t} with k the smallest of the three fitted rates, so the centre of mass can
//       still move at most 2 v_t √(E_k/E_t)/k.
// The record then keeps r, t and the centre of mass at the decision, the rate k and the
// extrapolated time at which E_k/E_t would cross the threshold. ClogTest picks what ends a replica:
// `full` the threshold only; `early` the threshold or the early test, whichever first; `both`
// (validation) the threshold only, with the early decision recorded on the side, so one run gives
// both classifications and both (r, t) pairs of every replica.
//
// Each replica has its own clock (steps run, its own Δt), limits (E_t, v_t, T) and records, so one
// detector serves a batch that mixes sweep points and refills finished slots with new replicas
// (restart) or drops them (compacted). All state lives in Views and observe() is one kernel over
// the replicas, so nothing crosses to the host during a run except the count of running replicas,
// when asked for.
#pragma once

#include "kernels/common/kernel_launch.hpp"
#include "kernels/common/kokkos_compat.hpp"
#include "kernels/common/vec.hpp"

#include <Kokkos_Core.hpp>

#include <cmath>
#include <cstdint>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

namespace mesoflow::droplets {

// Which test ends a replica (see the header comment).
enum class ClogTest { full, early, both };

inline ClogTest clog_test_from_name(const std::string& name) {
  if (name == "full") return ClogTest::full;
  if (name == "early") return ClogTest::early;
  if (name == "both") return ClogTest::both;
  throw std::invalid_argument("--clog-test: '" + name + "' is not one of full, early, both");
}

// Parameters of the early clog test (lengths σ, times t0).
struct EarlyClogParameters {
  double sample_interval = 0.5;  // Δt_s between ring-buffer samples
  double window = 20;            // τ_w, the span of the fit (W = round(τ_w/Δt_s) samples, 4..4096)
  double tolerance = 1e-3;       // on the displacement within the window and on the travel left
  double max_scatter = 0.5;      // rms residual of the ln(E_k/E_t) fit
  double min_rate = 1e-3;        // smallest decay rate k of E_k accepted, 1/t0

  int samples() const { return int(std::lround(window / sample_interval)); }
  // Throws std::invalid_argument naming the CLI flag and its range.
  void validate() const {
    const auto bad = [](const std::string& flag, double v, const std::string& range) {
      throw std::invalid_argument(flag + ": " + std::to_string(v) + " is out of range; expected " + range);
    };
    if (!(sample_interval >= 1e-3 && sample_interval <= 100)) bad("--clog-sample-interval", sample_interval, "[0.001, 100]");
    if (!(window > 0) || !(samples() >= 4 && samples() <= 4096))
      bad("--clog-window", window, "a window of 4..4096 samples of --clog-sample-interval");
    if (!(tolerance >= 1e-9 && tolerance <= 1)) bad("--clog-tolerance", tolerance, "[1e-09, 1]");
    if (!(max_scatter > 0 && max_scatter <= 10)) bad("--clog-max-scatter", max_scatter, "(0, 10]");
    if (!(min_rate > 0 && min_rate <= 100)) bad("--clog-min-rate", min_rate, "(0, 100]");
  }
};

// How the early test classified a replica.
namespace early_decision {
constexpr int none = 0;       // not clogged (censored at T)
constexpr int test = 1;       // clogged by the early test
constexpr int threshold = 2;  // clogged: E_k/E_t crossed the threshold before the early test decided
}  // namespace early_decision

// What happened to one replica; on the host.
struct ReplicaRecord {
  bool clogged = false;
  double distance = 0;   // r along g at the clog or at the time limit, σ
  double time = 0;       // t/t0 at the clog or the time limit
  double final_x = 0, final_y = 0;  // centre of mass at the end (unfolded), σ
  double steady_speed = 0;  // slope of r(t) over [T/2, T] in σ/t0; 0 if it clogged or had < 2 samples
  // The early test (ClogTest early or both; none under full): its classification, r and t at its
  // decision, the rate k of E_k and the extrapolated time E_k/E_t crosses the threshold (t0).
  int early = early_decision::none;
  double early_distance = 0, early_time = 0, early_rate = 0, early_crossing = 0;
  bool early_clogged() const { return early != early_decision::none; }
};

// Replica states: running, clogged, or censored (reached the time limit still moving).
namespace replica_status {
constexpr int running = 0;
constexpr int clogged = 1;
constexpr int censored = 2;
}  // namespace replica_status

namespace clog_detail {
// Least-squares slope of y(s) over samples [first, first + n) of the window (oldest first) of
// replica b in the ring `ring` (columns t, ln E, x, y) with `count` samples written so far; the
// residual rms through `rms` when non-null.
template <class Ring>
KOKKOS_INLINE_FUNCTION double window_slope(const Ring& ring, int b, int count, int first, int n, double t0, double* rms) {
  const int w = int(ring.extent(1));
  double ss = 0, sy = 0, sss = 0, ssy = 0, syy = 0;
  for (int i = first; i < first + n; ++i) {
    const int slot = (count - w + i) % w;
    const double s = ring(b, slot, 0) - t0, y = ring(b, slot, 1);
    ss += s;
    sy += y;
    sss += s * s;
    ssy += s * y;
    syy += y * y;
  }
  const double sxx = sss - ss * ss / n, sxy = ssy - ss * sy / n, yy = syy - sy * sy / n;
  const double slope = sxx > 0 ? sxy / sxx : 0.0;
  if (rms) {
    const double res = yy - slope * sxy;
    *rms = kmath::sqrt((res > 0 ? res : 0.0) / n);
  }
  return slope;
}
// dst(k, …) = src(keep[k], …) for Views of rank 1 to 3 (host round trip; compaction only).
template <class View>
void gather_rows(const View& src, const View& dst, const std::vector<int>& keep) {
  const auto s = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), src);
  const auto d = Kokkos::create_mirror_view(dst);
  for (std::size_t k = 0; k < keep.size(); ++k) {
    const std::size_t b = std::size_t(keep[k]);
    if constexpr (View::rank == 1) {
      d(k) = s(b);
    } else if constexpr (View::rank == 2) {
      for (std::size_t c = 0; c < s.extent(1); ++c) d(k, c) = s(b, c);
    } else {
      for (std::size_t c = 0; c < s.extent(1); ++c)
        for (std::size_t e = 0; e < s.extent(2); ++e) d(k, c, e) = s(b, c, e);
    }
  }
  Kokkos::deep_copy(dst, d);
}
}  // namespace clog_detail

// What a replica is measured against, per replica (a batch may mix sweep points): E_t = ½ M v_t²,
// v_t, the time limit T and the replica's time step Δt (its clock: t = steps·Δt).
struct ReplicaLimits {
  double terminal_energy = 1, terminal_speed = 1, time_limit = 1, dt = 1;
};

template <class ExecSpace = Kokkos::DefaultExecutionSpace>
class ClogDetector {
 public:
  using scalar_view = Kokkos::View<double*, ExecSpace>;

  // `threshold` on E_k/E_t; `gravity` ĝ (unit); `test` and `early` the early clog test (ignored
  // under ClogTest::full); observe() is called every `steps_per_observation` steps of the replicas.
  ClogDetector(int replicas, double threshold, const Vec<2, double>& gravity, ClogTest test = ClogTest::full,
               const EarlyClogParameters& early = {}, int steps_per_observation = 1)
      : status_("mesoflow::clog_detection::status", replicas),
        origin_("mesoflow::clog_detection::origin", replicas),
        end_("mesoflow::clog_detection::end", replicas),
        fit_("mesoflow::clog_detection::fit", replicas),
        decision_("mesoflow::clog_detection::decision", replicas),
        early_record_("mesoflow::clog_detection::early_record", replicas),
        ring_("mesoflow::clog_detection::ring", test == ClogTest::full ? 0 : replicas,
              test == ClogTest::full ? 1 : early.samples()),
        limits_("mesoflow::clog_detection::limits", replicas),
        clock_("mesoflow::clog_detection::clock", replicas),
        next_sample_("mesoflow::clog_detection::next_sample", replicas),
        threshold_(threshold),
        gravity_(gravity),
        test_(test),
        early_(early),
        steps_per_observation_(steps_per_observation) {
    if (replicas < 1) throw std::invalid_argument("clog detection: no replicas");
    if (!(threshold > 0 && threshold < 1)) throw std::invalid_argument("clog detection: threshold must be in (0, 1)");
    if (steps_per_observation < 1) throw std::invalid_argument("clog detection: steps per observation must be >= 1");
    early.validate();
    Kokkos::deep_copy(status_, replica_status::censored);  // idle until started
  }

  // Starts every replica from its current state, all with the same limits.
  template <class ReplicaState>
  void start(const ReplicaLimits& limits, const ReplicaState& state) {
    std::vector<int> all(static_cast<std::size_t>(replicas()));
    std::iota(all.begin(), all.end(), 0);
    restart(all, std::vector<ReplicaLimits>(all.size(), limits), state);
  }

  // (Re)starts replicas `which[k]` with limits[k] from their current state (state(b, com, ke) fills
  // com[2] and E_k of replica b): clock at 0, origin at the current centre of mass, records cleared.
  // Host setup, between observations (a batch refilling a slot with a new replica).
  template <class ReplicaState>
  void restart(const std::vector<int>& which, const std::vector<ReplicaLimits>& limits, const ReplicaState& state) {
    if (which.size() != limits.size()) throw std::invalid_argument("clog detection: limits for each restarted replica");
    if (which.empty()) return;
    Kokkos::View<int*, ExecSpace> slots("mesoflow::clog_detection::restart_slots", which.size());
    Kokkos::View<double* [5], ExecSpace> values("mesoflow::clog_detection::restart_limits", which.size());
    const auto slots_h = Kokkos::create_mirror_view(slots);
    const auto values_h = Kokkos::create_mirror_view(values);
    for (std::size_t k = 0; k < which.size(); ++k) {
      const ReplicaLimits& l = limits[k];
      if (which[k] < 0 || which[k] >= replicas())
        throw std::invalid_argument("clog detection: replica " + std::to_string(which[k]) + " outside [0, " +
                                    std::to_string(replicas()) + ")");
      if (!(l.terminal_energy > 0)) throw std::invalid_argument("clog detection: E_t must be > 0");
      if (!(l.terminal_speed > 0)) throw std::invalid_argument("clog detection: v_t must be > 0");
      if (!(l.time_limit > 0)) throw std::invalid_argument("clog detection: time limit must be > 0");
      if (!(l.dt > 0)) throw std::invalid_argument("clog detection: the replica's time step must be > 0");
      slots_h(k) = which[k];
      values_h(k, 0) = l.terminal_energy;
      values_h(k, 1) = l.terminal_speed;
      values_h(k, 2) = l.time_limit;
      values_h(k, 3) = l.dt;
      // The last step: T/Δt rounded up to whole observations.
      const double per = steps_per_observation_;
      values_h(k, 4) = std::ceil((std::ceil(l.time_limit / l.dt - 1e-9)) / per) * per;
    }
    Kokkos::deep_copy(slots, slots_h);
    Kokkos::deep_copy(values, values_h);
    const auto status = status_;
    const auto origin = origin_;
    const auto end = end_;
    const auto fit = fit_;
    const auto decision = decision_;
    const auto early_record = early_record_;
    const auto lim = limits_;
    const auto clock = clock_;
    const auto next = next_sample_;
    const double first_sample = early_.sample_interval;
    mesoflow::launch::parallel_for(
        "mesoflow::clog_detection::restart", Kokkos::RangePolicy<ExecSpace>(0, int(which.size())),
        KOKKOS_LAMBDA(int k) {
          const int b = slots(k);
          double com[2], ke;
          state(b, com, ke);
          origin(b, 0) = com[0];
          origin(b, 1) = com[1];
          for (int c = 0; c < 4; ++c) end(b, c) = 0;
          for (int c = 0; c < 5; ++c) fit(b, c) = 0;
          for (int c = 0; c < 6; ++c) early_record(b, c) = 0;
          for (int c = 0; c < 5; ++c) lim(b, c) = values(k, c);
          lim(b, 5) = 0;  // the clock's time and steps at the last change of the replica's step
          lim(b, 6) = 0;
          decision(b) = early_decision::none;
          clock(b, 0) = 0;  // steps run
          clock(b, 1) = 0;  // ring samples taken
          next(b) = first_sample;
          status(b) = replica_status::running;
        });
  }

  // Replicas whose step changes during a run (DropletScene's shape-following step): observe() reads
  // replica b's current step from time_steps(b). A change found at an observation is taken to have
  // happened at the previous one (the scene changes steps only between observations), and the clock
  // continues from there: t = t_c + (steps − steps_c)·Δt_new, the last step recomputed from the time
  // left. Without changes t = steps·Δt exactly, as without following.
  void follow_time_steps(const Kokkos::View<double*, ExecSpace>& time_steps) {
    if (time_steps.extent(0) != std::size_t(replicas()))
      throw std::invalid_argument("clog detection: " + std::to_string(time_steps.extent(0)) + " time steps for " +
                                  std::to_string(replicas()) + " replicas");
    time_steps_ = time_steps;
  }

  // Every replica still running has advanced steps_per_observation steps of its own Δt: updates its
  // clock, tracking and clog tests at its time t (steps·Δt, or as follow_time_steps says), and ends
  // it when it clogs or reaches its time limit.
  template <class ReplicaState>
  void observe(const ReplicaState& state) {
    const auto status = status_;
    const auto origin = origin_;
    const auto end = end_;
    const auto fit = fit_;
    const auto decision = decision_;
    const auto early_record = early_record_;
    const auto ring = ring_;
    const auto lim = limits_;
    const auto clock = clock_;
    const auto next = next_sample_;
    const double threshold = threshold_, ln_threshold = std::log(threshold_);
    const double gx = gravity_[0], gy = gravity_[1];
    const bool testing = test_ != ClogTest::full;
    const bool early_ends = test_ == ClogTest::early;
    const int w = testing ? int(ring_.extent(1)) : 1;
    const double tolerance = early_.tolerance, max_scatter = early_.max_scatter, min_rate = early_.min_rate;
    const double interval = early_.sample_interval;
    const long long per = steps_per_observation_;
    if (time_steps_.extent(0) > 0) follow_steps();
    mesoflow::launch::parallel_for(
        "mesoflow::clog_detection::observe", Kokkos::RangePolicy<ExecSpace>(0, replicas()), KOKKOS_LAMBDA(int b) {
          if (status(b) != replica_status::running) return;
          const long long steps = clock(b, 0) + per;
          clock(b, 0) = steps;
          const double t = lim(b, 5) + double(steps - (long long)lim(b, 6)) * lim(b, 3);
          const bool at_limit = double(steps) >= lim(b, 4);
          const double e_t = lim(b, 0), v_t = lim(b, 1), half = 0.5 * lim(b, 2);
          const bool sample = testing && t + 1e-9 >= next(b);
          int count = int(clock(b, 1));
          if (sample) {
            next(b) += interval;
            clock(b, 1) = ++count;
          }
          double com[2], ke;
          state(b, com, ke);
          const double r = (com[0] - origin(b, 0)) * gx + (com[1] - origin(b, 1)) * gy;
          if (t >= half) {  // least-squares sums of r(t) on [T/2, T]: n, Σs, Σr, Σs², Σsr with s = t − T/2
            const double s = t - half;
            fit(b, 0) += 1;
            fit(b, 1) += s;
            fit(b, 2) += r;
            fit(b, 3) += s * s;
            fit(b, 4) += s * r;
          }
          const bool clogged = ke < threshold * e_t;
          bool early_now = false;
          if (sample && decision(b) == early_decision::none && !clogged) {
            const double ratio = ke / e_t;
            const double ln_e = kmath::log(ratio > 1e-300 ? ratio : 1e-300);
            const int slot = (count - 1) % w;
            ring(b, slot, 0) = t;
            ring(b, slot, 1) = ln_e;
            ring(b, slot, 2) = com[0];
            ring(b, slot, 3) = com[1];
            if (count >= w) {
              // (1) the centre of mass stayed within the tolerance over the window.
              double moved = 0;
              for (int i = 0; i < w; ++i) {
                const double dx = ring(b, i, 2) - com[0], dy = ring(b, i, 3) - com[1];
                const double d2 = dx * dx + dy * dy;
                moved = d2 > moved ? d2 : moved;
              }
              if (moved < tolerance * tolerance) {
                // (2) an exponential decay over the window and both halves; (3) the travel left.
                double scatter = 0;
                const double k_all = -clog_detail::window_slope(ring, b, count, 0, w, t, &scatter);
                const double k_old = -clog_detail::window_slope(ring, b, count, 0, w / 2, t, nullptr);
                const double k_new = -clog_detail::window_slope(ring, b, count, w - w / 2, w / 2, t, nullptr);
                double k = k_all < k_old ? k_all : k_old;
                k = k < k_new ? k : k_new;
                if (k > min_rate && scatter < max_scatter && 2.0 * v_t * kmath::sqrt(ratio) / k < tolerance) {
                  early_now = true;
                  decision(b) = early_decision::test;
                  early_record(b, 0) = r;
                  early_record(b, 1) = t;
                  early_record(b, 2) = k;
                  early_record(b, 3) = t + (ln_e - ln_threshold) / k;
                  early_record(b, 4) = com[0];
                  early_record(b, 5) = com[1];
                }
              }
            }
          }
          if (clogged && testing && decision(b) == early_decision::none) {
            decision(b) = early_decision::threshold;
            early_record(b, 0) = r;
            early_record(b, 1) = t;
            early_record(b, 2) = 0;
            early_record(b, 3) = t;
            early_record(b, 4) = com[0];
            early_record(b, 5) = com[1];
          }
          const bool ends_clogged = clogged || (early_ends && early_now);
          if (ends_clogged || at_limit) {
            status(b) = ends_clogged ? replica_status::clogged : replica_status::censored;
            end(b, 0) = r;
            end(b, 1) = t;
            end(b, 2) = com[0];
            end(b, 3) = com[1];
          }
        });
  }

  // Replicas still running (a reduction read back on the host).
  int running() const {
    const auto status = status_;
    int n = 0;
    mesoflow::launch::parallel_reduce(
        "mesoflow::clog_detection::running", Kokkos::RangePolicy<ExecSpace>(0, replicas()),
        KOKKOS_LAMBDA(int b, int& acc) { acc += status(b) == replica_status::running ? 1 : 0; }, n);
    return n;
  }

  // Status of every replica and the record of each finished one (host copies; output steps only).
  std::vector<int> status() const {
    const auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), status_);
    return std::vector<int>(h.data(), h.data() + h.extent(0));
  }
  ReplicaRecord record(int b) const {
    const auto status = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), status_);
    const auto end = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), end_);
    const auto fit = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), fit_);
    const auto decision = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), decision_);
    const auto early = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), early_record_);
    if (status(b) == replica_status::running)
      throw std::logic_error("clog detection: replica " + std::to_string(b) + " is still running");
    ReplicaRecord out;
    out.clogged = status(b) == replica_status::clogged;
    out.distance = end(b, 0);
    out.time = end(b, 1);
    out.final_x = end(b, 2);
    out.final_y = end(b, 3);
    const double n = fit(b, 0), denominator = n * fit(b, 3) - fit(b, 1) * fit(b, 1);
    if (!out.clogged && n >= 2 && denominator > 0)
      out.steady_speed = (n * fit(b, 4) - fit(b, 1) * fit(b, 2)) / denominator;
    out.early = decision(b);
    if (out.early != early_decision::none) {
      out.early_distance = early(b, 0);
      out.early_time = early(b, 1);
      out.early_rate = early(b, 2);
      out.early_crossing = early(b, 3);
    } else {  // censored: the early test agrees with the end of the run
      out.early_distance = out.distance;
      out.early_time = out.time;
    }
    return out;
  }

  // A detector of the replicas keep[0], keep[1], … of this one, in that order, every record, clock
  // and ring buffer carried over (a batch compacting its running replicas).
  ClogDetector compacted(const std::vector<int>& keep) const {
    if (keep.empty()) throw std::invalid_argument("clog detection: nothing to keep");
    for (const int b : keep)
      if (b < 0 || b >= replicas())
        throw std::invalid_argument("clog detection: replica " + std::to_string(b) + " outside [0, " +
                                    std::to_string(replicas()) + ")");
    ClogDetector out(int(keep.size()), threshold_, gravity_, test_, early_, steps_per_observation_);
    clog_detail::gather_rows(status_, out.status_, keep);
    clog_detail::gather_rows(origin_, out.origin_, keep);
    clog_detail::gather_rows(end_, out.end_, keep);
    clog_detail::gather_rows(fit_, out.fit_, keep);
    clog_detail::gather_rows(decision_, out.decision_, keep);
    clog_detail::gather_rows(early_record_, out.early_record_, keep);
    if (ring_.extent(0) > 0) clog_detail::gather_rows(ring_, out.ring_, keep);
    clog_detail::gather_rows(limits_, out.limits_, keep);
    clog_detail::gather_rows(clock_, out.clock_, keep);
    clog_detail::gather_rows(next_sample_, out.next_sample_, keep);
    return out;
  }

  int replicas() const { return int(status_.extent(0)); }
  ClogTest test() const { return test_; }
  int steps_per_observation() const { return steps_per_observation_; }

  // The clocks of the running replicas whose step has changed since the last observation continue
  // from it at the new step: t_c, steps_c and the last step (T reached on the replica's own clock,
  // rounded up to whole observations) from the time left. Called by observe(); public because CUDA
  // refuses an extended lambda in a private member function.
  void follow_steps() {
    const auto status = status_;
    const auto lim = limits_;
    const auto clock = clock_;
    const auto time_steps = time_steps_;
    const double per = double(steps_per_observation_);
    mesoflow::launch::parallel_for(
        "mesoflow::clog_detection::follow_steps", Kokkos::RangePolicy<ExecSpace>(0, replicas()), KOKKOS_LAMBDA(int b) {
          if (status(b) != replica_status::running || time_steps(b) == lim(b, 3)) return;
          const long long previous = clock(b, 0);
          const double t_change = lim(b, 5) + double(previous - (long long)lim(b, 6)) * lim(b, 3);
          const double dt_new = time_steps(b), left = lim(b, 2) - t_change;
          lim(b, 5) = t_change;
          lim(b, 6) = double(previous);
          lim(b, 3) = dt_new;
          const double left_steps = left > 0 ? -kmath::floor(1e-9 - left / dt_new) : 0.0;  // ⌈left/Δt − 10⁻⁹⌉
          lim(b, 4) = double(previous) - kmath::floor(-left_steps / per) * per;            // whole observations
        });
  }

 private:
  Kokkos::View<int*, ExecSpace> status_;
  Kokkos::View<double* [2], ExecSpace> origin_;
  Kokkos::View<double* [4], ExecSpace> end_;  // r, t, x_com, y_com at the end
  Kokkos::View<double* [5], ExecSpace> fit_;  // least-squares sums (see observe)
  Kokkos::View<int*, ExecSpace> decision_;    // early_decision of each replica
  Kokkos::View<double* [6], ExecSpace> early_record_;  // r, t, k, crossing time, x_com, y_com at the early decision
  Kokkos::View<double** [4], ExecSpace> ring_;  // (replica, slot): t, ln(E_k/E_t), x_com, y_com
  // E_t, v_t, T, Δt, the last step, and the time and steps at the last change of Δt (follow_time_steps)
  Kokkos::View<double* [7], ExecSpace> limits_;
  Kokkos::View<long long* [2], ExecSpace> clock_;  // steps run, ring samples taken
  Kokkos::View<double*, ExecSpace> time_steps_;    // each replica's current step; empty: fixed (limits_ Δt)
  Kokkos::View<double*, ExecSpace> next_sample_;   // time of the next ring sample
  double threshold_;
  Vec<2, double> gravity_;
  ClogTest test_;
  EarlyClogParameters early_;
  int steps_per_observation_;
};

}  // namespace mesoflow::droplets
