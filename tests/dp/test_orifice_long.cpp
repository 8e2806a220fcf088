// Long validation (ctest label `long`): the stiff droplet of test_orifice.cpp at the paper's
// resolution N_v = 256 clogs above the w = 0.4σ orifice at the paper's threshold E_k/E_t < 10⁻¹⁷.
#include "scenes/droplets/orifice_run.hpp"

#include <gtest/gtest.h>

#include <iostream>

namespace mesoflow::droplets {
namespace {

TEST(OrificeLong, StiffDropletClogsAtPaperResolution) {
  OrificeScene s;  // Fig. 2 orifice, w = 0.4σ
  s.droplet.line_tension = 10;
  s.droplet.perimeter_stiffness = 1e-3 * 10;
  s.max_time = 3000;
  s.sample_interval = 0.1;
  const auto p = run_orifice(s);
  EXPECT_LT(p.dt, 1e-3);  // Γ = 10 at N_v = 256 is beyond the paper's Δt (kernels/dp/stability.hpp)
  EXPECT_EQ(p.outcome, OrificeOutcome::clogged) << "at t = " << p.t.back() << ", h = " << p.h.back();
  EXPECT_LT(p.h.back(), 0.0);
  EXPECT_LT(p.shape.back(), 1.01);
  std::cout << "[ measured ] Γ = 10, N_v = 256: clogged at t = " << p.t.back() << " t0, h = " << p.h.back()
            << "σ, 𝒜 = " << p.shape.back() << ", Δt = " << p.dt << "\n";
}

}  // namespace
}  // namespace mesoflow::droplets
