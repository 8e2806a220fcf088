// checkpoint.hpp — atomic key-value snapshots in HDF5, for bit-exact restarts.
//
// A checkpoint is an HDF5 file of named entries (a '/' in a name makes groups): arrays of double,
// float, int or int64 with their shape, scalars, and strings. Values are stored in the type they
// are given and read back only into that same type, so a restart sees exactly the bits written.
//
// CheckpointWriter writes "<path>.tmp" and commit() makes it durable (fsync) before renaming it
// over <path> and syncing the directory: <path> always holds the previous complete checkpoint or
// the new one, never a partial file, even if the run dies mid-write.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include "hdf5_util.hpp"

namespace mesoflow::io {

// Element types a checkpoint array may hold.
template <class T>
inline constexpr bool is_checkpoint_type_v =
    std::is_same_v<T, double> || std::is_same_v<T, float> || std::is_same_v<T, int> ||
    std::is_same_v<T, std::int64_t>;

class CheckpointWriter {
 public:
  // Starts a checkpoint that commit() will publish at `path`.
  explicit CheckpointWriter(const std::string& path);
  // Without commit(), the temporary file is removed and `path` is left untouched.
  ~CheckpointWriter();

  CheckpointWriter(const CheckpointWriter&) = delete;
  CheckpointWriter& operator=(const CheckpointWriter&) = delete;

  // Stores `data`, row-major with the given shape (empty shape: one scalar value).
  template <class T>
  void put(const std::string& name, const T* data, const std::vector<std::size_t>& shape) {
    static_assert(is_checkpoint_type_v<T>, "checkpoint arrays hold double, float, int or int64");
    put_array(name, data, native_type<T>(), shape);
  }

  void put_scalar(const std::string& name, double value);
  void put_scalar(const std::string& name, std::int64_t value);
  // Any other integer type (int, std::size_t, ...) is stored as int64.
  template <class Int, std::enable_if_t<std::is_integral_v<Int>, int> = 0>
  void put_scalar(const std::string& name, Int value) {
    put_scalar(name, static_cast<std::int64_t>(value));
  }
  void put_string(const std::string& name, const std::string& value);

  // Flushes, closes and fsyncs the temporary file, renames it over the final path and fsyncs the
  // directory. Nothing may be put afterwards.
  void commit();

  const std::string& path() const { return path_; }

 private:
  void put_array(const std::string& name, const void* data, hid_t mem_type,
                 const std::vector<std::size_t>& shape);
  hid_t file() const;

  std::string path_;
  std::string tmp_path_;
  File file_;
  bool committed_ = false;
};

class CheckpointReader {
 public:
  explicit CheckpointReader(const std::string& path);

  bool has(const std::string& name) const;

  // Shape of entry `name` (empty for a scalar).
  std::vector<std::size_t> shape(const std::string& name) const;

  // Reads array `name` into `out` (resized), and its shape into `*shape` when given. Throws when
  // the entry is missing or stores another type than T (float is never converted to double).
  template <class T>
  void get(const std::string& name, std::vector<T>& out,
           std::vector<std::size_t>* shape = nullptr) const {
    static_assert(is_checkpoint_type_v<T>, "checkpoint arrays hold double, float, int or int64");
    const std::vector<std::size_t> stored = typed_shape(name, native_type<T>());
    std::size_t count = 1;
    for (const std::size_t extent : stored) count *= extent;
    out.resize(count);
    read_array(name, native_type<T>(), out.data());
    if (shape != nullptr) *shape = stored;
  }

  // Reads array `name` into `out`, which holds `expected_shape` elements (a host mirror, say).
  // Throws when the entry is missing, or its type or shape differ from the request.
  template <class T>
  void get(const std::string& name, T* out, const std::vector<std::size_t>& expected_shape) const {
    static_assert(is_checkpoint_type_v<T>, "checkpoint arrays hold double, float, int or int64");
    check_shape(name, typed_shape(name, native_type<T>()), expected_shape);
    read_array(name, native_type<T>(), out);
  }

  double get_scalar_double(const std::string& name) const;
  std::int64_t get_scalar_int64(const std::string& name) const;
  std::string get_string(const std::string& name) const;

  const std::string& path() const { return path_; }

 private:
  Dataset open_entry(const std::string& name) const;
  std::vector<std::size_t> typed_shape(const std::string& name, hid_t mem_type) const;
  void check_shape(const std::string& name, const std::vector<std::size_t>& stored,
                   const std::vector<std::size_t>& expected) const;
  void read_array(const std::string& name, hid_t mem_type, void* out) const;

  std::string path_;
  File file_;
};

// True when `path` holds a committed checkpoint (commit() is atomic, so never a partial one).
bool checkpoint_exists(const std::string& path);

}  // namespace mesoflow::io
