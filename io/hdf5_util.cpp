// hdf5_util.cpp — see hdf5_util.hpp.
#include "hdf5_util.hpp"

#include <algorithm>
#include <cstring>
#include <stdexcept>

namespace mesoflow::io {

namespace {

// HDF5's most specific description of the last failure on this thread's error stack ("" when the
// stack is empty). The walk goes upward, from the innermost call to the API function.
std::string innermost_hdf5_message() {
  std::string message;
  const H5E_walk2_t take_first = [](unsigned, const H5E_error2_t* error, void* out) -> herr_t {
    auto& text = *static_cast<std::string*>(out);
    if (text.empty() && error->desc != nullptr) text = error->desc;
    return 0;
  };
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, take_first, &message);
  return message;
}

[[noreturn]] void throw_error(const std::string& detail, const std::string& file,
                              const std::string& object, const std::string& action) {
  std::string message = "mesoflow::io: cannot " + action + " '" + object + "'";
  if (!file.empty()) message += " in '" + file + "'";
  if (!detail.empty()) message += ": " + detail;
  throw std::runtime_error(message);
}

// Name of the file holding `loc`, or "" when it cannot be resolved.
std::string file_name_of(hid_t loc) {
  const ssize_t length = H5Fget_name(loc, nullptr, 0);
  if (length < 0) return {};
  std::vector<char> name(static_cast<std::size_t>(length) + 1);
  H5Fget_name(loc, name.data(), name.size());
  return name.data();
}

// Path of `loc` inside its file joined with `name` (returned as is when absolute).
std::string object_path(hid_t loc, const std::string& name) {
  if (!name.empty() && name.front() == '/') return name;
  const ssize_t length = H5Iget_name(loc, nullptr, 0);
  if (length <= 0) return name;
  std::vector<char> buffer(static_cast<std::size_t>(length) + 1);
  H5Iget_name(loc, buffer.data(), buffer.size());
  std::string path = buffer.data();
  if (name.empty()) return path;
  if (path.back() != '/') path += '/';
  return path + name;
}

// "dataset '/path'", or "attribute 'name' of '/path'" for an attribute, for messages.
std::string describe_object(hid_t obj) {
  if (H5Iget_type(obj) != H5I_ATTR) return "dataset '" + object_path(obj, "") + "'";
  const ssize_t length = H5Aget_name(obj, 0, nullptr);
  std::vector<char> name(static_cast<std::size_t>(std::max<ssize_t>(length, 0)) + 1, '\0');
  if (length > 0) H5Aget_name(obj, name.size(), name.data());
  return "attribute '" + std::string(name.data()) + "' of '" + object_path(obj, "") + "'";
}

// Stops HDF5 from printing its error stack to stderr: failures surface as exceptions instead.
// Error stacks are per thread in thread-safe builds, so this is repeated on each file access.
void silence_error_printing() { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }

// A simple dataspace of `shape`, or a scalar one when `shape` is empty; `max_shape` (same rank)
// allows growth where it holds H5S_UNLIMITED.
Dataspace make_space(const std::vector<hsize_t>& shape,
                     const std::vector<hsize_t>& max_shape = {}) {
  const hid_t id = shape.empty() ? H5Screate(H5S_SCALAR)
                                 : H5Screate_simple(static_cast<int>(shape.size()), shape.data(),
                                                    max_shape.empty() ? nullptr : max_shape.data());
  if (id < 0) raise_error("", "dataspace", "create");
  return Dataspace{id};
}

// Link creation properties that create missing intermediate groups.
PropertyList intermediate_groups() {
  PropertyList lcpl{H5Pcreate(H5P_LINK_CREATE)};
  if (!lcpl.valid() || H5Pset_create_intermediate_group(lcpl.get(), 1) < 0)
    raise_error("", "link creation property list", "create");
  return lcpl;
}

std::size_t element_count(const std::vector<hsize_t>& shape) {
  std::size_t count = 1;
  for (const hsize_t extent : shape) count *= static_cast<std::size_t>(extent);
  return count;
}

// Current (or, with `maximum`, largest allowed) extent of each dimension of a dataset.
std::vector<hsize_t> extents(hid_t dataset, bool maximum) {
  const Dataspace space{check_id(H5Dget_space(dataset), dataset, "", "read the shape of")};
  const int rank = H5Sget_simple_extent_ndims(space.get());
  if (rank < 0) raise_error_at(dataset, "", "read the rank of");
  std::vector<hsize_t> shape(static_cast<std::size_t>(rank));
  if (rank > 0)
    H5Sget_simple_extent_dims(space.get(), maximum ? nullptr : shape.data(),
                              maximum ? shape.data() : nullptr);
  return shape;
}

// The string type of `stored` as it is laid out in memory for reading: variable-length strings
// read as char*, fixed-length ones as blocks of H5Tget_size bytes.
Datatype memory_string_type(hid_t stored) {
  Datatype type{H5Tcopy(H5T_C_S1)};
  const bool variable = H5Tis_variable_str(stored) > 0;
  if (!type.valid() || H5Tset_size(type.get(), variable ? H5T_VARIABLE : H5Tget_size(stored)) < 0 ||
      H5Tset_cset(type.get(), H5Tget_cset(stored)) < 0)
    raise_error("", "string type", "create");
  return type;
}

// Variable-length strings as HDF5 allocates them when reading; freed whatever happens next.
struct VariableStrings {
  explicit VariableStrings(std::size_t count) : pointers(count, nullptr) {}
  VariableStrings(const VariableStrings&) = delete;
  VariableStrings& operator=(const VariableStrings&) = delete;
  ~VariableStrings() {
    for (char* pointer : pointers) H5free_memory(pointer);
  }
  std::vector<char*> pointers;
};

// Attribute `name` of the open group or dataset `obj`.
Attribute open_attribute(hid_t obj, const std::string& name) {
  return Attribute{check_id(H5Aopen(obj, name.c_str(), H5P_DEFAULT), obj, "",
                            "open attribute '" + name + "' of")};
}

// Opens `object` in `file` read-only and its attribute `name`.
Attribute open_attribute(const std::string& file, const std::string& object,
                         const std::string& name) {
  const File f = open_file(file, H5F_ACC_RDONLY);
  const Object obj{
      check_id(H5Oopen(f.get(), object.c_str(), H5P_DEFAULT), f.get(), object, "open object")};
  return open_attribute(obj.get(), name);
}

// Every value of the open attribute `attr` (named `name`) converted to the in-memory type `T`.
template <class T>
std::vector<T> read_attribute_values(const Attribute& attr, const std::string& name) {
  const std::string what = "attribute '" + name + "' of";
  const Dataspace space{
      check_id(H5Aget_space(attr.get()), attr.get(), "", "read the shape of " + what)};
  std::vector<T> values(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space.get())));
  check_status(H5Aread(attr.get(), native_type<T>(), values.data()), attr.get(), "",
               "read " + what);
  return values;
}

template <class T>
ArrayData<T> read_whole_dataset(const std::string& file, const std::string& path) {
  const File f = open_file(file, H5F_ACC_RDONLY);
  const Dataset dataset = open_dataset(f.get(), path);
  const std::vector<hsize_t> shape = dataset_shape(dataset.get());
  ArrayData<T> array{std::vector<T>(element_count(shape)), {shape.begin(), shape.end()}};
  read_dataset(dataset.get(), native_type<T>(), array.values.data());
  return array;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Errors

void raise_error(const std::string& file, const std::string& object, const std::string& action) {
  throw_error(innermost_hdf5_message(), file, object, action);
}

void raise_error_at(hid_t loc, const std::string& name, const std::string& action) {
  const std::string detail = innermost_hdf5_message();  // before other calls reset the stack
  throw_error(detail, file_name_of(loc), object_path(loc, name), action);
}

hid_t check_id(hid_t id, hid_t loc, const std::string& name, const std::string& action) {
  if (id < 0) raise_error_at(loc, name, action);
  return id;
}

void check_status(herr_t status, hid_t loc, const std::string& name, const std::string& action) {
  if (status < 0) raise_error_at(loc, name, action);
}

// ---------------------------------------------------------------------------------------------
// Types

Datatype bool_type() {
  Datatype type{H5Tenum_create(H5T_NATIVE_INT8)};
  const signed char no = 0, yes = 1;
  if (!type.valid() || H5Tenum_insert(type.get(), "FALSE", &no) < 0 ||
      H5Tenum_insert(type.get(), "TRUE", &yes) < 0)
    raise_error("", "boolean enum type", "create");
  return type;
}

Datatype string_type() {
  Datatype type{H5Tcopy(H5T_C_S1)};
  if (!type.valid() || H5Tset_size(type.get(), H5T_VARIABLE) < 0 ||
      H5Tset_cset(type.get(), H5T_CSET_UTF8) < 0)
    raise_error("", "string type", "create");
  return type;
}

std::string describe_type(hid_t type) {
  const std::string bits = std::to_string(8 * H5Tget_size(type));
  switch (H5Tget_class(type)) {
    case H5T_INTEGER: return (H5Tget_sign(type) == H5T_SGN_NONE ? "uint" : "int") + bits;
    case H5T_FLOAT: return "float" + bits;
    case H5T_STRING: return "string";
    case H5T_ENUM: return "enum";
    default: return "non-numeric type";
  }
}

bool same_representation(hid_t type, hid_t native) {
  const H5T_class_t type_class = H5Tget_class(type);
  if (type_class != H5Tget_class(native) || H5Tget_size(type) != H5Tget_size(native)) return false;
  return type_class != H5T_INTEGER || H5Tget_sign(type) == H5Tget_sign(native);
}

// ---------------------------------------------------------------------------------------------
// Files, groups, datasets

File create_file(const std::string& path) {
  silence_error_printing();
  const hid_t id = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (id < 0) raise_error("", path, "create file");
  return File{id};
}

File open_file(const std::string& path, unsigned flags) {
  File file = try_open_file(path, flags);
  if (!file.valid()) raise_error("", path, "open file");
  return file;
}

File try_open_file(const std::string& path, unsigned flags) {
  silence_error_printing();
  return File{H5Fopen(path.c_str(), flags, H5P_DEFAULT)};
}

bool path_exists(hid_t loc, const std::string& path) {
  if (path.empty()) return false;
  std::string prefix = path.front() == '/' ? "/" : "";
  std::size_t begin = prefix.size();
  while (begin < path.size()) {
    std::size_t end = path.find('/', begin);
    if (end == std::string::npos) end = path.size();
    prefix += path.substr(begin, end - begin);
    if (H5Lexists(loc, prefix.c_str(), H5P_DEFAULT) <= 0) return false;
    prefix += '/';
    begin = end + 1;
  }
  return true;
}

H5I_type_t object_type(hid_t loc, const std::string& path) {
  if (!path_exists(loc, path)) return H5I_BADID;
  const Object obj{H5Oopen(loc, path.c_str(), H5P_DEFAULT)};
  return obj.valid() ? H5Iget_type(obj.get()) : H5I_BADID;
}

std::vector<std::string> link_names(hid_t group) {
  H5G_info_t info;
  check_status(H5Gget_info(group, &info), group, "", "list the links of");
  std::vector<std::string> names;
  for (hsize_t index = 0; index < info.nlinks; ++index) {
    const auto name_at = [&](char* out, std::size_t size) {
      return H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, index, out, size,
                                H5P_DEFAULT);
    };
    const ssize_t length = name_at(nullptr, 0);
    if (length < 0) raise_error_at(group, "", "list the links of");
    std::vector<char> name(static_cast<std::size_t>(length) + 1);
    if (name_at(name.data(), name.size()) < 0) raise_error_at(group, "", "list the links of");
    names.emplace_back(name.data(), static_cast<std::size_t>(length));
  }
  return names;
}

Group open_group(hid_t loc, const std::string& path) {
  return Group{check_id(H5Gopen2(loc, path.c_str(), H5P_DEFAULT), loc, path, "open group")};
}

Group require_group(hid_t loc, const std::string& path) {
  if (path_exists(loc, path)) return open_group(loc, path);
  const PropertyList lcpl = intermediate_groups();
  return Group{check_id(H5Gcreate2(loc, path.c_str(), lcpl.get(), H5P_DEFAULT, H5P_DEFAULT), loc,
                        path, "create group")};
}

Dataset open_dataset(hid_t loc, const std::string& path) {
  return Dataset{check_id(H5Dopen2(loc, path.c_str(), H5P_DEFAULT), loc, path, "open dataset")};
}

Dataset write_dataset(hid_t loc, const std::string& path, hid_t type, hid_t mem_type,
                      const std::vector<hsize_t>& shape, const void* data) {
  const Dataspace space = make_space(shape);
  const PropertyList lcpl = intermediate_groups();
  Dataset dataset{check_id(
      H5Dcreate2(loc, path.c_str(), type, space.get(), lcpl.get(), H5P_DEFAULT, H5P_DEFAULT), loc,
      path, "create dataset")};
  if (element_count(shape) > 0)
    check_status(H5Dwrite(dataset.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data),
                 dataset.get(), "", "write dataset");
  return dataset;
}

std::vector<hsize_t> dataset_shape(hid_t dataset) { return extents(dataset, false); }

std::vector<hsize_t> dataset_max_shape(hid_t dataset) { return extents(dataset, true); }

Datatype dataset_type(hid_t dataset) {
  return Datatype{check_id(H5Dget_type(dataset), dataset, "", "read the type of")};
}

void read_dataset(hid_t dataset, hid_t mem_type, void* out) {
  if (element_count(dataset_shape(dataset)) == 0) return;
  check_status(H5Dread(dataset, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out), dataset, "",
               "read dataset");
}

// ---------------------------------------------------------------------------------------------
// Series

Dataset create_series(hid_t loc, const std::string& name, hid_t type,
                      const std::vector<hsize_t>& frame_shape,
                      const std::vector<hsize_t>& chunk_shape) {
  std::vector<hsize_t> shape{0}, max_shape{H5S_UNLIMITED};
  shape.insert(shape.end(), frame_shape.begin(), frame_shape.end());
  max_shape.insert(max_shape.end(), frame_shape.begin(), frame_shape.end());
  const Dataspace space = make_space(shape, max_shape);

  const PropertyList dcpl{H5Pcreate(H5P_DATASET_CREATE)};
  if (!dcpl.valid() ||
      H5Pset_chunk(dcpl.get(), static_cast<int>(chunk_shape.size()), chunk_shape.data()) < 0)
    raise_error_at(loc, name, "set the chunk shape of");
  return Dataset{check_id(
      H5Dcreate2(loc, name.c_str(), type, space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT), loc,
      name, "create dataset")};
}

void write_frame(hid_t series, hsize_t frame, const std::vector<hsize_t>& frame_shape,
                 hid_t mem_type, const void* data) {
  std::vector<hsize_t> extent{frame + 1}, start{frame}, count{1};
  extent.insert(extent.end(), frame_shape.begin(), frame_shape.end());
  start.resize(extent.size(), 0);
  count.insert(count.end(), frame_shape.begin(), frame_shape.end());
  check_status(H5Dset_extent(series, extent.data()), series, "", "extend dataset");

  const Dataspace file_space{check_id(H5Dget_space(series), series, "", "read the shape of")};
  check_status(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start.data(), nullptr,
                                   count.data(), nullptr),
               series, "", "select frame " + std::to_string(frame) + " of");
  const Dataspace memory_space = make_space(count);
  check_status(H5Dwrite(series, mem_type, memory_space.get(), file_space.get(), H5P_DEFAULT, data),
               series, "", "write frame " + std::to_string(frame) + " of");
}

void set_frame_count(hid_t series, hsize_t frames) {
  std::vector<hsize_t> extent = dataset_shape(series);
  if (extent.empty())
    throw std::runtime_error("mesoflow::io: " + describe_object(series) + " in '" +
                             file_name_of(series) + "' is a scalar, not a series of frames");
  extent[0] = frames;
  check_status(H5Dset_extent(series, extent.data()), series, "",
               "set the number of frames to " + std::to_string(frames) + " of");
}

// ---------------------------------------------------------------------------------------------
// Attributes

void write_attribute(hid_t obj, const std::string& name, hid_t type, hid_t mem_type,
                     const std::vector<hsize_t>& shape, const void* data) {
  const std::string what = "attribute '" + name + "' of";
  if (H5Aexists(obj, name.c_str()) > 0)
    check_status(H5Adelete(obj, name.c_str()), obj, "", "replace " + what);
  const Dataspace space = make_space(shape);
  const Attribute attr{
      check_id(H5Acreate2(obj, name.c_str(), type, space.get(), H5P_DEFAULT, H5P_DEFAULT), obj, "",
               "create " + what)};
  check_status(H5Awrite(attr.get(), mem_type, data), obj, "", "write " + what);
}

void write_attribute(hid_t obj, const std::string& name, bool value) {
  const Datatype type = bool_type();
  const signed char stored = value ? 1 : 0;
  write_attribute(obj, name, type.get(), type.get(), {}, &stored);
}

void write_attribute(hid_t obj, const std::string& name, const char* value) {
  const Datatype type = string_type();
  write_attribute(obj, name, type.get(), type.get(), {}, &value);
}

void write_attribute(hid_t obj, const std::string& name, const std::string& value) {
  write_attribute(obj, name, value.c_str());
}

void write_attribute(hid_t obj, const std::string& name, const std::vector<std::string>& values) {
  std::vector<const char*> pointers;
  for (const std::string& value : values) pointers.push_back(value.c_str());
  const Datatype type = string_type();
  write_attribute(obj, name, type.get(), type.get(), {values.size()}, pointers.data());
}

std::vector<std::string> read_strings(hid_t dataset_or_attribute) {
  const hid_t obj = dataset_or_attribute;
  const bool is_attribute = H5Iget_type(obj) == H5I_ATTR;
  const Datatype stored{
      check_id(is_attribute ? H5Aget_type(obj) : H5Dget_type(obj), obj, "", "read the type of")};
  if (H5Tget_class(stored.get()) != H5T_STRING)
    throw std::runtime_error("mesoflow::io: " + describe_object(obj) + " in '" + file_name_of(obj) +
                             "' holds " + describe_type(stored.get()) + ", not strings");
  const Dataspace space{
      check_id(is_attribute ? H5Aget_space(obj) : H5Dget_space(obj), obj, "", "read the shape of")};
  const auto count = static_cast<std::size_t>(H5Sget_simple_extent_npoints(space.get()));
  const Datatype memory = memory_string_type(stored.get());
  const auto read = [&](void* out) {
    const herr_t status = is_attribute
                              ? H5Aread(obj, memory.get(), out)
                              : H5Dread(obj, memory.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, out);
    check_status(status, obj, "", "read strings of");
  };

  std::vector<std::string> strings;
  if (H5Tis_variable_str(stored.get()) > 0) {
    VariableStrings variable(count);
    read(variable.pointers.data());
    for (const char* pointer : variable.pointers) strings.emplace_back(pointer ? pointer : "");
  } else {
    const std::size_t width = H5Tget_size(stored.get());
    std::vector<char> buffer(count * width);
    read(buffer.data());
    for (std::size_t i = 0; i < count; ++i)
      strings.emplace_back(&buffer[i * width], strnlen(&buffer[i * width], width));
  }
  return strings;
}

// ---------------------------------------------------------------------------------------------
// Whole-file readers

ArrayData<double> read_dataset_double(const std::string& file, const std::string& dataset) {
  return read_whole_dataset<double>(file, dataset);
}

ArrayData<std::int64_t> read_dataset_int64(const std::string& file, const std::string& dataset) {
  return read_whole_dataset<std::int64_t>(file, dataset);
}

std::vector<double> read_attribute_double(const std::string& file, const std::string& object,
                                          const std::string& name) {
  return read_attribute_values<double>(open_attribute(file, object, name), name);
}

std::vector<std::int64_t> read_attribute_int64(const std::string& file, const std::string& object,
                                               const std::string& name) {
  return read_attribute_values<std::int64_t>(open_attribute(file, object, name), name);
}

bool read_attribute_bool(const std::string& file, const std::string& object,
                         const std::string& name) {
  const Attribute attr = open_attribute(file, object, name);
  const Datatype type = bool_type();
  signed char value = 0;
  check_status(H5Aread(attr.get(), type.get(), &value), attr.get(), "", "read boolean");
  return value != 0;
}

std::vector<std::int64_t> read_attribute_int64(hid_t obj, const std::string& name) {
  return read_attribute_values<std::int64_t>(open_attribute(obj, name), name);
}

std::vector<std::string> read_attribute_strings(const std::string& file, const std::string& object,
                                                const std::string& name) {
  return read_strings(open_attribute(file, object, name).get());
}

std::string read_attribute_string(const std::string& file, const std::string& object,
                                  const std::string& name) {
  const std::vector<std::string> strings = read_attribute_strings(file, object, name);
  if (strings.size() != 1)
    throw std::runtime_error("mesoflow::io: attribute '" + name + "' of '" + object + "' in '" +
                             file + "' holds " + std::to_string(strings.size()) +
                             " strings, expected one");
  return strings.front();
}

}  // namespace mesoflow::io
