// Checkpoints of the bed preparation (studies/railway/preparation_checkpoint.hpp): a preparation
// stopped after its deposition and again after its tamping, then resumed, is bitwise the
// uninterrupted one, with the same stage reports; a deposition reused under other tamping and
// settling keys is bitwise that config's own preparation (reference in both: the run without
// the checkpoint; tolerance none, memcmp). A checkpoint made with another seed or config, or a
// stage the config does not run, is refused naming what differs. The traffic stage, which runs
// between the compaction and the settling, is tested here too: against its closed-form pulse,
// and stopped and resumed after it.
#include <catch2/catch.hpp>

#include <cstring>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "studies/railway/bed_preparation.hpp"
#include "studies/railway/compaction_stages.hpp"
#include "studies/railway/preparation_checkpoint.hpp"
#include "studies/railway/preparation_stage.hpp"
#include "tests/railway/tiny_bed.hpp"
#include "tests/support/temp_dir.hpp"

using namespace mfdem;

namespace {

// The tiny bed with every stage a checkpoint can fall between: deposit, tamp, consolidate, settle.
railway::PushStudyConfig staged_config(std::uint64_t seed = 7, double tamping_time = 0.02,
                                       const std::string& more = "") {
  std::string text = test::kTinyBed;
  const std::string keys = "tamping_depth = 0.004\ntamping_time = " + std::to_string(tamping_time) +
                           "\ntamping_sleeper_vertical = \"held\"\nconsolidation_gravity = 10.0\n"
                           "consolidation_time = 0.02\n" + more;
  const auto at = text.find("[preparation]\n") + std::string("[preparation]\n").size();
  text.insert(at, keys);
  railway::PushStudyConfig c = railway::parse_push_config(text, "staged.toml");
  c.seed = seed;
  return c;
}

std::optional<railway::Packing> run(const railway::PushStudyConfig& c, const std::filesystem::path& checkpoint,
                                    bool resume, const std::string& stop_after, railway::PreparationReport& report,
                                    const std::filesystem::path& deposit_from = {}) {
  railway::PreparationControl control;
  control.quiet = true;
  control.checkpoint = checkpoint;
  control.resume = resume;
  control.stop_after = stop_after;
  control.deposit_from = deposit_from;
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

// The staged tiny bed (no traffic): deposited into `deposited` (its checkpoint), then finished
// and saved as `finished`, as `mfdem pack` writes it.
railway::Packing finished_bed(const std::filesystem::path& deposited, const std::filesystem::path& finished) {
  railway::PreparationReport first, report;
  REQUIRE_FALSE(run(staged_config(), deposited, false, "deposit", first));
  const auto settled = run(staged_config(), {}, false, "", report, deposited);
  REQUIRE(settled);
  railway::save_finished_packing(finished, *settled, report.stages);
  return *settled;
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
    CHECK(last.stages[k].sleeper_base_start == whole.stages[k].sleeper_base_start);
    CHECK(last.stages[k].check_force_ratio == whole.stages[k].check_force_ratio);
    CHECK(last.stages[k].check_sleeper_base == whole.stages[k].check_sleeper_base);
  }
}

TEST_CASE("a checkpoint holds the sleeper where the last stage left it, with the stones that followed it",
          "[railway][checkpoint]") {
  // A sleeper that sank in the consolidation has stones on its top that followed it down. Its
  // checkpoint was once written with the sleeper at its design place: those stones then overlapped
  // it and the writing failed ("the bodies as given ... overlaps a wall"), study zone d 0.1.
  // Here the bed is moved the other way: the sleeper 40 mm up, one stone in the room it left.
  const test::TempDir dir;
  const railway::PushStudyConfig config = staged_config();
  railway::PreparationReport first, loaded;
  const auto tamped = dir.path() / "tamped.h5";
  REQUIRE_FALSE(run(config, tamped, false, "tamp", first));
  std::string next;
  railway::BedBetweenStages bed = railway::load_checkpoint(tamped, config, railway::CheckpointUse::kResume, loaded, next);
  REQUIRE(next == "consolidate");
  const dem::RigidBox design = railway::sleeper_box(config.geometry);
  bed.sleeper_centre = design.centre + dem::Vec3(0, 0, 0.04);
  const double r = bed.stones[0].pebbles[0].radius;
  REQUIRE(bed.stones[0].pebbles.size() == 1);
  bed.stones[0].position = bed.sleeper_centre - dem::Vec3(0, 0, design.half_extent.z() + 0.9 * r);
  bed.stones[0].velocity = bed.stones[0].angular_velocity = dem::Vec3::Zero();
  // The stone lies inside the design box, and touches the moved one by 0.1 of its radius.
  const auto at_design = dem::sphere_box_contact(bed.stones[0].position, r, design.centre, design.half_extent);
  REQUIRE(at_design);
  REQUIRE(at_design->overlap > r);
  railway::StageSetup setup;
  setup.sleeper = design;  // the box the next stage starts with, at its design place
  const auto moved = dir.path() / "moved.h5";
  REQUIRE_NOTHROW(railway::save_checkpoint(moved, config, bed, setup, loaded, "consolidate"));
  const railway::Packing saved = railway::load_packing(moved);
  CHECK(saved.sleeper.centre == bed.sleeper_centre);
  CHECK(saved.bodies[0].position == bed.stones[0].position);
}

TEST_CASE("a checkpoint is refused for another seed, another config or a stage not run", "[railway][checkpoint]") {
  const test::TempDir dir;
  const auto checkpoint = dir.path() / "checkpoint.h5";
  railway::PreparationReport report;
  CHECK_THROWS_WITH(run(staged_config(), checkpoint, true, "", report), Catch::Contains("no such checkpoint"));
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

TEST_CASE("a deposition reused under other tamping and settling is that config's own preparation",
          "[railway][checkpoint]") {
  const test::TempDir dir;
  const auto deposited = dir.path() / "deposited.h5";
  railway::PreparationReport first;
  REQUIRE_FALSE(run(staged_config(), deposited, false, "deposit", first));
  // Other keys that act after the deposition: no consolidation, longer tamping, other settling.
  const railway::PushStudyConfig other = staged_config(7, 0.03, "");
  std::string text = other.text;
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"consolidation_gravity = 10.0", "consolidation_gravity = 1.0"},
                                 {"max_settling_time = 0.1", "max_settling_time = 0.08\nlocal_damping = 0.5"}})
    text.replace(text.find(from), from.size(), to);
  const railway::PushStudyConfig later = railway::parse_push_config(text, "later.toml");
  railway::PreparationReport own, reused;
  const auto from_scratch = run(later, {}, false, "", own);
  const auto from_deposit = run(later, dir.path() / "checkpoint.h5", false, "", reused, deposited);
  REQUIRE(from_scratch);
  REQUIRE(from_deposit);
  CHECK(same_states(*from_scratch, *from_deposit));
  REQUIRE(reused.stages.size() == 3);  // deposit, tamp, settle
  CHECK(reused.stages[2].steps == own.stages[2].steps);
  CHECK(reused.stones_removed == own.stones_removed);
  // A key the deposition uses is refused, named with both values; so is a checkpoint after tamping.
  railway::PreparationReport refused;
  std::string changed = text;
  changed.replace(changed.find("deposition_local_damping = 0.2"), 30, "deposition_local_damping = 0.3");
  CHECK_THROWS_WITH(run(railway::parse_push_config(changed, "c.toml"), {}, false, "", refused, deposited),
                    Catch::Contains("preparation.deposition_local_damping = 0.2 in the checkpoint, 0.3 now"));
  const auto after_tamp = dir.path() / "after_tamp.h5";
  std::filesystem::copy_file(deposited, after_tamp);
  refused = {};
  REQUIRE_FALSE(run(staged_config(), after_tamp, true, "tamp", refused));
  refused = {};
  CHECK_THROWS_WITH(run(later, {}, false, "", refused, after_tamp),
                    Catch::Contains("saved before stage 'consolidate', not after the deposition"));
}

TEST_CASE("a traffic pulse is P sin^2(pi t / T): zero between axles, P at its middle", "[railway][traffic]") {
  // Reference: the closed form; tolerance 1e-12 P (round-off of sin).
  railway::PreparationSettings p;
  p.traffic_load = 9e4;
  p.traffic_period = 0.05;
  CHECK(railway::traffic_load_at(p, 0.0) == 0.0);
  CHECK(railway::traffic_load_at(p, 0.025) == Approx(9e4).margin(1e-12 * 9e4));
  CHECK(railway::traffic_load_at(p, 0.0125) == Approx(4.5e4).margin(1e-12 * 9e4));
  CHECK(railway::traffic_load_at(p, 0.05) == Approx(0.0).margin(1e-12 * 9e4));
  CHECK(railway::traffic_load_at(p, 0.075) == Approx(9e4).margin(1e-12 * 9e4));
}

TEST_CASE("traffic presses the sleeper into the bed while its rails hold it across, and a pack resumes after it",
          "[railway][traffic][checkpoint]") {
  // Three pulses of 10x the sleeper's weight on the tiny bed. References: against the same
  // deposition under pulses of 1e-6 N (its weight alone) the sleeper ends lower; held across
  // the track, its centre keeps its x to the bit; resumed after the traffic, the packing is
  // bitwise the uninterrupted one (memcmp).
  const test::TempDir dir;
  const std::string traffic = "traffic_cycles = 3\ntraffic_period = 0.01\ntraffic_load = ";
  const railway::PushStudyConfig heavy = staged_config(7, 0.02, traffic + "250.0\n");
  REQUIRE(railway::stopping_points(heavy) == std::vector<std::string>{"deposit", "tamp", "consolidate", "traffic"});
  const auto deposited = dir.path() / "deposited.h5";
  railway::PreparationReport first;
  REQUIRE_FALSE(run(heavy, deposited, false, "deposit", first));

  railway::PreparationReport whole, stopped, resumed_report, light_report;
  const auto uninterrupted = run(heavy, {}, false, "", whole, deposited);
  const auto checkpoint = dir.path() / "checkpoint.h5";
  railway::PreparationReport consolidated;
  REQUIRE_FALSE(run(heavy, checkpoint, false, "consolidate", consolidated, deposited));
  const double x_before = railway::load_packing(checkpoint).sleeper.centre.x();
  REQUIRE_FALSE(run(heavy, checkpoint, true, "traffic", stopped));
  const double x_after = railway::load_packing(checkpoint).sleeper.centre.x();
  const auto resumed = run(heavy, checkpoint, true, "", resumed_report);
  const auto light = run(staged_config(7, 0.02, traffic + "1e-6\n"), {}, false, "", light_report, deposited);
  REQUIRE(uninterrupted);
  REQUIRE(resumed);
  REQUIRE(light);

  CHECK(same_states(*uninterrupted, *resumed));
  CHECK(x_after == x_before);
  REQUIRE(stopped.stages.size() == 4);  // deposit, tamp, consolidate, traffic
  REQUIRE(light_report.stages.size() == 5);
  CHECK(stopped.stages[3].name == "traffic");
  const double before = *stopped.stages[2].sleeper_base;
  CHECK(stopped.stages[3].sleeper_base_start == before);  // the traffic starts where the consolidation left it
  const double loaded = *stopped.stages[3].sleeper_base;
  const double unloaded = *light_report.stages[3].sleeper_base;
  CAPTURE(before, loaded, unloaded);
  CHECK(loaded < unloaded);
}

TEST_CASE("a finished packing continued with more traffic keeps its stones and sinks under the pulses",
          "[railway][traffic][continue]") {
  // `mfdem pack --continue-from`: the tamped, consolidated and settled tiny bed (no traffic)
  // gets three pulses of 10x the sleeper's weight, then settles again. References: the
  // continuation starts from the packing's sleeper to the bit; against the same continuation
  // under pulses of 1e-6 N (its weight alone) the sleeper ends lower; the stones are the
  // packing's, in its order; the repeated stages are reported after the packing's own, renamed.
  const test::TempDir dir;
  const auto deposited = dir.path() / "deposited.h5";
  const auto finished = dir.path() / "settled.h5";
  const railway::Packing settled = finished_bed(deposited, finished);

  const std::string traffic = "traffic_cycles = 3\ntraffic_period = 0.01\ntraffic_load = ";
  const auto continued = [&](const railway::PushStudyConfig& c, const std::filesystem::path& from,
                             railway::PreparationReport& report) {
    railway::PreparationControl control;
    control.quiet = true;
    control.continue_from = from;
    return railway::prepare_bed(c, control, report);
  };
  railway::PreparationReport heavy_report, light_report;
  const railway::PushStudyConfig heavy_config = staged_config(7, 0.02, traffic + "250.0\n");
  const auto heavy = continued(heavy_config, finished, heavy_report);
  const auto light = continued(staged_config(7, 0.02, traffic + "1e-6\n"), finished, light_report);
  REQUIRE(heavy);
  REQUIRE(light);

  std::vector<std::string> names;
  for (const auto& s : heavy_report.stages) names.push_back(s.name);
  CHECK(names == std::vector<std::string>{"deposit", "tamp", "consolidate", "settle", "traffic", "settle_2"});
  CHECK(heavy->continued_from == finished.string());
  REQUIRE(heavy->stones.size() == settled.stones.size());
  for (std::size_t k = 0; k < heavy->stones.size(); ++k) CHECK(heavy->stones[k].id == settled.stones[k].id);
  CHECK(*heavy_report.stages[4].sleeper_base_start == dem::box_bottom(settled.sleeper));
  const double loaded = *heavy_report.stages[4].sleeper_base;
  const double unloaded = *light_report.stages[4].sleeper_base;
  CAPTURE(loaded, unloaded);
  CHECK(loaded < unloaded);

  // Stopped after its traffic and resumed, the continuation is bitwise the uninterrupted one
  // (memcmp) and still knows where it came from.
  const auto checkpoint = dir.path() / "checkpoint.h5";
  railway::PreparationControl stop;
  stop.quiet = true;
  stop.continue_from = finished;
  stop.checkpoint = checkpoint;
  stop.stop_after = "traffic";
  railway::PreparationReport stopped_report, resumed_report;
  REQUIRE_FALSE(railway::prepare_bed(heavy_config, stop, stopped_report));
  railway::PreparationControl resume;
  resume.quiet = true;
  resume.checkpoint = checkpoint;
  resume.resume = true;
  const auto resumed = railway::prepare_bed(heavy_config, resume, resumed_report);
  REQUIRE(resumed);
  CHECK(same_states(*heavy, *resumed));
  CHECK(resumed->continued_from == finished.string());
  CHECK(resumed_report.stages.back().name == "settle_2");

  // Continued again, the repeated names count on, and the file keeps every stage in order.
  const auto twice_file = dir.path() / "continued.h5";
  railway::save_finished_packing(twice_file, *heavy, heavy_report.stages);
  CHECK(railway::load_packing(twice_file).continued_from == finished.string());
  railway::PreparationReport again_report;
  const auto again = continued(staged_config(7, 0.02, "traffic_cycles = 1\ntraffic_period = 0.01\n"), twice_file,
                               again_report);
  REQUIRE(again);
  const auto again_file = dir.path() / "again.h5";
  railway::save_finished_packing(again_file, *again, again_report.stages);
  names.clear();
  for (const auto& s : railway::read_stage_reports(again_file)) names.push_back(s.name);
  CHECK(names == std::vector<std::string>{"deposit", "tamp", "consolidate", "settle", "traffic", "settle_2",
                                          "traffic_2", "settle_3"});
}

TEST_CASE("a packing is continued only with its own config's bed and with traffic to add",
          "[railway][continue]") {
  const test::TempDir dir;
  finished_bed(dir.path() / "deposited.h5", dir.path() / "settled.h5");
  const auto deposited = dir.path() / "deposited.h5";
  const auto finished = dir.path() / "settled.h5";
  const std::string traffic = "traffic_cycles = 2\ntraffic_period = 0.01\n";
  const auto attempt = [&](const railway::PushStudyConfig& c, const std::filesystem::path& from) {
    railway::PreparationControl control;
    control.quiet = true;
    control.continue_from = from;
    railway::PreparationReport report;
    return railway::prepare_bed(c, control, report);
  };
  CHECK_THROWS_WITH(attempt(staged_config(8, 0.02, traffic), finished),
                    Catch::Contains("settled.h5") && Catch::Contains("seed 7") && Catch::Contains("--seed 7"));
  CHECK_THROWS_WITH(attempt(staged_config(7, 0.03, traffic), finished),
                    Catch::Contains("settled.h5") && Catch::Contains("preparation.tamping_time = 0.02 in the packing") &&
                        Catch::Contains("only the traffic and settling keys may differ"));
  CHECK_THROWS_WITH(attempt(staged_config(), finished),
                    Catch::Contains("runs no traffic") && Catch::Contains("traffic_cycles"));
  CHECK_THROWS_WITH(attempt(staged_config(7, 0.02, traffic), deposited),
                    Catch::Contains("deposited.h5") && Catch::Contains("a checkpoint, not a finished packing"));
  CHECK_THROWS_WITH(attempt(staged_config(7, 0.02, traffic), dir.path() / "nowhere.h5"),
                    Catch::Contains("nowhere.h5") && Catch::Contains("no such file"));
}
