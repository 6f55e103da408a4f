// The options shared by simulating subcommands, and the error reporting of run_cli, in-process.
#include <omp.h>

#include <sstream>

#include <catch2/catch.hpp>

#include "studies/cli/app.hpp"
#include "studies/cli/common_options.hpp"
#include "tests/support/temp_dir.hpp"

using mfdem::CommonOptions;
using mfdem::cli::add_common_options;
using mfdem::cli::apply_thread_count;
using Catch::Matchers::Equals;

namespace {
CommonOptions parse_common(std::vector<const char*> arguments) {
  CommonOptions options;
  CLI::App command{"test"};
  add_common_options(command, options);
  arguments.insert(arguments.begin(), "mfdem");
  command.parse(static_cast<int>(arguments.size()), arguments.data());
  return options;
}
}  // namespace

TEST_CASE("common options parse into CommonOptions and record an explicit seed", "[cli]") {
  const auto options = parse_common({"--threads", "2", "--seed", "42", "--out", "scratch/run1", "--quiet"});
  CHECK(options.threads == 2);
  CHECK(options.seed == 42);
  CHECK(options.seed_given);
  CHECK(options.out == "scratch/run1");
  CHECK(options.quiet);
}

TEST_CASE("without options the defaults hold and the seed counts as not given", "[cli]") {
  const auto options = parse_common({});
  CHECK(options.threads == 0);
  CHECK(options.seed == 1);
  CHECK_FALSE(options.seed_given);
  CHECK(options.out == "out");
  CHECK_FALSE(options.quiet);
}

TEST_CASE("an explicit seed equal to the default still counts as given", "[cli]") {
  const auto options = parse_common({"--seed", "1"});
  CHECK(options.seed == 1);
  CHECK(options.seed_given);
}

TEST_CASE("the thread count sets OpenMP and 0 means all cores", "[cli]") {
  CommonOptions options;
  options.threads = 1;
  apply_thread_count(options);
  CHECK(omp_get_max_threads() == 1);
  options.threads = 0;
  apply_thread_count(options);
  CHECK(omp_get_max_threads() == omp_get_num_procs());
}

TEST_CASE("every line of an error message gets the mfdem prefix", "[cli]") {
  std::ostringstream err;
  mfdem::cli::print_error(err, "a.toml:2: unknown key 'x' in [top level]\na.toml:5: unknown key 'y' in [top level]");
  CHECK_THAT(err.str(), Equals("mfdem: error: a.toml:2: unknown key 'x' in [top level]\n"
                               "mfdem: error: a.toml:5: unknown key 'y' in [top level]\n"));
}

TEST_CASE("run_cli turns a config error into status 2 without output", "[cli]") {
  const mfdem::test::TempDir dir;
  const std::string file = dir.write("empty.toml", "").string();
  const std::vector<const char*> argv{"mfdem", "check", file.c_str()};
  std::ostringstream out, err;
  CHECK(mfdem::cli::run_cli(static_cast<int>(argv.size()), argv.data(), out, err) == 2);
  CHECK(out.str().empty());
  CHECK_THAT(err.str(), Catch::Matchers::StartsWith("mfdem: error: " + file + ": is empty"));
}
