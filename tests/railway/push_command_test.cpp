// `mfdem pack` and `mfdem push` refuse bad input with a message naming it (exit status 1 for a
// failure while running, 2 for a bad command line), before any simulation starts.
#include <catch2/catch.hpp>

#include "tests/support/run_mfdem.hpp"
#include "tests/support/temp_dir.hpp"

using mfdem::test::run_mfdem;

TEST_CASE("pack and push name the input they cannot use", "[railway][cli]") {
  const mfdem::test::TempDir dir;
  const std::string out = (dir.path() / "out").string();
  const auto missing = run_mfdem({"push", (dir.path() / "nowhere").string(), "--out", out, "-q"});
  CHECK(missing.status == 1);
  CHECK_THAT(missing.err, Catch::Contains("nowhere") && Catch::Contains("no such file") &&
                              Catch::Contains("mfdem pack"));
  CHECK_THAT(missing.err, !Catch::Contains("HDF5-DIAG"));  // our message, not HDF5's stack
  const auto preset = run_mfdem({"pack", "maxi", "--out", out, "-q"});
  CHECK(preset.status == 1);
  CHECK_THAT(preset.err, Catch::Contains("maxi") && Catch::Contains("mini, standard and paper"));
  const auto velocity = run_mfdem({"push", out, "--velocity", "-5"});
  CHECK(velocity.status == 2);
  CHECK_THAT(velocity.err, Catch::Contains("--velocity"));
}
