// The real `mfdem` executable: exit statuses and messages a user and a script rely on.
#include <catch2/catch.hpp>

#include "studies/cli/version.hpp"
#include "tests/support/run_mfdem.hpp"

using mfdem::test::run_mfdem;
using mfdem::test::TempDir;
using Catch::Matchers::Contains;
using Catch::Matchers::Equals;
using Catch::Matchers::StartsWith;

namespace {
constexpr int config_error = 2;  // also usage errors (studies/cli/app.hpp)
}

TEST_CASE("mfdem --version prints the version and the git revision", "[cli]") {
  const auto result = run_mfdem({"--version"});
  CHECK(result.status == 0);
  CHECK_FALSE(mfdem::cli::git_revision().empty());
  CHECK_THAT(result.out, Equals("mfdem 0.1.0 (git " + mfdem::cli::git_revision() + ")\n"));
}

TEST_CASE("mfdem version starts with the version line and names the compiler", "[cli]") {
  const auto result = run_mfdem({"version"});
  CHECK(result.status == 0);
  CHECK_THAT(result.out, StartsWith(mfdem::cli::version_line() + "\n") && Contains("compiler:") && Contains("OpenMP:"));
}

TEST_CASE("mfdem --help lists the subcommands and exits 0", "[cli]") {
  const auto result = run_mfdem({"--help"});
  CHECK(result.status == 0);
  CHECK_THAT(result.out, Contains("railway ballast") && Contains("run ") && Contains("check ") && Contains("version "));
  CHECK(result.err.empty());
}

TEST_CASE("mfdem run --help describes the run and the common options", "[cli]") {
  const auto result = run_mfdem({"run", "--help"});
  CHECK(result.status == 0);
  CHECK_THAT(result.out, Contains("Simulate a scene file") && Contains("--threads") && Contains("0 = all cores") &&
                             Contains("--seed") && Contains("--out") && Contains("--quiet") && Contains("--force-dt"));
}

TEST_CASE("mfdem check --help says what is checked", "[cli]") {
  const auto result = run_mfdem({"check", "--help"});
  CHECK(result.status == 0);
  CHECK_THAT(result.out, Contains("Validate scene files") && Contains("nearest valid") && Contains("OK: <file>"));
}

TEST_CASE("an unknown subcommand exits 2 and suggests the nearest", "[cli]") {
  const auto typo = run_mfdem({"chek", "scene.toml"});
  CHECK(typo.status == config_error);
  CHECK_THAT(typo.err, StartsWith("mfdem: error: unknown command 'chek'; did you mean 'check'?\n"));
  const auto unknown = run_mfdem({"frobnicate"});
  CHECK(unknown.status == config_error);
  // The list grows with new subcommands; these three are always there.
  CHECK_THAT(unknown.err, StartsWith("mfdem: error: unknown command 'frobnicate'; the commands are: ") &&
                              Contains("run") && Contains("check") && Contains("version"));
}

TEST_CASE("no subcommand is a usage error", "[cli]") {
  const auto result = run_mfdem({});
  CHECK(result.status == config_error);
  CHECK_THAT(result.err, StartsWith("mfdem: error: ") && Contains("mfdem --help"));
}

TEST_CASE("a negative thread count is a usage error naming --threads", "[cli]") {
  const auto result = run_mfdem({"run", "scene.toml", "--threads", "-1"});
  CHECK(result.status == config_error);
  CHECK_THAT(result.err, StartsWith("mfdem: error: --threads: must be 0 (all cores) or a positive count"));
}

TEST_CASE("mfdem check on a missing file exits 2 naming the file", "[cli]") {
  const TempDir dir;
  const auto file = (dir.path() / "missing.toml").string();
  const auto result = run_mfdem({"check", file});
  CHECK(result.status == config_error);
  CHECK_THAT(result.err, Equals("mfdem: error: " + file + ": no such file; expected a TOML config file (check the path)\n"));
  CHECK(result.out.empty());
}

TEST_CASE("mfdem check on an empty file exits 2", "[cli]") {
  const TempDir dir;
  const auto file = dir.write("empty.toml", "").string();
  const auto result = run_mfdem({"check", file});
  CHECK(result.status == config_error);
  CHECK_THAT(result.err, StartsWith("mfdem: error: " + file + ": is empty; expected a TOML config with"));
}

TEST_CASE("mfdem check on binary garbage exits 2", "[cli]") {
  const TempDir dir;
  const auto file = dir.write("garbage.toml", std::string("\x1f\x8b\x08\0\0\0\0\0", 8)).string();  // a gzip header
  const auto result = run_mfdem({"check", file});
  CHECK(result.status == config_error);
  CHECK_THAT(result.err, Equals("mfdem: error: " + file + ":1: not a text file (binary byte 0x1f at byte offset 0); "
                                "expected a TOML config in UTF-8 text\n"));
}

TEST_CASE("mfdem check on a TOML syntax error exits 2 with the line", "[cli]") {
  const TempDir dir;
  const auto file = dir.write("broken.toml", "[sleeper\nmass = 380\n").string();
  const auto result = run_mfdem({"check", file});
  CHECK(result.status == config_error);
  CHECK_THAT(result.err, StartsWith("mfdem: error: " + file + ":1:") && Contains("TOML syntax error"));
}

TEST_CASE("mfdem check reports every bad file and exits 2", "[cli]") {
  const TempDir dir;
  const auto empty = dir.write("empty.toml", "").string();
  const auto missing = (dir.path() / "missing.toml").string();
  const auto result = run_mfdem({"check", empty, missing});
  CHECK(result.status == config_error);
  CHECK_THAT(result.err, Contains(empty + ": is empty") && Contains(missing + ": no such file"));
}
