// output_paths.hpp — the files a driver writes, all named after its --output path, and the small
// CSV summary written beside the HDF5 file.
#pragma once

#include <string>
#include <vector>

namespace mesoflow::driver {

// For --output run.h5: run.h5 (H5MD), run.xdmf, run.csv, run.json, run.ckpt.h5.
struct OutputPaths {
  std::string trajectory, xdmf, csv, summary, checkpoint;

  explicit OutputPaths(const std::string& output);
};

// Writes the scalar observables `names` of an H5MD file as CSV columns step,time,<names...>.
void write_observables_csv(const std::string& h5md_path, const std::string& csv_path,
                           const std::vector<std::string>& names);

// Writes `text` to `path` atomically: a temporary beside it, then a rename.
void write_atomically(const std::string& path, const std::string& text);

// A number as a default std::ostream writes it (6 significant digits), for file names and labels.
std::string tag(double v);

// Runs scripts/<script> of the source tree with Debian's /usr/bin/python3 (python3-matplotlib;
// whatever python3 comes first on PATH may lack it) and `arguments`, each single-quoted, to write
// `png`. A failure is a warning naming the plot, not an error: the CSV beside it holds the data.
void plot_with_matplotlib(const std::string& driver, const std::string& script, const std::vector<std::string>& arguments,
                          const std::string& png, bool quiet);

}  // namespace mesoflow::driver
