// `mfdem check` on scenes a new user gets slightly wrong: each refused with exit status 2, the
// file, the key and the value named, and every file of the command checked.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "tests/support/run_mfdem.hpp"
#include "tests/support/temp_dir.hpp"

using Catch::Matchers::Contains;
using mfdem::test::run_mfdem;
namespace fs = std::filesystem;

namespace {

const fs::path kScene = fs::path(MFDEM_SOURCE_DIR) / "studies/scenes/verification/normal_impact.toml";

// The shipped scene with one line's start replaced.
std::string edited(const std::string& from, const std::string& to) {
  std::stringstream s;
  s << std::ifstream(kScene).rdbuf();
  std::string text = s.str();
  const auto at = text.find(from);
  REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}

}  // namespace

TEST_CASE("check refuses a scene the solver would refuse, names file and key, and checks the other files",
          "[cli][check]") {
  const mfdem::test::TempDir dir;
  const auto too_large_step = dir.write("step.toml", edited("time_step = 1e-6 ", "time_step = 1e-3 "));
  const auto result = run_mfdem({"check", too_large_step.string(), kScene.string()});
  CAPTURE(result.err, result.out);
  CHECK(result.status == 2);
  CHECK_THAT(result.err, Contains(too_large_step.string()) && Contains("time_step") &&
                             Contains("above the stability limit") && Contains("force_time_step = true") &&
                             Contains("--force-dt"));
  CHECK_THAT(result.out, Contains("OK: " + kScene.string()));  // the next file still checked
}

TEST_CASE("check names misspelt keys and tables and refuses values out of range or a periodic box too short", "[cli][check]") {
  const mfdem::test::TempDir dir;
  struct Case {
    const char* name;
    std::string text;
    std::vector<std::string> expected;
  };
  const Case cases[] = {
      {"key", edited("duration =", "duratoin ="), {"missing key 'duration'", "'duratoin'", "did you mean 'duration'?"}},
      {"table", edited("[materials.small]", "[materails.small]"), {"unknown key 'materails'", "did you mean 'materials'?"}},
      {"stiffness", edited("normal_stiffness = 2e7", "normal_stiffness = 1e300"),
       {"materials.small.normal_stiffness = 1e+300", "<= 1e+15"}},
      {"radius", edited("radius = 0.02 ", "radius = 1e300 "), {"sphere[0].radius = 1e+300", "<= 1000"}},
      {"periodic", edited("max = [0.3, 0.3, 0.2]", "max = [-0.05, 0.3, 0.2]\nperiodic = [\"x\"]"),
       {"[domain] min, max along x", "periodic length 0.05 m is below", "drop \"x\" from [domain] periodic"}},
  };
  for (const auto& c : cases) {
    const auto file = dir.write(std::string(c.name) + ".toml", c.text);
    const auto result = run_mfdem({"check", file.string()});
    CAPTURE(c.name, result.err);
    CHECK(result.status == 2);
    CHECK_THAT(result.err, Contains(file.string()));
    for (const auto& e : c.expected) CHECK_THAT(result.err, Contains(e));
  }
}

TEST_CASE("check validates push-study configs and presets too, with the section geometry", "[cli][check]") {
  // A push-study config (no [simulation] table) is read as `mfdem pack` reads it; a section too
  // short for its sleeper is refused naming the line and the key, before any stone is drawn.
  const mfdem::test::TempDir dir;
  std::stringstream mini;
  mini << std::ifstream(fs::path(MFDEM_SOURCE_DIR) / "studies/presets/mini.toml").rdbuf();
  std::string text = mini.str();
  const auto at = text.find("section_length = 0.20");
  REQUIRE(at != std::string::npos);
  const auto too_short = dir.write("short.toml", text.replace(at, 21, "section_length = 0.10"));
  const auto result = run_mfdem({"check", too_short.string(), "mini", "standard", "no-such-preset"});
  CAPTURE(result.out, result.err);
  CHECK(result.status == 2);
  CHECK_THAT(result.err, Contains(too_short.string() + ":12: [section] sleeper_width = 0.12 m") &&
                             Contains("section_length = 0.1 m"));
  CHECK_THAT(result.out, Contains("OK: mini (push-study config)") && Contains("OK: standard (push-study config)"));
  CHECK_THAT(result.err, Contains("no-such-preset: no such file, and not a preset"));
}
