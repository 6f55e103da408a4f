// `mfdem stats` refuses what cannot be run before any run, naming the option and the value.
#include <catch2/catch.hpp>

#include "tests/support/refusals.hpp"
#include "tests/support/temp_dir.hpp"

TEST_CASE("stats refuses bad models, seeds, widths and control variates", "[cli][stats]") {
  const mfdem::test::TempDir dir;
  const auto out = dir.path() / "stats";
  mfdem::test::check_refused_before_any_run("stats", "mini", out, {
      {{"--model", "layer-by-height:q=3"}, {"--model"}},
      {{"--model", "all-clump,all-ball"}, {"--model", "one model"}},
      {{"--seeds", "3-1"}, {"--seeds", "runs backwards"}},
      {{"--until-width", "2", "--max-seeds", "3", "--seeds", "1-5"}, {"--max-seeds 3", "fewer than the 5 seeds"}},
      {{"--width-output", "peak"}, {"--width-output"}},
      {{"--control-seeds", "1-9"}, {"--control-seeds", "without --control"}},
      {{"--control", "all-ball", "--seeds", "1-3", "--control-seeds", "2-9"}, {"lacks seeds 1 of --seeds"}},
      {{"--control", "all-clump", "--control-seeds", "1-9"}, {"--control all-clump", "the model itself"}},
      {{"--seed", "4"}, {"--seed 4", "--seeds"}},
      {{"--jobs", "2", "--until-width", "5"}, {"--jobs 2", "--until-width", "--jobs 1"}},
      {{"--jobs", "2", "--slice", "0/2"}, {"--jobs 2", "--slice"}},
  });
}
