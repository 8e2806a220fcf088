// lj_fluid_scene.hpp — the initial state of the Lennard-Jones reference scene (drivers/lj_fluid):
// N particles on a square/cubic lattice of per_side = ⌈N^{1/D}⌉ sites per edge, jittered by ±0.1 of
// the spacing from the counter-based stream (seed, 0, initial_condition, i, 0); Maxwell velocities
// at k_BT from (seed, 0, initial_condition, i, 1), with zero total momentum, rescaled to exactly
// k_BT over D (N − 1) degrees of freedom. Also the run's checkpoint, its fields declared once
// (write_checkpoint / read_checkpoint over scenes/common/checkpoint_fields.hpp).
#pragma once

#include "kernels/common/kernel_launch.hpp"
#include "io/checkpoint.hpp"
#include "kernels/common/box.hpp"
#include "kernels/common/neighbor_list.hpp"
#include "kernels/common/particles.hpp"
#include "kernels/common/random.hpp"
#include "kernels/common/reductions.hpp"
#include "scenes/common/checkpoint_fields.hpp"

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace mesoflow::lj_fluid {

template <int D, class Real, class Exec>
void place_on_lattice(const Particles<D, Real, Exec>& p, Real L, std::uint64_t seed) {
  const int n = int(p.size());
  const int per_side = int(std::ceil(std::pow(double(n), 1.0 / D) - 1e-9));
  const Real a = L / Real(per_side);
  const auto x = p.x;
  mesoflow::launch::parallel_for(
      "mesoflow::lj_fluid::lattice", Kokkos::RangePolicy<Exec>(0, n), KOKKOS_LAMBDA(int i) {
        RandomStream jitter(seed, 0, stream_tag::initial_condition, std::uint32_t(i), 0);
        int site = i;
        for (int d = 0; d < D; ++d) {
          x(i, d) = (Real(site % per_side) + Real(0.5) + Real(0.1) * jitter.template uniform_symmetric<Real>()) * a;
          site /= per_side;
        }
      });
}

// Maxwell velocities at k_BT with zero total momentum, rescaled to exactly k_BT.
template <int D, class Real, class Exec>
void thermalize(const Particles<D, Real, Exec>& p, double kT, std::uint64_t seed) {
  const auto v = p.v;
  const Real sd = Real(std::sqrt(kT));
  mesoflow::launch::parallel_for(
      "mesoflow::lj_fluid::maxwell", Kokkos::RangePolicy<Exec>(0, p.size()), KOKKOS_LAMBDA(int i) {
        RandomStream g(seed, 0, stream_tag::initial_condition, std::uint32_t(i), 1);
        for (int d = 0; d < D; ++d) v(i, d) = sd * g.template normal<Real>();
      });
  const auto P = momentum(p);
  double mass = 0;
  const auto m = p.mass;
  mesoflow::launch::parallel_reduce(
      "mesoflow::lj_fluid::total_mass", Kokkos::RangePolicy<Exec>(0, p.size()),
      KOKKOS_LAMBDA(int i, double& acc) { acc += m(i); }, mass);
  Real drift[D];
  for (int d = 0; d < D; ++d) drift[d] = Real(P[d] / mass);
  const double dof = double(D) * (double(p.size()) - 1.0);
  const double ke = kinetic_energy(p) - 0.5 * mass * [&] {
    double s = 0;
    for (int d = 0; d < D; ++d) s += double(drift[d]) * drift[d];
    return s;
  }();
  const Real scale = Real(std::sqrt(kT * dof / (2.0 * ke)));
  mesoflow::launch::parallel_for(
      "mesoflow::lj_fluid::rescale", Kokkos::RangePolicy<Exec>(0, p.size()), KOKKOS_LAMBDA(int i) {
        for (int d = 0; d < D; ++d) v(i, d) = scale * (v(i, d) - drift[d]);
      });
}

// Everything needed to continue a run bit-identically, declared once for writing and reading:
// the particle state including the forces of the last step (velocity Verlet's first half uses
// them) and the neighbor list's reference positions, from which a restarted run rebuilds exactly
// the same list; the dimension, precision and box identify the run.
template <class Archive, int D, class Real, class Exec>
void checkpoint_fields(Archive& a, std::int64_t& step, double& time, const Particles<D, Real, Exec>& p,
                       const typename Particles<D, Real, Exec>::vector_view& neighbor_reference,
                       std::int64_t& dimension, std::string& precision, std::vector<double>& box_lo_length) {
  a("step", step);
  a("time", time);
  a("dimension", dimension);
  a("precision", precision);
  a("box_lo_length", box_lo_length);
  a("position", p.x);
  a("velocity", p.v);
  a("force", p.f);
  a("mass", p.mass);
  a("type", p.type);
  a("body", p.body);
  a("neighbor_reference_position", neighbor_reference);
}

template <int D, class Real>
std::string precision_name() {
  return sizeof(Real) == 4 ? "float" : "double";
}
template <int D, class Real>
std::vector<double> box_lo_length(const Box<D, Real>& box) {
  std::vector<double> out;
  for (int d = 0; d < D; ++d) out.insert(out.end(), {double(box.lo[d]), double(box.length[d])});
  return out;
}

// Writes the checkpoint atomically (io::CheckpointWriter).
template <int D, class Real, class Exec>
void write_checkpoint(const std::string& path, std::int64_t step, double time, const Particles<D, Real, Exec>& p,
                      const NeighborList<D, Real, Exec>& list, const Box<D, Real>& box) {
  io::CheckpointWriter w(path);
  scene::SaveFields save(w);
  std::int64_t dimension = D;
  std::string precision = precision_name<D, Real>();
  std::vector<double> box_data = box_lo_length(box);
  checkpoint_fields(save, step, time, p, list.reference_positions(), dimension, precision, box_data);
  w.commit();
}

struct RestartPoint {
  std::int64_t step;
  double time;
};

// Restores the particles and rebuilds the neighbor list from its reference positions. Throws,
// before reading any field, if the checkpoint was written with another dimension, precision,
// particle count or box.
template <int D, class Real, class Exec>
RestartPoint read_checkpoint(const std::string& path, const Particles<D, Real, Exec>& p,
                             NeighborList<D, Real, Exec>& list, const Box<D, Real>& box) {
  io::CheckpointReader r(path);
  const std::string precision = precision_name<D, Real>();
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
  typename Particles<D, Real, Exec>::vector_view reference("mesoflow::restart::x_ref", p.size());
  scene::LoadFields load(r);
  RestartPoint at{};
  std::int64_t dimension = 0;
  std::string stored_precision;
  checkpoint_fields(load, at.step, at.time, p, reference, dimension, stored_precision, box_data);
  Particles<D, Real, Exec> at_reference = p;
  at_reference.x = reference;
  list.build(at_reference, box);
  return at;
}

}  // namespace mesoflow::lj_fluid
