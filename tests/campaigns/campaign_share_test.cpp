// Several processes filling one store, each with its share of a campaign (campaigns/run_slice.hpp,
// cli/campaign_share.hpp): the shares partition the runs, and the store and table they make
// together are the serial study's.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>

#include "studies/campaigns/run_slice.hpp"
#include "studies/config/config_error.hpp"
#include "tests/campaigns/micro_compare.hpp"
#include "tests/support/run_mfdem.hpp"
#include "tests/support/temp_dir.hpp"

using namespace mfdem;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

TEST_CASE("run slices K/N deal every run to exactly one of N processes", "[campaigns][share]") {
  for (std::size_t count : {1, 2, 3, 7})
    for (std::size_t run = 0; run < 50; ++run) {
      int holders = 0;
      for (std::size_t k = 0; k < count; ++k) holders += campaigns::RunSlice{k, count}.holds(run) ? 1 : 0;
      CHECK(holders == 1);
    }
  const auto slice = campaigns::parse_run_slice("2/4", "--slice");
  CHECK(slice.index == 2);
  CHECK(slice.count == 4);
  CHECK(slice.holds(6));
  CHECK_FALSE(slice.holds(7));
  for (const char* bad : {"4/4", "1", "/2", "1/", "a/2", "1/0", "-1/2", "1/2/3"})
    CHECK_THROWS_WITH(campaigns::parse_run_slice(bad, "--slice"), Contains(std::string("--slice ") + bad) &&
                                                                      Contains("0 <= K < N"));
}

TEST_CASE("compare split over two --slice processes makes the serial study's store and table", "[campaigns][cli][share]") {
  const test::TempDir dir;
  const auto config = dir.write("micro.toml", test::micro_bed());
  const std::string serial = (dir.path() / "serial").string(), shared = (dir.path() / "shared").string();
  const std::vector<std::string> study = {"compare", config.string(), "--models", "all-clump,all-ball", "--seeds", "1",
                                          "--threads", "1", "--no-figures"};
  auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> args = study;
    args.insert(args.end(), extra.begin(), extra.end());
    return args;
  };
  const auto alone = test::run_mfdem(with({"--out", serial, "--jobs", "1"}));
  INFO(alone.err);
  REQUIRE(alone.status == 0);
  // Two tasks of a job array, at once, each its share: the one that ends last writes the table.
  test::Outcome first, second;
  std::thread a([&] { first = test::run_mfdem(with({"--out", shared, "--slice", "0/2"})); });
  std::thread b([&] { second = test::run_mfdem(with({"--out", shared, "--slice", "1/2"})); });
  a.join();
  b.join();
  INFO(first.err << second.err);
  REQUIRE(first.status == 0);
  REQUIRE(second.status == 0);
  CHECK(fs::exists(fs::path(shared) / "compare.csv"));
  CHECK(test::without_wall_times(test::text_of(fs::path(shared) / "compare.csv")) ==
        test::without_wall_times(test::text_of(fs::path(serial) / "compare.csv")));
  // --slice with --jobs is one process's share computed by several: refused.
  const auto refused = test::run_mfdem(with({"--out", (dir.path() / "x").string(), "--slice", "0/2", "--jobs", "2"}));
  CHECK(refused.status == 2);
  CHECK_THAT(refused.err, Contains("--jobs 2") && Contains("--slice"));
}

TEST_CASE("stats with --jobs 2 makes the serial study's store and table", "[campaigns][cli][share][stats]") {
  const test::TempDir dir;
  const auto config = dir.write("micro.toml", test::micro_bed());
  const auto study = [&](const std::string& out, const std::string& jobs) {
    return std::vector<std::string>{"stats",     config.string(), "--seeds", "1-3",        "--threads", "1",
                                    "--jobs",    jobs,            "--out",   (dir.path() / out).string(),
                                    "--no-figures"};
  };
  const auto serial = test::run_mfdem(study("serial", "1"));
  INFO(serial.err);
  REQUIRE(serial.status == 0);
  const auto parallel = test::run_mfdem(study("parallel", "2"));
  INFO(parallel.err);
  REQUIRE(parallel.status == 0);
  CHECK(fs::exists(dir.path() / "parallel" / "logs" / "worker-1.log"));
  CHECK(test::without_wall_times(test::text_of(dir.path() / "parallel" / "stats.csv")) ==
        test::without_wall_times(test::text_of(dir.path() / "serial" / "stats.csv")));
}

#ifdef MFDEM_MPI
TEST_CASE("compare over two MPI ranks makes the serial study's store and table", "[campaigns][cli][share][mpi]") {
  const test::TempDir dir;
  const auto config = dir.write("micro.toml", test::micro_bed());
  const std::string serial = (dir.path() / "serial").string(), ranks = (dir.path() / "ranks").string();
  const std::string common = " compare " + test::shell_quoted(config.string()) +
                             " --models all-clump,all-ball --seeds 1-2 --threads 1 --no-figures --out ";
  REQUIRE(test::run_mfdem({"compare", config.string(), "--models", "all-clump,all-ball", "--seeds", "1-2", "--threads",
                           "1", "--no-figures", "--jobs", "1", "--out", serial}).status == 0);
  // OpenMPI refuses root unless told; a test machine's container often runs as root.
  const std::string command = "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpirun --oversubscribe -np 2 " +
                              test::shell_quoted(MFDEM_EXECUTABLE) + common + test::shell_quoted(ranks) +
                              " > " + test::shell_quoted((dir.path() / "mpi.log").string()) + " 2>&1";
  const int status = std::system(command.c_str());
  INFO(test::text_of(dir.path() / "mpi.log"));
  REQUIRE(status == 0);
  CHECK(test::without_wall_times(test::text_of(fs::path(ranks) / "compare.csv")) ==
        test::without_wall_times(test::text_of(fs::path(serial) / "compare.csv")));
  // Every run made once: four run folders, and the two ranks each computed two (their logs are quiet,
  // so the store tells): nothing left in work/.
  std::size_t runs = 0;
  for (const auto& entry : fs::directory_iterator(fs::path(ranks) / "runs")) runs += entry.is_directory() ? 1 : 0;
  CHECK(runs == 4);
  CHECK(fs::is_empty(fs::path(ranks) / "work"));
}
#endif
