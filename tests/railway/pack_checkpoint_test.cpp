// Checkpoints of the bed preparation (studies/railway/preparation_checkpoint.hpp): a preparation
// stopped after its deposition and again after its tamping, then resumed, is bitwise the
// uninterrupted one (reference: the uninterrupted run itself; tolerance none, memcmp), with the
// same stage reports; a checkpoint made with another seed or config, or a stage the config does
// not run, is refused naming what differs.
#include <catch2/catch.hpp>

#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include "studies/railway/bed_preparation.hpp"
#include "tests/railway/tiny_bed.hpp"
#include "tests/support/temp_dir.hpp"

using namespace mfdem;

namespace {

// The tiny bed with every stage a checkpoint can fall between: deposit, tamp, consolidate, settle.
railway::PushStudyConfig staged_config(std::uint64_t seed = 7, double tamping_time = 0.02) {
  std::string text = test::kTinyBed;
  const std::string keys = "tamping_depth = 0.004\ntamping_time = " + std::to_string(tamping_time) +
                           "\ntamping_sleeper_vertical = \"held\"\nconsolidation_gravity = 10.0\n"
                           "consolidation_time = 0.02\n";
  const auto at = text.find("[preparation]\n") + std::string("[preparation]\n").size();
  text.insert(at, keys);
  railway::PushStudyConfig c = railway::parse_push_config(text, "staged.toml");
  c.seed = seed;
  return c;
}

std::optional<railway::Packing> run(const railway::PushStudyConfig& c, const std::filesystem::path& checkpoint,
                                    bool resume, const std::string& stop_after, railway::PreparationReport& report) {
  railway::PreparationControl control;
  control.quiet = true;
  control.checkpoint = checkpoint;
  control.resume = resume;
  control.stop_after = stop_after;
  return railway::prepare_bed(c, control, report);
}

bool same_states(const railway::Packing& a, const railway::Packing& b) {
  if (a.bodies.size() != b.bodies.size()) return false;
  for (std::size_t k = 0; k < a.bodies.size(); ++k) {
    const auto& x = a.bodies[k];
    const auto& y = b.bodies[k];
    if (std::memcmp(x.position.data(), y.position.data(), sizeof(double) * 3) != 0 ||
        std::memcmp(x.velocity.data(), y.velocity.data(), sizeof(double) * 3) != 0 ||
        std::memcmp(x.orientation.coeffs().data(), y.orientation.coeffs().data(), sizeof(double) * 4) != 0 ||
        a.stones[k].id != b.stones[k].id)
      return false;
  }
  return a.sleeper.centre == b.sleeper.centre && a.springs.size() == b.springs.size();
}

}  // namespace

TEST_CASE("a preparation stopped after its stages and resumed is bitwise the uninterrupted one",
          "[railway][checkpoint]") {
  const test::TempDir dir;
  const railway::PushStudyConfig config = staged_config();
  REQUIRE(railway::stopping_points(config) == std::vector<std::string>{"deposit", "tamp", "consolidate"});

  railway::PreparationReport whole;
  const auto uninterrupted = run(config, dir.path() / "whole.h5", false, "", whole);
  REQUIRE(uninterrupted);

  const auto checkpoint = dir.path() / "checkpoint.h5";
  railway::PreparationReport first, second, last;
  CHECK_FALSE(run(config, checkpoint, false, "deposit", first));
  REQUIRE(std::filesystem::exists(checkpoint));
  CHECK_FALSE(std::filesystem::exists(dir.path() / "checkpoint.partial.h5"));
  CHECK_FALSE(run(config, checkpoint, true, "tamp", second));
  const auto resumed = run(config, checkpoint, true, "", last);
  REQUIRE(resumed);

  CHECK(same_states(*uninterrupted, *resumed));
  CHECK(resumed->preparation_time == uninterrupted->preparation_time);
  CHECK(last.stones_generated == whole.stones_generated);
  CHECK(last.stones_removed == whole.stones_removed);
  CHECK(last.time_step == whole.time_step);
  REQUIRE(last.stages.size() == whole.stages.size());
  for (std::size_t k = 0; k < whole.stages.size(); ++k) {
    CAPTURE(k);
    CHECK(last.stages[k].name == whole.stages[k].name);
    CHECK(last.stages[k].steps == whole.stages[k].steps);
    CHECK(last.stages[k].unbalanced_force_ratio == whole.stages[k].unbalanced_force_ratio);
    CHECK(last.stages[k].sleeper_base == whole.stages[k].sleeper_base);
    CHECK(last.stages[k].check_force_ratio == whole.stages[k].check_force_ratio);
  }
}

TEST_CASE("a checkpoint is refused for another seed, another config or a stage not run", "[railway][checkpoint]") {
  const test::TempDir dir;
  const auto checkpoint = dir.path() / "checkpoint.h5";
  railway::PreparationReport report;
  CHECK_THROWS_WITH(run(staged_config(), checkpoint, true, "", report), Catch::Contains("no checkpoint"));
  CHECK_THROWS_WITH(run(staged_config(), checkpoint, false, "settle", report),
                    Catch::Contains("expected one of: deposit, tamp, consolidate"));
  report = {};
  REQUIRE_FALSE(run(staged_config(), checkpoint, false, "deposit", report));
  report = {};
  CHECK_THROWS_WITH(run(staged_config(8), checkpoint, true, "", report), Catch::Contains("seed 7") &&
                    Catch::Contains("--seed 7"));
  report = {};
  CHECK_THROWS_WITH(run(staged_config(7, 0.03), checkpoint, true, "", report),
                    Catch::Contains("tamping_time = 0.020000") && Catch::Contains("tamping_time = 0.030000"));
  report = {};
  CHECK_THROWS_WITH(run(staged_config(), checkpoint, true, "deposit", report), Catch::Contains("already done"));
}
