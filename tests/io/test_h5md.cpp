// test_h5md.cpp — H5MD trajectory writer: exact round trip through the HDF5 C API, the H5MD
// layout (chunked, extendable series), error reporting, and the XDMF sidecar.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cctype>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "kernels/io/h5md_writer.hpp"

namespace {

namespace fs = std::filesystem;
using namespace mesoflow::io;

constexpr std::size_t kParticles = 5;
constexpr std::size_t kFrames = 3;

// A fresh directory for one test under the system temporary directory, removed afterwards.
class ScratchDir {
 public:
  ScratchDir() {
    const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = std::string(test->test_suite_name()) + "." + test->name();
    for (char& c : name)
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.') c = '_';
    path_ = fs::temp_directory_path() / ("mesoflow-" + name + "-" + std::to_string(::getpid()));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  fs::path path_;
};

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

TEST(H5mdWriter, H5dumpReadsTheFile) {
  const ScratchDir scratch;
  const std::string path = scratch.file("traj.h5");
  write_trajectory_file<double>(path, 3);
  if (std::system("command -v h5dump > /dev/null 2>&1") != 0) {
    std::cout << "[   NOTE   ] h5dump is not on PATH: the h5dump check is left out\n";
    return;
  }
  EXPECT_EQ(std::system(("h5dump -H '" + path + "' > /dev/null 2>&1").c_str()), 0);
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

TEST(XdmfSidecar, UnwritablePathThrowsNamingIt) {
  const ScratchDir scratch;
  H5mdWriter writer(scratch.file("traj.h5"));
  const std::string xdmf = "/nonexistent-dir/traj.xdmf";
  const std::string message = error_message<std::runtime_error>([&] { writer.write_xdmf(xdmf); });
  EXPECT_TRUE(contains(message, xdmf)) << message;
}

}  // namespace
