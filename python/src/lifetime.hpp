// lifetime.hpp — Kokkos' lifetime in a Python process, and NumPy views of Kokkos Views.
//
// Python may hold a scene after Kokkos is finalised (module globals outlive atexit hooks), and
// Kokkos must not free a View after finalize. So every bound object that owns device data derives
// from Releasable: it registers itself, and finalize_kokkos() releases each one's data first. A
// released object raises RuntimeError on use.
#pragma once

#include "kernels/common/kokkos_compat.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace py = pybind11;

namespace mesoflow::python {

class Releasable {
 public:
  Releasable() { registry().insert(this); }
  virtual ~Releasable() { registry().erase(this); }
  Releasable(const Releasable&) = delete;
  Releasable& operator=(const Releasable&) = delete;
  virtual void release() = 0;  // drops every View this object holds
  static std::set<Releasable*>& registry() {
    static std::set<Releasable*> r;
    return r;
  }
};

inline void require_kokkos();

// A scene (or run) owned by Python: built once Kokkos runs, released before Kokkos is finalised.
template <class T>
class Owned : public Releasable {
 public:
  template <class... Args>
  explicit Owned(const Args&... args) {
    require_kokkos();
    object_ = std::make_unique<T>(args...);
  }
  void release() override { object_.reset(); }
  T& get() {
    if (!object_) throw std::runtime_error("mesoflow: this object's data was released when Kokkos was finalised");
    return *object_;
  }

 private:
  std::unique_ptr<T> object_;
};

// Thrown from a run's per-sample hook when a Python callback returns False; the binding catches it
// and reports the run as stopped.
struct StopRun {};

// A NumPy copy of a host vector (a run's series).
inline py::array_t<double> array(const std::vector<double>& v) {
  return py::array_t<double>(py::ssize_t(v.size()), v.data());
}

// `steps` steps of any scene with step(), checking for Ctrl-C every `signal_every` steps.
template <class Scene>
void advance_steps(Scene& scene, long long steps, long long signal_every = 100) {
  if (steps < 0) throw std::invalid_argument("steps must be >= 0, got " + std::to_string(steps));
  for (long long k = 0; k < steps; ++k) {
    scene.step();
    if (k % signal_every == signal_every - 1 && PyErr_CheckSignals() != 0) throw pybind11::error_already_set();
  }
}

inline int& thread_count() {
  static int n = 0;
  return n;
}
inline bool& finalized_flag() {
  static bool f = false;
  return f;
}
inline int initialized_threads() { return thread_count(); }
inline bool finalized() { return finalized_flag(); }

inline void start_kokkos(int threads) {
  initialize_kokkos(threads);
  thread_count() = concurrency<Kokkos::DefaultHostExecutionSpace>();
}

inline void finalize_kokkos() {
  if (!Kokkos::is_initialized() || finalized()) return;
  for (Releasable* r : Releasable::registry()) r->release();
  Kokkos::finalize();
  finalized_flag() = true;
}

inline void require_kokkos() {
  if (finalized()) throw std::runtime_error("mesoflow: Kokkos has been finalised (at exit or by mesoflow.finalize())");
  if (!Kokkos::is_initialized()) start_kokkos(0);
}

inline bool host_backend() {
  return Kokkos::SpaceAccessibility<Kokkos::HostSpace,
                                    Kokkos::DefaultExecutionSpace::memory_space>::accessible;
}

// A NumPy array over a Kokkos View of rank 1 or 2, of any layout: on host backends a view of the
// same memory (no copy; `owner` is kept alive by the array), on device backends a host copy.
template <class View>
pybind11::array numpy_view(const View& v, pybind11::handle owner) {
  using T = typename View::non_const_value_type;
  static_assert(View::rank == 1 || View::rank == 2, "rank 1 or 2");
  std::vector<pybind11::ssize_t> shape, strides;
  for (int r = 0; r < int(View::rank); ++r) shape.push_back(pybind11::ssize_t(v.extent(r)));
  if (Kokkos::SpaceAccessibility<Kokkos::HostSpace, typename View::memory_space>::accessible) {
    for (int r = 0; r < int(View::rank); ++r) strides.push_back(pybind11::ssize_t(v.stride(r) * sizeof(T)));
    return pybind11::array(pybind11::dtype::of<T>(), shape, strides, v.data(), owner);
  }
  auto host = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), v);
  for (int r = 0; r < int(View::rank); ++r) strides.push_back(pybind11::ssize_t(host.stride(r) * sizeof(T)));
  return pybind11::array(pybind11::dtype::of<T>(), shape, strides, host.data());  // copies
}

}  // namespace mesoflow::python
