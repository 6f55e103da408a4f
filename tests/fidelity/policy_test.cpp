// Fidelity policies: each built-in policy's rule on stones of known geometry, the registry's
// parsing and refusals (each naming the parameter), and a user predicate registered by name.
#include <catch2/catch.hpp>

#include "fidelity/policy.hpp"

using namespace mfdem::fidelity;

namespace {

const BedScale kBed{0.30};  // sleeper base 0.30 m above the floor

Representation choose(const Policy& p, double height, double gap) { return p.choose({height, gap}); }

PolicyError refusal(const std::string& text) {
  try {
    PolicyRegistry::builtin().make(text, kBed);
  } catch (const PolicyError& e) {
    return e;
  }
  FAIL("no PolicyError for " << text);
  return PolicyError("", "");
}

}  // namespace

TEST_CASE("all-clump and all-ball decide every stone the same way", "[fidelity][policy]") {
  const Policy clump = PolicyRegistry::builtin().make("all-clump", kBed);
  const Policy ball = PolicyRegistry::builtin().make("all-ball", kBed);
  for (double h : {0.0, 0.1, 0.29, 0.5})
    for (double gap : {0.0, 0.02, 1.0}) {
      CHECK(choose(clump, h, gap) == Representation::clump);
      CHECK(choose(ball, h, gap) == Representation::ball);
    }
  CHECK(clump.describe() == "all-clump");
}

TEST_CASE("layer-by-height makes balls of the stones whose centre lies below h", "[fidelity][policy]") {
  const Policy p = PolicyRegistry::builtin().make("layer-by-height:h=0.15", kBed);
  CHECK(choose(p, 0.1499, 0.0) == Representation::ball);
  CHECK(choose(p, 0.15, 0.0) == Representation::clump);  // "below": the boundary stays a clump
  CHECK(choose(p, 0.2, 0.5) == Representation::clump);
  // h in metres is primary, its fraction of the floor-to-sleeper-base depth is kept beside it.
  CHECK(p.parameter("h") == 0.15);
  CHECK(p.parameter("h_fraction") == Approx(0.5).epsilon(1e-15));
  CHECK(p.describe() == "layer-by-height:h=0.15,h_fraction=0.5");
}

TEST_CASE("layer-by-height takes h as a fraction of the depth to the sleeper base", "[fidelity][policy]") {
  const Policy p = PolicyRegistry::builtin().make("layer-by-height:h_fraction=0.25", kBed);
  CHECK(p.parameter("h") == Approx(0.075).epsilon(1e-15));
  CHECK(choose(p, 0.074, 0.0) == Representation::ball);
  CHECK(choose(p, 0.076, 0.0) == Representation::clump);
}

TEST_CASE("layer-by-height at the floor makes no ball, at the sleeper base every stone below it",
          "[fidelity][policy]") {
  const Policy floor = PolicyRegistry::builtin().make("layer-by-height:h=0", kBed);
  const Policy base = PolicyRegistry::builtin().make("layer-by-height:h_fraction=1", kBed);
  for (double h : {0.0, 1e-9, 0.1, 0.2999})
    CHECK(choose(floor, h, 0.0) == Representation::clump);
  for (double h : {0.0, 0.1, 0.2999}) CHECK(choose(base, h, 0.0) == Representation::ball);
  CHECK(choose(base, 0.30, 0.0) == Representation::clump);
  CHECK(choose(base, 0.35, 0.0) == Representation::clump);
}

TEST_CASE("zone-by-distance keeps the stones within d of the sleeper as clumps", "[fidelity][policy]") {
  const Policy p = PolicyRegistry::builtin().make("zone-by-distance:d=0.05", kBed);
  CHECK(choose(p, 0.1, 0.0) == Representation::clump);
  CHECK(choose(p, 0.1, 0.05) == Representation::clump);
  CHECK(choose(p, 0.1, 0.0501) == Representation::ball);
  CHECK(choose(p, 0.4, 0.2) == Representation::ball);  // height plays no part
  const Policy touching = PolicyRegistry::builtin().make("zone-by-distance:d=0", kBed);
  CHECK(choose(touching, 0.1, 0.0) == Representation::clump);
  CHECK(choose(touching, 0.1, 1e-6) == Representation::ball);
}

TEST_CASE("a bad policy is refused naming the parameter and what was expected", "[fidelity][policy]") {
  CHECK_THAT(refusal("layer-by-heigth:h=0.1").what(),
             Catch::Contains("unknown fidelity policy 'layer-by-heigth'") && Catch::Contains("layer-by-height (h or h_fraction)"));
  CHECK(refusal("layer-by-height").parameter == "h");
  const PolicyError below = refusal("layer-by-height:h=-0.01");
  CHECK(below.parameter == "h");
  CHECK_THAT(below.what(), Catch::Contains("h = -0.01") && Catch::Contains("from 0 (the floor) to 0.3"));
  CHECK_THAT(refusal("layer-by-height:h=0.31").what(), Catch::Contains("h = 0.31"));
  CHECK(refusal("layer-by-height:h_fraction=1.2").parameter == "h_fraction");
  CHECK(refusal("layer-by-height:h=0.1,h_fraction=0.2").parameter == "h_fraction");
  CHECK(refusal("zone-by-distance").parameter == "d");
  const PolicyError negative = refusal("zone-by-distance:d=-1");
  CHECK(negative.parameter == "d");
  CHECK_THAT(negative.what(), Catch::Contains("d = -1") && Catch::Contains(">= 0"));
  CHECK(refusal("zone-by-distance:e=1").parameter == "e");
  CHECK(refusal("all-ball:h=1").parameter == "h");
  CHECK_THAT(refusal("layer-by-height:h=abc").what(), Catch::Contains("h = 'abc': expected a finite number"));
  CHECK_THAT(refusal("layer-by-height:h=nan").what(), Catch::Contains("expected a finite number"));
  CHECK_THAT(refusal("layer-by-height:h").what(), Catch::Contains("expected key=value"));
  CHECK(refusal("layer-by-height:h=0.1,h=0.2").parameter == "h");
}

TEST_CASE("a predicate on a stone becomes a named policy in a few lines", "[fidelity][policy]") {
  PolicyRegistry registry;
  registry.add("shoulder-clumps", "clumps above 0.2 m", [](const StoneGeometry& s) {
    return s.height > 0.2 ? Representation::clump : Representation::ball;
  });
  const Policy p = registry.make("shoulder-clumps", kBed);
  CHECK(choose(p, 0.25, 0.0) == Representation::clump);
  CHECK(choose(p, 0.15, 0.0) == Representation::ball);
  CHECK_THROWS_AS(registry.add("shoulder-clumps", "again", p.choose), std::invalid_argument);
  CHECK_THROWS_AS(registry.make("shoulder-clumps:x=1", kBed), PolicyError);
}

TEST_CASE("a policy spec reads back as written", "[fidelity][policy]") {
  const PolicySpec s = parse_policy_spec("zone-by-distance:d=0.035");
  CHECK(s.name == "zone-by-distance");
  REQUIRE(s.parameters.size() == 1);
  CHECK(s.parameters[0].value == 0.035);
  CHECK(s.text() == "zone-by-distance:d=0.035");
}
