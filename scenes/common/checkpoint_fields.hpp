// checkpoint_fields.hpp — a scene's checkpoint fields, declared once for writing and reading
// (issue 24, item 4).
//
// A scene lists the state a bit-identical restart needs in one member template,
//   template <class Archive> void checkpoint_fields(Archive& a) { a("position", p.x); a("step", step_); ... }
// and the same list writes a checkpoint (SaveFields over io::CheckpointWriter) and reads it back
// (LoadFields over io::CheckpointReader): names, types and shapes cannot drift apart between the two.
// Archive::loading tells the scene which way it runs (to rebuild what follows from the state, a
// neighbor list say, after a load).
//
// Entries: Kokkos Views of rank 1 (shape {n}) and rank 2 (row-major, shape {n, D}, as H5MD stores
// them), std::vector of double, float, int or int64 (shape {size}), integer scalars (stored as
// int64), double scalars and strings. Unsigned 32-bit Views (particle tags) are stored as int64.
// Host copies only: checkpoints are written on output steps, never inside the time-step loop.
#pragma once

#include "io/checkpoint.hpp"

#include <Kokkos_Core.hpp>

#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

namespace mesoflow::scene {

namespace detail {
template <class T>
using stored_t = std::conditional_t<std::is_same_v<T, std::uint32_t>, std::int64_t, T>;
}  // namespace detail

class SaveFields {
 public:
  static constexpr bool loading = false;
  explicit SaveFields(io::CheckpointWriter& w) : w_(w) {}

  template <class View, std::enable_if_t<Kokkos::is_view<View>::value, int> = 0>
  void operator()(const std::string& name, const View& v) {
    using T = detail::stored_t<typename View::non_const_value_type>;
    const auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), v);
    const std::size_t n = h.extent(0);
    if constexpr (View::rank == 1) {
      std::vector<T> out(n);
      for (std::size_t i = 0; i < n; ++i) out[i] = T(h(i));
      w_.put(name, out.data(), {n});
    } else {
      const std::size_t dim = h.extent(1);
      std::vector<T> out(n * dim);
      for (std::size_t i = 0; i < n; ++i)
        for (std::size_t d = 0; d < dim; ++d) out[i * dim + d] = T(h(i, d));
      w_.put(name, out.data(), {n, dim});
    }
  }
  template <class T>
  void operator()(const std::string& name, std::vector<T>& v) {
    w_.put(name, v.data(), {v.size()});
  }
  template <class Int, std::enable_if_t<std::is_integral_v<Int>, int> = 0>
  void operator()(const std::string& name, Int& x) {
    w_.put_scalar(name, std::int64_t(x));
  }
  void operator()(const std::string& name, double& x) { w_.put_scalar(name, x); }
  void operator()(const std::string& name, std::string& s) { w_.put_string(name, s); }

 private:
  io::CheckpointWriter& w_;
};

class LoadFields {
 public:
  static constexpr bool loading = true;
  explicit LoadFields(const io::CheckpointReader& r) : r_(r) {}

  // Views must be allocated at the stored size (a different size is an error naming the entry).
  template <class View, std::enable_if_t<Kokkos::is_view<View>::value, int> = 0>
  void operator()(const std::string& name, const View& v) {
    using T = detail::stored_t<typename View::non_const_value_type>;
    auto h = Kokkos::create_mirror_view(v);
    const std::size_t n = h.extent(0);
    const std::size_t dim = View::rank == 1 ? 1 : h.extent(1);
    std::vector<T> in(n * dim);
    r_.get(name, in.data(), View::rank == 1 ? std::vector<std::size_t>{n} : std::vector<std::size_t>{n, dim});
    if constexpr (View::rank == 1) {
      for (std::size_t i = 0; i < n; ++i) h(i) = typename View::non_const_value_type(in[i]);
    } else {
      for (std::size_t i = 0; i < n; ++i)
        for (std::size_t d = 0; d < dim; ++d) h(i, d) = in[i * dim + d];
    }
    Kokkos::deep_copy(v, h);
  }
  template <class T>
  void operator()(const std::string& name, std::vector<T>& v) {
    r_.get(name, v);
  }
  template <class Int, std::enable_if_t<std::is_integral_v<Int>, int> = 0>
  void operator()(const std::string& name, Int& x) {
    x = Int(r_.get_scalar_int64(name));
  }
  void operator()(const std::string& name, double& x) { x = r_.get_scalar_double(name); }
  void operator()(const std::string& name, std::string& s) { s = r_.get_string(name); }

  const io::CheckpointReader& reader() const { return r_; }

 private:
  const io::CheckpointReader& r_;
};

}  // namespace mesoflow::scene
