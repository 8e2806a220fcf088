// term_list.hpp — a scene's force terms, declared once (issue 24, item 2).
//
// A scene lists each physical term of its model once: its name, the paper's equation, whether it
// reads velocities (drag, friction, thermostats) and whether its coefficient is non-zero (a zero
// coefficient makes the term vanish, and the step then launches no kernel for it). Beside the terms
// the scene lists the kernel launches of one force evaluation, in order: a launch evaluates one or
// more terms fused in one loop (the DP shape loop: area, springs, line tension, gravity). From that
// one list come
//   - the step's force evaluation (evaluate(): every launch that serves an active term, in order),
//   - the NaN watchdog's term attribution (watchdog_terms(): each active term alone),
//   - the run summary's components (components(): one line per launch, naming its active terms).
// Everything here runs on the host and launches kernels through the callables the scene gives;
// nothing is called inside a kernel.
//
// Args are what a launch receives from the step (the velocities at which velocity-dependent terms
// are evaluated, for velocity Verlet's modified step), e.g. TermList<const VectorView&>.
#pragma once

#include "scenes/common/nan_watchdog.hpp"

#include <algorithm>
#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace mesoflow::scene {

struct Term {
  std::string name;                // "line tension Γ"
  std::string equation;            // "eq. 2" (of the scene's paper)
  bool velocity_dependent = false; // drag, friction, thermostats
  bool active = true;              // false: its coefficient is zero and it vanishes
  std::function<void()> alone;     // f ← this term alone at the current state (force array zeroed first)

  // "line tension Γ (eq. 2)": the name the watchdog and the summaries use.
  std::string label() const { return equation.empty() ? name : name + " (" + equation + ")"; }
};

template <class... Args>
class TermList {
 public:
  struct Launch {
    std::string name;                       // "shape loop"
    std::vector<std::string> terms;         // the terms it evaluates (names as declared)
    std::function<void(Args...)> run;       // adds the forces of its active terms
  };

  // Declares a term; names are unique.
  Term& term(Term t) {
    if (find(t.name) != nullptr) throw std::logic_error("term list: term '" + t.name + "' declared twice");
    terms_.push_back(std::move(t));
    return terms_.back();
  }

  // Declares the next launch of a force evaluation, over terms already declared.
  void launch(std::string name, std::vector<std::string> terms, std::function<void(Args...)> run) {
    for (const auto& t : terms)
      if (find(t) == nullptr)
        throw std::logic_error("term list: launch '" + name + "' names the undeclared term '" + t + "'");
    launches_.push_back(Launch{std::move(name), std::move(terms), std::move(run)});
  }

  // Whether a launch evaluates at least one active term (else the step skips it).
  bool serves_active_term(const Launch& l) const {
    return std::any_of(l.terms.begin(), l.terms.end(), [&](const std::string& t) { return find(t)->active; });
  }

  // The step's force evaluation: every launch that serves an active term, in declaration order.
  template <class... A>
  void evaluate(A&&... args) const {
    for (const auto& l : launches_)
      if (serves_active_term(l)) l.run(args...);
  }

  // Each active term alone, for the NaN watchdog's attribution.
  std::vector<watchdog::ForceTerm> watchdog_terms() const {
    std::vector<watchdog::ForceTerm> out;
    for (const auto& t : terms_)
      if (t.active && t.alone) out.push_back(watchdog::ForceTerm{t.label(), t.alone, t.velocity_dependent});
    return out;
  }

  // One line per launch that runs: "shape loop (one kernel): area elasticity K_a, …".
  std::vector<std::string> components() const {
    std::vector<std::string> out;
    for (const auto& l : launches_) {
      if (!serves_active_term(l)) continue;
      std::string line = l.name + ":";
      bool first = true;
      for (const auto& t : l.terms) {
        if (!find(t)->active) continue;
        line += (first ? " " : ", ") + t;
        first = false;
      }
      out.push_back(std::move(line));
    }
    return out;
  }

  const std::vector<Term>& terms() const { return terms_; }
  const std::vector<Launch>& launches() const { return launches_; }
  const Term* find(const std::string& name) const {
    for (const auto& t : terms_)
      if (t.name == name) return &t;
    return nullptr;
  }

 private:
  std::vector<Term> terms_;
  std::vector<Launch> launches_;
};

}  // namespace mesoflow::scene
