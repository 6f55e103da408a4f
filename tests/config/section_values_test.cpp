// Reading values through a Section: types, fallbacks, sub-tables, arrays of tables and locations.
#include <catch2/catch.hpp>

#include "studies/config/config.hpp"

using mfdem::config::ConfigError;
using mfdem::config::parse;
using Catch::Matchers::Contains;
using Catch::Matchers::Equals;
using Catch::Matchers::Message;

TEST_CASE("numbers accept TOML integers and floats exactly", "[config]") {
  const auto top = parse("kn = 2e7\nmass = 380\nmu = 0.5\n", "scene.toml");
  // Exact equality: each literal is exactly representable or parsed to the nearest double.
  CHECK(top.number("kn") == 2e7);
  CHECK(top.number("mass") == 380.0);
  CHECK(top.number("mu") == 0.5);
}

TEST_CASE("integers accept whole floats such as 1e6 and reject fractions", "[config]") {
  const auto top = parse("steps = 1e6\ncount = 12\nhalf = 2.5\n", "run.toml");
  CHECK(top.integer("steps") == 1000000);
  CHECK(top.integer("count") == 12);
  CHECK_THROWS_MATCHES(top.integer("half", {}, "number of stones"), ConfigError,
                       Message("run.toml:3: half = 2.5: expected a whole number (number of stones)"));
}

TEST_CASE("fallbacks apply only to absent keys", "[config]") {
  const auto top = parse("mu = 0.3\nsteps = 7\nperiodic = true\nname = \"a\"\ng = [0, 0, -9.81]\nout = [\"x\"]\n", "s.toml");
  CHECK(top.number_or("mu", 0.5) == 0.3);
  CHECK(top.number_or("mu_r", 0.25) == 0.25);
  CHECK(top.integer_or("steps", 1) == 7);
  CHECK(top.integer_or("stages", 3) == 3);
  CHECK(top.boolean_or("periodic", false) == true);
  CHECK(top.boolean_or("walls", true) == true);
  CHECK(top.text_or("name", "b") == "a");
  CHECK(top.text_or("title", "b") == "b");
  CHECK(top.vec3_or("g", {1, 2, 3}) == std::array<double, 3>{0, 0, -9.81});
  CHECK(top.vec3_or("v", {1, 2, 3}) == std::array<double, 3>{1, 2, 3});
  CHECK(top.strings_or("out", {}) == std::vector<std::string>{"x"});
  CHECK(top.strings_or("plots", {"f", "u"}) == std::vector<std::string>{"f", "u"});
}

TEST_CASE("vec3 requires exactly three finite numbers", "[config]") {
  const auto top = parse("gravity = [0, -9.81]\nsize = [1, 2, \"3\"]\n", "scene.toml");
  CHECK_THROWS_MATCHES(top.vec3("gravity", "gravity in m/s^2"), ConfigError,
                       Message("scene.toml:1: gravity = [0, -9.81]: expected 3 finite numbers [x, y, z] (gravity in m/s^2)"));
  CHECK_THROWS_WITH(top.vec3("size"), Equals("scene.toml:2: size = [1, 2, \"3\"]: expected 3 finite numbers [x, y, z]"));
}

TEST_CASE("text and lists of text are read as written", "[config]") {
  const auto top = parse("name = \"ballast bed\"\nplots = [\"force\", \"chains\"]\nbad = [\"a\", 1]\n", "s.toml");
  CHECK(top.text("name") == "ballast bed");
  CHECK(top.strings_or("plots", {}) == std::vector<std::string>{"force", "chains"});
  CHECK_THROWS_WITH(top.strings_or("bad", {}), Equals("s.toml:3: bad = [\"a\", 1]: expected a list of text strings, e.g. [\"a\", \"b\"]"));
}

TEST_CASE("choice accepts an allowed word and suggests the nearest one otherwise", "[config]") {
  const auto top = parse("model = \"clump\"\npolicy = \"layr\"\n", "scene.toml");
  CHECK(top.choice("model", {"clump", "ball"}) == "clump");
  CHECK(top.choice("shape", {"clump", "ball"}, "ball") == "ball");
  CHECK_THROWS_MATCHES(top.choice("policy", {"all-clump", "layer", "all-ball"}), ConfigError,
                       Message("scene.toml:2: policy = \"layr\": expected one of \"all-clump\", \"layer\", "
                               "\"all-ball\"; did you mean \"layer\"?"));
  CHECK_THROWS_MATCHES(top.choice("fidelity", {"clump", "ball"}), ConfigError,
                       Message("scene.toml: missing key 'fidelity' in [top level]: expected one of \"clump\", \"ball\""));
}

TEST_CASE("names lists user-named tables in file order", "[config]") {
  const auto top = parse("[materials.sleeper]\nkn = 5e9\n[materials.ballast]\nkn = 2e7\n[materials.wall]\nkn = 1e8\n", "s.toml");
  const auto materials = top.section("materials");
  CHECK(materials.names() == std::vector<std::string>{"sleeper", "ballast", "wall"});
  CHECK(materials.section("ballast").number("kn") == 2e7);
  CHECK(materials.section("ballast").path() == "materials.ballast");
}

TEST_CASE("arrays of tables are read in order with indexed paths", "[config]") {
  const auto top = parse(
      "[[wall]]\nstiffness = 1e8\n"    // lines 1-2
      "[[wall]]\nstiffness = 2e8\n"    // lines 3-4
      "[[wall]]\nstiffness = -1\n",    // lines 5-6
      "scene.toml");
  const auto walls = top.sections("wall");
  REQUIRE(walls.size() == 3);
  CHECK(walls[0].number("stiffness") == 1e8);
  CHECK(walls[1].number("stiffness") == 2e8);
  CHECK(walls[2].path() == "wall[2]");
  CHECK_THROWS_MATCHES(walls[2].number("stiffness", {.min = 0.0, .min_exclusive = true}, "wall stiffness in N/m"),
                       ConfigError, Message("scene.toml:6: wall[2].stiffness = -1: wall stiffness in N/m must be > 0"));
  CHECK(top.sections("sleeper").empty());
}

TEST_CASE("a key that is not an array of tables is rejected by sections", "[config]") {
  const auto top = parse("wall = [1, 2]\n", "scene.toml");
  CHECK_THROWS_MATCHES(top.sections("wall"), ConfigError,
                       Message("scene.toml:1: wall = [1, 2]: expected an array of tables, each starting with [[wall]]"));
}

TEST_CASE("optional sections are absent or read like required ones", "[config]") {
  const auto top = parse("[push]\nvelocity = 0.01\n", "scene.toml");
  CHECK_FALSE(top.optional_section("periodic").has_value());
  const auto push = top.optional_section("push");
  REQUIRE(push.has_value());
  CHECK(push->number("velocity") == 0.01);
}

TEST_CASE("where gives the line of the key then of the table then the file alone", "[config]") {
  const auto top = parse("title = \"t\"\n\n[sleeper]\nmass = 380\n", "scene.toml");
  const auto sleeper = top.section("sleeper");
  CHECK(top.where("title") == "scene.toml:1");
  CHECK(sleeper.where("mass") == "scene.toml:4");
  CHECK(sleeper.where("length") == "scene.toml:3");
  CHECK(top.where("gravity") == "scene.toml");
  CHECK(top.path().empty());
}

TEST_CASE("has reports presence without reading the value", "[config]") {
  const auto top = parse("[periodic]\naxis = \"y\"\n", "scene.toml");
  CHECK(top.has("periodic"));
  CHECK_FALSE(top.has("walls"));
}
