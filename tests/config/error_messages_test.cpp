// Every config error names the file, the line, the full dotted key, the value found and what was
// expected, in physics words. Messages are compared whole: they are the user interface.
#include <catch2/catch.hpp>

#include "studies/config/config.hpp"

using mfdem::config::ConfigError;
using mfdem::config::parse;
using mfdem::config::Range;
using Catch::Matchers::Contains;
using Catch::Matchers::Equals;

namespace {
const Range non_negative{.min = 0.0};
const Range positive{.min = 0.0, .min_exclusive = true};

const char* const ballast =
    "[materials.ballast]\n"  // line 1
    "density = \"heavy\"\n"  // line 2
    "friction = -0.1\n"      // line 3
    "kn = -2e7\n"            // line 4
    "ks = inf\n"             // line 5
    "damping = 1.5\n"        // line 6
    "rolling = nan\n";       // line 7
}  // namespace

TEST_CASE("a friction coefficient of -0.1 is rejected naming file line key value and bound", "[config]") {
  const auto materials = parse(ballast, "scene.toml").section("materials").section("ballast");
  CHECK_THROWS_MATCHES(materials.number("friction", non_negative, "friction coefficient"), ConfigError,
                       Catch::Matchers::Message(
                           "scene.toml:3: materials.ballast.friction = -0.1: friction coefficient must be >= 0"));
}

TEST_CASE("a negative stiffness is rejected with its exclusive bound", "[config]") {
  const auto materials = parse(ballast, "scene.toml").section("materials").section("ballast");
  CHECK_THROWS_MATCHES(materials.number("kn", positive, "normal stiffness kn in N/m"), ConfigError,
                       Catch::Matchers::Message(
                           "scene.toml:4: materials.ballast.kn = -20000000: normal stiffness kn in N/m must be > 0"));
}

TEST_CASE("a value of the wrong type is rejected saying what was expected", "[config]") {
  const auto materials = parse(ballast, "scene.toml").section("materials").section("ballast");
  CHECK_THROWS_MATCHES(
      materials.number("density", positive, "density in kg/m^3"), ConfigError,
      Catch::Matchers::Message(
          "scene.toml:2: materials.ballast.density = \"heavy\": expected a number (density in kg/m^3)"));
  CHECK_THROWS_MATCHES(materials.text("friction"), ConfigError,
                       Catch::Matchers::Message(
                           "scene.toml:3: materials.ballast.friction = -0.1: expected text in double quotes"));
  CHECK_THROWS_MATCHES(materials.boolean_or("kn", false), ConfigError,
                       Catch::Matchers::Message("scene.toml:4: materials.ballast.kn = -20000000: expected true or false"));
}

TEST_CASE("infinite and not-a-number values are rejected", "[config]") {
  const auto materials = parse(ballast, "scene.toml").section("materials").section("ballast");
  CHECK_THROWS_MATCHES(materials.number("ks", positive, "shear stiffness ks in N/m"), ConfigError,
                       Catch::Matchers::Message(
                           "scene.toml:5: materials.ballast.ks = inf: expected a finite number (shear stiffness ks in N/m)"));
  CHECK_THROWS_MATCHES(materials.number_or("rolling", 0.0), ConfigError,
                       Catch::Matchers::Message("scene.toml:7: materials.ballast.rolling = nan: expected a finite number"));
}

TEST_CASE("a two-sided range names both bounds", "[config]") {
  const auto materials = parse(ballast, "scene.toml").section("materials").section("ballast");
  const Range fraction{.min = 0.0, .max = 1.0, .max_exclusive = true};
  CHECK_THROWS_MATCHES(materials.number("damping", fraction, "local damping alpha"), ConfigError,
                       Catch::Matchers::Message(
                           "scene.toml:6: materials.ballast.damping = 1.5: local damping alpha must be >= 0 and < 1"));
}

TEST_CASE("a range error without a meaning names the key", "[config]") {
  const auto top = parse("steps = -3\n", "run.toml");
  CHECK_THROWS_MATCHES(top.integer("steps", {.min = 1.0}), ConfigError,
                       Catch::Matchers::Message("run.toml:1: steps = -3: steps must be >= 1"));
}

TEST_CASE("a missing required key is reported with its table and what it should hold", "[config]") {
  const auto materials = parse("\n[materials.ballast]\nkn = 2e7\n", "scene.toml").section("materials").section("ballast");
  CHECK_THROWS_MATCHES(
      materials.number("density", positive, "density in kg/m^3"), ConfigError,
      Catch::Matchers::Message(
          "scene.toml:2: missing key 'density' in [materials.ballast]: expected a number (density in kg/m^3)"));
  const auto top = parse("title = \"x\"\n", "scene.toml");
  CHECK_THROWS_MATCHES(top.section("sleeper"), ConfigError,
                       Catch::Matchers::Message(
                           "scene.toml: missing key 'sleeper' in [top level]: expected a table [sleeper]"));
}

TEST_CASE("a scalar where a table belongs is rejected", "[config]") {
  const auto top = parse("sleeper = 5\n", "scene.toml");
  CHECK_THROWS_MATCHES(top.section("sleeper"), ConfigError,
                       Catch::Matchers::Message("scene.toml:1: sleeper = 5: expected a table [sleeper]"));
}

TEST_CASE("fail reports a check made by the caller in the same form", "[config]") {
  const auto sleeper = parse("[sleeper]\nmass = 380\nsize = [2.6, 0.26, 0.21]\n", "scene.toml").section("sleeper");
  CHECK_THROWS_MATCHES(sleeper.fail("size", "sleeper must fit between the walls (0.6 m apart)"), ConfigError,
                       Catch::Matchers::Message(
                           "scene.toml:3: sleeper.size = [2.6, 0.26, 0.21]: sleeper must fit between the walls (0.6 m apart)"));
}

TEST_CASE("long values are cut short in messages", "[config]") {
  const std::string long_name(200, 'x');
  const auto top = parse("name = \"" + long_name + "\"\n", "scene.toml");
  try {
    top.number("name");
    FAIL("a text value was accepted as a number");
  } catch (const ConfigError& error) {
    const std::string message = error.what();
    CHECK_THAT(message, Contains("...: expected a number"));
    // 60 characters of value at most (value_text.cpp), plus the location, key and expectation.
    CHECK(message.size() < 120);
  }
}

TEST_CASE("keys that are not bare TOML words are quoted in the dotted path", "[config]") {
  const auto materials = parse("[materials.\"crushed granite\"]\nfriction = -1\n", "scene.toml").section("materials");
  const auto granite = materials.section(materials.names().at(0));
  CHECK_THAT(granite.path(), Equals("materials.\"crushed granite\""));
  CHECK_THROWS_WITH(granite.number("friction", non_negative),
                    Contains("materials.\"crushed granite\".friction = -1: friction must be >= 0"));
}
