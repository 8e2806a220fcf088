// hdf5_util.hpp — owning handles, error checks and small read/write helpers over the HDF5 C API.
//
// Every identifier returned by HDF5 is wrapped in a Handle that closes it, so no exit path leaks
// one. Every failed HDF5 call becomes a std::runtime_error naming the file, the object and the
// action, with HDF5's innermost diagnostic appended; HDF5's own printing of its error stack to
// stderr is switched off whenever these helpers open or create a file.
#pragma once

#include <hdf5.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace mesoflow::io {

// An HDF5 identifier that is closed with `Close` when the handle goes out of scope.
template <herr_t (*Close)(hid_t)>
class Handle {
 public:
  Handle() = default;
  explicit Handle(hid_t id) : id_(id) {}
  Handle(Handle&& other) noexcept : id_(std::exchange(other.id_, H5I_INVALID_HID)) {}
  Handle& operator=(Handle&& other) noexcept {
    if (this != &other) {
      reset();
      id_ = std::exchange(other.id_, H5I_INVALID_HID);
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() { reset(); }

  hid_t get() const { return id_; }
  bool valid() const { return id_ >= 0; }

  // Closes now and returns HDF5's status, for callers that must know the close succeeded
  // (closing a file is when its last buffers are written).
  herr_t close() { return Close(std::exchange(id_, H5I_INVALID_HID)); }

  void reset() {
    if (id_ >= 0) Close(std::exchange(id_, H5I_INVALID_HID));
  }

 private:
  hid_t id_ = H5I_INVALID_HID;
};

using File = Handle<H5Fclose>;
using Group = Handle<H5Gclose>;
using Dataset = Handle<H5Dclose>;
using Dataspace = Handle<H5Sclose>;
using Datatype = Handle<H5Tclose>;
using Attribute = Handle<H5Aclose>;
using PropertyList = Handle<H5Pclose>;
using Object = Handle<H5Oclose>;

// ---------------------------------------------------------------------------------------------
// Errors

// Throws std::runtime_error "mesoflow::io: cannot <action> '<object>' in '<file>': <HDF5 detail>".
// Reads HDF5's error stack first, so call it right after the failing HDF5 call.
[[noreturn]] void raise_error(const std::string& file, const std::string& object,
                              const std::string& action);

// As raise_error, with the file and object path resolved from `loc` (any open file, group or
// dataset) and `name` relative to it.
[[noreturn]] void raise_error_at(hid_t loc, const std::string& name, const std::string& action);

// Returns `id` when valid, otherwise raises the error for `name` below `loc`.
hid_t check_id(hid_t id, hid_t loc, const std::string& name, const std::string& action);

// Raises the error for `name` below `loc` when `status` is negative.
void check_status(herr_t status, hid_t loc, const std::string& name, const std::string& action);

// ---------------------------------------------------------------------------------------------
// Types

// The HDF5 in-memory type of a C++ arithmetic type.
template <class T>
hid_t native_type() {
  if constexpr (std::is_same_v<T, float>)
    return H5T_NATIVE_FLOAT;
  else if constexpr (std::is_same_v<T, double>)
    return H5T_NATIVE_DOUBLE;
  else if constexpr (std::is_same_v<T, int>)
    return H5T_NATIVE_INT;
  else if constexpr (std::is_same_v<T, long>)
    return H5T_NATIVE_LONG;
  else if constexpr (std::is_same_v<T, long long>)
    return H5T_NATIVE_LLONG;
  else
    static_assert(sizeof(T) == 0, "mesoflow::io: no HDF5 type for this C++ type");
}

// h5py's boolean type (an int8 enum FALSE=0, TRUE=1), so that h5py reads numpy.bool_.
Datatype bool_type();

// Variable-length UTF-8 string type, which h5py reads as `str`.
Datatype string_type();

// Short description of a stored type for error messages: "float32", "int64", "string", ...
std::string describe_type(hid_t type);

// True when the stored `type` holds exactly the values of the in-memory `native` type: same
// class, size and signedness, so reading needs no conversion.
bool same_representation(hid_t type, hid_t native);

// ---------------------------------------------------------------------------------------------
// Files, groups, datasets

File create_file(const std::string& path);                    // truncates an existing file
File open_file(const std::string& path, unsigned flags);      // H5F_ACC_RDONLY or H5F_ACC_RDWR
File try_open_file(const std::string& path, unsigned flags);  // as open_file; invalid on failure

// True when every link along `path` (relative to `loc`, or absolute) exists.
bool path_exists(hid_t loc, const std::string& path);

// What `path` below `loc` is: H5I_GROUP, H5I_DATASET, ..., or H5I_BADID when there is nothing
// there to open.
H5I_type_t object_type(hid_t loc, const std::string& path);

// Names of the links in `group`, in increasing name order.
std::vector<std::string> link_names(hid_t group);

Group open_group(hid_t loc, const std::string& path);
Group require_group(hid_t loc, const std::string& path);  // opens, or creates with parents
Dataset open_dataset(hid_t loc, const std::string& path);

// Creates a fixed-size dataset of `type` and `shape` (empty shape: a scalar) and writes `data`,
// laid out row-major in memory as `mem_type`. Missing parent groups are created.
Dataset write_dataset(hid_t loc, const std::string& path, hid_t type, hid_t mem_type,
                      const std::vector<hsize_t>& shape, const void* data);

// Extent of each dimension of a dataset (empty for a scalar).
std::vector<hsize_t> dataset_shape(hid_t dataset);

// Largest extent each dimension of a dataset may grow to (H5S_UNLIMITED: no limit).
std::vector<hsize_t> dataset_max_shape(hid_t dataset);

// The type a dataset is stored in.
Datatype dataset_type(hid_t dataset);

// Reads the whole dataset into `out`, converting to `mem_type`; `out` must hold every element.
void read_dataset(hid_t dataset, hid_t mem_type, void* out);

// ---------------------------------------------------------------------------------------------
// Series: datasets that grow by one frame along an unlimited leading axis

// Creates an empty series `name` below `loc` whose frames have `frame_shape` (empty: one value per
// frame), stored in chunks of `chunk_shape` (rank of frame_shape + 1, the frame axis first).
Dataset create_series(hid_t loc, const std::string& name, hid_t type,
                      const std::vector<hsize_t>& frame_shape,
                      const std::vector<hsize_t>& chunk_shape);

// Extends the series to `frame + 1` frames and writes one frame (row-major, `mem_type`) there.
void write_frame(hid_t series, hsize_t frame, const std::vector<hsize_t>& frame_shape,
                 hid_t mem_type, const void* data);

// Sets the number of frames of a series: frames past `frames` are dropped, and when it grows the
// new frames hold the fill value until written.
void set_frame_count(hid_t series, hsize_t frames);

// ---------------------------------------------------------------------------------------------
// Attributes (an existing attribute of the same name is replaced)

void write_attribute(hid_t obj, const std::string& name, hid_t type, hid_t mem_type,
                     const std::vector<hsize_t>& shape, const void* data);

template <class T>
void write_attribute(hid_t obj, const std::string& name, const T& value) {
  write_attribute(obj, name, native_type<T>(), native_type<T>(), {}, &value);
}

template <class T>
void write_attribute(hid_t obj, const std::string& name, const std::vector<T>& values) {
  write_attribute(obj, name, native_type<T>(), native_type<T>(), {values.size()}, values.data());
}

void write_attribute(hid_t obj, const std::string& name, bool value);
void write_attribute(hid_t obj, const std::string& name, const char* value);
void write_attribute(hid_t obj, const std::string& name, const std::string& value);
void write_attribute(hid_t obj, const std::string& name, const std::vector<std::string>& values);

// All strings of an open dataset or attribute of fixed- or variable-length string type.
std::vector<std::string> read_strings(hid_t dataset_or_attribute);

// Every value of the attribute `name` of the open group or dataset `obj`, as int64.
std::vector<std::int64_t> read_attribute_int64(hid_t obj, const std::string& name);

// ---------------------------------------------------------------------------------------------
// Whole-file readers for tests and analysis: each opens `file` read-only, reads, and closes it.

// A dataset read whole: values in row-major order and the extent of each dimension.
template <class T>
struct ArrayData {
  std::vector<T> values;
  std::vector<std::size_t> shape;
};

ArrayData<double> read_dataset_double(const std::string& file, const std::string& dataset);
ArrayData<std::int64_t> read_dataset_int64(const std::string& file, const std::string& dataset);

// Attribute `name` of the group or dataset `object`.
std::vector<double> read_attribute_double(const std::string& file, const std::string& object,
                                          const std::string& name);
std::vector<std::int64_t> read_attribute_int64(const std::string& file, const std::string& object,
                                               const std::string& name);
bool read_attribute_bool(const std::string& file, const std::string& object,
                         const std::string& name);
std::vector<std::string> read_attribute_strings(const std::string& file, const std::string& object,
                                                const std::string& name);
std::string read_attribute_string(const std::string& file, const std::string& object,
                                  const std::string& name);

}  // namespace mesoflow::io
