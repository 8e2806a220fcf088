// Acceptance test of the calibration (capillary-droplets §4.1, Fig. 3d; label long, ~1 min):
// Γ and b0/b∞ recovered together from a synthetic profile made by the orifice simulation.
#include "analysis/droplets/profile_calibration.hpp"
#include "dp/synthetic_profile.hpp"

#include <gtest/gtest.h>

#include <chrono>

namespace mesoflow::droplets {
namespace {

// Acceptance (label long): the Fig. 3(d) case at N_v = 32, both parameters: a 5×5 grid over
// Γ ∈ [0.6, 2], b0/b∞ ∈ [0.03, 0.2], then Nelder–Mead; at most 60 orifice passages.
TEST(CalibrateLong, RecoversFig3dParametersFromSyntheticProfile) {
  const auto start = std::chrono::steady_clock::now();
  const OrificeScene truth = fig3d_scene(32, 0.032);
  const auto measured = synthetic_measurement(truth);
  OrificeScene guess = truth;
  guess.droplet.line_tension = 0.8;
  guess.droplet.perimeter_stiffness = 1e-3 * 0.8;
  guess.droplet.near_wall_drag = 0.12;
  SimplexSettings s;
  s.x_tolerance = 0.01;
  s.max_evaluations = 60;
  CalibrationBounds bounds;
  bounds.gamma_min = 0.6;
  bounds.gamma_max = 2.0;
  bounds.drag_min = 0.03;
  bounds.drag_max = 0.2;
  const auto r = calibrate_orifice(measured, guess, FitParameters::both, bounds, s, 5);
  report("Fig. 3(d), N_v = 32, both", r, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  EXPECT_NEAR(r.line_tension / 1.08, 1.0, 0.05);
  EXPECT_NEAR(r.near_wall_drag / 0.07, 1.0, 0.05);
  EXPECT_LT(r.speed_deviation, 0.1);
}

}  // namespace
}  // namespace mesoflow::droplets
