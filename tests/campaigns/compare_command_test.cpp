// `mfdem compare` end to end on a micro bed (6-pebble clumps of 25 mm in a 0.12 m section, a
// 0.3 mm push): what it computes, that it computes each run once whatever happens to it, and
// what it refuses.
#include <catch2/catch.hpp>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "studies/campaigns/compare.hpp"
#include "studies/runs/run_store.hpp"
#include "tests/campaigns/micro_compare.hpp"
#include "tests/support/run_mfdem.hpp"
#include "tests/support/temp_dir.hpp"

using Catch::Matchers::Contains;
using mfdem::test::run_mfdem;
namespace fs = std::filesystem;

namespace {

using mfdem::test::micro_bed;
using mfdem::test::text_of;
using mfdem::test::without_wall_times;

std::vector<std::string> csv_fields(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream in(line);
  for (std::string field; std::getline(in, field, ',');) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

// A model that converts no stone: its bed, push and outputs are bitwise the reference's.
constexpr const char* kModels = "all-clump,layer-by-height:h=0,all-ball";

}  // namespace

TEST_CASE("compare: the same table on 1 and 2 threads and with two processes, and zero difference for an "
          "identical model", "[campaigns][cli]") {
  const mfdem::test::TempDir dir;
  const auto config = dir.write("micro.toml", micro_bed());
  const std::string one = (dir.path() / "one").string(), two = (dir.path() / "two").string();
  const auto first = run_mfdem({"compare", config.string(), "--models", kModels, "--seeds", "1", "--out", one,
                                "--jobs", "1", "--threads", "1"});
  INFO(first.err);
  REQUIRE(first.status == 0);
  CHECK_THAT(first.out, Contains("Cost") && Contains("Accuracy") && Contains("Verdict"));
  // Two worker processes of two threads each, into another store.
  const auto second = run_mfdem({"compare", config.string(), "--models", kModels, "--seeds", "1", "--out", two,
                                 "--jobs", "2", "--threads", "2", "--no-figures"});
  INFO(second.err);
  REQUIRE(second.status == 0);
  CHECK_FALSE(fs::exists(two + "/figures.h5"));  // --no-figures
  // The figures: their numbers from the C++, drawn by studies/python/mfdem (Debian's matplotlib,
  // which the quick start installs).
  CHECK(fs::exists(one + "/figures.h5"));
  for (const char* figure : {"force_displacement", "displacement_section", "force_chains", "speedup_error"})
    for (const char* type : {".png", ".svg"}) {
      CAPTURE(figure, type);
      CHECK(fs::file_size(fs::path(one) / "figures" / (std::string(figure) + type)) > 1000);
    }
  const std::string table = without_wall_times(text_of(one + "/compare.csv"));
  CHECK(table == without_wall_times(text_of(two + "/compare.csv")));
  // The model that converts nothing differs from the reference by exactly zero on every output.
  std::stringstream rows(text_of(one + "/compare.csv"));
  std::string header, reference, same;
  std::getline(rows, header);
  std::getline(rows, reference);
  std::getline(rows, same);
  CHECK_THAT(same, Contains("layer-by-height:h=0"));
  const std::vector<std::string> fields = csv_fields(same);
  REQUIRE(fields.size() == 42);
  // The paired differences of the four outputs (columns 13, 17, 21, 25) and the F(u) NRMS (28):
  // exactly 0; with one seed, no interval (its bounds empty).
  for (std::size_t column : {13u, 17u, 21u, 25u, 28u}) {
    CAPTURE(column);
    CHECK(fields[column] == "0");
    CHECK(fields[column + 1].empty());
  }
  // Each seed's difference of the four outputs (38-41): the one seed's, 0.
  for (std::size_t column : {38u, 39u, 40u, 41u}) {
    CAPTURE(column);
    CHECK(fields[column] == "0");
  }
  // One seed carries no verdict on an interval: the verdict says what that seed shows.
  CHECK_THAT(text_of(one + "/compare.md"),
             Contains("one seed, no interval: on it the peak force differs by +0.0 % (within 5 %), the contact force "
                      "by +0.0 % (within)"));
  const mfdem::runs::RunStore store(one);
  const auto records = store.records();
  REQUIRE(records.size() == 3);
  std::optional<double> peak_reference, peak_same;
  for (const auto& r : records) {
    CHECK(r.finished());
    if (r.label("model") == "all-clump") peak_reference = r.number("peak_force");
    if (r.label("model") == "layer-by-height:h=0 mu_r=0.3") peak_same = r.number("peak_force");
  }
  REQUIRE(peak_reference);
  CHECK(peak_same == peak_reference);  // bitwise
  // `mfdem plot` of two of the store's runs: the push figures, drawn by the same package.
  const fs::path plotted = dir.path() / "plot";
  const auto plot = run_mfdem({"plot", (store.run_folder(records[0].key)).string(),
                               (store.run_folder(records[1].key)).string(), "--out", plotted.string(), "-q"});
  INFO(plot.err);
  CHECK(plot.status == 0);
  for (const char* figure : {"force_displacement", "resistance_by_face", "displacement_section", "force_chains"}) {
    CAPTURE(figure);
    CHECK(fs::file_size(plotted / "figures" / (std::string(figure) + ".png")) > 1000);
  }
  const auto no_push = run_mfdem({"plot", dir.path().string(), "--out", plotted.string()});
  CHECK(no_push.status == 2);
  CHECK_THAT(no_push.err, Contains("no push.h5"));
  // Again: everything is found, nothing computed (no record is written anew).
  std::vector<fs::file_time_type> stamps;
  for (const auto& r : records) stamps.push_back(fs::last_write_time(store.run_folder(r.key) / "run.toml"));
  const auto again = run_mfdem({"compare", config.string(), "--models", kModels, "--seeds", "1", "--out", one,
                                "--jobs", "1"});
  CHECK(again.status == 0);
  CHECK_THAT(again.err, Contains("3 already in"));
  for (std::size_t k = 0; k < records.size(); ++k)
    CHECK(fs::last_write_time(store.run_folder(records[k].key) / "run.toml") == stamps[k]);
}

TEST_CASE("compare killed in the middle of a run recomputes only that run, and a failing run is recorded",
          "[campaigns][cli]") {
  const mfdem::test::TempDir dir;
  const auto config = dir.write("micro.toml", micro_bed());
  const std::string out = (dir.path() / "store").string();
  // h = 0.2 m lies above the sleeper base (0.08 m): refused by each run's bed, recorded as failed.
  // h = 0 converts nothing: computed after the restart, it must be bitwise the reference computed
  // before the kill, as in a study never interrupted.
  const std::string models = "all-clump,layer-by-height:h=0.2,all-ball,layer-by-height:h=0";
  const std::string command = mfdem::test::shell_quoted(MFDEM_EXECUTABLE) + " compare " + config.string() +
                              " --models " + models + " --seeds 1 --jobs 1 -q --out " + out;
  // Killed once the first run is published, while the next ones are in progress.
  const pid_t child = fork();
  if (child == 0) {
    execl("/bin/sh", "sh", "-c", ("exec " + command + " >/dev/null 2>&1").c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  const fs::path runs = fs::path(out) / "runs";
  // Up to 10 min: the first run takes seconds alone, minutes on a machine busy with a study.
  for (int waited = 0; waited < 3000 && (!fs::exists(runs) || fs::is_empty(runs)); ++waited)
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  kill(child, SIGKILL);
  waitpid(child, nullptr, 0);
  REQUIRE(fs::exists(runs));
  const auto before = mfdem::runs::RunStore(out).records();
  REQUIRE_FALSE(before.empty());
  REQUIRE(before.size() < 4);  // killed before the study's end
  const auto stamp = fs::last_write_time(runs / before.front().key / "run.toml");

  const auto resumed = run_mfdem({"compare", config.string(), "--models", models, "--seeds", "1", "--jobs", "1",
                                  "--out", out});
  INFO(resumed.err);
  REQUIRE(resumed.status == 0);
  const auto after = mfdem::runs::RunStore(out).records();
  REQUIRE(after.size() == 4);
  CHECK(fs::last_write_time(runs / before.front().key / "run.toml") == stamp);  // not recomputed
  CHECK(fs::is_empty(fs::path(out) / "work"));
  CHECK(fs::is_empty(fs::path(out) / "claims"));
  int failed = 0;
  for (const auto& r : after)
    if (!r.finished()) {
      ++failed;
      CHECK_THAT(r.message, Contains("h = 0.2"));
    }
  CHECK(failed == 1);
  CHECK_THAT(resumed.out, Contains("failed: layer-by-height:h=0.2"));
  std::optional<double> reference, same;
  for (const auto& r : after) {
    if (r.label("model") == "all-clump") reference = r.number("peak_force");
    if (r.label("model") == "layer-by-height:h=0 mu_r=0.3") same = r.number("peak_force");
  }
  REQUIRE(reference);
  CHECK(same == reference);
  // The index holds every run, rebuilt from the folders.
  const std::string index = text_of(out + "/index.csv");
  CHECK(std::count(index.begin(), index.end(), '\n') == 5);
}

TEST_CASE("compare refuses an unknown model, an empty or bad seed list and a reference not among the models",
          "[campaigns][cli][input]") {
  const mfdem::test::TempDir dir;
  const std::string out = (dir.path() / "store").string();
  const auto unknown = run_mfdem({"compare", "mini", "--models", "all-clump,all-bal", "--out", out});
  CHECK(unknown.status == 2);
  CHECK_THAT(unknown.err, Contains("--models all-clump,all-bal") && Contains("all-bal"));
  const auto empty = run_mfdem({"compare", "mini", "--seeds", "", "--out", out});
  CHECK(empty.status == 2);
  CHECK_THAT(empty.err, Contains("--seeds") && Contains("no seed"));
  const auto backwards = run_mfdem({"compare", "mini", "--seeds", "5-2", "--out", out});
  CHECK(backwards.status == 2);
  CHECK_THAT(backwards.err, Contains("5-2"));
  const auto reference = run_mfdem({"compare", "mini", "--models", "all-clump,all-ball", "--reference",
                                    "zone-by-distance:d=0.1", "--out", out});
  CHECK(reference.status == 2);
  CHECK_THAT(reference.err, Contains("--reference") && Contains("not one of the --models"));
  const auto twice = run_mfdem({"compare", "mini", "--models", "all-ball,all-ball", "--out", out});
  CHECK(twice.status == 2);
  CHECK_THAT(twice.err, Contains("given twice"));
  CHECK_FALSE(fs::exists(out));  // refused before the store was made
}

TEST_CASE("the processes of a resumed study start on different unfinished seeds", "[campaigns][cli]") {
  using mfdem::campaigns::seed_order;
  using V = std::vector<std::size_t>;
  // Seeds 1-5 with 1 and 2 complete: the two processes of --jobs 2 start on seeds 3 and 4, not both
  // on 3 (where the second would wait for the first's deposition); each ends with the complete ones.
  const std::vector<bool> incomplete = {false, false, true, true, true};
  CHECK(seed_order(incomplete, 0) == V{2, 3, 4, 0, 1});
  CHECK(seed_order(incomplete, 1) == V{3, 4, 2, 0, 1});
  CHECK(seed_order(incomplete, 4) == V{3, 4, 2, 0, 1});  // more processes than unfinished seeds: wraps
  CHECK(seed_order({false, false}, 1) == V{0, 1});       // nothing left: every seed once, no division by zero
  CHECK(seed_order({true, false, true}, 1) == V{2, 0, 1});
}

TEST_CASE("an undecided model's verdict says how many seeds would decide it", "[campaigns][cli]") {
  namespace campaigns = mfdem::campaigns;
  campaigns::CompareTable table;
  table.config = "study";
  table.seeds = {1, 2, 3, 4};
  campaigns::ModelRow reference, model;
  reference.model = "all-clump", reference.reference = true, reference.seeds = 4;
  model.model = "all-ball mu_r=0.3", model.seeds = 4;
  // The all-ball row of the study preset, seeds 1-4: the peak force decided (outside), the
  // maximum contact force +57.9 % with a standard deviation of 58.7 %: 8 seeds would place it.
  const auto difference = [](double mean, double sd) {
    campaigns::MeanInterval d;
    d.n = 4, d.mean = mean, d.standard_deviation = sd, d.half_width = 3.182 * sd / 2.0;
    return d;
  };
  model.peak_force.difference = difference(-0.343, 0.06);
  model.max_contact_force.difference = difference(0.579, 0.587);
  model.peak_verdict = campaigns::verdict(model.peak_force.difference, 0.05);
  model.contact_verdict = campaigns::verdict(model.max_contact_force.difference, 0.05);
  REQUIRE(model.peak_verdict == campaigns::Verdict::outside);
  REQUIRE(model.contact_verdict == campaigns::Verdict::undecided);
  table.rows = {reference, model};
  std::ostringstream decided;
  campaigns::print_compare_table(decided, table);
  CHECK_THAT(decided.str(), Contains("outside 5 % on the peak force"));  // one output outside decides it

  table.rows[1].peak_force.difference = difference(-0.06, 0.02);  // straddles -5 %: 1 % beyond the band
  table.rows[1].peak_verdict = campaigns::verdict(table.rows[1].peak_force.difference, 0.05);
  REQUIRE(table.rows[1].peak_verdict == campaigns::Verdict::undecided);
  std::ostringstream undecided;
  campaigns::print_compare_table(undecided, table);
  // The larger of the two counts: the peak's, (2 x 0.02 / 0.01)^2 = 16 in the normal limit, 18 with t (t_{0.975,17} = 2.110).
  CHECK(campaigns::seeds_to_decide(table.rows[1].peak_force.difference, 0.05) == 18);
  CHECK(campaigns::seeds_to_decide(table.rows[1].max_contact_force.difference, 0.05) == 8);
  CHECK_THAT(undecided.str(), Contains("not decided at 5 %: the intervals straddle it (about 18 seeds would decide it"));
}
