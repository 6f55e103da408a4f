// `mfdem optimise-layer` refuses what cannot be searched before any run, naming the option and value.
#include <catch2/catch.hpp>

#include <filesystem>
#include <string>

#include "tests/support/run_mfdem.hpp"
#include "tests/support/temp_dir.hpp"

using Catch::Matchers::Contains;
using mfdem::test::run_mfdem;

TEST_CASE("optimise-layer refuses bad families, ranges and seeds", "[cli][optimise]") {
  const mfdem::test::TempDir dir;
  const std::string out = (dir.path() / "opt").string();
  struct Case {
    std::vector<std::string> args;
    std::vector<std::string> expected;
  };
  const Case cases[] = {
      {{"--family", "layer-by-height"}, {"--family layer-by-height", "POLICY:EXTENT=LOWER:UPPER"}},
      {{"--family", "layer-by-height:mu_r=0:0.6"}, {"--family layer-by-height:mu_r=0:0.6", "one extent"}},
      {{"--family", "layer-by-height:h_fraction=0:0.8"}, {"h_fraction=0:0.8", "leaves no ball"}},
      {{"--family", "zone-by-distance:d=0.01:3"}, {"d=0.01:3", "no ball"}},
      {{"--family", "all-ball:h=0.1:0.2"}, {"--family all-ball", "layer-by-height or zone-by-distance"}},
      {{"--mu-r", "0.6:0"}, {"--mu-r", "empty range"}},
      {{"--seeds", "1"}, {"--seeds 1", "two seeds"}},
      {{"--uncalibrated", "layer-by-height:q=3"}, {"--uncalibrated"}},
  };
  for (const auto& c : cases) {
    std::vector<std::string> args = {"optimise-layer", "mini", "--out", out};
    args.insert(args.end(), c.args.begin(), c.args.end());
    const auto result = run_mfdem(args);
    CAPTURE(c.args, result.err);
    CHECK(result.status == 2);
    for (const auto& e : c.expected) CHECK_THAT(result.err, Contains(e));
    CHECK_FALSE(std::filesystem::exists(out + "/runs"));  // nothing run, no store made
  }
}
