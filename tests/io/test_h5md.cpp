// test_h5md.cpp — H5MD trajectory writer: exact round trip through the HDF5 C API, the H5MD
// layout (chunked, extendable series), error reporting, resuming after a restart, and the XDMF
// sidecar.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "scratch_dir.hpp"
#include "io/h5md_writer.hpp"

namespace {

namespace fs = std::filesystem;
using namespace mesoflow::io;

constexpr std::size_t kParticles = 5;
constexpr std::size_t kFrames = 3;

using ::mesoflow::testing::ScratchDir;

// Message of the `Exception` thrown by `action`; a test failure when none is thrown.
template <class Exception, class Action>
std::string error_message(Action&& action) {
  try {
    action();
  } catch (const Exception& error) {
    return error.what();
  }
  ADD_FAILURE() << "expected an exception";
  return {};
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

std::size_t count_of(const std::string& text, const std::string& part) {
  std::size_t count = 0;
  for (auto at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++count;
  return count;
}

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// ---------------------------------------------------------------------------------------------
// The test trajectory: kFrames frames of kParticles particles in a box periodic except along y.

const std::vector<double> kBoxLo{-1.0, -2.0, -3.0};
const std::vector<double> kBoxEdges{10.0, 20.0, 30.0};
const std::vector<bool> kPeriodic{true, false, true};

template <class T>
std::vector<T> first_axes(const std::vector<T>& values, int dim) {
  return std::vector<T>(values.begin(), values.begin() + dim);
}

// One frame of an element with `dim` components per particle: distinct values that are not exact
// in binary, so that any rounding or conversion on the way would show.
template <class Real>
std::vector<Real> frame_values(std::size_t frame, int dim, Real scale) {
  std::vector<Real> values(kParticles * static_cast<std::size_t>(dim));
  for (std::size_t k = 0; k < values.size(); ++k)
    values[k] = scale * static_cast<Real>(1 + frame * values.size() + k) / Real(3);
  return values;
}

std::vector<int> frame_ids(std::size_t frame) {
  std::vector<int> ids(kParticles);
  for (std::size_t i = 0; i < kParticles; ++i) ids[i] = static_cast<int>(10 * frame + i);
  return ids;
}

std::vector<double> momentum(std::size_t frame, int dim) {
  std::vector<double> values(static_cast<std::size_t>(dim));
  for (std::size_t d = 0; d < values.size(); ++d) values[d] = 0.1 * static_cast<double>(frame + d);
  return values;
}

std::int64_t step_of(std::size_t frame) { return 100 * static_cast<std::int64_t>(frame); }
double time_of(std::size_t frame) { return 0.5 * static_cast<double>(frame); }
double kinetic_energy(std::size_t frame) { return 1.5 * static_cast<double>(frame) + 0.1; }

void set_test_parameters(H5mdWriter& writer) {
  writer.set_parameter("dt", 0.005);
  writer.set_parameter("n_steps", 1000);
  writer.set_parameter("seed", 1234567890123LL);
  writer.set_parameter("thermostat", true);
  writer.set_parameter("integrator", "velocity-verlet");
  writer.set_parameter("scene", std::string("channel"));
}

// Writes the test trajectory: position, velocity (Real, dim components), mass (Real, scalar) and
// id (int) per particle, and the observables kinetic_energy (scalar) and momentum (dim values).
template <class Real>
void write_trajectory(H5mdWriter& writer, int dim) {
  writer.add_particles_group("fluid", dim, kParticles, first_axes(kBoxLo, dim),
                             first_axes(kBoxEdges, dim), first_axes(kPeriodic, dim));
  for (std::size_t frame = 0; frame < kFrames; ++frame) {
    const std::int64_t step = step_of(frame);
    const double time = time_of(frame);
    writer.append("fluid", "position", step, time, frame_values(frame, dim, Real(1)).data(),
                  kParticles, dim);
    writer.append("fluid", "velocity", step, time, frame_values(frame, dim, Real(-7)).data(),
                  kParticles, dim);
    writer.append("fluid", "mass", step, time, frame_values(frame, 1, Real(2)).data(), kParticles,
                  1);
    writer.append_int("fluid", "id", step, time, frame_ids(frame).data(), kParticles, 1);
    writer.append_observable("kinetic_energy", step, time, kinetic_energy(frame));
    writer.append_observable("momentum", step, time, momentum(frame, dim).data(),
                             static_cast<std::size_t>(dim));
  }
}

template <class Real>
void write_trajectory_file(const std::string& path, int dim) {
  H5mdWriter writer(path, "mesoflow", "9.9.9-test", "A. Tester");
  set_test_parameters(writer);
  write_trajectory<Real>(writer, dim);
}

// Expects the series `element` to hold kFrames frames of frame_values(frame, dim, scale), exactly,
// with the test steps and times.
template <class Real>
void expect_particle_element(const std::string& path, const std::string& element, int dim,
                             Real scale) {
  const ArrayData<double> value = read_dataset_double(path, element + "/value");
  std::vector<std::size_t> shape{kFrames, kParticles};
  if (dim > 1) shape.push_back(static_cast<std::size_t>(dim));
  ASSERT_EQ(value.shape, shape) << element;
  const std::size_t frame_size = kParticles * static_cast<std::size_t>(dim);
  for (std::size_t frame = 0; frame < kFrames; ++frame) {
    const std::vector<Real> expected = frame_values(frame, dim, scale);
    for (std::size_t k = 0; k < frame_size; ++k)
      ASSERT_EQ(value.values[frame * frame_size + k], static_cast<double>(expected[k]))
          << element << " frame " << frame << " value " << k;
  }
}

void expect_steps_and_times(const std::string& path, const std::string& element) {
  const ArrayData<std::int64_t> steps = read_dataset_int64(path, element + "/step");
  const ArrayData<double> times = read_dataset_double(path, element + "/time");
  EXPECT_EQ(steps.shape, std::vector<std::size_t>{kFrames}) << element;
  EXPECT_EQ(times.shape, std::vector<std::size_t>{kFrames}) << element;
  for (std::size_t frame = 0; frame < kFrames && frame < steps.values.size(); ++frame) {
    EXPECT_EQ(steps.values[frame], step_of(frame)) << element;
    EXPECT_EQ(times.values[frame], time_of(frame)) << element;
  }
}

// Storage properties of a dataset, read with the plain C API.
struct Storage {
  H5D_layout_t layout = H5D_LAYOUT_ERROR;
  std::vector<hsize_t> chunk;
  std::vector<hsize_t> max_shape;
  H5T_class_t type_class = H5T_NO_CLASS;
  std::size_t type_size = 0;
};

Storage storage_of(const std::string& path, const std::string& dataset_path) {
  const File file = open_file(path, H5F_ACC_RDONLY);
  const Dataset dataset = open_dataset(file.get(), dataset_path);
  const PropertyList dcpl{H5Dget_create_plist(dataset.get())};
  const Dataspace space{H5Dget_space(dataset.get())};
  const Datatype type{H5Dget_type(dataset.get())};
  const int rank = H5Sget_simple_extent_ndims(space.get());
  Storage storage;
  storage.layout = H5Pget_layout(dcpl.get());
  storage.max_shape.resize(static_cast<std::size_t>(rank));
  H5Sget_simple_extent_dims(space.get(), nullptr, storage.max_shape.data());
  if (storage.layout == H5D_CHUNKED) {
    storage.chunk.resize(static_cast<std::size_t>(rank));
    H5Pget_chunk(dcpl.get(), rank, storage.chunk.data());
  }
  storage.type_class = H5Tget_class(type.get());
  storage.type_size = H5Tget_size(type.get());
  return storage;
}

// ---------------------------------------------------------------------------------------------
// Round trip and layout, for float and double data in 2D and 3D

template <class Real, int Dim>
struct Layout {
  using real = Real;
  static constexpr int dim = Dim;
};

using Layouts =
    ::testing::Types<Layout<float, 2>, Layout<float, 3>, Layout<double, 2>, Layout<double, 3>>;

template <class L>
class H5mdRoundTrip : public ::testing::Test {};
TYPED_TEST_SUITE(H5mdRoundTrip, Layouts);

TYPED_TEST(H5mdRoundTrip, ParticleDataReadsBackExactly) {
  using Real = typename TypeParam::real;
  constexpr int dim = TypeParam::dim;
  const ScratchDir scratch;
  const std::string path = scratch.file("traj.h5");
  write_trajectory_file<Real>(path, dim);

  expect_particle_element(path, "/particles/fluid/position", dim, Real(1));
  expect_particle_element(path, "/particles/fluid/velocity", dim, Real(-7));
  expect_particle_element(path, "/particles/fluid/mass", 1, Real(2));
  for (const char* element : {"position", "velocity", "mass", "id"})
    expect_steps_and_times(path, std::string("/particles/fluid/") + element);

  const ArrayData<std::int64_t> ids = read_dataset_int64(path, "/particles/fluid/id/value");
  ASSERT_EQ(ids.shape, (std::vector<std::size_t>{kFrames, kParticles}));
  for (std::size_t frame = 0; frame < kFrames; ++frame)
    for (std::size_t i = 0; i < kParticles; ++i)
      EXPECT_EQ(ids.values[frame * kParticles + i], frame_ids(frame)[i]);
}

TYPED_TEST(H5mdRoundTrip, ObservablesReadBackExactly) {
  constexpr int dim = TypeParam::dim;
  const ScratchDir scratch;
  const std::string path = scratch.file("traj.h5");
  write_trajectory_file<typename TypeParam::real>(path, dim);

  const ArrayData<double> energy = read_dataset_double(path, "/observables/kinetic_energy/value");
  ASSERT_EQ(energy.shape, std::vector<std::size_t>{kFrames});
  const ArrayData<double> p = read_dataset_double(path, "/observables/momentum/value");
  ASSERT_EQ(p.shape, (std::vector<std::size_t>{kFrames, static_cast<std::size_t>(dim)}));
  for (std::size_t frame = 0; frame < kFrames; ++frame) {
    EXPECT_EQ(energy.values[frame], kinetic_energy(frame));
    for (std::size_t d = 0; d < static_cast<std::size_t>(dim); ++d)
      EXPECT_EQ(p.values[frame * dim + d], momentum(frame, dim)[d]);
  }
  expect_steps_and_times(path, "/observables/kinetic_energy");
  expect_steps_and_times(path, "/observables/momentum");
}

TYPED_TEST(H5mdRoundTrip, MetadataAndBoxFollowH5md) {
  constexpr int dim = TypeParam::dim;
  const ScratchDir scratch;
  const std::string path = scratch.file("traj.h5");
  write_trajectory_file<typename TypeParam::real>(path, dim);

  EXPECT_EQ(read_attribute_int64(path, "/h5md", "version"), (std::vector<std::int64_t>{1, 1}));
  EXPECT_EQ(read_attribute_string(path, "/h5md/author", "name"), "A. Tester");
  EXPECT_EQ(read_attribute_string(path, "/h5md/creator", "name"), "mesoflow");
  EXPECT_EQ(read_attribute_string(path, "/h5md/creator", "version"), "9.9.9-test");

  const std::string box = "/particles/fluid/box";
  EXPECT_EQ(read_attribute_int64(path, box, "dimension"), std::vector<std::int64_t>{dim});
  const std::vector<std::string> boundary{"periodic", "none", "periodic"};
  EXPECT_EQ(read_attribute_strings(path, box, "boundary"), first_axes(boundary, dim));
  const ArrayData<double> edges = read_dataset_double(path, box + "/edges");
  const ArrayData<double> offset = read_dataset_double(path, box + "/offset");
  EXPECT_EQ(edges.shape, std::vector<std::size_t>{static_cast<std::size_t>(dim)});
  EXPECT_EQ(edges.values, first_axes(kBoxEdges, dim));
  EXPECT_EQ(offset.values, first_axes(kBoxLo, dim));
}

TYPED_TEST(H5mdRoundTrip, SeriesAreChunkedExtendableAndKeepTheirPrecision) {
  using Real = typename TypeParam::real;
  constexpr auto dim = static_cast<hsize_t>(TypeParam::dim);
  const ScratchDir scratch;
  const std::string path = scratch.file("traj.h5");
  write_trajectory_file<Real>(path, TypeParam::dim);

  const Storage position = storage_of(path, "/particles/fluid/position/value");
  EXPECT_EQ(position.layout, H5D_CHUNKED);
  EXPECT_EQ(position.chunk, (std::vector<hsize_t>{1, kParticles, dim}));
  EXPECT_EQ(position.max_shape, (std::vector<hsize_t>{H5S_UNLIMITED, kParticles, dim}));
  EXPECT_EQ(position.type_class, H5T_FLOAT);
  EXPECT_EQ(position.type_size, sizeof(Real));

  const Storage mass = storage_of(path, "/particles/fluid/mass/value");
  EXPECT_EQ(mass.max_shape, (std::vector<hsize_t>{H5S_UNLIMITED, kParticles}));
  EXPECT_EQ(mass.type_size, sizeof(Real));
  const Storage ids = storage_of(path, "/particles/fluid/id/value");
  EXPECT_EQ(ids.type_class, H5T_INTEGER);
  EXPECT_EQ(ids.type_size, sizeof(int));

  for (const char* series : {"/particles/fluid/position/step", "/particles/fluid/position/time",
                             "/observables/kinetic_energy/value", "/observables/momentum/value"}) {
    const Storage storage = storage_of(path, series);
    EXPECT_EQ(storage.layout, H5D_CHUNKED) << series;
    EXPECT_EQ(storage.max_shape.at(0), H5S_UNLIMITED) << series;
  }
  const Storage step = storage_of(path, "/particles/fluid/position/step");
  EXPECT_EQ(step.type_class, H5T_INTEGER);
  EXPECT_EQ(step.type_size, 8u);
}

// ---------------------------------------------------------------------------------------------
// Parameters, external tools, errors

TEST(H5mdWriter, ParametersAreAttributesOfTheParametersGroup) {
  const ScratchDir scratch;
  const std::string path = scratch.file("params.h5");
  {
    H5mdWriter writer(path);
    set_test_parameters(writer);
    writer.set_parameter("dt", 0.01);  // replaces the first value
  }
  EXPECT_EQ(read_attribute_double(path, "/parameters", "dt"), std::vector<double>{0.01});
  EXPECT_EQ(read_attribute_int64(path, "/parameters", "n_steps"), std::vector<std::int64_t>{1000});
  EXPECT_EQ(read_attribute_int64(path, "/parameters", "seed"),
            std::vector<std::int64_t>{1234567890123LL});
  EXPECT_TRUE(read_attribute_bool(path, "/parameters", "thermostat"));
  EXPECT_EQ(read_attribute_string(path, "/parameters", "integrator"), "velocity-verlet");
  EXPECT_EQ(read_attribute_string(path, "/parameters", "scene"), "channel");
  EXPECT_EQ(read_attribute_string(path, "/h5md/creator", "version"), MESOFLOW_VERSION);
}

// An independent reader, HDF5's own h5dump, opens the file and sees the H5MD layout. h5dump is part
// of the required tools (hdf5-tools, installed by scripts/bootstrap): without it this test fails.
TEST(H5mdWriter, H5dumpReadsTheFile) {
  const ScratchDir scratch;
  const std::string path = scratch.file("traj.h5");
  write_trajectory_file<double>(path, 3);
  ASSERT_EQ(std::system("command -v h5dump > /dev/null 2>&1"), 0)
      << "h5dump is not on PATH: install hdf5-tools (scripts/bootstrap does) to run this check";
  FILE* pipe = popen(("h5dump -H '" + path + "' 2>&1").c_str(), "r");
  ASSERT_NE(pipe, nullptr) << "cannot run h5dump";
  std::string header;
  char buffer[4096];
  for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;) header.append(buffer, n);
  const int status = pclose(pipe);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "h5dump -H failed:\n" << header;
  for (const char* object : {"GROUP \"h5md\"", "GROUP \"particles\"", "GROUP \"fluid\"", "GROUP \"position\"",
                             "GROUP \"observables\"", "GROUP \"kinetic_energy\"", "DATASET \"value\"",
                             "DATASET \"step\"", "DATASET \"time\"", "H5T_IEEE_F64LE"})
    EXPECT_NE(header.find(object), std::string::npos) << "h5dump -H shows no " << object << ":\n" << header;
}

TEST(H5mdWriter, FlushMakesFramesVisibleWhileWriting) {
  const ScratchDir scratch;
  const std::string path = scratch.file("traj.h5");
  H5mdWriter writer(path);
  writer.add_particles_group("fluid", 2, kParticles, {0, 0}, {1, 1}, {true, true});
  writer.append("fluid", "position", 0, 0.0, frame_values(0, 2, 1.0).data(), kParticles, 2);
  writer.flush();
  EXPECT_EQ(writer.path(), path);
  // Reading needs the writer's file lock released, so check the flushed copy.
  fs::copy_file(path, scratch.file("copy.h5"));
  EXPECT_EQ(read_dataset_double(scratch.file("copy.h5"), "/particles/fluid/position/value").shape,
            (std::vector<std::size_t>{1, kParticles, 2}));
}

TEST(H5mdWriter, UnwritablePathThrowsNamingIt) {
  const std::string path = "/nonexistent-dir/x.h5";
  const std::string message = error_message<std::runtime_error>([&] { H5mdWriter writer(path); });
  EXPECT_TRUE(contains(message, path)) << message;
}

TEST(H5mdWriter, ReaderErrorsNameFileAndObjectWithoutPrintingTheHdf5Stack) {
  const ScratchDir scratch;
  const std::string path = scratch.file("traj.h5");
  write_trajectory_file<double>(path, 3);
  ::testing::internal::CaptureStderr();
  const std::string message = error_message<std::runtime_error>(
      [&] { read_dataset_double(path, "/particles/fluid/charge/value"); });
  const std::string printed = ::testing::internal::GetCapturedStderr();
  EXPECT_TRUE(contains(message, path)) << message;
  EXPECT_TRUE(contains(message, "/particles/fluid/charge/value")) << message;
  EXPECT_EQ(printed, "");
}

TEST(H5mdWriter, RejectsInconsistentAppends) {
  const ScratchDir scratch;
  const std::string path = scratch.file("traj.h5");
  H5mdWriter writer(path);
  writer.add_particles_group("fluid", 3, kParticles, {0, 0, 0}, {1, 1, 1}, {true, true, true});
  const std::vector<double> data = frame_values(0, 3, 1.0);
  const std::vector<float> data_float = frame_values(0, 3, 1.0f);
  writer.append("fluid", "velocity", 0, 0.0, data.data(), kParticles, 3);

  const auto rejected = [&](auto&& append) {
    const std::string message = error_message<std::invalid_argument>(append);
    EXPECT_TRUE(contains(message, path)) << message;
  };
  rejected([&] { writer.append("walls", "position", 0, 0.0, data.data(), kParticles, 3); });
  rejected([&] { writer.append("fluid", "position", 0, 0.0, data.data(), kParticles - 1, 3); });
  rejected([&] { writer.append("fluid", "position", 0, 0.0, data.data(), kParticles, 2); });
  rejected([&] { writer.append("fluid", "velocity", 1, 0.1, data_float.data(), kParticles, 3); });
  rejected([&] { writer.append("fluid", "velocity", 1, 0.1, data.data(), kParticles, 1); });
  rejected([&] { writer.append("fluid", "box", 1, 0.1, data.data(), kParticles, 3); });
  rejected([&] {
    writer.add_particles_group("fluid", 3, kParticles, {0, 0, 0}, {1, 1, 1}, {true, true, true});
  });
  rejected([&] { writer.add_particles_group("rods", 3, kParticles, {0, 0}, {1, 1}, {true}); });
  writer.append_observable("energy", 0, 0.0, 1.0);
  rejected([&] { writer.append_observable("energy", 1, 0.1, data.data(), 3); });
}

TEST(H5mdWriter, LeavesNoHdf5IdentifierOpen) {
  const ScratchDir scratch;
  const std::string path = scratch.file("traj.h5");
  {
    H5mdWriter writer(path);
    write_trajectory<float>(writer, 3);
    writer.write_xdmf(scratch.file("traj.xdmf"));
    const std::vector<double> wrong(15);
    EXPECT_THROW(writer.append("fluid", "position", 9, 0.9, wrong.data(), kParticles, 3),
                 std::invalid_argument);
  }
  read_dataset_double(path, "/particles/fluid/position/value");
  read_attribute_strings(path, "/particles/fluid/box", "boundary");
  EXPECT_THROW(read_dataset_double(path, "/missing"), std::runtime_error);
  EXPECT_THROW(read_attribute_string(path, "/h5md", "version"), std::runtime_error);
  EXPECT_EQ(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL), 0);
}

// ---------------------------------------------------------------------------------------------
// Restarts: a run writes particle frames every kFrameInterval steps and observables every
// kObservableInterval steps up to kLastStep; a restarted run resumes its file at a checkpoint.

constexpr std::int64_t kFrameInterval = 10;
constexpr std::int64_t kObservableInterval = 5;
constexpr std::int64_t kLastStep = 100;

double time_at(std::int64_t step) { return 0.005 * static_cast<double>(step); }

// Appends the outputs of steps first_step..last_step, whose data depend on the step only, in the
// order a run writes them.
template <class Real>
void write_steps(H5mdWriter& writer, int dim, std::int64_t first_step, std::int64_t last_step) {
  for (std::int64_t step = first_step; step <= last_step; ++step) {
    const double time = time_at(step);
    if (step % kFrameInterval == 0) {
      const auto frame = static_cast<std::size_t>(step / kFrameInterval);
      writer.append("fluid", "position", step, time, frame_values(frame, dim, Real(1)).data(),
                    kParticles, dim);
      writer.append("fluid", "velocity", step, time, frame_values(frame, dim, Real(-7)).data(),
                    kParticles, dim);
      writer.append("fluid", "mass", step, time, frame_values(frame, 1, Real(2)).data(), kParticles,
                    1);
      writer.append_int("fluid", "id", step, time, frame_ids(frame).data(), kParticles, 1);
    }
    if (step % kObservableInterval == 0) {
      const auto frame = static_cast<std::size_t>(step / kObservableInterval);
      writer.append_observable("kinetic_energy", step, time, kinetic_energy(frame));
      writer.append_observable("momentum", step, time, momentum(frame, dim).data(),
                               static_cast<std::size_t>(dim));
    }
  }
}

// A run started in a new file `path` that has written its outputs up to `last_step`.
template <class Real>
void start_run(const std::string& path, int dim, std::int64_t last_step) {
  H5mdWriter writer(path, "mesoflow", "9.9.9-test", "A. Tester");
  set_test_parameters(writer);
  writer.add_particles_group("fluid", dim, kParticles, first_axes(kBoxLo, dim),
                             first_axes(kBoxEdges, dim), first_axes(kPeriodic, dim));
  write_steps<Real>(writer, dim, 0, last_step);
}

// The run restarted from its checkpoint at `checkpoint_step`, continued to kLastStep.
template <class Real>
void resume_run(const std::string& path, int dim, std::int64_t checkpoint_step) {
  H5mdWriter writer = H5mdWriter::resume(path, checkpoint_step);
  write_steps<Real>(writer, dim, checkpoint_step + 1, kLastStep);
}

std::vector<std::int64_t> steps_from(std::int64_t first, std::int64_t last, std::int64_t every) {
  std::vector<std::int64_t> steps;
  for (std::int64_t step = first; step <= last; step += every) steps.push_back(step);
  return steps;
}

// Everything a file holds, by path: "/particles/fluid/position/value" for a group or dataset,
// "/parameters@dt" for an attribute. A dataset or attribute maps to its type, its shape and its
// values (the bytes of its native type, or its strings); a group to "group".
using Content = std::map<std::string, std::string>;

std::string values_of(hid_t dataset_or_attribute) {
  const hid_t obj = dataset_or_attribute;
  const bool is_attribute = H5Iget_type(obj) == H5I_ATTR;
  const Datatype stored{is_attribute ? H5Aget_type(obj) : H5Dget_type(obj)};
  const Dataspace space{is_attribute ? H5Aget_space(obj) : H5Dget_space(obj)};
  std::vector<hsize_t> shape(static_cast<std::size_t>(H5Sget_simple_extent_ndims(space.get())));
  H5Sget_simple_extent_dims(space.get(), shape.data(), nullptr);
  std::string text = describe_type(stored.get()) + " (" +
                     std::to_string(H5Tget_size(stored.get())) + " bytes) shape";
  for (const hsize_t extent : shape) text += " " + std::to_string(extent);
  text += ": ";
  if (H5Tget_class(stored.get()) == H5T_STRING) {
    for (const std::string& value : read_strings(obj)) text += value + '\0';
    return text;
  }
  const Datatype native{H5Tget_native_type(stored.get(), H5T_DIR_DEFAULT)};
  std::vector<char> bytes(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space.get())) *
                          H5Tget_size(native.get()));
  if (!bytes.empty()) {
    const herr_t status =
        is_attribute ? H5Aread(obj, native.get(), bytes.data())
                     : H5Dread(obj, native.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, bytes.data());
    EXPECT_GE(status, 0);
  }
  return text + std::string(bytes.begin(), bytes.end());
}

void collect_attributes(hid_t obj, const std::string& path, Content& content) {
  struct Target {
    const std::string& path;
    Content& content;
  } target{path, content};
  const H5A_operator2_t add = [](hid_t loc, const char* name, const H5A_info_t*, void* data) {
    auto& into = *static_cast<Target*>(data);
    const Attribute attribute{H5Aopen(loc, name, H5P_DEFAULT)};
    into.content[into.path + "@" + name] = values_of(attribute.get());
    return herr_t{0};
  };
  EXPECT_GE(H5Aiterate2(obj, H5_INDEX_NAME, H5_ITER_INC, nullptr, add, &target), 0) << path;
}

void collect_group(hid_t group, const std::string& path, Content& content) {
  collect_attributes(group, path.empty() ? "/" : path, content);
  for (const std::string& name : link_names(group)) {
    const std::string child = path + "/" + name;
    const H5I_type_t type = object_type(group, name);
    if (type == H5I_GROUP) {
      content[child] = "group";
      collect_group(open_group(group, name).get(), child, content);
    } else if (type == H5I_DATASET) {
      const Dataset dataset = open_dataset(group, name);
      content[child] = values_of(dataset.get());
      collect_attributes(dataset.get(), child, content);
    } else {
      content[child] = "neither group nor dataset";
    }
  }
}

Content file_content(const std::string& path) {
  const File file = open_file(path, H5F_ACC_RDONLY);
  Content content;
  collect_group(file.get(), "", content);
  return content;
}

// Expects the files to hold the same groups, datasets and attributes, with the same types, shapes
// and values, bit for bit.
void expect_same_content(const std::string& expected_path, const std::string& actual_path) {
  const Content expected = file_content(expected_path);
  const Content actual = file_content(actual_path);
  std::vector<std::string> expected_paths, actual_paths;
  for (const auto& entry : expected) expected_paths.push_back(entry.first);
  for (const auto& entry : actual) actual_paths.push_back(entry.first);
  EXPECT_EQ(actual_paths, expected_paths);
  for (const auto& [path, value] : expected) {
    const auto found = actual.find(path);
    if (found != actual.end()) {
      EXPECT_TRUE(found->second == value) << path << " differs";
    }
  }
}

template <class L>
class H5mdResume : public ::testing::Test {};
TYPED_TEST_SUITE(H5mdResume, Layouts);

TYPED_TEST(H5mdResume, ContinuesAsAnUninterruptedRun) {
  using Real = typename TypeParam::real;
  constexpr int dim = TypeParam::dim;
  const ScratchDir scratch;
  const std::string uninterrupted = scratch.file("uninterrupted.h5");
  const std::string restarted = scratch.file("restarted.h5");
  start_run<Real>(uninterrupted, dim, kLastStep);
  // Checkpoint at step 50, killed after the outputs of step 80.
  start_run<Real>(restarted, dim, 80);
  resume_run<Real>(restarted, dim, 50);

  const Content content = file_content(uninterrupted);
  for (const char* dataset : {"/particles/fluid/position/value", "/particles/fluid/id/time",
                              "/observables/momentum/step", "/parameters@dt"})
    EXPECT_EQ(content.count(dataset), 1u) << dataset;
  expect_same_content(uninterrupted, restarted);
  EXPECT_EQ(read_dataset_int64(restarted, "/particles/fluid/velocity/step").values,
            steps_from(0, kLastStep, kFrameInterval));
  EXPECT_EQ(read_dataset_int64(restarted, "/observables/momentum/step").values,
            steps_from(0, kLastStep, kObservableInterval));
}

TYPED_TEST(H5mdResume, CutsEverySeriesBackToTheCheckpoint) {
  using Real = typename TypeParam::real;
  constexpr int dim = TypeParam::dim;
  const ScratchDir scratch;
  const std::string stopped = scratch.file("stopped.h5");
  const std::string cut = scratch.file("cut.h5");
  start_run<Real>(stopped, dim, 55);
  start_run<Real>(cut, dim, kLastStep);
  H5mdWriter::resume(cut, 55);

  expect_same_content(stopped, cut);
  std::vector<std::size_t> position_shape{6, kParticles, static_cast<std::size_t>(dim)};
  EXPECT_EQ(read_dataset_double(cut, "/particles/fluid/position/value").shape, position_shape);
  EXPECT_EQ(read_dataset_double(cut, "/particles/fluid/mass/time").shape,
            std::vector<std::size_t>{6});
  EXPECT_EQ(read_dataset_int64(cut, "/observables/kinetic_energy/step").values,
            steps_from(0, 55, kObservableInterval));
}

TEST(H5mdResume, BeforeTheFirstFrameLeavesEmptySeriesThatGrowAgain) {
  const ScratchDir scratch;
  const std::string uninterrupted = scratch.file("uninterrupted.h5");
  const std::string restarted = scratch.file("restarted.h5");
  start_run<double>(uninterrupted, 3, kLastStep);
  start_run<double>(restarted, 3, 30);
  {
    H5mdWriter writer = H5mdWriter::resume(restarted, -1);
    writer.write_xdmf(scratch.file("restarted.xdmf"));
  }
  EXPECT_EQ(read_dataset_double(restarted, "/particles/fluid/position/value").shape,
            (std::vector<std::size_t>{0, kParticles, 3}));
  EXPECT_EQ(read_dataset_int64(restarted, "/particles/fluid/id/value").shape,
            (std::vector<std::size_t>{0, kParticles}));
  EXPECT_EQ(read_dataset_double(restarted, "/observables/momentum/value").shape,
            (std::vector<std::size_t>{0, 3}));
  EXPECT_EQ(read_dataset_int64(restarted, "/observables/momentum/step").shape,
            std::vector<std::size_t>{0});
  EXPECT_EQ(count_of(read_text(scratch.file("restarted.xdmf")), "GridType=\"Uniform\""), 0u);

  resume_run<double>(restarted, 3, -1);
  expect_same_content(uninterrupted, restarted);
}

TEST(H5mdResume, GroupWithoutElementsTakesTheParticleCountOfItsFirstAppend) {
  const ScratchDir scratch;
  const std::string uninterrupted = scratch.file("uninterrupted.h5");
  const std::string restarted = scratch.file("restarted.h5");
  start_run<float>(uninterrupted, 2, kLastStep);
  start_run<float>(restarted, 2, -1);
  resume_run<float>(restarted, 2, -1);
  expect_same_content(uninterrupted, restarted);

  H5mdWriter writer = H5mdWriter::resume(restarted, -1);
  const std::vector<float> data = frame_values(0, 2, 1.0f);
  writer.append("fluid", "position", 0, 0.0, data.data(), kParticles, 2);
  EXPECT_THROW(writer.append("fluid", "mass", 0, 0.0, data.data(), kParticles + 1, 1),
               std::invalid_argument);
}

TEST(H5mdResume, ContinuesAFileLeftOpenByAKilledRun) {
  const ScratchDir scratch;
  const std::string uninterrupted = scratch.file("uninterrupted.h5");
  const std::string restarted = scratch.file("restarted.h5");
  start_run<double>(uninterrupted, 3, kLastStep);
  // The killed run flushes its frames on output steps and dies without closing the file.
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    try {
      H5mdWriter writer(restarted, "mesoflow", "9.9.9-test", "A. Tester");
      set_test_parameters(writer);
      writer.add_particles_group("fluid", 3, kParticles, kBoxLo, kBoxEdges, kPeriodic);
      write_steps<double>(writer, 3, 0, 80);
      writer.flush();
      std::_Exit(0);
    } catch (...) {
      std::_Exit(1);
    }
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);

  resume_run<double>(restarted, 3, 50);
  expect_same_content(uninterrupted, restarted);
}

TEST(H5mdResume, DropsAFrameWrittenOnlyInPart) {
  const ScratchDir scratch;
  const std::string complete = scratch.file("complete.h5");
  const std::string torn = scratch.file("torn.h5");
  start_run<double>(complete, 3, 40);
  start_run<double>(torn, 3, 40);
  {
    // Killed in mid-append: the value and step of a frame at step 50 written, not its time.
    const File file = open_file(torn, H5F_ACC_RDWR);
    const Dataset value = open_dataset(file.get(), "/particles/fluid/velocity/value");
    const Dataset step = open_dataset(file.get(), "/particles/fluid/velocity/step");
    const std::int64_t step_50 = 50;
    write_frame(value.get(), 5, {kParticles, 3}, H5T_NATIVE_DOUBLE,
                frame_values(5, 3, -7.0).data());
    write_frame(step.get(), 5, {}, native_type<std::int64_t>(), &step_50);
  }
  resume_run<double>(torn, 3, kLastStep);
  resume_run<double>(complete, 3, kLastStep);
  expect_same_content(complete, torn);
  EXPECT_EQ(read_dataset_int64(torn, "/particles/fluid/velocity/step").values,
            steps_from(0, 40, kFrameInterval));
}

TEST(H5mdResume, KeepsParametersAndReplacesThoseSetAgain) {
  const ScratchDir scratch;
  const std::string path = scratch.file("traj.h5");
  start_run<double>(path, 3, 50);
  {
    H5mdWriter writer = H5mdWriter::resume(path, 50);
    EXPECT_EQ(writer.path(), path);
    writer.set_parameter("dt", 0.01);
    writer.set_parameter("restarted_at", 50);
  }
  EXPECT_EQ(read_attribute_double(path, "/parameters", "dt"), std::vector<double>{0.01});
  EXPECT_EQ(read_attribute_int64(path, "/parameters", "restarted_at"),
            std::vector<std::int64_t>{50});
  EXPECT_EQ(read_attribute_int64(path, "/parameters", "n_steps"), std::vector<std::int64_t>{1000});
  EXPECT_EQ(read_attribute_string(path, "/parameters", "integrator"), "velocity-verlet");
  EXPECT_EQ(read_attribute_string(path, "/h5md/author", "name"), "A. Tester");
  EXPECT_EQ(read_attribute_string(path, "/h5md/creator", "version"), "9.9.9-test");
}

TEST(H5mdResume, RejectsInconsistentAppendsAsAFreshWriterDoes) {
  const ScratchDir scratch;
  const std::string path = scratch.file("traj.h5");
  start_run<float>(path, 3, 50);
  H5mdWriter writer = H5mdWriter::resume(path, 50);
  const std::vector<double> data = frame_values(6, 3, 1.0);
  const std::vector<float> data_float = frame_values(6, 3, 1.0f);
  EXPECT_THROW(writer.append("fluid", "velocity", 60, 0.3, data.data(), kParticles, 3),
               std::invalid_argument);
  EXPECT_THROW(writer.append("fluid", "position", 60, 0.3, data_float.data(), kParticles - 1, 3),
               std::invalid_argument);
  EXPECT_THROW(writer.append("fluid", "mass", 60, 0.3, data_float.data(), kParticles, 3),
               std::invalid_argument);
  EXPECT_THROW(writer.append_int("fluid", "id", 60, 0.3, frame_ids(6).data(), kParticles, 2),
               std::invalid_argument);
  EXPECT_THROW(writer.append_observable("kinetic_energy", 60, 0.3, data.data(), 3),
               std::invalid_argument);
  EXPECT_THROW(writer.append_observable("momentum", 60, 0.3, 1.0), std::invalid_argument);
  EXPECT_THROW(writer.add_particles_group("fluid", 3, kParticles, kBoxLo, kBoxEdges, kPeriodic),
               std::invalid_argument);
  writer.append("fluid", "position", 60, 0.3, data_float.data(), kParticles, 3);
}

TEST(H5mdResume, MissingFileThrowsNamingIt) {
  const ScratchDir scratch;
  const std::string path = scratch.file("missing.h5");
  const std::string message =
      error_message<std::runtime_error>([&] { H5mdWriter::resume(path, 0); });
  EXPECT_TRUE(contains(message, path)) << message;
  EXPECT_FALSE(fs::exists(path));
}

TEST(H5mdResume, FileNotWrittenByTheWriterThrowsNamingIt) {
  const ScratchDir scratch;
  const std::string text = scratch.file("text.h5");
  std::ofstream(text) << "not HDF5\n";
  const std::string plain = scratch.file("plain.h5");
  create_file(plain);
  const std::string broken = scratch.file("broken.h5");
  start_run<double>(broken, 3, 20);
  {
    const File file = open_file(broken, H5F_ACC_RDWR);
    ASSERT_GE(H5Ldelete(file.get(), "/observables/momentum/time", H5P_DEFAULT), 0);
  }

  for (const std::string& path : {text, plain, broken}) {
    const std::string message =
        error_message<std::runtime_error>([&] { H5mdWriter::resume(path, 10); });
    EXPECT_TRUE(contains(message, path)) << message;
  }
  EXPECT_TRUE(contains(error_message<std::runtime_error>([&] { H5mdWriter::resume(broken, 10); }),
                       "/observables/momentum"));
  EXPECT_EQ(read_dataset_int64(broken, "/particles/fluid/position/step").shape,
            std::vector<std::size_t>{3});
  EXPECT_EQ(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL), 0);
}

TEST(H5mdResume, FileOpenElsewhereThrowsNamingIt) {
  const ScratchDir scratch;
  const std::string path = scratch.file("traj.h5");
  start_run<double>(path, 3, 50);
  const auto expect_refused = [&](const std::string& reason) {
    const std::string message =
        error_message<std::runtime_error>([&] { H5mdWriter::resume(path, 50); });
    EXPECT_TRUE(contains(message, path)) << message;
    EXPECT_TRUE(contains(message, reason)) << message;
  };
  {
    H5mdWriter writer = H5mdWriter::resume(path, 50);
    expect_refused("open already in this process");
    write_steps<double>(writer, 3, 51, 60);
  }
  {
    const File reader = open_file(path, H5F_ACC_RDONLY);
    expect_refused("already open for read-only");
  }

  // Another process holding the file: HDF5's file lock refuses it.
  int holding[2], release[2];
  ASSERT_EQ(::pipe(holding), 0);
  ASSERT_EQ(::pipe(release), 0);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    const File file = try_open_file(path, H5F_ACC_RDWR);
    const char held = file.valid() ? 'y' : 'n';
    char done = 0;
    const bool ok = ::write(holding[1], &held, 1) == 1 && ::read(release[0], &done, 1) == 1;
    std::_Exit(ok ? 0 : 1);
  }
  char held = 0;
  ASSERT_EQ(::read(holding[0], &held, 1), 1);
  EXPECT_EQ(held, 'y');
  expect_refused("lock");
  const char done = 'x';
  EXPECT_EQ(::write(release[1], &done, 1), 1);
  int status = 0;
  EXPECT_EQ(::waitpid(child, &status, 0), child);
  for (const int fd : {holding[0], holding[1], release[0], release[1]}) ::close(fd);

  EXPECT_EQ(read_dataset_int64(path, "/particles/fluid/position/step").values,
            steps_from(0, 60, kFrameInterval));
}

// ---------------------------------------------------------------------------------------------
// XDMF sidecar

TEST(XdmfSidecar, HasOneGridPerFrameSlicingTheH5File) {
  const ScratchDir scratch;
  const std::string h5 = scratch.file("traj.h5");
  const std::string xdmf = scratch.file("traj.xdmf");
  {
    H5mdWriter writer(h5);
    write_trajectory<double>(writer, 3);
    writer.write_xdmf(xdmf);
  }
  ASSERT_TRUE(fs::exists(xdmf));
  const std::string text = read_text(xdmf);

  EXPECT_TRUE(contains(text, "<Xdmf Version=\"3.0\">"));
  EXPECT_EQ(count_of(text, "GridType=\"Collection\" CollectionType=\"Temporal\""), 1u);
  EXPECT_EQ(count_of(text, "GridType=\"Uniform\""), kFrames);
  EXPECT_EQ(count_of(text, "TopologyType=\"Polyvertex\" NumberOfElements=\"5\""), kFrames);
  EXPECT_EQ(count_of(text, "GeometryType=\"XYZ\""), kFrames);
  for (const char* time : {"<Time Value=\"0\"/>", "<Time Value=\"0.5\"/>", "<Time Value=\"1\"/>"})
    EXPECT_EQ(count_of(text, time), 1u) << time;

  // The h5 file is named relative to the sidecar, not by its absolute path.
  EXPECT_EQ(count_of(text, ">traj.h5:/particles/fluid/position/value<"), kFrames);
  EXPECT_FALSE(contains(text, h5));

  // Each frame selects (1, N, D) or (1, N) values starting at frame t of the (T, N, D) dataset.
  EXPECT_EQ(count_of(text, "ItemType=\"HyperSlab\" Dimensions=\"1 5 3\""), 2 * kFrames);
  EXPECT_EQ(count_of(text, "ItemType=\"HyperSlab\" Dimensions=\"1 5\""), 2 * kFrames);
  for (std::size_t frame = 0; frame < kFrames; ++frame) {
    const std::string t = std::to_string(frame);
    EXPECT_EQ(count_of(text, ">" + t + " 0 0  1 1 1  1 5 3<"), 2u) << "frame " << t;
    EXPECT_EQ(count_of(text, ">" + t + " 0  1 1  1 5<"), 2u) << "frame " << t;
  }
  EXPECT_EQ(count_of(text, "Dimensions=\"3 5 3\" NumberType=\"Float\" Precision=\"8\""),
            2 * kFrames);
  EXPECT_EQ(count_of(text, "Dimensions=\"3 5\" NumberType=\"Int\" Precision=\"4\""), kFrames);
  EXPECT_EQ(count_of(text, "Name=\"velocity\" AttributeType=\"Vector\""), kFrames);
  EXPECT_EQ(count_of(text, "Name=\"mass\" AttributeType=\"Scalar\""), kFrames);
  EXPECT_EQ(count_of(text, "Name=\"id\" AttributeType=\"Scalar\""), kFrames);
}

TEST(XdmfSidecar, TwoDimensionalFloatGeometry) {
  const ScratchDir scratch;
  {
    H5mdWriter writer(scratch.file("traj.h5"));
    write_trajectory<float>(writer, 2);
    writer.write_xdmf(scratch.file("traj.xdmf"));
  }
  const std::string text = read_text(scratch.file("traj.xdmf"));
  EXPECT_EQ(count_of(text, "GeometryType=\"XY\""), kFrames);
  EXPECT_EQ(count_of(text, "ItemType=\"HyperSlab\" Dimensions=\"1 5 2\""), 2 * kFrames);
  EXPECT_EQ(count_of(text, "Dimensions=\"3 5 2\" NumberType=\"Float\" Precision=\"4\""),
            2 * kFrames);
}

TEST(XdmfSidecar, AttributesAppearOnlyAtStepsTheyWereWritten) {
  const ScratchDir scratch;
  {
    H5mdWriter writer(scratch.file("traj.h5"));
    writer.add_particles_group("fluid", 2, kParticles, {0, 0}, {1, 1}, {true, true});
    for (std::size_t frame = 0; frame < kFrames; ++frame) {
      const std::vector<double> values = frame_values(frame, 2, 1.0);
      writer.append("fluid", "position", step_of(frame), time_of(frame), values.data(), kParticles,
                    2);
      if (frame != 1)
        writer.append("fluid", "velocity", step_of(frame), time_of(frame), values.data(),
                      kParticles, 2);
    }
    writer.write_xdmf(scratch.file("traj.xdmf"));
  }
  const std::string text = read_text(scratch.file("traj.xdmf"));
  EXPECT_EQ(count_of(text, "GridType=\"Uniform\""), kFrames);
  EXPECT_EQ(count_of(text, "Name=\"velocity\""), 2u);
  // Position frame 2 pairs with velocity frame 1 (same step); velocity has no frame 2.
  EXPECT_EQ(count_of(text, ">0 0 0  1 1 1  1 5 2<"), 2u);
  EXPECT_EQ(count_of(text, ">1 0 0  1 1 1  1 5 2<"), 2u);
  EXPECT_EQ(count_of(text, ">2 0 0  1 1 1  1 5 2<"), 1u);
}

TEST(XdmfSidecar, NamesTheH5FileRelativeToTheSidecar) {
  const ScratchDir scratch;
  fs::create_directories(scratch.file("view"));
  {
    H5mdWriter writer(scratch.file("traj.h5"));
    write_trajectory<double>(writer, 3);
    writer.write_xdmf(scratch.file("view/traj.xdmf"));
  }
  const std::string text = read_text(scratch.file("view/traj.xdmf"));
  EXPECT_EQ(count_of(text, ">../traj.h5:/particles/fluid/position/value<"), kFrames);
}

TEST(XdmfSidecar, ListsTheKeptAndTheNewFramesAfterResume) {
  const ScratchDir scratch;
  fs::create_directories(scratch.file("uninterrupted"));
  fs::create_directories(scratch.file("restarted"));
  {
    start_run<double>(scratch.file("uninterrupted/traj.h5"), 3, kLastStep);
    H5mdWriter writer = H5mdWriter::resume(scratch.file("uninterrupted/traj.h5"), kLastStep);
    writer.write_xdmf(scratch.file("uninterrupted/traj.xdmf"));
  }
  const std::string restarted = scratch.file("restarted/traj.xdmf");
  start_run<double>(scratch.file("restarted/traj.h5"), 3, 80);
  H5mdWriter writer = H5mdWriter::resume(scratch.file("restarted/traj.h5"), 50);
  writer.write_xdmf(restarted);
  EXPECT_EQ(count_of(read_text(restarted), "GridType=\"Uniform\""), 6u);
  EXPECT_EQ(count_of(read_text(restarted), "Dimensions=\"6 5 3\" NumberType=\"Float\""), 12u);

  write_steps<double>(writer, 3, 51, kLastStep);
  writer.write_xdmf(restarted);
  const std::string text = read_text(restarted);
  EXPECT_EQ(count_of(text, "GridType=\"Uniform\""), 11u);
  EXPECT_EQ(count_of(text, "<Time Value=\"0.5\"/>"), 1u);
  EXPECT_EQ(text, read_text(scratch.file("uninterrupted/traj.xdmf")));
}

TEST(XdmfSidecar, UnwritablePathThrowsNamingIt) {
  const ScratchDir scratch;
  H5mdWriter writer(scratch.file("traj.h5"));
  const std::string xdmf = "/nonexistent-dir/traj.xdmf";
  const std::string message = error_message<std::runtime_error>([&] { writer.write_xdmf(xdmf); });
  EXPECT_TRUE(contains(message, xdmf)) << message;
}

}  // namespace
