// test_checkpoint.cpp — restart checkpoints: bit-exact round trip, atomic replacement, strict
// types and shapes, and errors that name what failed.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cctype>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "scratch_dir.hpp"
#include "io/checkpoint.hpp"
#include "io/h5md_writer.hpp"

// Named: this file shares a unity translation unit with test_h5md.cpp (tests/CMakeLists.txt).
namespace checkpoint_test {

namespace fs = std::filesystem;
using namespace mesoflow::io;

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

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

// Values whose bits a lossy path would change: signed zero, subnormals, extremes, NaN, infinity.
template <class Real>
std::vector<Real> awkward_reals() {
  using limits = std::numeric_limits<Real>;
  return {Real(0.1),          Real(-0.0),        limits::denorm_min(), limits::min(),
          limits::max(),      limits::lowest(),  limits::epsilon(),    limits::quiet_NaN(),
          limits::infinity(), Real(1) / Real(3), Real(-2.5e-3),        Real(42)};
}

// Commits a checkpoint at `path` holding the scalar "step" and, if given, one extra entry.
void commit_checkpoint(const std::string& path, std::int64_t step, const std::string& extra = "") {
  CheckpointWriter writer(path);
  writer.put_scalar("step", step);
  if (!extra.empty()) writer.put_string(extra, "present");
  writer.commit();
}

TEST(Checkpoint, RoundTripIsBitExact) {
  const ScratchDir scratch;
  const std::string path = scratch.file("restart.h5");
  const std::vector<double> doubles = awkward_reals<double>();
  const std::vector<float> floats = awkward_reals<float>();
  const std::vector<int> ints{
      0, -1, 1, std::numeric_limits<int>::min(), std::numeric_limits<int>::max(), 7};
  const std::vector<std::int64_t> int64s{0, -1, std::numeric_limits<std::int64_t>::min(),
                                         std::numeric_limits<std::int64_t>::max()};
  {
    CheckpointWriter writer(path);
    writer.put("particles/position", doubles.data(), {4, 3});
    writer.put("particles/velocity", floats.data(), {12});
    writer.put("particles/species", ints.data(), {2, 3});
    writer.put("rng/counters", int64s.data(), {int64s.size()});
    writer.put_scalar("time", 0.1 + 0.2);
    writer.put_scalar("step", std::int64_t{9007199254740993});
    writer.put_scalar("n_particles", 12);
    writer.put_string("scene", "channel · 2D");
    writer.commit();
  }

  const CheckpointReader reader(path);
  std::vector<double> doubles_read;
  std::vector<float> floats_read;
  std::vector<int> ints_read;
  std::vector<std::int64_t> int64s_read;
  std::vector<std::size_t> shape;
  reader.get("particles/position", doubles_read, &shape);
  EXPECT_EQ(shape, (std::vector<std::size_t>{4, 3}));
  EXPECT_TRUE(same_bits(doubles_read, doubles));
  reader.get("particles/velocity", floats_read, &shape);
  EXPECT_EQ(shape, std::vector<std::size_t>{12});
  EXPECT_TRUE(same_bits(floats_read, floats));
  reader.get("particles/species", ints_read);
  EXPECT_EQ(ints_read, ints);
  reader.get("rng/counters", int64s_read);
  EXPECT_EQ(int64s_read, int64s);

  const double time = reader.get_scalar_double("time");
  const double expected_time = 0.1 + 0.2;
  EXPECT_EQ(std::memcmp(&time, &expected_time, sizeof time), 0);
  EXPECT_EQ(reader.get_scalar_int64("step"), 9007199254740993);
  EXPECT_EQ(reader.get_scalar_int64("n_particles"), 12);
  EXPECT_EQ(reader.get_string("scene"), "channel · 2D");
  EXPECT_TRUE(reader.has("particles/position"));
  EXPECT_TRUE(reader.has("particles"));
  EXPECT_FALSE(reader.has("particles/force"));
  EXPECT_EQ(reader.shape("time"), std::vector<std::size_t>{});
}

TEST(Checkpoint, ReadsIntoAPreallocatedBufferOfTheExpectedShape) {
  const ScratchDir scratch;
  const std::string path = scratch.file("restart.h5");
  const std::vector<float> values = awkward_reals<float>();
  const std::vector<double> box{1.0, 2.0};
  {
    CheckpointWriter writer(path);
    writer.put("position", values.data(), {6, 2});
    writer.put("box", box.data(), {2});
    writer.commit();
  }
  const CheckpointReader reader(path);
  std::vector<float> buffer(values.size());
  reader.get("position", buffer.data(), {6, 2});
  EXPECT_TRUE(same_bits(buffer, values));

  std::string message = error_message<std::runtime_error>([&] {
    reader.get("position", buffer.data(), {4, 3});
  });
  EXPECT_TRUE(contains(message, "'position'")) << message;
  EXPECT_TRUE(contains(message, "(6, 2)")) << message;
  EXPECT_TRUE(contains(message, "(4, 3)")) << message;
  message = error_message<std::runtime_error>([&] { reader.get_scalar_double("box"); });
  EXPECT_TRUE(contains(message, "'box' has shape (2), requested ()")) << message;
}

TEST(Checkpoint, WriterDestroyedWithoutCommitLeavesThePreviousCheckpoint) {
  const ScratchDir scratch;
  const std::string path = scratch.file("restart.h5");
  commit_checkpoint(path, 1);
  {
    CheckpointWriter writer(path);
    writer.put_scalar("step", std::int64_t{2});
    EXPECT_TRUE(fs::exists(path + ".tmp"));
  }
  EXPECT_FALSE(fs::exists(path + ".tmp"));
  EXPECT_TRUE(checkpoint_exists(path));
  EXPECT_EQ(CheckpointReader(path).get_scalar_int64("step"), 1);
}

TEST(Checkpoint, CommitReplacesThePreviousCheckpointWhole) {
  const ScratchDir scratch;
  const std::string path = scratch.file("restart.h5");
  commit_checkpoint(path, 1, "old_only");
  commit_checkpoint(path, 2, "new_only");

  EXPECT_FALSE(fs::exists(path + ".tmp"));
  const CheckpointReader reader(path);
  EXPECT_EQ(reader.get_scalar_int64("step"), 2);
  EXPECT_TRUE(reader.has("new_only"));
  EXPECT_FALSE(reader.has("old_only"));
}

TEST(Checkpoint, PutAfterCommitIsAnError) {
  const ScratchDir scratch;
  CheckpointWriter writer(scratch.file("restart.h5"));
  writer.commit();
  EXPECT_THROW(writer.put_scalar("late", 1.0), std::logic_error);
  EXPECT_THROW(writer.commit(), std::logic_error);
}

TEST(Checkpoint, TypeMismatchThrowsNamingTheEntry) {
  const ScratchDir scratch;
  const std::string path = scratch.file("restart.h5");
  const std::vector<float> density{1.0f, 2.0f};
  const std::vector<int> ids{1, 2};
  {
    CheckpointWriter writer(path);
    writer.put("density", density.data(), {2});
    writer.put("ids", ids.data(), {2});
    writer.put_string("scene", "channel");
    writer.commit();
  }
  const CheckpointReader reader(path);
  std::vector<double> as_double;
  std::string message =
      error_message<std::runtime_error>([&] { reader.get("density", as_double); });
  EXPECT_TRUE(contains(message, "'density'")) << message;
  EXPECT_TRUE(contains(message, "float32")) << message;
  EXPECT_TRUE(contains(message, "float64")) << message;
  EXPECT_TRUE(contains(message, path)) << message;

  std::vector<std::int64_t> as_int64;
  message = error_message<std::runtime_error>([&] { reader.get("ids", as_int64); });
  EXPECT_TRUE(contains(message, "'ids'") && contains(message, "int32")) << message;
  message = error_message<std::runtime_error>([&] { reader.get_scalar_double("scene"); });
  EXPECT_TRUE(contains(message, "'scene'") && contains(message, "string")) << message;
}

TEST(Checkpoint, MissingEntryThrowsNamingIt) {
  const ScratchDir scratch;
  const std::string path = scratch.file("restart.h5");
  commit_checkpoint(path, 1);
  const CheckpointReader reader(path);
  std::vector<double> values;
  for (const std::string name : {"velocity", "particles/velocity"}) {
    const std::string message =
        error_message<std::runtime_error>([&] { reader.get(name, values); });
    EXPECT_TRUE(contains(message, "'" + name + "'")) << message;
    EXPECT_TRUE(contains(message, path)) << message;
  }
  EXPECT_TRUE(
      contains(error_message<std::runtime_error>([&] { reader.get_string("scene"); }), "'scene'"));
}

TEST(Checkpoint, UnwritableDirectoryThrowsNamingThePath) {
  const std::string path = "/nonexistent-dir/x.h5";
  const std::string message =
      error_message<std::runtime_error>([&] { CheckpointWriter writer(path); });
  EXPECT_TRUE(contains(message, path)) << message;
}

TEST(Checkpoint, ExistsOnlyForCommittedCheckpoints) {
  const ScratchDir scratch;
  const std::string path = scratch.file("restart.h5");
  EXPECT_FALSE(checkpoint_exists(path));
  {
    CheckpointWriter writer(path);
    writer.put_scalar("step", std::int64_t{1});
    EXPECT_FALSE(checkpoint_exists(path));
    writer.commit();
  }
  EXPECT_TRUE(checkpoint_exists(path));

  // Neither a text file nor another HDF5 file is taken for a checkpoint.
  std::ofstream(scratch.file("notes.txt")) << "not hdf5\n";
  EXPECT_FALSE(checkpoint_exists(scratch.file("notes.txt")));
  { const H5mdWriter trajectory(scratch.file("traj.h5")); }
  EXPECT_FALSE(checkpoint_exists(scratch.file("traj.h5")));
  const std::string message =
      error_message<std::runtime_error>([&] { CheckpointReader reader(scratch.file("traj.h5")); });
  EXPECT_TRUE(contains(message, "not a mesoflow checkpoint")) << message;
}

TEST(Checkpoint, LeavesNoHdf5IdentifierOpen) {
  const ScratchDir scratch;
  const std::string path = scratch.file("restart.h5");
  const std::vector<double> values{1.0, 2.0};
  {
    CheckpointWriter writer(path);
    writer.put("values", values.data(), {2});
    writer.put_string("scene", "channel");
    EXPECT_THROW(writer.put("values", values.data(), {2}), std::runtime_error);  // duplicate
    writer.commit();
  }
  {
    CheckpointWriter abandoned(path);
    abandoned.put_scalar("step", std::int64_t{3});
  }
  {
    const CheckpointReader reader(path);
    std::vector<float> wrong_type;
    EXPECT_THROW(reader.get("values", wrong_type), std::runtime_error);
    EXPECT_EQ(reader.get_string("scene"), "channel");
  }
  EXPECT_TRUE(checkpoint_exists(path));
  EXPECT_EQ(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL), 0);
}

}  // namespace checkpoint_test
