// particle_io.hpp — moving particle data between Kokkos Views and files: H5MD frames (the host
// copies and frames of scenes/common/particle_frames.hpp) and checkpoints. Only output steps touch
// the host; the time-step loop never does.
#pragma once

#include "kernels/common/box.hpp"
#include "kernels/common/neighbor_list.hpp"
#include "kernels/common/particles.hpp"
#include "io/checkpoint.hpp"
#include "io/h5md_writer.hpp"
#include "scenes/common/particle_frames.hpp"

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace mesoflow::driver {

// The host copies and H5MD frames (scenes/common/particle_frames.hpp), under their driver names.
using scene::add_particles_group;
using scene::from_host_vector;
using scene::from_row_major;
using scene::to_host_vector;
using scene::to_row_major;
using scene::write_frame;

// Everything needed to continue a run bit-identically: particle state including the forces of
// the last step (velocity Verlet's first half uses them), and the neighbor list's reference
// positions, from which the restarted run rebuilds exactly the same list.
template <int D, class Real, class ExecSpace>
void write_checkpoint(const std::string& path, std::int64_t step, double time,
                      const Particles<D, Real, ExecSpace>& p, const NeighborList<D, Real, ExecSpace>& list,
                      const Box<D, Real>& box) {
  io::CheckpointWriter w(path);
  const std::vector<std::size_t> vec_shape{p.size(), std::size_t(D)}, scalar_shape{p.size()};
  w.put_scalar("step", step);
  w.put_scalar("time", time);
  w.put_scalar("dimension", std::int64_t(D));
  w.put_string("precision", sizeof(Real) == 4 ? "float" : "double");
  w.put("position", to_row_major(p.x).data(), vec_shape);
  w.put("velocity", to_row_major(p.v).data(), vec_shape);
  w.put("force", to_row_major(p.f).data(), vec_shape);
  w.put("mass", to_host_vector(p.mass).data(), scalar_shape);
  w.put("type", to_host_vector(p.type).data(), scalar_shape);
  w.put("body", to_host_vector(p.body).data(), scalar_shape);
  w.put("neighbor_reference_position", to_row_major(list.reference_positions()).data(), vec_shape);
  std::vector<double> box_data;
  for (int d = 0; d < D; ++d) box_data.insert(box_data.end(), {double(box.lo[d]), double(box.length[d])});
  w.put("box_lo_length", box_data.data(), {std::size_t(D), std::size_t(2)});
  w.commit();
}

struct RestartPoint {
  std::int64_t step;
  double time;
};

// Restores particles and rebuilds the neighbor list from its reference positions. Throws if the
// checkpoint was written with another dimension, precision, particle count or box.
template <int D, class Real, class ExecSpace>
RestartPoint read_checkpoint(const std::string& path, const Particles<D, Real, ExecSpace>& p,
                             NeighborList<D, Real, ExecSpace>& list, const Box<D, Real>& box) {
  io::CheckpointReader r(path);
  const std::string precision = sizeof(Real) == 4 ? "float" : "double";
  if (r.get_scalar_int64("dimension") != D || r.get_string("precision") != precision)
    throw std::runtime_error("checkpoint " + path + " holds a " + std::to_string(r.get_scalar_int64("dimension")) +
                             "D " + r.get_string("precision") + " run; this run is " + std::to_string(D) + "D " +
                             precision);
  const std::size_t stored = r.shape("position").at(0);
  if (stored != p.size())
    throw std::runtime_error("checkpoint " + path + " holds " + std::to_string(stored) + " particles, this run has " +
                             std::to_string(p.size()));
  std::vector<double> box_data;
  r.get("box_lo_length", box_data);
  for (int d = 0; d < D; ++d)
    if (box_data.at(2 * d) != double(box.lo[d]) || box_data.at(2 * d + 1) != double(box.length[d]))
      throw std::runtime_error("checkpoint " + path + " was written for a box of length " +
                               std::to_string(box_data.at(2 * d + 1)) + " along axis " + std::to_string(d) +
                               ", this run's box is " + std::to_string(double(box.length[d])) +
                               ": restart with the parameters of the interrupted run");
  std::vector<Real> data;
  typename Particles<D, Real, ExecSpace>::vector_view reference("mesoflow::restart::x_ref", p.size());
  Particles<D, Real, ExecSpace> at_reference = p;
  at_reference.x = reference;
  std::vector<int> ints;
  r.get("body", ints);
  from_host_vector(p.body, ints);
  r.get("neighbor_reference_position", data);
  from_row_major(reference, data);
  list.build(at_reference, box);
  r.get("position", data);
  from_row_major(p.x, data);
  r.get("velocity", data);
  from_row_major(p.v, data);
  r.get("force", data);
  from_row_major(p.f, data);
  r.get("mass", data);
  from_host_vector(p.mass, data);
  r.get("type", ints);
  from_host_vector(p.type, ints);
  return {r.get_scalar_int64("step"), r.get_scalar_double("time")};
}

}  // namespace mesoflow::driver
