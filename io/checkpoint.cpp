// checkpoint.cpp — see checkpoint.hpp.
#include "io/checkpoint_stop.hpp"
#include "checkpoint.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace mesoflow::io {

namespace {

// Root attribute marking a file as a mesoflow checkpoint; its value is the format version.
constexpr const char* kMarker = "mesoflow_checkpoint";
constexpr int kFormatVersion = 1;

[[noreturn]] void raise_system_error(int error, const std::string& action) {
  throw std::system_error(error, std::generic_category(), "mesoflow::io: cannot " + action);
}

// Forces the contents of `path` (a file, or a directory's entries) to stable storage.
void sync_path(const std::string& path, int flags) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | flags);
  if (fd < 0) {
    const int error = errno;
    raise_system_error(error, "open '" + path + "' to fsync it");
  }
  const int status = ::fsync(fd);
  const int error = errno;
  ::close(fd);
  if (status != 0) raise_system_error(error, "fsync '" + path + "'");
}

std::string directory_of(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  return parent.empty() ? "." : parent.string();
}

std::string shape_text(const std::vector<std::size_t>& shape) {
  std::string text = "(";
  for (std::size_t i = 0; i < shape.size(); ++i) text += (i ? ", " : "") + std::to_string(shape[i]);
  return text + ")";
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Writer

CheckpointWriter::CheckpointWriter(const std::string& path)
    : path_((before_checkpoint(), path)), tmp_path_(path + ".tmp"), file_(create_file(tmp_path_)) {
  write_attribute(file_.get(), kMarker, kFormatVersion);
}

CheckpointWriter::~CheckpointWriter() {
  if (committed_) return;
  file_.reset();
  std::remove(tmp_path_.c_str());
}

hid_t CheckpointWriter::file() const {
  if (committed_)
    throw std::logic_error("mesoflow::io: checkpoint '" + path_ + "' is committed: no more puts");
  return file_.get();
}

void CheckpointWriter::put_array(const std::string& name, const void* data, hid_t mem_type,
                                 const std::vector<std::size_t>& shape) {
  const std::vector<hsize_t> dims(shape.begin(), shape.end());
  write_dataset(file(), name, mem_type, mem_type, dims, data);
}

void CheckpointWriter::put_scalar(const std::string& name, double value) { put(name, &value, {}); }

void CheckpointWriter::put_scalar(const std::string& name, std::int64_t value) {
  put(name, &value, {});
}

void CheckpointWriter::put_string(const std::string& name, const std::string& value) {
  const Datatype type = string_type();
  const char* text = value.c_str();
  write_dataset(file(), name, type.get(), type.get(), {}, &text);
}

void CheckpointWriter::commit() {
  const hid_t id = file();
  check_status(H5Fflush(id, H5F_SCOPE_GLOBAL), id, "", "flush");
  if (file_.close() < 0) raise_error("", tmp_path_, "close file");
  sync_path(tmp_path_, 0);
  if (std::rename(tmp_path_.c_str(), path_.c_str()) != 0) {
    const int error = errno;
    raise_system_error(error, "rename '" + tmp_path_ + "' to '" + path_ + "'");
  }
  committed_ = true;
  sync_path(directory_of(path_), O_DIRECTORY);
}

// ---------------------------------------------------------------------------------------------
// Reader

CheckpointReader::CheckpointReader(const std::string& path)
    : path_(path), file_(open_file(path, H5F_ACC_RDONLY)) {
  if (H5Aexists(file_.get(), kMarker) <= 0)
    throw std::runtime_error("mesoflow::io: '" + path_ + "' is not a mesoflow checkpoint (no '" +
                             kMarker + "' attribute)");
}

bool CheckpointReader::has(const std::string& name) const { return path_exists(file_.get(), name); }

std::vector<std::size_t> CheckpointReader::shape(const std::string& name) const {
  const std::vector<hsize_t> dims = dataset_shape(open_entry(name).get());
  return {dims.begin(), dims.end()};
}

Dataset CheckpointReader::open_entry(const std::string& name) const {
  if (!has(name))
    throw std::runtime_error("mesoflow::io: checkpoint '" + path_ + "' has no entry '" + name +
                             "'");
  return open_dataset(file_.get(), name);
}

std::vector<std::size_t> CheckpointReader::typed_shape(const std::string& name,
                                                       hid_t mem_type) const {
  const Dataset dataset = open_entry(name);
  const Datatype stored{
      check_id(H5Dget_type(dataset.get()), dataset.get(), "", "read the type of")};
  if (!same_representation(stored.get(), mem_type))
    throw std::runtime_error("mesoflow::io: checkpoint '" + path_ + "': entry '" + name +
                             "' holds " + describe_type(stored.get()) + ", requested " +
                             describe_type(mem_type));
  const std::vector<hsize_t> dims = dataset_shape(dataset.get());
  return {dims.begin(), dims.end()};
}

void CheckpointReader::check_shape(const std::string& name, const std::vector<std::size_t>& stored,
                                   const std::vector<std::size_t>& expected) const {
  if (stored != expected)
    throw std::runtime_error("mesoflow::io: checkpoint '" + path_ + "': entry '" + name +
                             "' has shape " + shape_text(stored) + ", requested " +
                             shape_text(expected));
}

void CheckpointReader::read_array(const std::string& name, hid_t mem_type, void* out) const {
  read_dataset(open_entry(name).get(), mem_type, out);
}

double CheckpointReader::get_scalar_double(const std::string& name) const {
  double value = 0;
  get(name, &value, {});
  return value;
}

std::int64_t CheckpointReader::get_scalar_int64(const std::string& name) const {
  std::int64_t value = 0;
  get(name, &value, {});
  return value;
}

std::string CheckpointReader::get_string(const std::string& name) const {
  const std::vector<std::string> strings = read_strings(open_entry(name).get());
  if (strings.size() != 1)
    throw std::runtime_error("mesoflow::io: checkpoint '" + path_ + "': entry '" + name +
                             "' holds " + std::to_string(strings.size()) +
                             " strings, expected one");
  return strings.front();
}

bool checkpoint_exists(const std::string& path) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) return false;
  const File file = try_open_file(path, H5F_ACC_RDONLY);
  return file.valid() && H5Aexists(file.get(), kMarker) > 0;
}

}  // namespace mesoflow::io
