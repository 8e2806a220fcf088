// h5md_writer.cpp — see h5md_writer.hpp.
#include "h5md_writer.hpp"

#include <algorithm>
#include <charconv>
#include <filesystem>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <utility>

namespace mesoflow::io {

namespace {

// Per-particle data is chunked one frame at a time (frames are written, and mostly read, whole),
// with at most this many particles per chunk so that a chunk stays within a few MiB.
constexpr hsize_t kMaxParticlesPerChunk = 65536;

// Per-frame values (step, time, observables) are chunked in blocks of frames: one chunk per frame
// would cost an entry in the chunk index for every few bytes of data.
constexpr hsize_t kValuesPerSeriesChunk = 1024;

[[noreturn]] void usage_error(const std::string& file, const std::string& message) {
  throw std::invalid_argument("mesoflow::io::H5mdWriter('" + file + "'): " + message);
}

// A file that resume cannot continue.
[[noreturn]] void resume_error(const std::string& file, const std::string& message) {
  throw std::runtime_error("mesoflow::io::H5mdWriter::resume('" + file + "'): " + message);
}

// Group and element names become single HDF5 link names.
void check_name(const std::string& file, const std::string& kind, const std::string& name) {
  if (name.empty() || name.find('/') != std::string::npos)
    usage_error(file, kind + " name '" + name + "' must be non-empty and contain no '/'");
}

// Shortest decimal text that reads back as the same double.
std::string format_number(double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

std::string join(const std::vector<hsize_t>& values, const std::string& separator = " ") {
  std::string text;
  for (const hsize_t value : values)
    text += (text.empty() ? "" : separator) + std::to_string(value);
  return text;
}

std::string shape_text(const std::vector<hsize_t>& shape) { return "(" + join(shape, ", ") + ")"; }

std::string xml_escape(const std::string& text) {
  std::string escaped;
  for (const char c : text) {
    switch (c) {
      case '&': escaped += "&amp;"; break;
      case '<': escaped += "&lt;"; break;
      case '>': escaped += "&gt;"; break;
      case '"': escaped += "&quot;"; break;
      default: escaped += c;
    }
  }
  return escaped;
}

// `target` as seen from the directory of `reference`; absolute when no relative path exists.
std::string relative_to_directory_of(const std::string& target, const std::string& reference) {
  namespace fs = std::filesystem;
  const fs::path absolute_target = fs::absolute(target).lexically_normal();
  const fs::path directory = fs::absolute(reference).lexically_normal().parent_path();
  const fs::path relative = absolute_target.lexically_relative(directory);
  return (relative.empty() ? absolute_target : relative).generic_string();
}

// XDMF's NumberType and Precision attributes for a native numeric type.
std::string xdmf_number_type(hid_t mem_type) {
  const char* kind = H5Tget_class(mem_type) == H5T_FLOAT ? "Float" : "Int";
  return std::string("NumberType=\"") + kind + "\" Precision=\"" +
         std::to_string(H5Tget_size(mem_type)) + "\"";
}

// XDMF DataItem selecting frame `frame` (of `frames`) of the series `reference` ("file:/path"),
// as a HyperSlab whose start/stride/count rows pick that frame whole.
void write_frame_item(std::ostream& out, const std::string& indent, const std::string& reference,
                      hsize_t frame, hsize_t frames, const std::vector<hsize_t>& frame_shape,
                      hid_t mem_type) {
  const std::size_t rank = frame_shape.size() + 1;
  std::vector<hsize_t> start(rank, 0), stride(rank, 1), count{1}, whole{frames};
  start[0] = frame;
  count.insert(count.end(), frame_shape.begin(), frame_shape.end());
  whole.insert(whole.end(), frame_shape.begin(), frame_shape.end());
  out << indent << "<DataItem ItemType=\"HyperSlab\" Dimensions=\"" << join(count) << "\">\n"
      << indent << "  <DataItem Dimensions=\"3 " << rank << "\" Format=\"XML\">" << join(start)
      << "  " << join(stride) << "  " << join(count) << "</DataItem>\n"
      << indent << "  <DataItem Dimensions=\"" << join(whole) << "\" " << xdmf_number_type(mem_type)
      << " Format=\"HDF\">" << reference << "</DataItem>\n"
      << indent << "</DataItem>\n";
}

// Index of the frame written at `step`, trying `hint` first (elements are usually written
// together).
std::optional<std::size_t> frame_at_step(const std::vector<std::int64_t>& steps, std::int64_t step,
                                         std::size_t hint) {
  if (hint < steps.size() && steps[hint] == step) return hint;
  const auto found = std::find(steps.begin(), steps.end(), step);
  if (found == steps.end()) return std::nullopt;
  return static_cast<std::size_t>(found - steps.begin());
}

}  // namespace

H5mdWriter::H5mdWriter(const std::string& path, const std::string& creator_name,
                       const std::string& creator_version, const std::string& author)
    : path_(path), file_(create_file(path)) {
  const Group h5md = require_group(file_.get(), "h5md");
  write_attribute(h5md.get(), "version", std::vector<int>{1, 1});
  write_attribute(require_group(h5md.get(), "author").get(), "name", author);
  const Group creator = require_group(h5md.get(), "creator");
  write_attribute(creator.get(), "name", creator_name);
  write_attribute(creator.get(), "version", creator_version);
}

H5mdWriter::H5mdWriter(std::string path, File file)
    : path_(std::move(path)), file_(std::move(file)) {}

// ---------------------------------------------------------------------------------------------
// Resuming

H5mdWriter H5mdWriter::resume(const std::string& path, std::int64_t last_step) {
  if (!std::filesystem::exists(path)) resume_error(path, "no such file");
  File file = try_open_file(path, H5F_ACC_RDWR);
  if (!file.valid()) raise_error("", path, "open for appending");
  // HDF5 hands out a second identifier for a file this process has open already, where a second
  // writer would corrupt the first one's frames.
  if (H5Fget_obj_count(file.get(), H5F_OBJ_FILE) > 1)
    resume_error(path, "the file is open already in this process (by another writer or reader)");
  H5mdWriter writer(path, std::move(file));
  writer.load_contents(last_step);
  return writer;
}

void H5mdWriter::load_contents(std::int64_t last_step) {
  const hid_t file = file_.get();
  const auto not_h5md = [&] {
    resume_error(path_, "not an H5MD 1.1 file (/h5md with version {1, 1}, author, creator)");
  };
  if (object_type(file, "h5md") != H5I_GROUP) not_h5md();
  const Group h5md = open_group(file, "h5md");
  if (H5Aexists(h5md.get(), "version") <= 0 ||
      read_attribute_int64(h5md.get(), "version") != std::vector<std::int64_t>{1, 1} ||
      object_type(h5md.get(), "author") != H5I_GROUP ||
      object_type(h5md.get(), "creator") != H5I_GROUP)
    not_h5md();
  for (const char* top : {"particles", "observables"})
    if (path_exists(file, top) && object_type(file, top) != H5I_GROUP)
      resume_error(path_, std::string("/") + top + " is not a group");

  if (path_exists(file, "particles"))
    for (const std::string& group : link_names(open_group(file, "particles").get()))
      groups_.emplace(group, load_particles_group(group, last_step));
  if (path_exists(file, "observables")) {
    for (const std::string& name : link_names(open_group(file, "observables").get())) {
      const std::string where = "/observables/" + name;
      Series series = load_series(where, last_step);
      if (H5Tequal(series.mem_type, H5T_NATIVE_DOUBLE) <= 0 || series.frame_shape.size() > 1)
        resume_error(path_, where + " holds " + describe_type(series.mem_type) +
                                " frames of shape " + shape_text(series.frame_shape) +
                                ", not float64 frames of shape () or (count)");
      observables_.emplace(name, std::move(series));
    }
  }

  // The file is changed only once all of it has loaded: now the frames after last_step go.
  const auto cut = [](const Series& series) {
    for (const Dataset* dataset : {&series.value, &series.step, &series.time})
      set_frame_count(dataset->get(), series.steps.size());
  };
  for (const auto& [group, particles] : groups_)
    for (const auto& [name, series] : particles.elements) cut(series);
  for (const auto& [name, series] : observables_) cut(series);
}

H5mdWriter::ParticlesGroup H5mdWriter::load_particles_group(const std::string& group,
                                                            std::int64_t last_step) {
  const std::string where = "/particles/" + group;
  if (object_type(file_.get(), where + "/box") != H5I_GROUP)
    resume_error(path_, where + " has no box group");
  const Group box = open_group(file_.get(), where + "/box");
  const std::vector<std::int64_t> dimension = H5Aexists(box.get(), "dimension") > 0
                                                  ? read_attribute_int64(box.get(), "dimension")
                                                  : std::vector<std::int64_t>{};
  if (dimension.size() != 1 || (dimension[0] != 2 && dimension[0] != 3))
    resume_error(path_, where + "/box has no dimension attribute of 2 or 3");

  ParticlesGroup particles;
  particles.dim = static_cast<int>(dimension[0]);
  for (const std::string& name : link_names(open_group(file_.get(), where).get())) {
    if (name == "box") continue;
    const std::string element = where + "/" + name;
    Series series = load_series(element, last_step);
    const std::vector<hsize_t>& shape = series.frame_shape;  // (N) or (N, components)
    if (shape.empty() || shape.size() > 2 || shape[0] == 0 || (shape.size() == 2 && shape[1] < 2))
      resume_error(path_, element + " holds frames of shape " + shape_text(shape) +
                              ", not (N) or (N, components)");
    if (name == "position" &&
        shape != std::vector<hsize_t>{shape[0], static_cast<hsize_t>(particles.dim)})
      resume_error(path_, element + " holds frames of shape " + shape_text(shape) +
                              ", not positions in the group's " + std::to_string(particles.dim) +
                              " dimensions");
    if (particles.n_particles != 0 && shape[0] != particles.n_particles)
      resume_error(path_, element + " holds " + std::to_string(shape[0]) +
                              " particles, other elements of the group " +
                              std::to_string(particles.n_particles));
    particles.n_particles = shape[0];
    particles.elements.emplace(name, std::move(series));
  }
  return particles;
}

H5mdWriter::Series H5mdWriter::load_series(const std::string& series_path, std::int64_t last_step) {
  const auto invalid = [&](const std::string& reason) {
    resume_error(path_, series_path + " is not a time series of this writer: " + reason);
  };
  for (const char* name : {"value", "step", "time"})
    if (object_type(file_.get(), series_path + "/" + name) != H5I_DATASET)
      invalid(std::string("it has no dataset '") + name + "'");

  Series series;
  series.value = open_dataset(file_.get(), series_path + "/value");
  series.step = open_dataset(file_.get(), series_path + "/step");
  series.time = open_dataset(file_.get(), series_path + "/time");
  const Datatype value_type = dataset_type(series.value.get());
  // A named array, not a braced list in the loop: nvcc's front end garbles a range-for over a
  // braced list of these macros (each expands to a comma expression).
  const hid_t natives[] = {H5T_NATIVE_FLOAT, H5T_NATIVE_DOUBLE, H5T_NATIVE_INT};
  for (const hid_t native : natives)
    if (same_representation(value_type.get(), native)) series.mem_type = native;
  if (series.mem_type == H5I_INVALID_HID) invalid("value holds " + describe_type(value_type.get()));
  if (!same_representation(dataset_type(series.step.get()).get(), native_type<std::int64_t>()) ||
      !same_representation(dataset_type(series.time.get()).get(), H5T_NATIVE_DOUBLE))
    invalid("step is not int64 or time not float64");

  std::vector<hsize_t> lengths;
  for (const Dataset* dataset : {&series.value, &series.step, &series.time}) {
    const std::vector<hsize_t> shape = dataset_shape(dataset->get());
    if (shape.empty() || dataset_max_shape(dataset->get())[0] != H5S_UNLIMITED)
      invalid("its datasets cannot grow by frames");
    lengths.push_back(shape[0]);
  }
  if (dataset_shape(series.step.get()).size() != 1 || dataset_shape(series.time.get()).size() != 1)
    invalid("step or time holds more than one value per frame");
  const std::vector<hsize_t> value_shape = dataset_shape(series.value.get());
  series.frame_shape.assign(value_shape.begin() + 1, value_shape.end());

  // A frame counts when value, step and time all hold it (a run killed while appending may have
  // written some of the three), and is kept when its step is at most last_step; load_contents
  // cuts the datasets to the frames kept.
  series.steps.resize(static_cast<std::size_t>(lengths[1]));
  series.times.resize(static_cast<std::size_t>(lengths[2]));
  read_dataset(series.step.get(), native_type<std::int64_t>(), series.steps.data());
  read_dataset(series.time.get(), H5T_NATIVE_DOUBLE, series.times.data());
  const auto frames = static_cast<std::size_t>(std::min({lengths[0], lengths[1], lengths[2]}));
  const auto after_checkpoint =
      std::find_if(series.steps.begin(), series.steps.begin() + static_cast<std::ptrdiff_t>(frames),
                   [&](std::int64_t step) { return step > last_step; });
  const auto kept = static_cast<std::size_t>(after_checkpoint - series.steps.begin());
  series.steps.resize(kept);
  series.times.resize(kept);
  return series;
}

// ---------------------------------------------------------------------------------------------
// Parameters

Group H5mdWriter::parameters_group() { return require_group(file_.get(), "parameters"); }

void H5mdWriter::set_parameter(const std::string& name, double value) {
  write_attribute(parameters_group().get(), name, value);
}

void H5mdWriter::set_parameter(const std::string& name, long long value) {
  write_attribute(parameters_group().get(), name, value);
}

void H5mdWriter::set_parameter(const std::string& name, bool value) {
  write_attribute(parameters_group().get(), name, value);
}

void H5mdWriter::set_parameter(const std::string& name, const std::string& value) {
  write_attribute(parameters_group().get(), name, value);
}

void H5mdWriter::set_parameter(const std::string& name, const char* value) {
  write_attribute(parameters_group().get(), name, value);
}

// ---------------------------------------------------------------------------------------------
// Particles

void H5mdWriter::add_particles_group(const std::string& group, int dim, std::size_t n_particles,
                                     const std::vector<double>& box_lo,
                                     const std::vector<double>& box_edges,
                                     const std::vector<bool>& periodic) {
  check_name(path_, "particles group", group);
  const std::string where = "particles group '" + group + "': ";
  if (groups_.count(group) != 0) usage_error(path_, where + "added twice");
  if (dim != 2 && dim != 3)
    usage_error(path_, where + "dim must be 2 or 3, got " + std::to_string(dim));
  if (n_particles == 0) usage_error(path_, where + "needs at least one particle");
  const auto axes = static_cast<std::size_t>(dim);
  if (box_lo.size() != axes || box_edges.size() != axes || periodic.size() != axes)
    usage_error(path_, where + "box_lo, box_edges and periodic need one entry per axis");

  const Group box = require_group(file_.get(), "particles/" + group + "/box");
  write_attribute(box.get(), "dimension", dim);
  std::vector<std::string> boundary;
  for (const bool is_periodic : periodic) boundary.push_back(is_periodic ? "periodic" : "none");
  write_attribute(box.get(), "boundary", boundary);
  write_dataset(box.get(), "edges", H5T_NATIVE_DOUBLE, H5T_NATIVE_DOUBLE, {axes}, box_edges.data());
  write_dataset(box.get(), "offset", H5T_NATIVE_DOUBLE, H5T_NATIVE_DOUBLE, {axes}, box_lo.data());
  groups_[group] = ParticlesGroup{dim, n_particles, {}};
}

void H5mdWriter::append_int(const std::string& group, const std::string& name, std::int64_t step,
                            double time, const int* data, std::size_t n, int dim) {
  append_particles(group, name, step, time, data, native_type<int>(), n, dim);
}

void H5mdWriter::append_particles(const std::string& group, const std::string& name,
                                  std::int64_t step, double time, const void* data, hid_t mem_type,
                                  std::size_t n, int dim) {
  append_frame(particle_series(group, name, mem_type, n, dim), step, time, data);
}

H5mdWriter::Series& H5mdWriter::particle_series(const std::string& group, const std::string& name,
                                                hid_t mem_type, std::size_t n, int dim) {
  const auto found = groups_.find(group);
  if (found == groups_.end())
    usage_error(path_, "particles group '" + group + "' was not added by add_particles_group");
  ParticlesGroup& particles = found->second;
  const std::string element = "/particles/" + group + "/" + name;
  if (n == 0) usage_error(path_, element + ": needs at least one particle");
  // A resumed group that had no element yet takes the particle count of its first append.
  const std::size_t n_particles = particles.n_particles != 0 ? particles.n_particles : n;
  if (n != n_particles)
    usage_error(path_, element + ": " + std::to_string(n) + " particles given, the group has " +
                           std::to_string(n_particles));
  if (dim < 1) usage_error(path_, element + ": dim must be >= 1, got " + std::to_string(dim));
  if (name == "position" && dim != particles.dim)
    usage_error(path_, element + ": positions have the group's " + std::to_string(particles.dim) +
                           " components, got " + std::to_string(dim));

  std::vector<hsize_t> frame_shape{n};
  std::vector<hsize_t> chunk{1, std::min<hsize_t>(n, kMaxParticlesPerChunk)};
  if (dim > 1) {
    frame_shape.push_back(static_cast<hsize_t>(dim));
    chunk.push_back(static_cast<hsize_t>(dim));
  }
  const auto existing = particles.elements.find(name);
  if (existing != particles.elements.end()) {
    const Series& series = existing->second;
    if (series.frame_shape != frame_shape || H5Tequal(series.mem_type, mem_type) <= 0)
      usage_error(path_, element + " holds " + describe_type(series.mem_type) +
                             " frames of shape " + shape_text(series.frame_shape) + ", got " +
                             describe_type(mem_type) + " of shape " + shape_text(frame_shape));
    return existing->second;
  }
  check_name(path_, "element", name);
  if (name == "box") usage_error(path_, element + ": 'box' is the group's box, not an element");
  particles.n_particles = n;
  return particles.elements
      .emplace(name, create_series_group(element, mem_type, frame_shape, chunk))
      .first->second;
}

// ---------------------------------------------------------------------------------------------
// Observables

void H5mdWriter::append_observable(const std::string& name, std::int64_t step, double time,
                                   double value) {
  append_frame(observable_series(name, {}), step, time, &value);
}

void H5mdWriter::append_observable(const std::string& name, std::int64_t step, double time,
                                   const double* values, std::size_t count) {
  if (count == 0) usage_error(path_, "observable '" + name + "': needs at least one value");
  append_frame(observable_series(name, {count}), step, time, values);
}

H5mdWriter::Series& H5mdWriter::observable_series(const std::string& name,
                                                  const std::vector<hsize_t>& frame_shape) {
  const auto existing = observables_.find(name);
  if (existing != observables_.end()) {
    if (existing->second.frame_shape != frame_shape)
      usage_error(path_, "observable '" + name + "' holds frames of shape " +
                             shape_text(existing->second.frame_shape) + ", got " +
                             shape_text(frame_shape));
    return existing->second;
  }
  check_name(path_, "observable", name);
  const hsize_t values_per_frame = frame_shape.empty() ? 1 : frame_shape[0];
  std::vector<hsize_t> chunk{std::max<hsize_t>(1, kValuesPerSeriesChunk / values_per_frame)};
  chunk.insert(chunk.end(), frame_shape.begin(), frame_shape.end());
  return observables_
      .emplace(name,
               create_series_group("/observables/" + name, H5T_NATIVE_DOUBLE, frame_shape, chunk))
      .first->second;
}

// ---------------------------------------------------------------------------------------------
// Time series

H5mdWriter::Series H5mdWriter::create_series_group(const std::string& path, hid_t mem_type,
                                                   const std::vector<hsize_t>& frame_shape,
                                                   const std::vector<hsize_t>& value_chunk) {
  const Group group = require_group(file_.get(), path);
  Series series;
  series.value = create_series(group.get(), "value", mem_type, frame_shape, value_chunk);
  series.step =
      create_series(group.get(), "step", native_type<std::int64_t>(), {}, {kValuesPerSeriesChunk});
  series.time = create_series(group.get(), "time", H5T_NATIVE_DOUBLE, {}, {kValuesPerSeriesChunk});
  series.frame_shape = frame_shape;
  series.mem_type = mem_type;
  return series;
}

void H5mdWriter::append_frame(Series& series, std::int64_t step, double time, const void* data) {
  const hsize_t frame = series.steps.size();
  write_frame(series.value.get(), frame, series.frame_shape, series.mem_type, data);
  write_frame(series.step.get(), frame, {}, native_type<std::int64_t>(), &step);
  write_frame(series.time.get(), frame, {}, H5T_NATIVE_DOUBLE, &time);
  series.steps.push_back(step);
  series.times.push_back(time);
}

void H5mdWriter::flush() {
  check_status(H5Fflush(file_.get(), H5F_SCOPE_LOCAL), file_.get(), "", "flush");
}

// ---------------------------------------------------------------------------------------------
// XDMF sidecar

void H5mdWriter::write_xdmf(const std::string& xdmf_path) {
  flush();
  std::ofstream out(xdmf_path);
  if (!out) throw std::runtime_error("mesoflow::io: cannot create XDMF file '" + xdmf_path + "'");
  const std::string h5_name = xml_escape(relative_to_directory_of(path_, xdmf_path));
  out << "<?xml version=\"1.0\" ?>\n"
      << "<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n"
      << "<Xdmf Version=\"3.0\">\n"
      << "  <Domain>\n";
  for (const auto& [group, particles] : groups_) write_xdmf_group(out, h5_name, group, particles);
  out << "  </Domain>\n"
      << "</Xdmf>\n";
  out.close();
  if (!out) throw std::runtime_error("mesoflow::io: cannot write XDMF file '" + xdmf_path + "'");
}

void H5mdWriter::write_xdmf_group(std::ostream& out, const std::string& h5_name,
                                  const std::string& group, const ParticlesGroup& particles) {
  if (particles.elements.count("position") == 0) return;
  const std::string name = xml_escape(group);
  out << "    <Grid Name=\"" << name << "\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  const std::size_t frames = particles.elements.at("position").steps.size();
  for (std::size_t frame = 0; frame < frames; ++frame)
    write_xdmf_frame(out, h5_name + ":/particles/" + name + "/", name, particles, frame);
  out << "    </Grid>\n";
}

void H5mdWriter::write_xdmf_frame(std::ostream& out, const std::string& prefix,
                                  const std::string& name, const ParticlesGroup& particles,
                                  std::size_t frame) {
  const Series& positions = particles.elements.at("position");
  const std::int64_t step = positions.steps[frame];
  out << "      <Grid Name=\"" << name << "_" << step << "\" GridType=\"Uniform\">\n"
      << "        <Time Value=\"" << format_number(positions.times[frame]) << "\"/>\n"
      << "        <Topology TopologyType=\"Polyvertex\" NumberOfElements=\""
      << particles.n_particles << "\" NodesPerElement=\"1\"/>\n"
      << "        <Geometry GeometryType=\"" << (particles.dim == 3 ? "XYZ" : "XY") << "\">\n";
  write_frame_item(out, "          ", prefix + "position/value", frame, positions.steps.size(),
                   positions.frame_shape, positions.mem_type);
  out << "        </Geometry>\n";

  // Every other element written at the same step becomes a point attribute of this frame.
  for (const auto& [element, series] : particles.elements) {
    const auto match = frame_at_step(series.steps, step, frame);
    if (element == "position" || !match) continue;
    const bool scalar = series.frame_shape.size() == 1;
    out << "        <Attribute Name=\"" << xml_escape(element) << "\" AttributeType=\""
        << (scalar ? "Scalar" : "Vector") << "\" Center=\"Node\">\n";
    write_frame_item(out, "          ", prefix + xml_escape(element) + "/value", *match,
                     series.steps.size(), series.frame_shape, series.mem_type);
    out << "        </Attribute>\n";
  }
  out << "      </Grid>\n";
}

}  // namespace mesoflow::io
