// `mfdem calibrate` refuses what cannot be calibrated before any run, naming the option and value.
#include <catch2/catch.hpp>

#include "tests/support/refusals.hpp"
#include "tests/support/temp_dir.hpp"

TEST_CASE("calibrate refuses empty, ball-less and out-of-bed ranges, reused seeds and bad targets", "[cli][calibrate]") {
  const mfdem::test::TempDir dir;
  const auto out = dir.path() / "cal";
  mfdem::test::check_refused_before_any_run("calibrate", "mini", out, {
      {{"--parameters", "mu_r=0.6:0"}, {"--parameters", "mu_r=0.6:0", "empty range"}},
      {{"--parameters", "mu_r=0:0.6,h_fraction=0:0.8"}, {"h_fraction=0:0.8", "leaves no ball"}},
      {{"--parameters", "mu_r=0:0.6,h_fraction=0.3:2"}, {"h_fraction=0.3:2"}},
      {{"--policy", "zone-by-distance", "--parameters", "mu_r=0:0.6,d=0.01:3"}, {"d=0.01:3", "no ball"}},
      {{"--policy", "all-ball"}, {"--policy all-ball"}},
      {{"--verify-seeds", "3-4"}, {"--verify-seeds 3-4", "seed 3", "fresh"}},
      {{"--reference", "peak=12030"}, {"--reference peak=12030", "contact="}},
      {{"--seeds", ""}, {"--seeds"}},
      {{"--cheap-seeds", "1-3"}, {"--cheap-seeds 1-3", "fewer than the 3"}},
      {{"--cheap-cost", "0.3"}, {"--cheap-cost 0.3", "no cheap level"}},
      {{"--initial-cheap", "8"}, {"--initial-cheap 8", "no cheap level"}},
  });
}
