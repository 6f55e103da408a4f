// `mfdem trade` end to end on the micro bed: a knob inside its range runs, one past its edge is
// refused before any run with the knob named, the table and figure are written, and the same
// study again recomputes nothing.
#include <catch2/catch.hpp>

#include <filesystem>
#include <map>

#include "studies/runs/run_store.hpp"
#include "tests/campaigns/micro_compare.hpp"
#include "tests/support/refusals.hpp"
#include "tests/support/run_mfdem.hpp"
#include "tests/support/temp_dir.hpp"

using Catch::Matchers::Contains;
using mfdem::test::run_mfdem;
namespace fs = std::filesystem;

TEST_CASE("trade runs each knob's settings against the reference, refuses those past an edge and recomputes "
          "nothing when run again", "[campaigns][cli][trade]") {
  const mfdem::test::TempDir dir;
  const auto config = dir.write("micro.toml", mfdem::test::micro_bed());
  const std::string out = (dir.path() / "trade").string();
  const std::vector<std::string> study = {"trade",   config.string(), "--knob", "velocity=0.05,0.1",
                                          "--knob",  "push_damping=0,1", "--seeds", "1",
                                          "--threads", "1",           "--out",  out};
  const auto first = run_mfdem(study);
  INFO(first.err);
  REQUIRE(first.status == 0);
  CHECK_THAT(first.err, Contains("push_damping=1 is refused before it runs"));
  CHECK_THAT(first.out, Contains("velocity=0.1") && Contains("Stability edges") &&
                            Contains("push_damping: safe at 0, unsafe at 1"));
  const std::string csv = mfdem::test::text_of(fs::path(out) / "trade.csv");
  CHECK_THAT(csv, Contains("velocity,0.1,\"velocity=0.1\",\"ran\""));
  CHECK_THAT(csv, Contains("\"refused: --knob push_damping=1: push.local_damping = 1"));
  CHECK(fs::file_size(fs::path(out) / "figures" / "trade.png") > 1000);
  // Two runs (the reference and velocity 0.1), one deposition and one prepared bed: a setting of the
  // push shares the seed's bed, hard-linked into both runs' folders.
  mfdem::runs::RunStore store(out);
  const auto records = store.records();
  REQUIRE(records.size() == 2);
  std::size_t depositions = 0, beds = 0;
  for (const auto& entry : fs::directory_iterator(fs::path(out) / "shared")) {
    depositions += entry.path().filename().string().rfind("deposit-", 0) == 0 ? 1 : 0;
    beds += entry.path().filename().string().rfind("bed-", 0) == 0 ? 1 : 0;
  }
  CHECK(depositions == 1);
  CHECK(beds == 1);
  for (const auto& r : records) CHECK(fs::exists(store.run_folder(r.key) / "packing.h5"));
  // Again: every run found, none rewritten, the same table.
  std::map<std::string, fs::file_time_type> written;
  for (const auto& r : records) written[r.key] = fs::last_write_time(store.run_folder(r.key) / "run.toml");
  const auto second = run_mfdem(study);
  REQUIRE(second.status == 0);
  for (const auto& r : records) CHECK(fs::last_write_time(store.run_folder(r.key) / "run.toml") == written[r.key]);
  CHECK(mfdem::test::text_of(fs::path(out) / "trade.csv") == csv);
}

TEST_CASE("trade with --jobs 2 computes the serial study's runs in two processes and writes its table once",
          "[campaigns][cli][trade]") {
  const mfdem::test::TempDir dir;
  const auto config = dir.write("micro.toml", mfdem::test::micro_bed());
  const auto study = [&](const std::string& out, const std::string& jobs) {
    return std::vector<std::string>{"trade",  config.string(), "--knob", "velocity=0.05,0.1", "--seeds",
                                    "1",      "--threads",     "1",      "--jobs",            jobs,
                                    "--out",  (dir.path() / out).string()};
  };
  const auto serial = run_mfdem(study("serial", "1"));
  REQUIRE(serial.status == 0);
  const auto parallel = run_mfdem(study("parallel", "2"));
  INFO(parallel.err);
  REQUIRE(parallel.status == 0);
  CHECK_THAT(parallel.out, Contains("velocity=0.1") && Contains("Stability edges"));
  // The worker ran slice 1/2 into the same store and wrote no table of its own.
  const std::string worker_log = mfdem::test::text_of(dir.path() / "parallel" / "logs" / "worker-1.log");
  CHECK_THAT(worker_log, !Contains("Stability edges"));
  const auto runs_of = [&](const std::string& out) {
    std::map<std::string, double> peaks;
    for (const auto& r : mfdem::runs::RunStore(dir.path() / out).records()) peaks[r.key] = *r.number("peak_force");
    return peaks;
  };
  const auto serial_runs = runs_of("serial");
  REQUIRE(serial_runs.size() == 2);
  CHECK(runs_of("parallel") == serial_runs);  // the same keys, bitwise the same peaks
}

TEST_CASE("trade refuses unknown knobs, a knob given twice and a refused reference before any run", "[cli][trade]") {
  const mfdem::test::TempDir dir;
  mfdem::test::check_refused_before_any_run("trade", "mini", dir.path() / "trade", {
      {{"--knob", "speed=1,2"}, {"--knob speed=1,2", "unknown knob 'speed'"}},
      {{"--knob", "velocity=0.1", "--knob", "velocity=0.2"}, {"--knob velocity=0.2", "given twice"}},
      {{"--knob", "time_step_safety=1.5,2"}, {"the reference setting", "time_step_safety=1.5"}},
      {{"--knob", "velocity=0.1", "--seeds", "2-1"}, {"--seeds"}},
  });
}
