// json_summary.hpp — the one JSON writer of the drivers' summaries (issue 24, item 1).
//
// A summary is an nlohmann::ordered_json (Debian's nlohmann-json3-dev): keys keep the order in
// which the driver sets them, doubles are written as the shortest text that reads back to the same
// double (so a summary compares bit for bit between runs), and strings are escaped by the library —
// no JSON is assembled from strings by hand. write_summary() writes to `<path>.tmp` and renames, so
// a reader never sees half a file. Non-finite numbers have no JSON form: they are written as null,
// and summary_number() makes that explicit where a driver has a value that may be missing.
#pragma once

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>

namespace mesoflow::cli {

using Json = nlohmann::ordered_json;

// A number, or null where it is not finite (a fit that did not converge, an empty sample).
inline Json summary_number(double x) { return std::isfinite(x) ? Json(x) : Json(nullptr); }

// Writes `summary` (indented by 2) to `path` atomically; throws std::runtime_error naming the path.
inline void write_summary(const std::string& path, const Json& summary) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp);
    if (!out) throw std::runtime_error("cannot write the summary " + path);
    out << summary.dump(2) << '\n';
    if (!out) throw std::runtime_error("cannot write the summary " + path);
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
    throw std::runtime_error("cannot move the summary into place: " + path);
}

}  // namespace mesoflow::cli
