// hopper_sweep.hpp — one width of the `hopper` driver's Q(w) sweep (hopper-flows §2.4, §4, App. B):
// the scene at width w (seed + the width's index), FIRE, then the flow measurement
// (flow_measurement.hpp) with, over the windows that make Q, the window-averaged velocity profile
// on the hopper axis (Gaussian coarse-graining of width σ_avg at h = 0, 0.25, … 23.75 σ_avg above
// the orifice, kernels/common/coarse_graining.hpp) and, for soft particles, the number density ρ_n
// in the region above the orifice and the corrected flow rate Q' = Q/(ρ_n a_avg) of Appendix B.
// Also the outputs of a sweep's widths: their fields declared once (WidthRun::attributes), the
// results file's observables and the CSV tables. Host composition; physics stays in kernels/.
//
// Units (§2.2): σ_avg, g, ρ; t0 = √(σ_avg/g); Q in σ_avg^d/t0.
#pragma once

#include "kernels/common/coarse_graining.hpp"
#include "io/h5md_writer.hpp"
#include "scenes/hopper/dp_hopper_scene.hpp"
#include "scenes/hopper/flow_measurement.hpp"
#include "scenes/hopper/hopper_scene.hpp"

#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <fstream>
#include <iomanip>
#include <string>
#include <type_traits>
#include <vector>

namespace mesoflow::hopper {

constexpr int profile_points = 96;
constexpr double profile_dh = 0.25;  // σ_avg between profile points, from h = 0

// Window averages over the measuring windows of one width.
struct WidthMeasurement {
  std::array<double, profile_points> n{}, vg_sum{};
  double orifice_count = 0;
  int samples = 0;
};

// One width's run: the flow result, the rate of every window (the window_flow_rate observable),
// the window-averaged profiles and the scene's counters at the end.
struct WidthRun {
  struct Scalars {  // the fixed-size part (trivially copyable: ranks send it as bytes)
    double Q = 0, Q_error = 0;
    bool clogged = false, steady = false;
    double steady_time = 0, result_end_time = 0;
    long long steps = 0;  // at the end of the run (the profile frames' step)
    double time = 0;      // t/t0 at the end
    double rho_n = NAN, Q_corrected = NAN;
    long long insertions = 0;
    double max_insertion_overlap = 0;
    double seconds = 0;  // wall time of this width's run
    std::size_t windows = 0;
  } scalars;
  WidthMeasurement measured;
  struct Window {
    std::int64_t step;
    double time, q;
  };
  std::vector<Window> windows;

  // The per-width attributes of the results file, declared once: a(name, value) for each, in the
  // order they are written; Q_corrected for soft particles only (polygons keep their area).
  template <class Archive>
  void attributes(double w, bool soft_particles, Archive&& a) const {
    if (soft_particles) a("Q_corrected", scalars.Q_corrected);
    a("w", w);
    a("Q", scalars.Q);
    a("Q_error", scalars.Q_error);
    a("clogged", scalars.clogged);
    a("steady", scalars.steady);
    a("insertions", scalars.insertions);
    a("max_insertion_overlap", scalars.max_insertion_overlap);
  }

  // As bytes (ranks send their runs to rank 0), and back from `bytes` at `offset`.
  void append_bytes(std::vector<char>& out) const {
    Scalars s = scalars;
    s.windows = windows.size();
    append_raw(out, s);
    append_raw(out, measured);
    for (const Window& w : windows) append_raw(out, w);
  }
  void read_bytes(const std::vector<char>& in, std::size_t& offset) {
    read_raw(in, offset, scalars);
    read_raw(in, offset, measured);
    windows.resize(scalars.windows);
    for (Window& w : windows) read_raw(in, offset, w);
  }

  // The result without its window rates (they are in `windows`).
  FlowResult result() const {
    FlowResult r;
    r.Q = scalars.Q;
    r.Q_error = scalars.Q_error;
    r.clogged = scalars.clogged;
    r.steady = scalars.steady;
    r.steady_time = scalars.steady_time;
    r.end_time = scalars.result_end_time;
    return r;
  }

 private:
  template <class T>
  static void append_raw(std::vector<char>& out, const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    const char* p = reinterpret_cast<const char*>(&value);
    out.insert(out.end(), p, p + sizeof(T));
  }
  template <class T>
  static void read_raw(const std::vector<char>& in, std::size_t& offset, T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    if (offset + sizeof(T) > in.size()) throw std::runtime_error("hopper sweep: a width's run is cut short");
    std::memcpy(&value, in.data() + offset, sizeof(T));
    offset += sizeof(T);
  }
};

// Sets the parameter `name` of an outer sweep (--vary: drag, friction, pair-energy,
// perimeter-stiffness, bending) to v in the scene parameters.
inline void set_varied(const std::string& name, double v, HopperParameters& sp, DpHopperParameters& dp) {
  if (name == "drag") sp.drag = dp.drag = v;
  else if (name == "friction") sp.friction = dp.friction = v;
  else if (name == "pair-energy") sp.pair_energy = v;
  else if (name == "perimeter-stiffness") dp.perimeter_stiffness = v;
  else if (name == "bending") dp.bending_stiffness = v;
}

// Scene parameters for width index k: the base with w and seed + k.
template <class SceneParameters>
SceneParameters at_width(const SceneParameters& base, double w, std::size_t k) {
  SceneParameters p = base;
  p.orifice = w;
  p.seed = base.seed + k;
  return p;
}

inline void validate(const HopperParameters& p, int dim) { p.validate(dim); }
inline void validate(const DpHopperParameters& p, int) { p.validate(); }

// The DP scene's parameters from the driver's shared ones (N, W, θ_w, ζ, μ, seed, dt, --force-dt in
// `shared`) and the polygon ones in `dp`.
inline DpHopperParameters polygon_parameters(const HopperParameters& shared, DpHopperParameters dp, double dt) {
  dp.particles = shared.particles;
  dp.hopper_width = shared.hopper_width;
  dp.wall_angle = shared.wall_angle;
  dp.drag = shared.drag;
  dp.friction = shared.friction;
  dp.friction_component = shared.friction_component;
  dp.seed = shared.seed;
  dp.dt = dt;
  dp.force_dt = shared.force_dt;
  return dp;
}
// The SP scene's parameters with dt, or min(10⁻³, 0.9 × the stability limit) for dt = 0.
inline HopperParameters particle_parameters(HopperParameters sp, double dt, int dim) {
  sp.dt = dt > 0 ? dt : std::min(1e-3, 0.9 * sp.max_stable_dt(dim));
  return sp;
}

// Runs width index k of a sweep with scene parameters `base` (see the file comment); Q and its
// error from mean_and_error (measure_flow_rate; the driver passes analysis::block_average).
// on_result(scene, result) is called once the flow is measured (the driver reports it).
template <class Scene, class SceneParameters, class MeanAndError, class OnResult>
WidthRun run_width(const SceneParameters& base, double w, std::size_t k, const FlowSettings& flow,
                   MeanAndError&& mean_and_error, OnResult&& on_result) {
  constexpr bool soft_particles = std::is_same_v<SceneParameters, HopperParameters>;
  const auto width_start = std::chrono::steady_clock::now();
  Scene scene(at_width(base, w, k));
  scene.relax();
  WidthRun run;
  WidthMeasurement& m = run.measured;
  const auto r = measure_flow_rate<Scene>(scene, flow, mean_and_error, [&](const Scene& s, double q, bool measuring) {
    run.windows.push_back({std::int64_t(s.steps()), s.time(), q});
    if (!measuring) return;
    const auto prof = gaussian_axis_profile<profile_points>(s.particles(), 0.0, profile_dh, 1.0);
    for (int j = 0; j < profile_points; ++j) {
      m.n[j] += prof.number_density[j];
      m.vg_sum[j] += prof.velocity_sum[j];
    }
    if constexpr (soft_particles) m.orifice_count += s.orifice_region_count();
    ++m.samples;
  });
  if (m.samples > 0) {
    for (int j = 0; j < profile_points; ++j) {
      m.n[j] /= m.samples;
      m.vg_sum[j] /= m.samples;
    }
    m.orifice_count /= m.samples;
  }
  WidthRun::Scalars& v = run.scalars;
  // ρ_n for soft particles; Q' = Q/(ρ_n a_avg) is analysis (analysis/hopper/flow_rate_fits.hpp).
  if constexpr (soft_particles) v.rho_n = m.orifice_count / scene.orifice_region_measure();
  v.Q = r.Q;
  v.Q_error = r.Q_error;
  v.clogged = r.clogged;
  v.steady = r.steady;
  v.steady_time = r.steady_time;
  v.result_end_time = r.end_time;
  v.steps = scene.steps();
  v.time = scene.time();
  v.insertions = scene.insertions();
  v.max_insertion_overlap = scene.max_insertion_overlap();
  v.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - width_start).count();
  on_result(scene, r);
  return run;
}

// The results file's per-width observables (window_flow_rate_<k>, profile_number_density_<k>,
// profile_vg_<k>) and attributes (WidthRun::attributes, suffixed _<k>).
inline void write_width_outputs(io::H5mdWriter& h5, const std::vector<double>& widths, const std::vector<WidthRun>& runs,
                                bool soft_particles) {
  for (std::size_t k = 0; k < widths.size(); ++k) {
    const WidthRun& run = runs[k];
    const WidthRun::Scalars& v = run.scalars;
    const std::string suffix = "_" + std::to_string(k);
    for (const WidthRun::Window& w : run.windows) h5.append_observable("window_flow_rate" + suffix, w.step, w.time, w.q);
    const WidthMeasurement& m = run.measured;
    if (m.samples > 0) {
      h5.append_observable("profile_number_density" + suffix, v.steps, v.time, m.n.data(), m.n.size());
      h5.append_observable("profile_vg" + suffix, v.steps, v.time, m.vg_sum.data(), m.vg_sum.size());
    }
    run.attributes(widths[k], soft_particles, [&](const std::string& name, const auto& value) {
      h5.set_parameter(name + suffix, value);
    });
  }
}

// <out>.csv (w, Q, Q_error, Q_corrected, number_density_orifice, clogged, steady) and
// <stem>_profile.csv (w, h, n, vg_sum, vg_mean).
inline void write_width_tables(const std::string& csv_path, const std::string& profile_path,
                               const std::vector<double>& widths, const std::vector<WidthRun>& runs) {
  std::ofstream csv(csv_path);
  csv << std::setprecision(10) << "w,Q,Q_error,Q_corrected,number_density_orifice,clogged,steady\n";
  for (std::size_t k = 0; k < widths.size(); ++k) {
    const WidthRun::Scalars& v = runs[k].scalars;
    csv << widths[k] << ',' << v.Q << ',' << v.Q_error << ',' << v.Q_corrected << ',' << v.rho_n << ','
        << int(v.clogged) << ',' << int(v.steady) << '\n';
  }
  std::ofstream pcsv(profile_path);
  pcsv << std::setprecision(10) << "w,h,n,vg_sum,vg_mean\n";
  for (std::size_t k = 0; k < widths.size(); ++k) {
    const WidthMeasurement& m = runs[k].measured;
    if (m.samples == 0) continue;
    for (int j = 0; j < profile_points; ++j)
      pcsv << widths[k] << ',' << j * profile_dh << ',' << m.n[j] << ',' << m.vg_sum[j] << ','
           << (m.n[j] > 1e-6 ? m.vg_sum[j] / m.n[j] : 0.0) << '\n';
  }
}

}  // namespace mesoflow::hopper
