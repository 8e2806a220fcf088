// Tests of the driver command-line conventions (DriverApp), ProgressLine and KernelTimers.
// Every DriverApp test runs a small in-process driver on an argv vector and checks the exit code
// and the text written to its out and err streams.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "drivers/common/cli.hpp"
#include "drivers/common/progress.hpp"

namespace mesoflow::cli {
namespace {

namespace fs = std::filesystem;

::testing::AssertionResult Contains(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "\"" << part << "\" is not in:\n" << text;
}

struct Parameters {
  double dt = 0.001;
  double temperature = 1.0;
  int steps = 100;
  std::size_t particles = 1000;
  std::string model = "dp";
};

class CliDriverApp : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("mesoflow-test-cli-" + std::to_string(::getpid()) + "-" + test->test_suite_name() + "-" + test->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Runs a driver with the parameters of `Parameters` on `args`; fills params, out, err, ran, resolved.
  int run(const std::vector<std::string>& args) {
    params = Parameters{};
    DriverApp app("test driver", (dir_ / "out.h5").string());
    app.add_real("--dt", params.dt, "time step", 0.0, 0.1, Bounds::left_open);
    app.add_positive("--temperature", params.temperature, "thermostat temperature kT");
    app.add_int("--steps", params.steps, "number of time steps", 1, 1000000);
    app.add_positive("--particles", params.particles, "number of particles");
    app.add_choice("--model", params.model, "fluid model", {"dp", "sp"});

    std::vector<const char*> argv{"test_driver"};
    for (const std::string& arg : args) argv.push_back(arg.c_str());
    std::ostringstream out_stream;
    std::ostringstream err_stream;
    ran = false;
    const int code = app.run(
        static_cast<int>(argv.size()), argv.data(),
        [&] {
          ran = true;
          resolved = app.resolved_parameters();
        },
        out_stream, err_stream);
    out = out_stream.str();
    err = err_stream.str();
    return code;
  }

  std::string write_file(const std::string& name, const std::string& text) const {
    const fs::path path = dir_ / name;
    std::ofstream(path) << text;
    return path.string();
  }

  // Expects a usage error: exit code 2, nothing ran, and an error message that contains every part.
  void expect_usage_error(const std::vector<std::string>& args, const std::vector<std::string>& parts) {
    EXPECT_EQ(run(args), exit_code::usage);
    EXPECT_FALSE(ran);
    EXPECT_EQ(err.rfind("error: ", 0), 0u) << err;
    EXPECT_TRUE(Contains(err, "run with --help for the list of parameters"));
    for (const std::string& part : parts) EXPECT_TRUE(Contains(err, part));
  }

  Parameters params;
  std::string out;
  std::string err;
  bool ran = false;
  RunParameters resolved;
  fs::path dir_;
};

using CliErrors = CliDriverApp;

// ---- What a driver gets.

TEST_F(CliDriverApp, HelpReturnsZeroAndListsEveryParameter) {
  EXPECT_EQ(run({"--help"}), exit_code::success);
  EXPECT_FALSE(ran);
  for (const char* flag :
       {"--help", "--config", "--dry-run", "--quiet", "--output", "--dt", "--temperature", "--steps", "--model"}) {
    EXPECT_TRUE(Contains(out, flag));
  }
  EXPECT_TRUE(Contains(out, "--dt REAL in (0, 0.1]=0.001"));
  EXPECT_TRUE(Contains(out, "--particles INT >= 1=1000"));
  EXPECT_TRUE(Contains(out, "--quiet "));
  EXPECT_FALSE(Contains(out, "--quiet="));
  EXPECT_EQ(err, "");
}

TEST_F(CliDriverApp, DefaultsReachTheBody) {
  EXPECT_EQ(run({}), exit_code::success);
  EXPECT_TRUE(ran);
  EXPECT_EQ(params.dt, 0.001);
  EXPECT_EQ(params.steps, 100);
  EXPECT_EQ(params.model, "dp");
  EXPECT_EQ(err, "");
}

TEST_F(CliDriverApp, FlagsSetValues) {
  EXPECT_EQ(run({"--dt", "0.05", "--steps=7", "--model", "sp", "--temperature", "+2.5"}), exit_code::success);
  EXPECT_EQ(params.dt, 0.05);
  EXPECT_EQ(params.steps, 7);
  EXPECT_EQ(params.model, "sp");
  EXPECT_EQ(params.temperature, 2.5);
}

TEST_F(CliDriverApp, IntegersAreDecimalEvenWithLeadingZeros) {
  EXPECT_EQ(run({"--steps", "010"}), exit_code::success);
  EXPECT_EQ(params.steps, 10);
}

TEST_F(CliDriverApp, ResolvedParametersListEveryKeyWithItsValue) {
  EXPECT_EQ(run({"--dt", "0.02", "--quiet"}), exit_code::success);
  const RunParameters expected{{"quiet", "true"},   {"output", (dir_ / "out.h5").string()},
                               {"dt", "0.02"},      {"temperature", "1.0"},
                               {"steps", "100"},    {"particles", "1000"},
                               {"model", "dp"}};
  EXPECT_EQ(resolved, expected);
}

TEST_F(CliDriverApp, DryRunPrintsTomlThatRoundTripsThroughConfig) {
  const std::vector<std::string> args{"--dt",    "0.0123456789012345",
                                      "--steps", "42",
                                      "--model", "sp",
                                      "--temperature", "3",
                                      "--output", (dir_ / "dir with space/o.h5").string()};
  fs::create_directories(dir_ / "dir with space");
  EXPECT_EQ(run(args), exit_code::success);
  const RunParameters from_flags = resolved;

  EXPECT_EQ(run([&] {
              std::vector<std::string> dry = args;
              dry.push_back("--dry-run");
              return dry;
            }()),
            exit_code::success);
  EXPECT_FALSE(ran);
  EXPECT_TRUE(Contains(out, "dt = 0.0123456789012345\n"));
  EXPECT_TRUE(Contains(out, "temperature = 3.0\n"));
  EXPECT_TRUE(Contains(out, "model = 'sp'\n"));
  EXPECT_TRUE(Contains(out, "# time step\n"));
  EXPECT_FALSE(Contains(out, "dry-run"));

  EXPECT_EQ(run({"--config", write_file("dry-run.toml", out)}), exit_code::success) << err;
  EXPECT_EQ(params.dt, 0.0123456789012345);
  EXPECT_EQ(params.steps, 42);
  EXPECT_EQ(params.model, "sp");
  EXPECT_EQ(params.temperature, 3.0);
  EXPECT_EQ(resolved, from_flags);
}

TEST_F(CliDriverApp, TomlConfigFileSetsValues) {
  const std::string config = write_file("run.toml",
                                        "# a comment\n"
                                        "dt = 0.05  # trailing comment\n"
                                        "steps = 12\n"
                                        "model = \"sp\"\n"
                                        "quiet = true\n");
  EXPECT_EQ(run({"--config", config}), exit_code::success) << err;
  EXPECT_EQ(params.dt, 0.05);
  EXPECT_EQ(params.steps, 12);
  EXPECT_EQ(params.model, "sp");
  EXPECT_EQ(resolved.front(), (std::pair<std::string, std::string>{"quiet", "true"}));
}

TEST_F(CliDriverApp, IniConfigFileSetsValues) {
  const std::string config = write_file("run.ini",
                                        "; a comment\n"
                                        "[default]\n"
                                        "dt=0.05\n"
                                        "model=sp\n");
  EXPECT_EQ(run({"--config", config}), exit_code::success) << err;
  EXPECT_EQ(params.dt, 0.05);
  EXPECT_EQ(params.model, "sp");
}

TEST_F(CliDriverApp, CommandLineOverridesConfig) {
  const std::string config = write_file("run.toml", "dt = 0.05\nsteps = 12\n");
  EXPECT_EQ(run({"--steps", "13", "--config", config}), exit_code::success) << err;
  EXPECT_EQ(params.dt, 0.05);
  EXPECT_EQ(params.steps, 13);
}

TEST_F(CliDriverApp, BodyExceptionReturnsFailureWithItsMessage) {
  DriverApp app("test driver", (dir_ / "out.h5").string());
  const char* argv[] = {"test_driver"};
  std::ostringstream out_stream;
  std::ostringstream err_stream;
  const int code = app.run(
      1, argv, [] { throw std::runtime_error("particle 7 left the box"); }, out_stream, err_stream);
  EXPECT_EQ(code, exit_code::failure);
  EXPECT_EQ(err_stream.str(), "error: particle 7 left the box\n");
}

TEST_F(CliDriverApp, DefaultOutsideItsRangeIsAProgrammingError) {
  DriverApp app("test driver", "out.h5");
  double dt = 0.5;
  int steps = 0;
  std::string model = "xx";
  double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(app.add_real("--dt", dt, "time step", 0.0, 0.1), std::invalid_argument);
  EXPECT_THROW(app.add_positive("--steps", steps, "steps"), std::invalid_argument);
  EXPECT_THROW(app.add_choice("--model", model, "model", {"dp", "sp"}), std::invalid_argument);
  EXPECT_THROW(app.add_positive("--kt", nan, "temperature"), std::invalid_argument);
  EXPECT_THROW(app.add_int("--steps", steps, "steps", 0, 1LL << 40), std::invalid_argument);
}

// ---- Bad input: exit code 2 and a message naming what is wrong.

TEST_F(CliErrors, MissingConfigFileIsNamed) {
  const std::string missing = (dir_ / "missing.toml").string();
  expect_usage_error({"--config", missing}, {"--config " + missing, "No such file or directory"});
}

TEST_F(CliErrors, OutOfRangeValueNamesOptionAndRange) {
  expect_usage_error({"--dt", "0.5"}, {"--dt: value 0.5 is not a finite number in (0, 0.1]"});
  expect_usage_error({"--dt", "0"}, {"--dt: value 0 is not a finite number in (0, 0.1]"});
  expect_usage_error({"--steps", "0"}, {"--steps: value 0 is not an integer in [1, 1000000]"});
  expect_usage_error({"--particles", "-5"}, {"--particles: value -5 is not an integer >= 1"});
}

TEST_F(CliErrors, NanIsRejected) {
  expect_usage_error({"--dt", "nan"}, {"--dt: value nan is not a finite number in (0, 0.1]"});
  expect_usage_error({"--temperature", "NaN"}, {"--temperature: value NaN is not a finite number in (0, inf)"});
  expect_usage_error({"--config", write_file("nan.toml", "dt = nan\n")},
                     {"--dt: value nan is not a finite number"});
}

TEST_F(CliErrors, InfinityIsRejected) {
  expect_usage_error({"--temperature", "inf"}, {"--temperature: value inf is not a finite number in (0, inf)"});
  expect_usage_error({"--dt", "-inf"}, {"--dt: value -inf is not a finite number"});
  expect_usage_error({"--temperature", "1e400"}, {"--temperature: value 1e400 is not a finite number"});
}

TEST_F(CliErrors, NonNumericTextIsRejected) {
  expect_usage_error({"--dt", "fast"}, {"--dt: value fast is not a finite number in (0, 0.1]"});
  expect_usage_error({"--dt", "0.01s"}, {"--dt: value 0.01s is not a finite number"});
  expect_usage_error({"--steps", "many"}, {"--steps: value many is not an integer in [1, 1000000]"});
}

TEST_F(CliErrors, FractionalIntegerIsRejected) {
  expect_usage_error({"--steps", "2.5"}, {"--steps: value 2.5 is not an integer in [1, 1000000]"});
}

TEST_F(CliErrors, UnknownChoiceListsTheChoices) {
  expect_usage_error({"--model", "mpc"}, {"--model: value mpc is not one of {dp, sp}"});
}

TEST_F(CliErrors, UnknownConfigKeyIsNamed) {
  const std::string config = write_file("typo.toml", "dt = 0.05\ntemprature = 2.0\n");
  expect_usage_error({"--config", config}, {"--config " + config + ": unknown key 'temprature'"});
}

TEST_F(CliErrors, UnknownConfigSectionIsNamed) {
  const std::string config = write_file("section.toml", "[fluid]\ndt = 0.05\n");
  expect_usage_error({"--config", config}, {"unknown section [fluid]"});
}

TEST_F(CliErrors, CommandLineOnlyFlagInConfigIsNamed) {
  const std::string config = write_file("flags.toml", "dry-run = true\n");
  expect_usage_error({"--config", config}, {"key 'dry-run' is a command-line flag only"});
}

TEST_F(CliErrors, StringCutShortByHashIsRejected) {
  const std::string config = write_file("hash.toml", "output = \"run#1.h5\"\n");
  expect_usage_error({"--config", config}, {"key 'output': unterminated string"});
}

TEST_F(CliErrors, UnknownFlagIsNamed) {
  expect_usage_error({"--dtt", "0.05"}, {"unknown arguments --dtt 0.05"});
  expect_usage_error({"stray"}, {"unknown argument stray"});
}

TEST_F(CliErrors, UnwritableOutputNamesThePath) {
  expect_usage_error(
      {"--output", "/nonexistent-dir/out.h5"},
      {"--output /nonexistent-dir/out.h5: cannot create a file in /nonexistent-dir", "No such file or directory"});
  expect_usage_error({"--output", dir_.string()}, {"--output " + dir_.string() + ": Is a directory"});
}

TEST_F(CliErrors, OutputCheckLeavesNoProbeFileBehind) {
  EXPECT_EQ(run({"--output", (dir_ / "new.h5").string()}), exit_code::success);
  EXPECT_TRUE(fs::is_empty(dir_));
}

// ---- ProgressLine and KernelTimers.

TEST(CliProgressLine, DisabledPrintsNothing) {
  std::ostringstream out;
  ProgressLine progress(100, 1000, false, out, ProgressLine::Clock::duration::zero());
  for (int step = 1; step <= 100; ++step) progress.update(step);
  progress.finish();
  EXPECT_EQ(out.str(), "");
}

TEST(CliProgressLine, EnabledPrintsParsableLines) {
  std::ostringstream out;
  ProgressLine progress(100, 1000, true, out, ProgressLine::Clock::duration::zero());
  for (int step = 1; step <= 100; ++step) progress.update(step);
  progress.finish();

  const std::regex progress_line(
      R"(step (\d+)/100 \(\d+\.\d%\)  \d\.\de[+-]\d+ steps/s  \d\.\de[+-]\d+ particle-updates/s  ETA \d+:\d\d:\d\d)");
  const std::regex summary_line(
      R"(done: 100 steps in \d+:\d\d:\d\d \(.+ s\)  mean \d\.\de[+-]\d+ steps/s  \d\.\de[+-]\d+ particle-updates/s)");
  std::istringstream lines(out.str());
  std::vector<std::string> printed;
  for (std::string line; std::getline(lines, line);) printed.push_back(line);
  ASSERT_GE(printed.size(), 2u);
  for (std::size_t i = 0; i + 1 < printed.size(); ++i) {
    EXPECT_TRUE(std::regex_match(printed[i], progress_line)) << printed[i];
  }
  EXPECT_TRUE(std::regex_match(printed.back(), summary_line)) << printed.back();
  EXPECT_EQ(out.str().find('\r'), std::string::npos);
}

TEST(CliKernelTimers, TableListsEveryKernelWithItsCalls) {
  KernelTimers timers;
  for (int i = 0; i < 3; ++i) {
    ScopedTimer timer(timers, "neighbor");
  }
  { ScopedTimer timer(timers, "pair_force"); }
  std::ostringstream out;
  timers.print(out);
  const std::string table = out.str();
  EXPECT_TRUE(Contains(table, "% of run"));
  EXPECT_TRUE(std::regex_search(table, std::regex(R"(neighbor +\d+\.\d{3} +\d+\.\d +3\n)"))) << table;
  EXPECT_TRUE(std::regex_search(table, std::regex(R"(pair_force +\d+\.\d{3} +\d+\.\d +1\n)"))) << table;
  EXPECT_TRUE(std::regex_search(table, std::regex(R"(\nrun +\d+\.\d{3} +100\.0\n)"))) << table;
}

}  // namespace
}  // namespace mesoflow::cli
