// cli.cpp — DriverApp: parsing, validation, config files, --dry-run and the --output check.
#include "drivers/common/cli.hpp"

#include <stdexcept>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <system_error>

namespace mesoflow::cli {
namespace {

// ---- Numbers: parsed and printed with <charconv>, so locale-independent and exactly round-tripping.

// A leading '+' is accepted, as strtod would; from_chars itself rejects it.
std::string_view without_plus(std::string_view text) {
  if (text.size() > 1 && text.front() == '+' && text[1] != '+' && text[1] != '-') text.remove_prefix(1);
  return text;
}

template <class Number>
std::optional<Number> parse_number(std::string_view text) {
  text = without_plus(text);
  Number value{};
  const char* end = text.data() + text.size();
  const auto [stop, error] = std::from_chars(text.data(), end, value);
  if (error != std::errc() || stop != end) return std::nullopt;
  return value;
}

// The value of a single-valued option, as CLI11 hands it to the option's callback.
template <class Number>
std::optional<Number> parse_result(const CLI::results_t& results) {
  if (results.size() != 1) return std::nullopt;
  return parse_number<Number>(results.front());
}

// The shortest text that reads back to exactly `value` ("0.1", "1e-05", "inf").
std::string shortest(double value) {
  std::array<char, 32> buffer{};
  const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  return std::string(buffer.data(), result.ptr);
}

// As shortest(), but always a TOML float ("2.0" rather than the integer "2").
std::string toml_real(double value) {
  std::string text = shortest(value);
  if (text.find_first_of(".en") == std::string::npos) text += ".0";
  return text;
}

struct Interval {
  double lo;
  double hi;
  Bounds bounds;

  bool contains(double x) const {
    const bool lo_closed = bounds == Bounds::closed || bounds == Bounds::right_open;
    const bool hi_closed = bounds == Bounds::closed || bounds == Bounds::left_open;
    return (lo_closed ? x >= lo : x > lo) && (hi_closed ? x <= hi : x < hi);
  }
  bool contains_finite(double x) const { return std::isfinite(x) && contains(x); }

  std::string str() const {
    const bool lo_closed = bounds == Bounds::closed || bounds == Bounds::right_open;
    const bool hi_closed = bounds == Bounds::closed || bounds == Bounds::left_open;
    return (lo_closed ? "[" : "(") + shortest(lo) + ", " + shortest(hi) + (hi_closed ? "]" : ")");
  }
};

std::string joined(const std::vector<std::string>& words, const std::string& separator) {
  std::string text;
  for (const std::string& word : words) text += (text.empty() ? "" : separator) + word;
  return text;
}

std::string choice_list(const std::vector<std::string>& choices) { return "{" + joined(choices, ", ") + "}"; }

// `allowed` reads as a predicate: "in (0, 0.1]", ">= 1", "one of {dp, sp}".
void require_valid_default(const std::string& flag, bool valid, const std::string& value,
                           const std::string& allowed) {
  if (!valid) throw std::invalid_argument(flag + ": the default " + value + " is not " + allowed);
}

// ---- Validators. CLI11 prefixes their messages with the option name: "--dt: value nan is ...".

CLI::Validator real_validator(const Interval& allowed) {
  return CLI::Validator(
      [allowed](std::string& text) -> std::string {
        const std::optional<double> value = parse_number<double>(text);
        if (value && allowed.contains_finite(*value)) return {};
        return "value " + text + " is not a finite number in " + allowed.str();
      },
      "");
}

CLI::Validator integer_validator(const detail::IntegerRange& allowed) {
  return CLI::Validator(
      [allowed](std::string& text) -> std::string {
        const std::optional<long long> value = parse_number<long long>(text);
        if (value && allowed.contains(*value)) return {};
        return "value " + text + " is not an integer " + allowed.str();
      },
      "");
}

CLI::Validator choice_validator(const std::vector<std::string>& choices) {
  return CLI::Validator(
      [choices](std::string& text) -> std::string {
        if (std::find(choices.begin(), choices.end(), text) != choices.end()) return {};
        return "value " + text + " is not one of " + choice_list(choices);
      },
      "");
}

// ---- Config files.

// CLI11's TOML reader (which reads INI too), made strict. CLI11 2.1.2 reports an unknown key as
// "INI was not able to parse KEY" (also for TOML files) and a section header as "SECTION.++"; this
// reader names the key or section plainly, refuses keys of command-line-only flags, and refuses a
// string that CLI11 cut short: it ends a value at the first '#', even inside quotes.
class StrictConfig final : public CLI::ConfigTOML {
 public:
  explicit StrictConfig(const CLI::App& app) : app_(app) {}

  std::vector<CLI::ConfigItem> from_config(std::istream& input) const override {
    std::vector<CLI::ConfigItem> items = CLI::ConfigTOML::from_config(input);
    for (const CLI::ConfigItem& item : items) check(item);
    return items;
  }

 private:
  // CLI11 marks the opening and closing of a [section] with items named "++" and "--".
  static bool is_section_marker(const CLI::ConfigItem& item) { return item.name == "++" || item.name == "--"; }

  void check(const CLI::ConfigItem& item) const {
    if (is_section_marker(item)) throw CLI::ConfigError("unknown section [" + joined(item.parents, ".") + "]");
    const CLI::Option* option = item.parents.empty() ? find_option(item.name) : nullptr;
    if (option == nullptr) throw CLI::ConfigError("unknown key '" + item.fullname() + "'");
    if (!option->get_configurable()) {
      throw CLI::ConfigError("key '" + item.name + "' is a command-line flag only, not a config key");
    }
    if (std::any_of(item.inputs.begin(), item.inputs.end(), is_unterminated_string)) {
      throw CLI::ConfigError("key '" + item.name + "': unterminated string (a '#' starts a comment even in quotes)");
    }
  }

  // CLI11 has already removed a matching pair of quotes.
  static bool is_unterminated_string(const std::string& value) {
    const bool quoted = !value.empty() && (value.front() == '"' || value.front() == '\'');
    return quoted && (value.size() == 1 || value.back() != value.front());
  }

  // The lookup CLI11 itself applies to a config key.
  const CLI::Option* find_option(const std::string& key) const {
    const CLI::Option* option = app_.get_option_no_throw("--" + key);
    if (option == nullptr && key.size() == 1) option = app_.get_option_no_throw("-" + key);
    return option != nullptr ? option : app_.get_option_no_throw(key);
  }

  const CLI::App& app_;
};

std::string toml_string(const std::string& text) {
  // A TOML literal string needs no escapes, so backslashes in paths survive CLI11's reader, which
  // does not unescape; a text holding an apostrophe falls back to a basic string.
  if (text.find('\'') == std::string::npos) return "'" + text + "'";
  return "\"" + text + "\"";
}

std::string toml_comment(const std::string& text) {
  std::string comment = "# ";
  for (const char c : text) comment += c == '\n' ? std::string("\n# ") : std::string(1, c);
  return comment + "\n";
}

// ---- Files.

std::string system_message(int error_number) { return std::generic_category().message(error_number); }

std::string unreadable_reason(const std::string& path) {
  struct stat status {};
  if (::stat(path.c_str(), &status) != 0) return system_message(errno);
  if (S_ISDIR(status.st_mode)) return system_message(EISDIR);
  const int descriptor = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (descriptor < 0) return system_message(errno);
  ::close(descriptor);
  return "not a readable file";
}

std::string parent_directory(const std::string& path) {
  const std::string parent = std::filesystem::path(path).parent_path().string();
  return parent.empty() ? "." : parent;
}

// An existing file must open for writing; it is opened without truncation, so it is left untouched.
std::string existing_file_problem(const std::string& path, const struct stat& status) {
  if (S_ISDIR(status.st_mode)) return system_message(EISDIR);
  const int descriptor = ::open(path.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC);
  if (descriptor < 0) return "cannot open it for writing: " + system_message(errno);
  ::close(descriptor);
  return {};
}

// A new file must be creatable in an existing directory: a probe file is created there and removed.
std::string new_file_problem(const std::string& path) {
  const std::string directory = parent_directory(path);
  std::string probe = directory + "/.mesoflow-probe-XXXXXX";
  const int descriptor = ::mkstemp(probe.data());
  if (descriptor < 0) return "cannot create a file in " + directory + ": " + system_message(errno);
  ::close(descriptor);
  ::unlink(probe.c_str());
  return {};
}

// Why the output file cannot be written; empty when it can.
std::string output_problem(const std::string& path) {
  if (path.empty()) return "the path is empty";
  struct stat status {};
  if (::stat(path.c_str(), &status) == 0) return existing_file_problem(path, status);
  if (errno != ENOENT) return system_message(errno);
  return new_file_problem(path);
}

int usage_error(std::ostream& err, const std::string& message) {
  err << "error: " << message << "\nrun with --help for the list of parameters\n";
  return exit_code::usage;
}

int run_body(const std::function<void()>& body, std::ostream& err) {
  try {
    body();
  } catch (const std::invalid_argument& e) {  // parameters the option ranges alone cannot judge
    return usage_error(err, e.what());
  } catch (const std::exception& e) {
    err << "error: " << e.what() << '\n';
    return exit_code::failure;
  } catch (...) {
    err << "error: the run stopped on an exception of unknown type\n";
    return exit_code::failure;
  }
  return exit_code::success;
}

}  // namespace

std::string detail::IntegerRange::str() const {
  if (open_ended) return ">= " + std::to_string(lo);
  return "in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
}

DriverApp::DriverApp(const std::string& description, const std::string& default_output) : output_(default_output) {
  cli_.description(description);
  cli_.footer(
      "Every parameter is also a config-file key: its flag without the leading dashes.\n"
      "Precedence: defaults < --config file < command line. Exit codes: 0 success, 1 the run\n"
      "failed, 2 bad parameters (nothing ran).");
  cli_.config_formatter(std::make_shared<StrictConfig>(cli_));
  config_ = cli_.set_config("--config", "", "read parameters from a TOML or INI file");
  config_->type_name("FILE");
  cli_.add_flag("--dry-run", dry_run_, "print the resolved parameters as a TOML config file and exit")
      ->configurable(false);
  add_flag("--quiet", quiet_, "do not print the progress line");
  add_string("--output", output_, "output file; its directory must exist")->type_name("PATH");
}

CLI::Option* DriverApp::add_real(const std::string& flag, double& var, const std::string& description, double lo,
                                 double hi, Bounds bounds) {
  const Interval allowed{lo, hi, bounds};
  require_valid_default(flag, allowed.contains_finite(var), shortest(var), "in " + allowed.str());
  // Converted here rather than by CLI11, whose strtold-then-narrow can misround by one ulp.
  const auto assign = [&var](const CLI::results_t& results) {
    const std::optional<double> value = parse_result<double>(results);
    if (value) var = *value;
    return value.has_value();
  };
  CLI::Option* option = cli_.add_option(flag, assign, description);
  option->check(real_validator(allowed))->type_name("REAL in " + allowed.str());
  return add_parameter(option, description, ValueKind::number, [&var] { return toml_real(var); });
}

CLI::Option* DriverApp::add_positive(const std::string& flag, double& var, const std::string& description) {
  return add_real(flag, var, description, 0.0, std::numeric_limits<double>::infinity(), Bounds::open);
}

CLI::Option* DriverApp::add_integer(const std::string& flag, const std::string& description,
                                    const detail::IntegerRange& allowed, const std::function<long long()>& current,
                                    std::function<void(long long)> assign) {
  const long long default_value = current();
  require_valid_default(flag, allowed.contains(default_value), std::to_string(default_value), allowed.str());
  // Converted here rather than by CLI11, which reads "010" as octal 8.
  const auto convert = [assign = std::move(assign)](const CLI::results_t& results) {
    const std::optional<long long> value = parse_result<long long>(results);
    if (value) assign(*value);
    return value.has_value();
  };
  CLI::Option* option = cli_.add_option(flag, convert, description);
  option->check(integer_validator(allowed))->type_name("INT " + allowed.str());
  return add_parameter(option, description, ValueKind::number, [current] { return std::to_string(current()); });
}

CLI::Option* DriverApp::add_choice(const std::string& flag, std::string& var, const std::string& description,
                                   const std::vector<std::string>& choices) {
  const bool valid = std::find(choices.begin(), choices.end(), var) != choices.end();
  require_valid_default(flag, valid, var, "one of " + choice_list(choices));
  CLI::Option* option = cli_.add_option(flag, var, description);
  option->check(choice_validator(choices))->type_name(choice_list(choices));
  return add_parameter(option, description, ValueKind::text, [&var] { return var; });
}

CLI::Option* DriverApp::add_flag(const std::string& flag, bool& var, const std::string& description) {
  CLI::Option* option = cli_.add_flag(flag, var, description);
  return add_parameter(option, description, ValueKind::boolean, [&var] { return var ? "true" : "false"; });
}

CLI::Option* DriverApp::add_string(const std::string& flag, std::string& var, const std::string& description) {
  CLI::Option* option = cli_.add_option(flag, var, description)->type_name("TEXT");
  return add_parameter(option, description, ValueKind::text, [&var] { return var; });
}

CLI::Option* DriverApp::add_parameter(CLI::Option* option, const std::string& description, ValueKind kind,
                                      std::function<std::string()> value) {
  if (kind != ValueKind::boolean) option->default_str(value());  // shown by --help; a switch has none
  parameters_.push_back({option->get_single_name(), description, kind, std::move(value)});
  return option;
}

int DriverApp::run(int argc, const char* const argv[], const std::function<void()>& body, std::ostream& out,
                   std::ostream& err) {
  if (const std::optional<int> code = parse(argc, argv, out, err)) return *code;
  if (dry_run_) {
    out << to_toml();
    return exit_code::success;
  }
  if (const std::string problem = output_problem(output_); !problem.empty()) {
    return usage_error(err, "--output " + output_ + ": " + problem);
  }
  return run_body(body, err);
}

std::optional<int> DriverApp::parse(int argc, const char* const argv[], std::ostream& out, std::ostream& err) {
  try {
    cli_.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    out << cli_.help();
    return exit_code::success;
  } catch (const CLI::FileError&) {
    const std::string path = config_path();
    return usage_error(err, "--config " + path + ": cannot read the file: " + unreadable_reason(path));
  } catch (const CLI::ConfigError& e) {
    return usage_error(err, "--config " + config_path() + ": " + e.what());
  } catch (const CLI::ExtrasError&) {
    return usage_error(err, unexpected_arguments_message());
  } catch (const CLI::ParseError& e) {
    return usage_error(err, e.what());
  }
  return std::nullopt;
}

std::string DriverApp::config_path() const {
  const std::vector<std::string>& files = config_->results();
  return files.empty() ? std::string() : files.front();
}

// CLI11 2.1.2 lists unexpected arguments in reverse order; remaining() keeps the command-line order.
std::string DriverApp::unexpected_arguments_message() const {
  const std::vector<std::string> arguments = cli_.remaining();
  return (arguments.size() == 1 ? "unknown argument " : "unknown arguments ") + joined(arguments, " ");
}

RunParameters DriverApp::resolved_parameters() const {
  RunParameters resolved;
  resolved.reserve(parameters_.size());
  for (const Parameter& parameter : parameters_) resolved.emplace_back(parameter.key, parameter.value());
  return resolved;
}

std::string DriverApp::to_toml() const {
  std::ostringstream toml;
  toml << toml_comment(cli_.get_description()) << "# resolved parameters; read back with --config FILE\n";
  for (const Parameter& parameter : parameters_) {
    const std::string value = parameter.value();
    toml << '\n'
         << toml_comment(parameter.description) << parameter.key << " = "
         << (parameter.kind == ValueKind::text ? toml_string(value) : value) << '\n';
  }
  return toml.str();
}

}  // namespace mesoflow::cli
