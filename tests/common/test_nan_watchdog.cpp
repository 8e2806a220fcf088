// The NaN watchdog (scenes/common/nan_watchdog.hpp) on a toy system whose blow-up is known
// exactly, and on the orifice droplet run above its stability limit.
#include "scenes/common/nan_watchdog.hpp"
#include "scenes/droplets/orifice_run.hpp"
#include "scenes/hopper/hopper_scene.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <limits>
#include <string>

namespace {

using namespace mesoflow;
using Exec = Kokkos::DefaultExecutionSpace;
using Field2 = Kokkos::View<double* [1], Kokkos::LayoutLeft, Exec>;

// Independent oscillators x'' = −k x + barrier, symplectic Euler. With k Δt² > 4 the scheme is
// unstable: |x| grows by a factor ~k Δt² per step until it overflows. The barrier term
// b √(L − |x|) is finite for |x| ≤ L and NaN beyond, so it yields the first non-finite force once a
// particle leaves [−L, L] (with b = 0 it is still evaluated: √ of a negative number is NaN).
struct Toy {
  Field2 x{"toy::x", 8}, v{"toy::v", 8}, f{"toy::f", 8};
  double k = 1, dt = 0.1, barrier = 0, range = 1e300;
  long long steps = 0;
};

void spring_force(const Toy& t) {
  const auto x = t.x, f = t.f;
  const double k = t.k;
  Kokkos::parallel_for(
      "test::spring", Kokkos::RangePolicy<Exec>(0, 8), KOKKOS_LAMBDA(int i) { f(i, 0) = -k * x(i, 0); });
}

void barrier_force(const Toy& t) {
  const auto x = t.x, f = t.f;
  const double b = t.barrier, range = t.range;
  Kokkos::parallel_for(
      "test::barrier", Kokkos::RangePolicy<Exec>(0, 8),
      KOKKOS_LAMBDA(int i) { f(i, 0) = b * kmath::sqrt(range - kmath::fabs(x(i, 0))); });
}

void add_forces(const Toy& t) {
  const auto x = t.x, f = t.f;
  const double k = t.k, b = t.barrier, range = t.range;
  Kokkos::parallel_for(
      "test::forces", Kokkos::RangePolicy<Exec>(0, 8), KOKKOS_LAMBDA(int i) {
        f(i, 0) = -k * x(i, 0);
        if (range < 1e300) f(i, 0) += b * kmath::sqrt(range - kmath::fabs(x(i, 0)));
      });
}

void toy_step(Toy& t) {
  add_forces(t);
  const auto x = t.x, v = t.v, f = t.f;
  const double dt = t.dt;
  Kokkos::parallel_for(
      "test::update", Kokkos::RangePolicy<Exec>(0, 8), KOKKOS_LAMBDA(int i) {
        v(i, 0) += dt * f(i, 0);
        x(i, 0) += dt * v(i, 0);
      });
  ++t.steps;
}

void set_positions(Toy& t, double x0, int mover = -1, double x_mover = 0) {
  auto h = Kokkos::create_mirror_view(t.x);
  for (int i = 0; i < 8; ++i) h(i, 0) = i == mover ? x_mover : x0 * (1 + 0.1 * i);
  Kokkos::deep_copy(t.x, h);
  Kokkos::deep_copy(t.v, 0.0);
  Kokkos::deep_copy(t.f, 0.0);
}

watchdog::Watched watch(Toy& t) {
  watchdog::Watched w;
  w.state = {watchdog::Field::of("position", t.x), watchdog::Field::of("velocity", t.v)};
  w.step = [&t] { toy_step(t); };
  w.steps = [&t] { return t.steps; };
  w.set_steps = [&t](long long s) { t.steps = s; };
  w.terms = {{"spring", [&t] { spring_force(t); }}};
  if (t.range < 1e300) w.terms.push_back({"barrier", [&t] { barrier_force(t); }});
  const auto f = t.f;
  w.first_bad_force = [f] { return first_non_finite(f); };
  w.max_force = [f] { return max_norm(f); };
  return w;
}

// The first step after which x or v holds a non-finite value, by plain stepping.
long long first_non_finite_step(Toy t) {
  t.x = Field2("toy::x2", 8);
  t.v = Field2("toy::v2", 8);
  t.f = Field2("toy::f2", 8);
  set_positions(t, 1.0);
  t.steps = 0;
  while (t.steps < 100000) {
    toy_step(t);
    if (first_non_finite(t.x) >= 0 || first_non_finite(t.v) >= 0) return t.steps;
  }
  return -1;
}

TEST(FiniteCheck, FindsTheLowestNonFiniteIndexAndTheLargestNorm) {
  Kokkos::View<double* [3], Kokkos::LayoutLeft, Exec> a("a", 1000);
  Kokkos::deep_copy(a, 1.0);
  EXPECT_EQ(first_non_finite(a), -1);
  EXPECT_NEAR(max_norm(a), std::sqrt(3.0), 1e-15);
  {
    Kokkos::View<double* [3], Kokkos::LayoutLeft, Exec> big("big", 10);
    auto hb = Kokkos::create_mirror_view(big);
    Kokkos::deep_copy(hb, 0.0);
    hb(4, 0) = 3e200;
    hb(4, 2) = -4e200;  // |.|² overflows a double; the scaled norm does not
    Kokkos::deep_copy(big, hb);
    EXPECT_NEAR(max_norm(big) / 5e200, 1.0, 1e-14);
  }
  auto h = Kokkos::create_mirror_view(a);
  Kokkos::deep_copy(h, a);
  h(731, 2) = std::numeric_limits<double>::quiet_NaN();
  h(912, 0) = std::numeric_limits<double>::infinity();
  h(400, 1) = -7.0;
  Kokkos::deep_copy(a, h);
  EXPECT_EQ(first_non_finite(a), 731);
  Kokkos::View<float*, Exec> b("b", 50);
  EXPECT_EQ(first_non_finite(b), -1);
  auto hb = Kokkos::create_mirror_view(b);
  hb(49) = -std::numeric_limits<float>::infinity();
  Kokkos::deep_copy(b, hb);
  EXPECT_EQ(first_non_finite(b), 49);
}

TEST(NanWatchdog, NamesTheStepAndTheLargestTermOfAnOverflowAndKeepsTheLastGoodState) {
  Toy t;
  t.k = 1000;  // k Δt² = 10: |x| grows by ~7.9 per step, overflowing after ~340 steps
  t.dt = 0.1;
  const long long expected = first_non_finite_step(t);
  ASSERT_GT(expected, 50);
  set_positions(t, 1.0);
  watchdog::NanWatchdog dog(watch(t), 25);
  try {
    for (;;) {
      toy_step(t);
      dog.after_step();
    }
  } catch (const watchdog::NonFiniteState& e) {
    const auto& d = e.diagnosis();
    EXPECT_EQ(d.first_bad_step, expected) << e.what();
    EXPECT_EQ(d.detected_step % 25, 0);
    EXPECT_GE(d.detected_step, expected);
    EXPECT_LT(d.detected_step - expected, 25);
    EXPECT_EQ(d.last_good_step, d.detected_step - 25);
    // −k x with k = 1000 overflows before x does, or is the largest finite force.
    EXPECT_EQ(d.term, "spring");
    EXPECT_TRUE(d.term_non_finite || d.term_force > 1e250) << e.what();
    EXPECT_NE(std::string(e.what()).find("step " + std::to_string(expected) + " made it non-finite"), std::string::npos)
        << e.what();
    // Left in the last good state: finite, at the last good step.
    EXPECT_EQ(t.steps, d.last_good_step);
    EXPECT_EQ(first_non_finite(t.x), -1);
    EXPECT_EQ(first_non_finite(t.v), -1);
    return;
  }
}

TEST(NanWatchdog, NamesTheTermAndParticleThatTurnedNonFinite) {
  Toy t;
  t.k = 0;  // free flight: particle 5 drifts out of the barrier's range [−1, 1] at a known step
  t.barrier = 1e-3;
  t.range = 1.0;
  t.dt = 0.01;
  set_positions(t, 0.0, 5, 0.5);
  {
    auto v = Kokkos::create_mirror_view(t.v);
    Kokkos::deep_copy(v, 0.0);
    v(5, 0) = 1.0;
    Kokkos::deep_copy(t.v, v);
  }
  watchdog::NanWatchdog dog(watch(t), 100);
  try {
    for (int s = 0; s < 10000; ++s) {
      toy_step(t);
      dog.after_step();
    }
    FAIL() << "the barrier term never produced a non-finite force";
  } catch (const watchdog::NonFiniteState& e) {
    const auto& d = e.diagnosis();
    EXPECT_TRUE(d.term_non_finite) << e.what();
    EXPECT_EQ(d.term, "barrier");
    EXPECT_EQ(d.term_index, 5);
    EXPECT_EQ(d.index, 5);
    // x_5 ≈ 0.5 + 0.01 n (the barrier's push is ~10⁻⁵): it leaves [−1, 1] near step 50, and the
    // force evaluated in the following step is NaN.
    EXPECT_GE(d.first_bad_step, 50);
    EXPECT_LE(d.first_bad_step, 53);
    EXPECT_EQ(d.detected_step, 100);
    EXPECT_EQ(d.last_good_step, 0);
    EXPECT_NE(std::string(e.what()).find("'barrier' is non-finite on particle 5"), std::string::npos) << e.what();
  }
}

TEST(NanWatchdog, SaysWhenTheReplayStaysFinite) {
  Toy t;
  t.k = 1;
  t.dt = 0.01;
  set_positions(t, 1.0);
  watchdog::NanWatchdog dog(watch(t), 10);
  for (int s = 0; s < 30; ++s) {
    toy_step(t);
    dog.after_step();
  }
  EXPECT_EQ(dog.last_good_step(), 30);
  for (int s = 0; s < 5; ++s) toy_step(t);
  {  // corrupt the state outside a step
    auto v = Kokkos::create_mirror_view(t.v);
    Kokkos::deep_copy(v, t.v);
    v(3, 0) = std::numeric_limits<double>::quiet_NaN();
    Kokkos::deep_copy(t.v, v);
  }
  try {
    dog.check();
    FAIL() << "the check passed a NaN";
  } catch (const watchdog::NonFiniteState& e) {
    EXPECT_EQ(e.diagnosis().first_bad_step, -1);
    EXPECT_EQ(e.diagnosis().index, 3);
    EXPECT_EQ(e.diagnosis().field, "velocity");
    EXPECT_NE(std::string(e.what()).find("stayed finite"), std::string::npos) << e.what();
    EXPECT_EQ(t.steps, 30);
  }
}

TEST(NanWatchdog, RefusesANonFiniteStartAndABadInterval) {
  Toy t;
  set_positions(t, 1.0);
  EXPECT_THROW(watchdog::NanWatchdog(watch(t), 0), std::invalid_argument);
  auto x = Kokkos::create_mirror_view(t.x);
  Kokkos::deep_copy(x, t.x);
  x(2, 0) = std::numeric_limits<double>::infinity();
  Kokkos::deep_copy(t.x, x);
  EXPECT_THROW(watchdog::NanWatchdog(watch(t), 10), std::invalid_argument);
}

// The orifice droplet forced to 40× its stability limit blows up; the watchdog stops the run
// and names a force term of the scene and a vertex of the droplet.
TEST(NanWatchdog, StopsAnOrificeDropletForcedAboveItsStabilityLimit) {
  droplets::DropletParameters par;
  par.vertices = 64;
  par.dt = 40 * droplets::droplet_stability(par, true).max_dt();
  par.force_dt = true;
  droplets::DropletScene<double, Exec> scene(par, droplets::orifice_surfaces<double>(0.4), {Vec<2, double>{{0.0, 2.0}}});
  watchdog::NanWatchdog dog(scene.watched(), 50);
  try {
    for (int s = 0; s < 200000; ++s) {
      scene.step();
      dog.after_step();
    }
    FAIL() << "a droplet at 40x the stability limit stayed finite";
  } catch (const watchdog::NonFiniteState& e) {
    const auto& d = e.diagnosis();
    std::cout << e.what() << '\n';
    EXPECT_GE(d.first_bad_step, 1) << e.what();
    EXPECT_FALSE(d.term.empty()) << e.what();
    EXPECT_NE(std::string(e.what()).find("of droplet 0"), std::string::npos) << e.what();
    EXPECT_EQ(d.detected_step % 50, 0);
    EXPECT_EQ(scene.steps(), d.last_good_step);
    EXPECT_EQ(first_non_finite(scene.particles().x), -1);
  }
}

// A 2D soft-particle hopper with friction forced to 30× its stability limit: the watchdog stops it,
// leaves it in its last good state, and names a term of the scene.
TEST(NanWatchdog, StopsAHopperForcedAboveItsStabilityLimit) {
  hopper::HopperParameters par;
  par.particles = 200;
  par.friction = 10;
  par.dt = 30 * par.stability_limit(2).max_dt;
  par.force_dt = true;
  hopper::HopperScene<2, double, Exec> scene(par);
  watchdog::NanWatchdog dog(scene.watched(), 20);
  try {
    for (int s = 0; s < 100000; ++s) {
      scene.step();
      dog.after_step();
    }
    FAIL() << "a hopper at 30x the stability limit stayed finite";
  } catch (const watchdog::NonFiniteState& e) {
    std::cout << e.what() << '\n';
    const auto& d = e.diagnosis();
    EXPECT_GE(d.first_bad_step, 1) << e.what();
    EXPECT_FALSE(d.term.empty()) << e.what();
    EXPECT_EQ(scene.steps(), d.last_good_step);
    EXPECT_EQ(first_non_finite(scene.particles().x), -1);
    EXPECT_EQ(first_non_finite(scene.particles().v), -1);
  }
}

}  // namespace
