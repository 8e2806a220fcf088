// crystal_record.hpp — the setup and the recorded frames of the microfluidic-crystal runs
// (mpc-microfluidic-crystal-phonons §4, Appendix B) in the channel flow of channel_flow.hpp.
//
// Setup: N discs at spacing a = L/N along x, y on a triangle wave of `wavelength` discs about W/2
// (zigzag()), starting on the axis (a single disc sits on the axis, as in the paper's calibration
// of K). Frames (CrystalRecord::record): the disc centres, unwrapped along x, and velocities; the
// mean disc velocity u_d and the mean solvent velocity u_oil; with one disc, the solvent's velocity
// profile u_x(y) far from the disc (periodic distance along x from its centre at least R + W,
// where a disc's disturbance of channel flow has decayed to e^{−4.2} ≈ 1.5% of it), in bins of half
// a cell across the channel, summed over the measured frames: its centre-line value is the
// undisturbed oil speed on the axis where the disc sits, its mean the undisturbed mean oil speed
// (docs/mpc.md, "K of a single disc"). The frames are kept in memory for the analysis at the end,
// and with the unwrapping state in checkpoints (checkpoint_fields(), declared once).
#pragma once

#include "scenes/crystal/channel_flow.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iomanip>
#include <stdexcept>
#include <string>
#include <vector>

namespace mesoflow::crystal {

// Disc centres of the zigzag (amplitude < 0: the largest without wall contact).
inline std::vector<std::array<double, 2>> zigzag(const mpc::ChannelFlowParameters<double>& f, long long discs,
                                                 long long wavelength, double amplitude_request) {
  const double spacing = f.length / double(discs);
  const double largest = 0.5 * f.width - f.disc_radius - std::pow(2.0, 1.0 / 6.0) * f.wca_r0;
  const double amplitude = amplitude_request < 0 ? std::max(0.0, largest) : amplitude_request;
  if (discs > 1 && spacing < 2 * f.disc_radius)
    throw std::invalid_argument("--discs " + std::to_string(discs) + ": spacing L/N = " + std::to_string(spacing) +
                                " is below the disc diameter 2R = " + std::to_string(2 * f.disc_radius));
  if (amplitude > 0.5 * f.width - f.disc_radius)
    throw std::invalid_argument("--amplitude " + std::to_string(amplitude) + ": must be at most W/2 - R = " +
                                std::to_string(0.5 * f.width - f.disc_radius));
  std::vector<std::array<double, 2>> centres(static_cast<std::size_t>(discs));
  for (long long j = 0; j < discs; ++j) {
    const double s = double(j % wavelength) / double(wavelength);
    const double triangle = 1 - 4 * std::abs(s - 0.25 - std::floor(s + 0.25));  // 0 at s = 0, ±1 at s = 1/4, 3/4
    centres[std::size_t(j)] = {(double(j) + 0.5) * spacing, 0.5 * f.width + amplitude * triangle};
  }
  return centres;
}

// The far-field profile's bins (one disc only; bins = 0: none).
struct FarField {
  double from_disc = 0;  // R + W
  int bins = 0;
  double bin_width = 0;
  // {mean, axis} speed of per-bin sums: the mean over every sample, the axis over the bins within
  // half a cell of y = W/2; 0 where a bin set is empty.
  std::array<double, 2> speeds(const std::vector<double>& sum, const std::vector<double>& count, double width,
                               double cell) const {
    double s = 0, c = 0, as = 0, ac = 0;
    for (int b = 0; b < bins; ++b) {
      s += sum[std::size_t(b)];
      c += count[std::size_t(b)];
      if (std::abs((b + 0.5) * bin_width - 0.5 * width) < 0.5 * cell) {
        as += sum[std::size_t(b)];
        ac += count[std::size_t(b)];
      }
    }
    return {c > 0 ? s / c : 0.0, ac > 0 ? as / ac : 0.0};
  }
};

// One recorded frame.
struct Frame {
  std::int64_t step = 0;
  double time = 0;
  std::vector<double> position, velocity;  // discs, row-major (x unwrapped)
  double u_d = 0, u_oil = 0;
  std::array<double, 2> far_speeds{};      // this frame's far-field {mean, axis} speeds (one disc)
};

class CrystalRecord {
 public:
  CrystalRecord(const mpc::ChannelFlowParameters<double>& f, const std::vector<std::array<double, 2>>& centres,
                std::int64_t warmup_steps)
      : f_(f), warmup_steps_(warmup_steps), last_folded(centres.size()), image_shift(centres.size(), 0.0) {
    if (centres.size() == 1) {
      far_.from_disc = f.disc_radius + f.width;
      far_.bins = int(std::llround(2 * f.width / f.cell_size));
      far_.bin_width = f.width / double(far_.bins);
      if (!(far_.bins > 0 && f.length > 2 * far_.from_disc)) far_.bins = 0;
    }
    far_sum.assign(std::size_t(far_.bins), 0.0);
    far_count.assign(std::size_t(far_.bins), 0.0);
    for (std::size_t k = 0; k < centres.size(); ++k) last_folded[k] = centres[k][0];
  }

  // Records the flow's current frame (host copies: frames are hundreds of steps apart).
  template <class Real, class Exec>
  Frame record(const mpc::ChannelFlow<Real, Exec>& flow) {
    const auto X = host_rows(flow.discs().x);
    const auto U = host_rows(flow.discs().u);
    const std::size_t nd = last_folded.size();
    Frame fr;
    fr.step = std::int64_t(flow.steps_done());
    fr.time = flow.time();
    fr.position.resize(2 * nd);
    fr.velocity.resize(2 * nd);
    for (std::size_t k = 0; k < nd; ++k) {
      const double xf = double(X[2 * k]);
      double jump = xf - last_folded[k];  // a disc moves far less than L/2 between frames
      image_shift[k] -= f_.length * std::round(jump / f_.length);
      last_folded[k] = xf;
      fr.position[2 * k] = xf + image_shift[k];
      fr.position[2 * k + 1] = double(X[2 * k + 1]);
      fr.velocity[2 * k] = double(U[2 * k]);
      fr.velocity[2 * k + 1] = double(U[2 * k + 1]);
      fr.u_d += fr.velocity[2 * k] / double(nd);
    }
    fr.u_oil = flow.solvent_momentum()[0] / (f_.mass * double(flow.num_solvent()));
    steps.push_back(fr.step);
    for (std::size_t k = 0; k < nd; ++k) {
      x.push_back(fr.position[2 * k]);
      y.push_back(fr.position[2 * k + 1]);
    }
    u_d.push_back(fr.u_d);
    u_oil.push_back(fr.u_oil);
    if (far_.bins > 0) {
      const auto xs = host_rows(flow.positions());
      const auto vs = host_rows(flow.velocities());
      const double xd = double(X[0]);
      std::vector<double> sum(std::size_t(far_.bins), 0.0), count(std::size_t(far_.bins), 0.0);
      for (std::size_t i = 0; i < flow.num_solvent(); ++i) {
        double dx = double(xs[2 * i]) - xd;
        dx -= f_.length * std::round(dx / f_.length);
        if (std::abs(dx) < far_.from_disc) continue;
        const int b = std::min(far_.bins - 1, std::max(0, int(double(xs[2 * i + 1]) / far_.bin_width)));
        sum[std::size_t(b)] += double(vs[2 * i]);
        count[std::size_t(b)] += 1.0;
      }
      fr.far_speeds = far_.speeds(sum, count, f_.width, f_.cell_size);
      if (fr.step >= warmup_steps_)
        for (int b = 0; b < far_.bins; ++b) {
          far_sum[std::size_t(b)] += sum[std::size_t(b)];
          far_count[std::size_t(b)] += count[std::size_t(b)];
        }
    }
    return fr;
  }

  template <class Archive>
  void checkpoint_fields(Archive& a) {
    a("record/steps", steps);
    a("record/x", x);
    a("record/y", y);
    a("record/u_d", u_d);
    a("record/u_oil", u_oil);
    if (far_.bins > 0) {
      a("record/far_sum", far_sum);
      a("record/far_count", far_count);
    }
    a("record/last_folded", last_folded);
    a("record/image_shift", image_shift);
  }

  // The far-field profile over the measured frames as CSV at `path`: per bin y, the mean u_x
  // (0 where it has no samples) and the samples.
  void write_far_profile(const std::string& path) const {
    std::ofstream csv(path);
    csv << std::setprecision(10) << "y,u_x,samples\n";
    for (int b = 0; b < far_.bins; ++b) {
      const double c = far_count[std::size_t(b)];
      csv << (b + 0.5) * far_.bin_width << "," << (c > 0 ? far_sum[std::size_t(b)] / c : 0.0) << "," << c << "\n";
    }
  }

  const FarField& far_field() const { return far_; }
  std::array<double, 2> far_speeds() const { return far_.speeds(far_sum, far_count, f_.width, f_.cell_size); }

  std::vector<std::int64_t> steps;
  std::vector<double> x, y;                // unwrapped centres, frame-major
  std::vector<double> u_d, u_oil;          // per frame
  std::vector<double> far_sum, far_count;  // one disc: Σ v_x and samples per height bin over measured frames

 private:
  template <class View>
  static std::vector<typename View::non_const_value_type> host_rows(const View& v) {
    const auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), v);
    std::vector<typename View::non_const_value_type> out(h.extent(0) * 2);
    for (std::size_t i = 0; i < h.extent(0); ++i)
      for (std::size_t d = 0; d < 2; ++d) out[i * 2 + d] = h(i, d);
    return out;
  }

  mpc::ChannelFlowParameters<double> f_;
  std::int64_t warmup_steps_;
  FarField far_;
  std::vector<double> last_folded, image_shift;
};

}  // namespace mesoflow::crystal
