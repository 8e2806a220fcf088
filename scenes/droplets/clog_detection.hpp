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
// All state lives in Views and observe() is one kernel over the replicas, so nothing crosses to the
// host during a run except the count of running replicas, when asked for.
#pragma once

#include "kernels/common/kokkos_compat.hpp"
#include "kernels/common/vec.hpp"

#include <Kokkos_Core.hpp>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace mesoflow::droplets {

// What happened to one replica; on the host.
struct ReplicaRecord {
  bool clogged = false;
  double distance = 0;   // r along g at the clog or at the time limit, σ
  double time = 0;       // t/t0 at the clog or the time limit
  double final_x = 0, final_y = 0;  // centre of mass at the end (unfolded), σ
  double steady_speed = 0;  // slope of r(t) over [T/2, T] in σ/t0; 0 if it clogged or had < 2 samples
};

// Replica states: running, clogged, or censored (reached the time limit still moving).
namespace replica_status {
constexpr int running = 0;
constexpr int clogged = 1;
constexpr int censored = 2;
}  // namespace replica_status

template <class ExecSpace = Kokkos::DefaultExecutionSpace>
class ClogDetector {
 public:
  using scalar_view = Kokkos::View<double*, ExecSpace>;

  // `terminal_energy` E_t = ½ M v_t²; `threshold` on E_k/E_t; `time_limit` T; `gravity` ĝ (unit).
  ClogDetector(int replicas, double terminal_energy, double threshold, double time_limit, const Vec<2, double>& gravity)
      : status_("mesoflow::clog_detection::status", replicas),
        origin_("mesoflow::clog_detection::origin", replicas),
        end_("mesoflow::clog_detection::end", replicas),
        fit_("mesoflow::clog_detection::fit", replicas),
        terminal_energy_(terminal_energy),
        threshold_(threshold),
        time_limit_(time_limit),
        gravity_(gravity) {
    if (replicas < 1) throw std::invalid_argument("clog detection: no replicas");
    if (!(terminal_energy > 0)) throw std::invalid_argument("clog detection: E_t must be > 0");
    if (!(threshold > 0 && threshold < 1)) throw std::invalid_argument("clog detection: threshold must be in (0, 1)");
    if (!(time_limit > 0)) throw std::invalid_argument("clog detection: time limit must be > 0");
  }

  // Records the starting centres of mass: state(b, com, ke) fills com[2] and E_k of replica b.
  template <class ReplicaState>
  void start(const ReplicaState& state) {
    const auto origin = origin_;
    Kokkos::parallel_for(
        "mesoflow::clog_detection::start", Kokkos::RangePolicy<ExecSpace>(0, replicas()), KOKKOS_LAMBDA(int b) {
          double com[2], ke;
          state(b, com, ke);
          origin(b, 0) = com[0];
          origin(b, 1) = com[1];
        });
  }

  // Checks every running replica at time t: clogged if E_k/E_t < threshold, else censored if
  // `at_limit` (the run has reached T: the clog test comes first).
  template <class ReplicaState>
  void observe(double t, bool at_limit, const ReplicaState& state) {
    const auto status = status_;
    const auto origin = origin_;
    const auto end = end_;
    const auto fit = fit_;
    const double e_clog = threshold_ * terminal_energy_, half = 0.5 * time_limit_;
    const double gx = gravity_[0], gy = gravity_[1];
    Kokkos::parallel_for(
        "mesoflow::clog_detection::observe", Kokkos::RangePolicy<ExecSpace>(0, replicas()), KOKKOS_LAMBDA(int b) {
          if (status(b) != replica_status::running) return;
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
          const bool clogged = ke < e_clog;
          if (clogged || at_limit) {
            status(b) = clogged ? replica_status::clogged : replica_status::censored;
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
    Kokkos::parallel_reduce(
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
    return out;
  }

  int replicas() const { return int(status_.extent(0)); }

 private:
  Kokkos::View<int*, ExecSpace> status_;
  Kokkos::View<double* [2], ExecSpace> origin_;
  Kokkos::View<double* [4], ExecSpace> end_;  // r, t, x_com, y_com at the end
  Kokkos::View<double* [5], ExecSpace> fit_;  // least-squares sums (see observe)
  double terminal_energy_, threshold_, time_limit_;
  Vec<2, double> gravity_;
};

}  // namespace mesoflow::droplets
