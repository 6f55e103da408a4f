// `mfdem optimise-layer` refuses what cannot be searched before any run, naming the option and value.
#include <catch2/catch.hpp>

#include "tests/support/refusals.hpp"
#include "tests/support/temp_dir.hpp"

TEST_CASE("optimise-layer refuses bad families, ranges and seeds", "[cli][optimise]") {
  const mfdem::test::TempDir dir;
  const auto out = dir.path() / "opt";
  mfdem::test::check_refused_before_any_run("optimise-layer", "mini", out, {
      {{"--family", "layer-by-height"}, {"--family layer-by-height", "POLICY:EXTENT=LOWER:UPPER"}},
      {{"--family", "layer-by-height:mu_r=0:0.6"}, {"--family layer-by-height:mu_r=0:0.6", "one extent"}},
      {{"--family", "layer-by-height:h_fraction=0:0.8"}, {"h_fraction=0:0.8", "leaves no ball"}},
      {{"--family", "zone-by-distance:d=0.01:3"}, {"d=0.01:3", "no ball"}},
      {{"--family", "all-ball:h=0.1:0.2"}, {"--family all-ball", "layer-by-height or zone-by-distance"}},
      {{"--mu-r", "0.6:0"}, {"--mu-r", "empty range"}},
      {{"--seeds", "1"}, {"--seeds 1", "two seeds"}},
      {{"--uncalibrated", "layer-by-height:q=3"}, {"--uncalibrated"}},
  });
}
