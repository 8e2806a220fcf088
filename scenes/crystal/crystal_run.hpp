// crystal_run.hpp — the run of the `crystal` driver (mpc-microfluidic-crystal-phonons §4,
// Appendix B) as its parameters give it: the channel flow (channel_flow.hpp) with its discs on the
// zigzag of crystal_record.hpp, the step counts of the measured time, the frames and the
// checkpoints, and the run with its record: a fresh run (start: a new results file with the
// parameters and the first frame) or a restart (resume: the state of a checkpoint, the results
// file resumed at its step); then frames (disc positions, unwrapped along x, and velocities; u_oil,
// u_d, and with one disc the far-field speeds, as observables) every frame interval and at the end,
// and checkpoints every checkpoint interval and at the end, each with the scene's signature.
// Composition and recording only: K, the phonon spectra and the theory are analysis/crystal/.
//
// Units (Appendix B): cell size Δx, solvent particle mass m, k_BT; τ = Δx √(m/k_BT).
#pragma once

#include "io/checkpoint.hpp"
#include "io/h5md_writer.hpp"
#include "kernels/mpc/mpc_viscosity.hpp"
#include "scenes/common/checkpoint_fields.hpp"
#include "scenes/common/nan_watchdog.hpp"
#include "scenes/common/time_step_limit.hpp"
#include "scenes/crystal/crystal_record.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace mesoflow::crystal {

// The study's parameters (defaults: the paper's scene, as the driver's options give them).
struct CrystalRunParameters {
  mpc::ChannelFlowParameters<double> flow;
  std::string rule = "at+a";
  std::string wall_virtual = "mirror";  // mpc::WallVirtualRule: mirror images or Appendix B's particles
  long long discs = 90;
  long long wavelength = 6;  // discs per zigzag period
  double amplitude = -1;     // zigzag amplitude /Δx; < 0: the largest without wall contact
  double warmup = 0;         // τ before the measured frames
  double time = 100;         // τ measured
  double frame_interval = 1; // τ between frames
  double checkpoint_interval = 500;  // τ between checkpoints
  long long check_every = 100;       // steps between NaN-watchdog checks
  double calibrated_ratio = 0;  // K of a single-disc run for the theory curves; 0: this run's u_d/u_oil
  long long seed = 1;
  std::string precision = "double";
  bool force_dt = false;  // run a step above the stability limit (a warning instead of an error)

  // The run's own ranges (the driver's options give the same) and the step against the stability
  // limit of the discs' WCA contacts and the solvent's bounce-back (kernels/mpc/stability.hpp);
  // the channel's own values are checked where the flow is built. Throws std::invalid_argument
  // naming the parameter and its range.
  void validate() const {
    const auto range = [](const char* name, double v, double lo, double hi, bool open_lo) {
      if (!std::isfinite(v) || v > hi || v < lo || (open_lo && v == lo)) {
        std::ostringstream m;
        m << "crystal: " << name << " must be in " << (open_lo ? "(" : "[") << lo << ", " << hi << "], got " << v;
        throw std::invalid_argument(m.str());
      }
    };
    if (rule != "at+a" && rule != "at-a" && rule != "srd")
      throw std::invalid_argument("crystal: rule must be one of at+a, at-a, srd, got '" + rule + "'");
    if (wall_virtual != "mirror" && wall_virtual != "maxwell")
      throw std::invalid_argument("crystal: wall_virtual must be mirror or maxwell, got '" + wall_virtual + "'");
    if (precision != "double" && precision != "float")
      throw std::invalid_argument("crystal: precision must be double or float, got '" + precision + "'");
    range("discs", double(discs), 0, 1e6, false);
    range("wavelength", double(wavelength), 1, 1e6, false);
    range("amplitude", amplitude, -1, 1e4, false);
    range("warmup", warmup, 0, 1e9, false);
    range("time", time, 0, 1e9, true);
    range("frame_interval", frame_interval, 0, 1e9, true);
    range("checkpoint_interval", checkpoint_interval, 0, 1e9, true);
    range("check_every", double(check_every), 1, 1e6, false);
    range("calibrated_ratio", calibrated_ratio, 0, 1, false);
    range("seed", double(seed), 0, 4294967295.0, false);
    range("h", flow.h, 0, 10, true);
    const auto limit = mpc::channel_flow_stability(flow, discs > 0);
    cli::check_time_step("crystal", flow.h, {limit.max_dt(), limit.limiting_term("τ")}, force_dt);
  }
};

// η of eq. (B.3) (MPC-AT+a, d = 2, large n).
inline double viscosity_b3(const mpc::ChannelFlowParameters<double>& p) {
  return mpc::at_plus_a_viscosity(p.density, p.kT, p.mass, p.h, p.cell_size);
}

// The parameters a restart must share with the run it continues (all but the run length,
// output and threads), as a string stored in the checkpoint.
inline std::string scene_signature(const CrystalRunParameters& par) {
  const auto& f = par.flow;
  std::ostringstream s;
  s << std::setprecision(17) << "L=" << f.length << " W=" << f.width << " R=" << f.disc_radius << " n=" << f.density
    << " h=" << f.h << " g=" << f.body_acceleration << " gamma=" << f.friction << " eps=" << f.wca_epsilon
    << " r0=" << f.wca_r0 << " rule=" << par.rule << " walls=" << par.wall_virtual << " N=" << par.discs
    << " wavelength=" << par.wavelength
    << " amplitude=" << par.amplitude << " warmup=" << par.warmup << " frame=" << par.frame_interval
    << " seed=" << par.seed << " precision=" << par.precision;
  return s.str();
}

template <class Real, class Exec = Kokkos::DefaultExecutionSpace>
class CrystalRun {
 public:
  // The scene of `par`; checkpoints go to `checkpoint_path` with `signature`.
  CrystalRun(const CrystalRunParameters& par, std::string checkpoint_path, std::string signature)
      : f_(par.flow),
        setup_(setup(par)),
        flow_(setup_.first, real_centres(setup_.second)),
        warmup_steps_(steps_of(par.warmup)),
        total_steps_(warmup_steps_ + steps_of(par.time)),
        frame_steps_(std::max<std::int64_t>(1, steps_of(par.frame_interval))),
        checkpoint_steps_(std::max<std::int64_t>(1, steps_of(par.checkpoint_interval))),
        check_every_(par.check_every),
        rec_(f_, setup_.second, warmup_steps_),
        checkpoint_path_(std::move(checkpoint_path)),
        signature_(std::move(signature)) {}

  // A fresh run: the results file at `path` with the resolved parameters (key, value), the
  // solvent particles, the disc mass, η of eq. (B.3) and the discs' group, and the first frame.
  void start(const std::string& path, const std::vector<std::pair<std::string, std::string>>& resolved) {
    h5_.emplace(path, "mesoflow", MESOFLOW_VERSION, "mesoflow crystal");
    for (const auto& [key, value] : resolved) h5_->set_parameter(key, value);
    h5_->set_parameter("solvent_particles", flow_.num_solvent());
    h5_->set_parameter("disc_mass", double(flow_.discs().mass()));
    h5_->set_parameter("viscosity_b3", viscosity_b3(f_));
    h5_->add_particles_group("discs", 2, discs(), {0.0, 0.0}, {f_.length, f_.width}, {true, false});
    record_frame();
  }
  // A restart: the flow and the record from the checkpoint `ck`, the results file at `path`
  // resumed at its step.
  void resume(const io::CheckpointReader& ck, const std::string& path) {
    scene::LoadFields load(ck);
    flow_.checkpoint_fields(load);
    rec_.checkpoint_fields(load);
    h5_.emplace(io::H5mdWriter::resume(path, std::int64_t(flow_.steps_done())));
  }

  // Steps to the end of the run, with frames and checkpoints (file comment); progress(step) after
  // every step.
  template <class Progress>
  void run(Progress&& progress) {
    // The NaN watchdog, also checked before every frame and checkpoint: the last checkpoint always
    // holds a finite state.
    watchdog::NanWatchdog watch(flow_.watched(), check_every_);
    while (std::int64_t(flow_.steps_done()) < total_steps_) {
      flow_.step();
      watch.after_step();
      const std::int64_t step = std::int64_t(flow_.steps_done());
      const bool frame = step % frame_steps_ == 0 || step == total_steps_;
      const bool at_checkpoint = step % checkpoint_steps_ == 0 || step == total_steps_;
      if (frame || at_checkpoint) watch.check();
      if (frame) record_frame();
      if (at_checkpoint) checkpoint();
      progress(step);
    }
  }

  // A checkpoint of the state now (a run stopped between checkpoints, e.g. by a caller's request,
  // resumes from here); the state is the last frame's, which the watchdog checked.
  void checkpoint_now() { checkpoint(); }

  // Writes the results file's XDMF sidecar at `xdmf` and closes it.
  void close(const std::string& xdmf) {
    h5_->write_xdmf(xdmf);
    h5_.reset();
  }

  const mpc::ChannelFlow<Real, Exec>& flow() const { return flow_; }
  const CrystalRecord& record() const { return rec_; }
  std::size_t discs() const { return setup_.second.size(); }
  bool far_field() const { return rec_.far_field().bins > 0; }
  std::int64_t warmup_steps() const { return warmup_steps_; }
  std::int64_t total_steps() const { return total_steps_; }
  std::int64_t frame_steps() const { return frame_steps_; }

 private:
  // The flow's parameters at precision Real and the disc centres (checked as the options give them).
  static std::pair<mpc::ChannelFlowParameters<Real>, std::vector<std::array<double, 2>>> setup(
      const CrystalRunParameters& par) {
    const auto& f = par.flow;
    auto fp = mpc::converted<Real>(f);
    fp.walls = true;
    fp.rule = mpc::parse_collision_rule(par.rule);
    fp.wall_virtual = mpc::parse_wall_virtual_rule(par.wall_virtual);
    fp.seed = std::uint64_t(par.seed);
    if (std::abs(f.length / f.cell_size - std::round(f.length / f.cell_size)) > 1e-9)
      throw std::invalid_argument("--length " + std::to_string(f.length) + ": must be a multiple of the cell size");
    return {fp, zigzag(f, par.discs, par.wavelength, par.amplitude)};
  }
  static std::vector<std::array<Real, 2>> real_centres(const std::vector<std::array<double, 2>>& centres_d) {
    std::vector<std::array<Real, 2>> centres;
    for (const auto& c : centres_d) centres.push_back({Real(c[0]), Real(c[1])});
    return centres;
  }
  std::int64_t steps_of(double t) const { return std::int64_t(std::llround(t / f_.h)); }

  void record_frame() {
    const std::size_t nd = discs();
    const auto fr = rec_.record(flow_);
    h5_->append("discs", "position", fr.step, fr.time, fr.position.data(), nd, 2);
    h5_->append("discs", "velocity", fr.step, fr.time, fr.velocity.data(), nd, 2);
    h5_->append_observable("u_oil", fr.step, fr.time, fr.u_oil);
    h5_->append_observable("u_d", fr.step, fr.time, fr.u_d);
    if (far_field()) {
      h5_->append_observable("u_far_mean", fr.step, fr.time, fr.far_speeds[0]);
      h5_->append_observable("u_far_axis", fr.step, fr.time, fr.far_speeds[1]);
    }
  }
  void checkpoint() {
    h5_->flush();
    io::CheckpointWriter ck(checkpoint_path_);
    scene::SaveFields save(ck);
    flow_.checkpoint_fields(save);
    rec_.checkpoint_fields(save);
    ck.put_string("scene", signature_);
    ck.commit();
  }

  mpc::ChannelFlowParameters<double> f_;
  std::pair<mpc::ChannelFlowParameters<Real>, std::vector<std::array<double, 2>>> setup_;
  mpc::ChannelFlow<Real, Exec> flow_;
  std::int64_t warmup_steps_, total_steps_, frame_steps_, checkpoint_steps_;
  long long check_every_;
  CrystalRecord rec_;
  const std::string checkpoint_path_, signature_;
  std::optional<io::H5mdWriter> h5_;
};

}  // namespace mesoflow::crystal
