// Synthetic measured profiles for the calibration tests (test_calibrate, test_calibrate_long), and
// the calibration over orifice passages as the `calibrate` driver composes it.
#pragma once

#include "analysis/droplets/profile_calibration.hpp"
#include "scenes/droplets/orifice_run.hpp"

#include <gtest/gtest.h>

#include <iostream>
#include <optional>

namespace mesoflow::droplets {

// Synthetic "experiment": the orifice simulation itself at known parameters, every 4th sample as a
// video frame. Δ_v is 0 at the true parameters, so the fit must come back to them.
inline MeasuredProfile synthetic_measurement(const OrificeScene& truth) {
  const auto prof = run_orifice(truth);
  EXPECT_EQ(prof.outcome, OrificeOutcome::passed);
  MeasuredProfile m;
  for (std::size_t i = 0; i < prof.h.size(); i += 4) {
    if (prof.h[i] < -1.2) continue;  // frames from the funnel on, as in Fig. 2–4
    m.h.push_back(prof.h[i]);
    m.vg_over_vt.push_back(prof.vg[i] / truth.droplet.terminal_speed);
  }
  return m;
}

inline OrificeScene fig3d_scene(int vertices, double terminal_speed) {
  OrificeScene s;  // Fig. 3(d): w = 0.7σ, Γ = 1.08, b0/b∞ = 0.07, V_t = 0.032
  s.droplet.vertices = vertices;
  s.droplet.line_tension = 1.08;
  s.droplet.perimeter_stiffness = 1e-3 * 1.08;
  s.droplet.near_wall_drag = 0.07;
  s.droplet.terminal_speed = terminal_speed;
  s.width = 0.7;
  s.start_h = -1.5;
  s.end_h = 1.0;
  return s;
}

// The fit of analysis/droplets/profile_calibration.hpp over orifice passages of `scene` with the
// trial Γ (K_l/Γ held) and b0/b∞ (calibration_scene), first guesses and v_t from the scene: as in
// drivers/droplets/calibrate.cpp.
inline CalibrationResult<OrificeProfile> calibrate_orifice(const MeasuredProfile& measured, const OrificeScene& scene,
                                                           FitParameters fit, const CalibrationBounds& bounds,
                                                           const SimplexSettings& settings, int grid_points) {
  const auto passage = [&](std::optional<double> line_tension, std::optional<double> near_wall_drag) {
    return run_orifice(calibration_scene(scene, line_tension, near_wall_drag));
  };
  return calibrate(measured, passage, {scene.droplet.line_tension, scene.droplet.near_wall_drag},
                   scene.droplet.terminal_speed, fit, bounds, settings, grid_points);
}

inline void report(const char* what, const CalibrationResult<OrificeProfile>& r, double seconds) {
  std::cout << "[ measured ] " << what << ": Γ = " << r.line_tension << ", b0/b∞ = " << r.near_wall_drag
            << ", Δ_v = " << r.speed_deviation << " after " << r.history.size() << " orifice runs, " << seconds
            << " s\n";
  for (const auto& e : r.history)
    std::cout << "             Γ = " << e.line_tension << ", b0/b∞ = " << e.near_wall_drag << ": Δ_v = " << e.speed_deviation
              << " (" << to_string(e.outcome) << ", " << e.seconds << " s)\n";
}

}  // namespace mesoflow::droplets
