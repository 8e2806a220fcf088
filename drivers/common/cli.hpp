// cli.hpp — the command-line conventions shared by every mesoflow driver.
//
// DriverApp wraps CLI::App (CLI11) so that every driver gets the same built-in parameters (--help,
// --config, --dry-run, --quiet, --output), numeric parameters whose errors name the parameter and its
// allowed range, and one entry point, run(), that maps every outcome to an exit code.
// docs/command-line.md describes the conventions for users.
#pragma once

#include <CLI/CLI.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <functional>
#include <iostream>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace mesoflow::cli {

// Exit codes of DriverApp::run().
namespace exit_code {
inline constexpr int success = 0;  // the run finished, or --help / --dry-run was answered
inline constexpr int failure = 1;  // the driver body threw
inline constexpr int usage = 2;    // bad command line, config file or --output path: nothing ran
}  // namespace exit_code

// Which ends belong to an allowed range lo..hi: [lo, hi], (lo, hi), (lo, hi], [lo, hi).
enum class Bounds { closed, open, left_open, right_open };

// Resolved parameters as (config key, value) pairs in registration order; values are written as in
// the --dry-run TOML, without the quotes around strings.
using RunParameters = std::vector<std::pair<std::string, std::string>>;

namespace detail {

template <class Int>
inline constexpr bool is_integer_v = std::is_integral_v<Int> && !std::is_same_v<Int, bool>;

template <class Int>
constexpr bool representable(long long value) {
  if constexpr (std::is_signed_v<Int>) {
    return value >= static_cast<long long>(std::numeric_limits<Int>::min()) &&
           value <= static_cast<long long>(std::numeric_limits<Int>::max());
  } else {
    return value >= 0 && static_cast<unsigned long long>(value) <= std::numeric_limits<Int>::max();
  }
}

// The largest value of Int that a long long holds too.
template <class Int>
constexpr long long max_value() {
  constexpr auto limit = static_cast<unsigned long long>(std::numeric_limits<long long>::max());
  return static_cast<long long>(std::min<unsigned long long>(std::numeric_limits<Int>::max(), limit));
}

// The values an integer parameter accepts.
struct IntegerRange {
  long long lo;
  long long hi;
  bool open_ended;  // hi is only the limit of the parameter's type

  bool contains(long long value) const { return value >= lo && value <= hi; }
  std::string str() const;  // "in [1, 100]", or ">= 1" when open-ended
};

}  // namespace detail

class DriverApp {
 public:
  // default_output: the --output path used when neither a config file nor a flag sets one.
  DriverApp(const std::string& description, const std::string& default_output);
  DriverApp(const DriverApp&) = delete;
  DriverApp& operator=(const DriverApp&) = delete;

  // Parameters. Each is a flag (--name VALUE) and a config key (name = VALUE). `var` holds the
  // default and, once run() has parsed, the resolved value. A default that the parameter itself
  // would reject throws std::invalid_argument, so a driver cannot ship an unusable default.

  // A finite real number in lo..hi; NaN and ±inf are always rejected.
  CLI::Option* add_real(const std::string& flag, double& var, const std::string& description, double lo, double hi,
                        Bounds bounds = Bounds::closed);
  // A finite real number > 0.
  CLI::Option* add_positive(const std::string& flag, double& var, const std::string& description);

  // A decimal integer in [lo, hi]; both bounds must fit in Int. With hi the largest Int, the range
  // is shown as ">= lo".
  template <class Int, std::enable_if_t<detail::is_integer_v<Int>, int> = 0>
  CLI::Option* add_int(const std::string& flag, Int& var, const std::string& description, long long lo,
                       long long hi) {
    if (!detail::representable<Int>(lo) || !detail::representable<Int>(hi)) {
      throw std::invalid_argument(flag + ": the range [" + std::to_string(lo) + ", " + std::to_string(hi) +
                                  "] does not fit the parameter's integer type");
    }
    const detail::IntegerRange allowed{lo, hi, hi == detail::max_value<Int>()};
    return add_integer(
        flag, description, allowed, [&var] { return static_cast<long long>(var); },
        [&var](long long value) { var = static_cast<Int>(value); });
  }
  // A decimal integer >= 1.
  template <class Int, std::enable_if_t<detail::is_integer_v<Int>, int> = 0>
  CLI::Option* add_positive(const std::string& flag, Int& var, const std::string& description) {
    return add_int(flag, var, description, 1, detail::max_value<Int>());
  }

  // One of a fixed set of words.
  CLI::Option* add_choice(const std::string& flag, std::string& var, const std::string& description,
                          const std::vector<std::string>& choices);
  // A switch: --name sets it, a config file says name = true or name = false.
  CLI::Option* add_flag(const std::string& flag, bool& var, const std::string& description);
  // Free text, such as a file name.
  CLI::Option* add_string(const std::string& flag, std::string& var, const std::string& description);

  // Parses argv (defaults < --config file < command line), then answers --help or --dry-run, or
  // checks that --output can be written and calls body. Messages go to out and err; returns an
  // exit_code. Never throws for bad input: errors are printed as "error: <message>".
  int run(int argc, const char* const argv[], const std::function<void()>& body, std::ostream& out = std::cout,
          std::ostream& err = std::cerr);

  const std::string& output() const { return output_; }
  bool quiet() const { return quiet_; }

  // The parameters as they are now (after run(): as resolved), e.g. for HDF5 attributes.
  RunParameters resolved_parameters() const;
  // The parameters as a TOML config file that --config reads back to the same values (--dry-run).
  std::string to_toml() const;

 private:
  enum class ValueKind { number, boolean, text };
  struct Parameter {
    std::string key;
    std::string description;
    ValueKind kind;
    std::function<std::string()> value;
  };

  CLI::Option* add_integer(const std::string& flag, const std::string& description,
                           const detail::IntegerRange& allowed, const std::function<long long()>& current,
                           std::function<void(long long)> assign);
  CLI::Option* add_parameter(CLI::Option* option, const std::string& description, ValueKind kind,
                             std::function<std::string()> value);
  // The exit code when parsing ends the run (help, or an error); nothing when the run goes on.
  std::optional<int> parse(int argc, const char* const argv[], std::ostream& out, std::ostream& err);
  std::string config_path() const;
  std::string unexpected_arguments_message() const;

  CLI::App cli_;
  std::vector<Parameter> parameters_;
  CLI::Option* config_ = nullptr;
  std::string output_;
  bool quiet_ = false;
  bool dry_run_ = false;
};

// The comma list `text` of option `flag`: each item a number that `accept` takes (else an
// error naming the option, the item and `range`), at least one.
template <class Accept>
std::vector<double> parse_number_list(const std::string& text, const std::string& flag, const Accept& accept,
                                      const std::string& range) {
  std::vector<double> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    std::size_t used = 0;
    double v = 0;
    try {
      v = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size() || !std::isfinite(v) || !accept(v))
      throw std::invalid_argument(flag + ": each value must be a number " + range + ", got '" + item + "'");
    out.push_back(v);
  }
  if (out.empty()) throw std::invalid_argument(flag + ": at least one value, got '" + text + "'");
  return out;
}

// The comma list `text` of option `flag`, each value in (lo, hi] (parse_number_list).
inline std::vector<double> parse_number_list_in(const std::string& text, const std::string& flag, double lo,
                                                double hi) {
  std::ostringstream range;
  range << "in (" << lo << ", " << hi << "]";
  return parse_number_list(text, flag, [=](double v) { return v > lo && v <= hi; }, range.str());
}

// A CLI11 check of option `flag`: its text is a comma list of values in (lo, hi]
// (parse_number_list_in), else the error names the option, the item and the range.
inline CLI::Validator number_list_check(const std::string& flag, double lo, double hi) {
  return CLI::Validator(
      [=](std::string& text) {
        try {
          parse_number_list_in(text, flag, lo, hi);
          return std::string();
        } catch (const std::exception& e) {
          return std::string(e.what());
        }
      },
      "LIST");
}

// A comma-separated list of finite reals in the closed range [lo, hi] (std::from_chars: no locale);
// the error names the flag, the item and the range.
inline std::vector<double> parse_real_list(const std::string& flag, const std::string& text, double lo, double hi) {
  std::vector<double> values;
  std::stringstream in(text);
  std::string item;
  const std::string range = "comma-separated reals in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  while (std::getline(in, item, ',')) {
    item.erase(0, item.find_first_not_of(' '));
    item.erase(item.find_last_not_of(' ') + 1);
    double v = 0;
    const auto [end, error] = std::from_chars(item.data(), item.data() + item.size(), v);
    if (item.empty() || error != std::errc() || end != item.data() + item.size() || !std::isfinite(v) || v < lo ||
        v > hi)
      throw std::invalid_argument(flag + ": value '" + item + "' in '" + text + "' is not allowed; expected " + range);
    values.push_back(v);
  }
  if (values.empty()) throw std::invalid_argument(flag + ": empty list; expected " + range);
  return values;
}


}  // namespace mesoflow::cli
