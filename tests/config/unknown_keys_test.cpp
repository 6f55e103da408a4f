// finish() rejects keys the program never asked for: typos in keys and in section names.
#include <catch2/catch.hpp>

#include "studies/config/config.hpp"

using mfdem::config::ConfigError;
using mfdem::config::parse;
using mfdem::config::Section;
using Catch::Matchers::Message;

namespace {
// What a scene reader would ask of [materials.<name>].
void read_material(const Section& material) {
  material.number("kn");
  material.number_or("friction", 0.5);
  material.number_or("rolling_friction", 0.0);
}
}  // namespace

TEST_CASE("a typo in a section name is caught with the nearest known name", "[config]") {
  const auto top = parse(
      "title = \"demo\"\n"      // line 1
      "\n"                      // line 2
      "[sleeper]\n"             // line 3
      "mass = 380\n"            // line 4
      "\n\n\n\n"                // lines 5-8
      "[materails.ballast]\n"   // line 9
      "kn = 2e7\n",
      "scene.toml");
  top.text("title");
  top.section("sleeper").number("mass");
  CHECK_FALSE(top.has("materials"));
  CHECK_THROWS_MATCHES(top.finish(), ConfigError,
                       Message("scene.toml:9: unknown key 'materails' in [top level]; did you mean 'materials'?"));
}

TEST_CASE("a typo in a key is caught inside its table", "[config]") {
  const auto top = parse("[materials.ballast]\nkn = 2e7\nfrcition = 0.5\n", "scene.toml");
  const auto materials = top.section("materials");
  for (const auto& name : materials.names()) read_material(materials.section(name));
  CHECK_THROWS_MATCHES(top.finish(), ConfigError,
                       Message("scene.toml:3: unknown key 'frcition' in [materials.ballast]; did you mean 'friction'?"));
}

TEST_CASE("every unknown key is reported once in file order", "[config]") {
  const auto top = parse("[sleeper]\nmas = 380\nlength = 2.6\n[push]\nvelocty = 1\n", "scene.toml");
  top.section("push").number_or("velocity", 0.01);
  top.section("sleeper").number_or("mass", 380.0);
  CHECK_THROWS_MATCHES(top.finish(), ConfigError,
                       Message("scene.toml:2: unknown key 'mas' in [sleeper]; did you mean 'mass'?\n"
                               "scene.toml:3: unknown key 'length' in [sleeper]; expected one of: mass\n"
                               "scene.toml:5: unknown key 'velocty' in [push]; did you mean 'velocity'?"));
}

TEST_CASE("a table nothing is read from says so", "[config]") {
  const auto top = parse("[notes]\nauthor = \"me\"\n", "scene.toml");
  top.section("notes");
  CHECK_THROWS_MATCHES(top.finish(), ConfigError,
                       Message("scene.toml:2: unknown key 'author' in [notes]; nothing is read from [notes]"));
}

TEST_CASE("unknown keys in arrays of tables name the element", "[config]") {
  const auto top = parse("[[wall]]\nstiffness = 1\n[[wall]]\nstifness = 2\n", "scene.toml");
  for (const auto& wall : top.sections("wall")) wall.number_or("stiffness", 1e8);
  CHECK_THROWS_MATCHES(top.finish(), ConfigError,
                       Message("scene.toml:4: unknown key 'stifness' in [wall[1]]; did you mean 'stiffness'?"));
}

TEST_CASE("finish passes when every key was read and copies share what was asked", "[config]") {
  const auto top = parse("[materials.ballast]\nkn = 2e7\nfriction = 0.5\n[materials.sleeper]\nkn = 5e9\n", "s.toml");
  const Section materials = top.section("materials");
  for (const auto& name : materials.names()) read_material(materials.section(name));
  const Section copy = top;  // a copy sees the keys asked through the original
  CHECK_NOTHROW(copy.finish());
}

TEST_CASE("sub-tables never opened are reported as unknown keys not searched", "[config]") {
  const auto top = parse("[sleeper]\nmass = 380\n[sleepr]\nmass = 1\n", "s.toml");
  top.section("sleeper").number("mass");
  CHECK_THROWS_MATCHES(top.finish(), ConfigError,
                       Message("s.toml:3: unknown key 'sleepr' in [top level]; did you mean 'sleeper'?"));
}
