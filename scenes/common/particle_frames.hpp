// particle_frames.hpp — particle data from Kokkos Views to the host and into H5MD frames, for a
// scene's record of its run (and the drivers' particle I/O, drivers/common/particle_io.hpp). Only
// output steps touch the host; the time-step loop never does.
#pragma once

#include "kernels/common/box.hpp"
#include "kernels/common/particles.hpp"
#include "io/h5md_writer.hpp"

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace mesoflow::scene {

// Row-major (particle-major, component fastest) host copy of an (n × D) View, as H5MD and
// checkpoints store it.
template <class View>
std::vector<typename View::non_const_value_type> to_row_major(const View& v) {
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), v);
  const std::size_t n = h.extent(0), dim = h.extent(1);
  std::vector<typename View::non_const_value_type> out(n * dim);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t d = 0; d < dim; ++d) out[i * dim + d] = h(i, d);
  return out;
}

template <class View>
void from_row_major(const View& v, const std::vector<typename View::non_const_value_type>& data) {
  auto h = Kokkos::create_mirror_view(v);
  const std::size_t n = h.extent(0), dim = h.extent(1);
  if (data.size() != n * dim) throw std::runtime_error("particle data of the wrong size");
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t d = 0; d < dim; ++d) h(i, d) = data[i * dim + d];
  Kokkos::deep_copy(v, h);
}

template <class View>
std::vector<typename View::non_const_value_type> to_host_vector(const View& v) {
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), v);
  return std::vector<typename View::non_const_value_type>(h.data(), h.data() + h.extent(0));
}

template <class View>
void from_host_vector(const View& v, const std::vector<typename View::non_const_value_type>& data) {
  if (data.size() != v.extent(0)) throw std::runtime_error("particle data of the wrong size");
  auto h = Kokkos::create_mirror_view(v);
  for (std::size_t i = 0; i < data.size(); ++i) h(i) = data[i];
  Kokkos::deep_copy(v, h);
}

template <int D, class Real>
void add_particles_group(io::H5mdWriter& out, const std::string& group, std::size_t n, const Box<D, Real>& box) {
  std::vector<double> lo(D), edges(D);
  std::vector<bool> periodic(D);
  for (int d = 0; d < D; ++d) {
    lo[d] = box.lo[d];
    edges[d] = box.length[d];
    periodic[d] = box.periodic[d];
  }
  out.add_particles_group(group, D, n, lo, edges, periodic);
}

// One trajectory frame: positions and velocities.
template <int D, class Real, class ExecSpace>
void write_frame(io::H5mdWriter& out, const std::string& group, std::int64_t step, double time,
                 const Particles<D, Real, ExecSpace>& p) {
  const auto x = to_row_major(p.x), v = to_row_major(p.v);
  out.append(group, "position", step, time, x.data(), p.size(), D);
  out.append(group, "velocity", step, time, v.data(), p.size(), D);
}

}  // namespace mesoflow::scene
