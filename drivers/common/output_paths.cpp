#include "drivers/common/output_paths.hpp"

#include "io/hdf5_util.hpp"

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <stdexcept>

namespace mesoflow::driver {

OutputPaths::OutputPaths(const std::string& output) {
  const auto slash = output.find_last_of('/');
  const auto dot = output.find_last_of('.');
  const std::string stem =
      dot != std::string::npos && (slash == std::string::npos || dot > slash) ? output.substr(0, dot) : output;
  trajectory = output;
  xdmf = stem + ".xdmf";
  csv = stem + ".csv";
  summary = stem + ".json";
  checkpoint = stem + ".ckpt.h5";
}

void write_observables_csv(const std::string& h5md_path, const std::string& csv_path,
                           const std::vector<std::string>& names) {
  if (names.empty()) throw std::invalid_argument("write_observables_csv: no observables named");
  const std::string first = "/observables/" + names.front();
  const auto steps = io::read_dataset_int64(h5md_path, first + "/step");
  const auto times = io::read_dataset_double(h5md_path, first + "/time");
  std::vector<io::ArrayData<double>> columns;
  for (const auto& name : names) {
    columns.push_back(io::read_dataset_double(h5md_path, "/observables/" + name + "/value"));
    if (columns.back().values.size() != steps.values.size())
      throw std::runtime_error("observable " + name + " in " + h5md_path + " has " +
                               std::to_string(columns.back().values.size()) + " samples, " + names.front() +
                               " has " + std::to_string(steps.values.size()));
  }
  std::ofstream csv(csv_path);
  if (!csv) throw std::runtime_error("cannot write " + csv_path);
  csv << "step,time";
  for (const auto& name : names) csv << ',' << name;
  csv << '\n' << std::setprecision(12);
  for (std::size_t k = 0; k < steps.values.size(); ++k) {
    csv << steps.values[k] << ',' << times.values[k];
    for (const auto& c : columns) csv << ',' << c.values[k];
    csv << '\n';
  }
  if (!csv) throw std::runtime_error("error while writing " + csv_path);
}

void write_atomically(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp);
    f << text;
    if (!f) throw std::runtime_error("cannot write " + tmp);
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) throw std::runtime_error("cannot rename " + tmp + " to " + path);
}

std::string tag(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

void plot_with_matplotlib(const std::string& driver, const std::string& script, const std::vector<std::string>& arguments,
                          const std::string& png, bool quiet) {
  auto quoted = [](const std::string& a) {
    std::string q = "'";
    for (char c : a) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
  };
  std::string command = "/usr/bin/python3 " + quoted(std::string(MESOFLOW_SOURCE_DIR) + "/scripts/" + script);
  for (const auto& a : arguments) command += " " + quoted(a);
  if (quiet) command += " >/dev/null 2>&1";
  if (std::system(command.c_str()) != 0)
    std::cerr << driver << ": warning: the plot " << png << " was not written (python3-matplotlib missing?)\n";
}

}  // namespace mesoflow::driver
