// The study configs: the shipped presets and what they hold, and a config's bad values refused by
// file, key and value.
#include <catch2/catch.hpp>

#include <string>

#include "studies/config/config_error.hpp"
#include "studies/railway/bed_preparation.hpp"
#include "studies/railway/push_config.hpp"
#include "tests/railway/tiny_bed.hpp"

using namespace mfdem;

namespace {

railway::PushStudyConfig tiny_config() { return railway::parse_push_config(mfdem::test::kTinyBed, "tiny.toml"); }

}  // namespace

TEST_CASE("a study config with bad values is refused naming file, key and value", "[railway][config]") {
  const auto refused = [](const std::string& replace, const std::string& by) {
    std::string text = mfdem::test::kTinyBed;
    text.replace(text.find(replace), replace.size(), by);
    return railway::parse_push_config(text, "tiny.toml");
  };
  CHECK_THROWS_WITH(refused("depth_under_sleeper = 0.08", "depth_under_sleeper = -0.08"),
                    Catch::Contains("tiny.toml") && Catch::Contains("depth_under_sleeper") &&
                        Catch::Contains("-0.08") && Catch::Contains("> 0"));
  CHECK_THROWS_WITH(refused("representation = \"ball\"", "representation = \"cube\""),
                    Catch::Contains("representation") && Catch::Contains("clump"));
  CHECK_THROWS_WITH(refused("[push]", "[push]\nvelocty = 0.1"), Catch::Contains("velocity"));
  CHECK_THROWS_WITH(refused("max_settling_time = 0.1", "max_settling_time = 0.1\nconsolidation_gravity = 0.5"),
                    Catch::Contains("tiny.toml") && Catch::Contains("consolidation_gravity") &&
                        Catch::Contains("0.5"));
  CHECK_THROWS_WITH(refused("[push]", "[push]\nsleeper_vertical = \"fixed\""),
                    Catch::Contains("tiny.toml") && Catch::Contains("sleeper_vertical") &&
                        Catch::Contains("fixed") && Catch::Contains("held"));
  CHECK_THROWS_WITH(refused("max_settling_time = 0.1", "max_settling_time = 0.1\ntamping_sleeper_vertical = \"up\""),
                    Catch::Contains("tiny.toml") && Catch::Contains("tamping_sleeper_vertical") &&
                        Catch::Contains("up") && Catch::Contains("held"));
  CHECK(refused("max_settling_time = 0.1", "max_settling_time = 0.1\ntamping_sleeper_vertical = \"held\"")
            .preparation.tamping_sleeper_held);
  CHECK_FALSE(railway::parse_push_config(mfdem::test::kTinyBed, "tiny.toml").preparation.tamping_sleeper_held);
  CHECK_THROWS_WITH(refused("max_settling_time = 0.1", "max_settling_time = 0.1\nexpansion_strain = 0.2"),
                    Catch::Contains("tiny.toml") && Catch::Contains("expansion_strain") && Catch::Contains("0.2"));
  // Geometry that parses but cannot be built is refused when the bed is prepared.
  railway::PreparationReport report;
  auto narrow = tiny_config();
  narrow.geometry.shoulder_width = 0.01;  // narrower than one 25 mm stone
  CHECK_THROWS_WITH(railway::prepare_bed(narrow, true, report),
                    Catch::Contains("shoulder_width") && Catch::Contains("0.01"));
  auto wide = tiny_config();
  wide.geometry.sleeper_width = 0.25;  // wider than the 0.2 m section: outside the box
  CHECK_THROWS_WITH(railway::prepare_bed(wide, true, report), Catch::Contains("sleeper_width"));
}

TEST_CASE("the shipped presets load, with their documented sizes", "[railway][config]") {
  // Reference: studies/presets/*.toml and README.md there; mini is the demo's miniature, the
  // other two the design notes' full-size section.
  const auto mini = railway::load_push_config("mini");
  CHECK(mini.name == "mini");
  CHECK(mini.geometry.sleeper_length == 0.30);
  CHECK(mini.stones.representation == mfdem::fidelity::Representation::clump);
  for (const char* name : {"standard", "paper"}) {
    const auto full = railway::load_push_config(name);
    CHECK(full.geometry.sleeper_length == 2.6);
    CHECK(full.geometry.sleeper_mass == 380.0);
    CHECK(full.geometry.depth_under_sleeper == 0.30);
    CHECK(full.ballast.normal_stiffness == 2e7);  // Table 1
    CHECK(full.sleeper.normal_stiffness == 5e9);
    // Tamped 20 mm with the sleeper held, then consolidated at 10 g (results/push_test, stop 18).
    CHECK(full.preparation.tamping_depth == 0.020);
    CHECK(full.preparation.tamping_sleeper_held);
    CHECK(full.preparation.consolidation_gravity == 10.0);
    // Long enough for the creeping crib: standard seed 1 meets 1e-3 at 0.72 s (stop 25).
    CHECK(full.preparation.max_settling_time == 1.0);
  }
  // study: standard's section with the sleeper and the spacing shortened, prepared and pushed as
  // standard (its depth, shoulders, slopes, materials, preparation and push are standard's).
  const auto study = railway::load_push_config("study");
  const auto standard = railway::load_push_config("standard");
  CHECK(study.geometry.sleeper_length == 0.6);
  CHECK(study.geometry.section_length == 0.4);
  CHECK(study.geometry.sleeper_mass == Approx(380.0 * 0.6 / 2.6).epsilon(1e-3));
  CHECK(study.geometry.section_length - study.geometry.sleeper_width > 2 * 0.063);  // a crib of two stones of D
  CHECK(study.geometry.depth_under_sleeper == standard.geometry.depth_under_sleeper);
  CHECK(study.geometry.shoulder_width == standard.geometry.shoulder_width);
  CHECK(study.geometry.shoulder_slope == standard.geometry.shoulder_slope);
  CHECK(study.geometry.sleeper_width == standard.geometry.sleeper_width);
  CHECK(study.geometry.sleeper_height == standard.geometry.sleeper_height);
  CHECK(study.geometry.periodic_along_track);
  CHECK(study.ballast.normal_stiffness == standard.ballast.normal_stiffness);
  CHECK(study.ballast.friction == standard.ballast.friction);
  CHECK(study.preparation.tamping_depth == standard.preparation.tamping_depth);
  CHECK(study.preparation.consolidation_gravity == standard.preparation.consolidation_gravity);
  CHECK(study.preparation.max_settling_time == standard.preparation.max_settling_time);
  CHECK(study.push.velocity == standard.push.velocity);
  CHECK(study.push.distance == standard.push.distance);
  // The velocity the rate checks chose on standard seeds 1-3 (results/push_test, stop 25).
  CHECK(railway::load_push_config("standard").push.velocity == 0.025);
  // The paper's setting: walls along the track, a wall sleeper held in the push, a trafficked bed.
  const auto paper = railway::load_push_config("paper");
  CHECK_FALSE(paper.geometry.periodic_along_track);
  CHECK(paper.push.sleeper_held_vertically);
  CHECK(paper.preparation.traffic_cycles == 20);
  CHECK(paper.preparation.traffic_load == 90e3);
  CHECK_THROWS_WITH(railway::load_push_config("maxi"), Catch::Contains("mini, study, standard and paper"));
}
