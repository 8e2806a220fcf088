// h5md_writer.hpp — trajectories and observables in the H5MD 1.1 layout, with an XDMF sidecar.
//
// Layout (https://www.nongnu.org/h5md/h5md.html; docs/output-format.md has the full page):
//   /h5md                        attribute version = {1, 1}
//     author, creator            attributes name (and version for the creator)
//   /parameters                  one attribute per run parameter
//   /particles/<group>/box       attributes dimension, boundary; datasets edges[D], offset[D]
//   /particles/<group>/<name>/   value (T, N, D), or (T, N) for one component; step (T); time (T)
//   /observables/<name>/         value (T), or (T, count); step (T); time (T)
// `value` datasets are chunked and grow along T; `step` is int64 and `time` double.
#pragma once

#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <map>
#include <string>
#include <type_traits>
#include <vector>

#include "hdf5_util.hpp"

namespace mesoflow::io {

// Writes one H5MD file; the file is closed when the writer is destroyed. Not thread-safe: one
// host thread appends, typically from host mirrors refreshed on output steps.
class H5mdWriter {
 public:
  // Creates `path` (truncating an existing file) and writes the /h5md metadata group, with the
  // creating program and the author (H5MD requires both).
  explicit H5mdWriter(const std::string& path, const std::string& creator_name = "mesoflow",
                      const std::string& creator_version = MESOFLOW_VERSION,
                      const std::string& author = "unknown");

  // Reopens the trajectory `path` written by an H5mdWriter, to continue it after a restart from a
  // checkpoint taken at `last_step`. Every time series (each particles element and observable)
  // is cut back to its frames at steps <= last_step, dropping those written after the checkpoint,
  // so that appending the frames from there on gives the file an uninterrupted run would have
  // written. The particles groups, elements and observables of the file are known again, with
  // their precision and shapes (add_particles_group is not called again for a group of the file);
  // /h5md and /parameters are kept as they are. Throws std::runtime_error naming `path` when it is
  // missing, not an H5MD file of this writer's layout, or open elsewhere (by another writer or
  // reader in this process, or in another process: HDF5 locks the files it opens).
  static H5mdWriter resume(const std::string& path, std::int64_t last_step);

  H5mdWriter(H5mdWriter&&) = default;
  H5mdWriter& operator=(H5mdWriter&&) = default;

  const std::string& path() const { return path_; }

  // Run parameters, stored as attributes of /parameters (set again: replaced).
  void set_parameter(const std::string& name, double value);
  void set_parameter(const std::string& name, long long value);
  void set_parameter(const std::string& name, bool value);
  void set_parameter(const std::string& name, const std::string& value);
  void set_parameter(const std::string& name, const char* value);
  // Any other integer type (int, std::size_t, ...) is stored as a 64-bit integer.
  template <class Int, std::enable_if_t<std::is_integral_v<Int>, int> = 0>
  void set_parameter(const std::string& name, Int value) {
    set_parameter(name, static_cast<long long>(value));
  }

  // Whether /particles/<group> is declared (by add_particles_group, or in a resumed file).
  bool has_particles_group(const std::string& group) const { return groups_.count(group) != 0; }
  // Declares /particles/<group> with `n_particles` particles in `dim` (2 or 3) dimensions and its
  // fixed box [box_lo, box_lo + box_edges), periodic or not per axis. Must precede appends to it.
  // The groups of a resumed file are declared already.
  void add_particles_group(const std::string& group, int dim, std::size_t n_particles,
                           const std::vector<double>& box_lo, const std::vector<double>& box_edges,
                           const std::vector<bool>& periodic);

  // Appends one frame of the per-particle element /particles/<group>/<name>: `n` particles of
  // `dim` components, particle-major (component fastest). dim == 1 stores a scalar per particle.
  // The element is created by its first append, in the precision of `data`; later appends must
  // match its precision, particle count and dim. A "position" element has the group's dim.
  template <class Real>
  void append(const std::string& group, const std::string& name, std::int64_t step, double time,
              const Real* data, std::size_t n, int dim) {
    static_assert(std::is_same_v<Real, float> || std::is_same_v<Real, double>,
                  "H5mdWriter::append takes float or double data; append_int takes integers");
    append_particles(group, name, step, time, data, native_type<Real>(), n, dim);
  }

  // As append, for integer elements (ids, species, images).
  void append_int(const std::string& group, const std::string& name, std::int64_t step, double time,
                  const int* data, std::size_t n, int dim);

  // Appends one frame of /observables/<name>: a scalar, or `count` values.
  void append_observable(const std::string& name, std::int64_t step, double time, double value);
  void append_observable(const std::string& name, std::int64_t step, double time,
                         const double* values, std::size_t count);

  // Writes HDF5's buffers to the file, so that readers see every frame appended so far.
  void flush();

  // Flushes, then writes an XDMF 3 description of every particles group that has a "position"
  // element: one Polyvertex grid per position frame, with each other element of the group stored
  // at the same step as an attribute. The .h5 file is named relative to the .xdmf, so the two can
  // be moved together. Needs no reading back: the frames are tracked in memory.
  void write_xdmf(const std::string& xdmf_path);

 private:
  // One time-dependent element: its open datasets and the (step, time) of each frame written.
  struct Series {
    Dataset value, step, time;
    std::vector<hsize_t> frame_shape;  // shape of one frame of `value`
    hid_t mem_type = H5I_INVALID_HID;  // native type of the values (predefined: not owned)
    std::vector<std::int64_t> steps;
    std::vector<double> times;
  };

  struct ParticlesGroup {
    int dim = 0;
    // 0 only for a resumed group that has no element yet: its first append sets the count.
    std::size_t n_particles = 0;
    std::map<std::string, Series> elements;
  };

  // A writer of the open `file`, knowing none of its contents yet (see resume).
  H5mdWriter(std::string path, File file);

  void load_contents(std::int64_t last_step);
  ParticlesGroup load_particles_group(const std::string& group, std::int64_t last_step);
  Series load_series(const std::string& series_path, std::int64_t last_step);
  Group parameters_group();
  void append_particles(const std::string& group, const std::string& name, std::int64_t step,
                        double time, const void* data, hid_t mem_type, std::size_t n, int dim);
  Series& particle_series(const std::string& group, const std::string& name, hid_t mem_type,
                          std::size_t n, int dim);
  Series& observable_series(const std::string& name, const std::vector<hsize_t>& frame_shape);
  Series create_series_group(const std::string& path, hid_t mem_type,
                             const std::vector<hsize_t>& frame_shape,
                             const std::vector<hsize_t>& value_chunk);
  void append_frame(Series& series, std::int64_t step, double time, const void* data);
  static void write_xdmf_group(std::ostream& out, const std::string& h5_name,
                               const std::string& group, const ParticlesGroup& particles);
  static void write_xdmf_frame(std::ostream& out, const std::string& prefix,
                               const std::string& name, const ParticlesGroup& particles,
                               std::size_t frame);

  std::string path_;
  File file_;
  // Declared after file_, so destroyed first: every dataset is closed before the file.
  std::map<std::string, ParticlesGroup> groups_;
  std::map<std::string, Series> observables_;
};

}  // namespace mesoflow::io
