// nan_watchdog.hpp — a cheap periodic check that stops a run on the first non-finite value, names
// the particle, the force term that produced it and the step, and leaves the system in its last
// good state (issue 8, item 3).
//
// Every `interval` steps the watchdog runs one min-index reduction per state field
// (kernels/common/finite_check.hpp). A finite state is copied to a last-good buffer on the device
// (a copy kernel, no host transfer); a checkpoint written after a check therefore always holds a
// good state, and a failed check stops the run before the next one could overwrite it. On a failed
// check the watchdog
//   1. restores the last good state (step G) and replays the steps one at a time, checking after
//      each, to find the first step s whose result is non-finite (the runs are deterministic at a
//      fixed thread count, so the replay retraces the run);
//   2. restores again and replays to the state before step s, then evaluates every force term of
//      the system alone on that state: the first term that yields a non-finite force is named;
//      if all are finite, it also tries the positions after step s's drift (where velocity Verlet
//      evaluates that step's forces); if all are finite there too (the update overflowed), the
//      term with the largest force before the step is named;
//   3. restores the last good state and throws NonFiniteState with the diagnosis.
// Its cost is the check: one reduction per state field and one copy kernel per field per interval
// (docs/nan-watchdog.md).
#pragma once

#include "kernels/common/finite_check.hpp"

#include <Kokkos_Core.hpp>

#include <functional>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace mesoflow::watchdog {

// One field of the dynamic state (positions, velocities, forces, densities…): checked, and kept
// in a last-good copy on its own memory space.
struct Field {
  std::string name;                      // "velocity", …
  std::function<long long()> first_bad;  // lowest non-finite index, or -1
  std::function<void()> save, restore;   // current ↔ last-good copy

  template <class View>
  static Field of(std::string name, const View& v) {
    using buffer_type = typename View::non_const_type;
    buffer_type copy(Kokkos::view_alloc(Kokkos::WithoutInitializing, "mesoflow::watchdog::last_good::" + name),
                     v.layout());
    Field f;
    f.name = std::move(name);
    if constexpr (std::is_floating_point_v<typename View::value_type>)
      f.first_bad = [v] { return first_non_finite(v, "mesoflow::watchdog::check"); };
    else
      f.first_bad = [] { return -1LL; };
    f.save = [v, copy] { copy_field(copy, v, "mesoflow::watchdog::save"); };
    f.restore = [v, copy] { copy_field(v, copy, "mesoflow::watchdog::restore"); };
    return f;
  }

  // A field that is kept with the state but not checked (integer data: types, ids, flags).
  template <class View>
  static Field kept(std::string name, const View& v) {
    Field f = of(std::move(name), v);
    f.first_bad = [] { return -1LL; };
    return f;
  }
};

// One force term evaluated alone: evaluate() leaves in the force array only that term's forces at
// the current state.
struct ForceTerm {
  std::string name;
  std::function<void()> evaluate;
  bool uses_velocity = false;  // drag, friction, thermostats: skipped where the velocities are non-finite
};

// What a scene hands the watchdog. Scenes build it (see DropletScene::watched()); everything here
// runs on the host and launches kernels, nothing is called inside a kernel.
struct Watched {
  std::vector<Field> state;                          // everything a step reads: positions first, then velocities
  std::function<void()> step;                        // one time step
  std::function<long long()> steps;                  // the step counter
  std::function<void(long long)> set_steps;          // restores the counter with the state
  std::function<void()> save_host, restore_host;     // host-side state: RNG, counters (may be empty)
  std::function<void()> after_restore;               // e.g. rebuild neighbor lists (may be empty)
  std::vector<ForceTerm> terms;                      // every force term of the scene
  std::function<long long()> first_bad_force;        // over the force array
  std::function<double()> max_force;                 // max_i |f_i|
  std::function<std::string(long long)> particle;    // "vertex 17 of droplet 0"; empty: "particle i"
};

struct Diagnosis {
  long long detected_step = 0;  // the check that failed
  long long first_bad_step = -1;  // the step whose result was first non-finite (-1: replay stayed finite)
  long long last_good_step = 0;
  std::string field;            // the first non-finite field at detection
  long long index = -1;         // its particle
  std::string term;             // the force term named (empty if the replay stayed finite)
  bool term_non_finite = false; // the term's force itself was non-finite (else: the largest force)
  bool term_after_drift = false; // ... at the positions of first_bad_step (else: of the step before)
  long long term_index = -1;    // the particle on which the term's force was non-finite
  double term_force = 0;        // the largest |F| of the named term otherwise
  std::string message;
};

class NonFiniteState : public std::runtime_error {
 public:
  explicit NonFiniteState(Diagnosis d) : std::runtime_error(d.message), diagnosis_(std::move(d)) {}
  const Diagnosis& diagnosis() const { return diagnosis_; }

 private:
  Diagnosis diagnosis_;
};

// The common part of a particle scene's view: positions, velocities and forces as the state (the
// forces of the last step feed velocity Verlet's first half-kick), and the force array as where
// each term alone writes. Scenes add step, counter, terms and any further state.
template <class ParticlesT>
Watched watch_particles(const ParticlesT& p) {
  Watched w;
  w.state = {Field::of("position", p.x), Field::of("velocity", p.v), Field::of("force", p.f)};
  const auto f = p.f;
  w.first_bad_force = [f] { return first_non_finite(f, "mesoflow::watchdog::term_check"); };
  w.max_force = [f] { return max_norm(f, "mesoflow::watchdog::term_max"); };
  return w;
}

// Whether a scene provides watched() (scenes without one run unwatched).
template <class Scene, class = void>
struct has_watched : std::false_type {};
template <class Scene>
struct has_watched<Scene, std::void_t<decltype(std::declval<Scene&>().watched())>> : std::true_type {};
template <class Scene>
inline constexpr bool has_watched_v = has_watched<Scene>::value;

class NanWatchdog {
 public:
  // Checks the current state (it must be finite) and keeps it as the first good state.
  NanWatchdog(Watched w, long long interval) : w_(std::move(w)), interval_(interval) {
    if (interval_ < 1)
      throw std::invalid_argument("NaN watchdog: check interval must be >= 1 step, got " + std::to_string(interval_));
    for (const auto& f : w_.state)
      if (const long long i = f.first_bad(); i >= 0)
        throw std::invalid_argument("NaN watchdog: the initial " + f.name + " of " + particle(i) + " is not finite");
    save();
  }

  // Call after every step: checks every `interval` steps.
  void after_step() {
    if (w_.steps() - last_good_step_ >= interval_) check();
  }

  // Checks now (before a checkpoint or output): saves a good state or throws NonFiniteState.
  void check() {
    const auto bad = first_bad_field();
    if (bad.first < 0) {
      save();
      return;
    }
    throw NonFiniteState(diagnose(bad.first, bad.second));
  }

  long long last_good_step() const { return last_good_step_; }
  long long interval() const { return interval_; }

 private:
  // (field index, particle index) of the first non-finite entry, or (-1, -1).
  std::pair<int, long long> first_bad_field() const {
    for (std::size_t k = 0; k < w_.state.size(); ++k)
      if (const long long i = w_.state[k].first_bad(); i >= 0) return {int(k), i};
    return {-1, -1};
  }

  void save() {
    for (auto& f : w_.state) f.save();
    if (w_.save_host) w_.save_host();
    last_good_step_ = w_.steps();
  }

  void restore() {
    for (auto& f : w_.state) f.restore();
    w_.set_steps(last_good_step_);
    if (w_.restore_host) w_.restore_host();
    if (w_.after_restore) w_.after_restore();
  }

  std::string particle(long long i) const { return w_.particle ? w_.particle(i) : "particle " + std::to_string(i); }

  Diagnosis diagnose(int field, long long index) {
    Diagnosis d;
    d.detected_step = w_.steps();
    d.last_good_step = last_good_step_;
    d.field = w_.state[std::size_t(field)].name;
    d.index = index;
    // 1. Replay from the last good state to the first non-finite step.
    restore();
    while (w_.steps() < d.detected_step) {
      w_.step();
      if (first_bad_field().first >= 0) {
        d.first_bad_step = w_.steps();
        break;
      }
    }
    // 2. The state before that step, every term alone.
    if (d.first_bad_step >= 0) {
      restore();
      while (w_.steps() < d.first_bad_step - 1) w_.step();
      double largest = -1;
      for (const auto& term : w_.terms) {
        term.evaluate();
        if (const long long i = w_.first_bad_force(); i >= 0) {
          d.term = term.name;
          d.term_non_finite = true;
          d.term_index = i;
          break;
        }
        if (const double m = w_.max_force(); m > largest) {
          largest = m;
          d.term = term.name;
          d.term_force = m;
        }
      }
      // 2b. Velocity Verlet evaluates the step's forces at the positions after its drift: if those
      // are still finite, evaluate the terms there (velocity-dependent ones only if the velocities
      // are finite too).
      if (!d.term_non_finite && !w_.state.empty()) {
        restore();
        while (w_.steps() < d.first_bad_step - 1) w_.step();
        w_.step();
        const bool positions_finite = w_.state[0].first_bad() < 0;
        const bool velocities_finite = w_.state.size() < 2 || w_.state[1].first_bad() < 0;
        for (const auto& term : w_.terms) {
          if (!positions_finite || (term.uses_velocity && !velocities_finite)) continue;
          term.evaluate();
          if (const long long i = w_.first_bad_force(); i >= 0) {
            d.term = term.name;
            d.term_non_finite = true;
            d.term_after_drift = true;
            d.term_index = i;
            break;
          }
        }
      }
    }
    // 3. Leave the system in its last good state.
    restore();
    std::ostringstream s;
    s << "non-finite " << d.field << " of " << particle(d.index) << " found at step " << d.detected_step << "; ";
    if (d.first_bad_step < 0) {
      s << "a replay from step " << d.last_good_step << " stayed finite, so the state was changed outside the time step";
    } else {
      s << "step " << d.first_bad_step << " made it non-finite: ";
      if (d.term_non_finite && d.term_after_drift)
        s << "the force term '" << d.term << "' is non-finite on " << particle(d.term_index)
          << " at the positions of step " << d.first_bad_step << " (where the step evaluates its forces)";
      else if (d.term_non_finite)
        s << "the force term '" << d.term << "' is non-finite on " << particle(d.term_index) << " at step "
          << d.first_bad_step - 1;
      else if (!d.term.empty())
        s << "every force term was finite at step " << d.first_bad_step - 1 << "; the largest, |F| = " << d.term_force
          << ", came from '" << d.term << "' (the update overflowed: a time step above the stability limit?)";
      else
        s << "the scene has no force terms (the update overflowed)";
    }
    s << ". The run stopped; the last good state (step " << d.last_good_step
      << ") is kept and no later checkpoint was written";
    d.message = s.str();
    return d;
  }

  Watched w_;
  long long interval_;
  long long last_good_step_ = 0;
};

// A watchdog checking every `interval` steps where the scene provides watched(), none otherwise.
template <class Scene>
std::optional<NanWatchdog> watch_if_possible(Scene& scene, long long interval) {
  if constexpr (has_watched_v<Scene>)
    return NanWatchdog(scene.watched(), interval);
  else
    return std::nullopt;
}

}  // namespace mesoflow::watchdog
