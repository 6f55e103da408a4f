// What a push may not be given, and what a folder of results may never hold: numbers that are
// not finite or make no step, a seed a push does not have, and an earlier run's files beside a
// new run's. Each refusal exits 2 before any work and names the option; each new run replaces
// the folder's earlier results as a whole.
#include <catch2/catch.hpp>
#include <hdf5.h>
#include <sys/stat.h>
#include <unistd.h>
#include <toml++/toml.h>

#include <cmath>
#include <vector>

#include <filesystem>
#include <fstream>
#include <string>

#include "tests/railway/tiny_bed.hpp"
#include "tests/support/run_mfdem.hpp"
#include "tests/support/temp_dir.hpp"

using Catch::Matchers::Contains;
using mfdem::test::run_mfdem;
namespace fs = std::filesystem;

namespace {

std::string status_of(const fs::path& summary) {
  return toml::parse_file(summary.string())["status"].value_or(std::string("(none)"));
}

}  // namespace

TEST_CASE("a push refuses numbers that are not finite, make no step, or a seed of its own",
          "[railway][cli][input]") {
  const mfdem::test::TempDir dir;
  const auto config = dir.write("tiny.toml", mfdem::test::kTinyBed);
  const std::string bed = (dir.path() / "bed").string();
  REQUIRE(run_mfdem({"pack", config.string(), "--out", bed, "-q", "--threads", "1"}).status == 0);
  const std::string out = (dir.path() / "push").string();
  for (const auto& [option, value] : {std::pair{"--velocity", "nan"}, {"--velocity", "inf"}, {"--distance", "nan"},
                                      {"--distance", "1e-300"}, {"--velocity", "1e-300"}}) {
    const auto refused = run_mfdem({"push", bed, option, value, "--out", out, "-q"});
    CAPTURE(option, value, refused.err);
    CHECK(refused.status == 2);
    CHECK_THAT(refused.err, Contains(std::string(option).substr(2)));
    CHECK_FALSE(fs::exists(out + "/push.h5"));
  }
  // push-test checks the push's numbers before it packs (a pack of the paper preset takes hours).
  for (const auto& [option, value] : {std::pair{"--velocity", "nan"}, {"--velocity", "0"}, {"--distance", "0"}}) {
    const std::string one_shot = (dir.path() / "one_shot").string();
    const auto refused = run_mfdem({"push-test", config.string(), option, value, "--out", one_shot, "-q"});
    CAPTURE(option, value, refused.err);
    CHECK(refused.status == 2);
    CHECK_THAT(refused.err, Contains(std::string(option)) && Contains("expected"));
    CHECK_FALSE(fs::exists(one_shot));  // nothing made: not even the folder
  }
  // --out: empty, or a file, is refused before any work, naming the option.
  const auto empty_out = run_mfdem({"push-test", config.string(), "--out", ""});
  CHECK(empty_out.status == 2);
  CHECK_THAT(empty_out.err, Contains("--out") && Contains("empty path"));
  // A folder nobody may write into (/sys refuses even root): refused before the pack starts.
  if (::mkdir("/sys/mfdem-write-probe", 0700) != 0) {
    const auto read_only = run_mfdem({"pack", config.string(), "--out", "/sys/mfdem-out", "-q"});
    CHECK(read_only.status == 2);
    CHECK_THAT(read_only.err, Contains("--out") && Contains("cannot write into /sys"));
  } else {
    ::rmdir("/sys/mfdem-write-probe");
    WARN("/sys is writable here: the read-only --out refusal is not exercised");
  }
  const auto file_out = run_mfdem({"push", bed, "--out", bed + "/packing.h5"});
  CHECK(file_out.status == 2);
  CHECK_THAT(file_out.err, Contains("--out") && Contains("is a file"));
  // A pack stopped after its deposition leaves a checkpoint, which push names as such.
  const std::string stopped = (dir.path() / "stopped").string();
  REQUIRE(run_mfdem({"pack", config.string(), "--stop-after", "deposit", "--out", stopped, "-q", "--threads", "1"})
              .status == 0);
  for (const std::string& given : {stopped, stopped + "/checkpoint.h5"}) {
    const auto checkpoint = run_mfdem({"push", given, "--out", out, "-q"});
    CAPTURE(given, checkpoint.err);
    CHECK(checkpoint.status == 2);
    CHECK_THAT(checkpoint.err, Contains("checkpoint.h5 is a checkpoint") && Contains("not a finished packing") &&
                                   Contains("--resume"));
  }
  // A packing whose last frame holds a NaN position (a damaged or hand-edited file) is refused
  // naming the file, the body and the value, before the solver sees it.
  const std::string damaged = (dir.path() / "damaged").string();
  fs::create_directories(damaged);
  fs::copy_file(bed + "/packing.h5", damaged + "/packing.h5");
  {
    const hid_t file = H5Fopen((damaged + "/packing.h5").c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    REQUIRE(file >= 0);
    const hid_t set = H5Dopen2(file, "frames/000000/position", H5P_DEFAULT);
    REQUIRE(set >= 0);
    const hid_t space = H5Dget_space(set);
    std::vector<double> xyz(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
    H5Sclose(space);
    H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, xyz.data());
    xyz[3 * 2 + 2] = std::nan("");  // body 2's z
    H5Dwrite(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, xyz.data());
    H5Dclose(set);
    H5Fclose(file);
  }
  const auto nan_position = run_mfdem({"push", damaged, "--out", out, "-q"});
  CAPTURE(nan_position.err);
  CHECK(nan_position.status == 2);
  CHECK_THAT(nan_position.err, Contains(damaged + "/packing.h5") && Contains("body 2") && Contains("nan m") &&
                                   Contains("finite positions"));
  const auto seeded = run_mfdem({"push", bed, "--seed", "5", "--out", out, "-q"});
  CHECK(seeded.status == 2);
  CHECK_THAT(seeded.err, Contains("--seed 5") && Contains("packing's"));
  const auto negative = run_mfdem({"pack", config.string(), "--seed", "-1", "--out", out, "-q"});
  CHECK(negative.status == 2);
  CHECK_THAT(negative.err, Contains("--seed -1") && Contains("whole number >= 0"));
}

TEST_CASE("a new run replaces the folder's earlier results as a whole, and a refused one leaves them",
          "[railway][cli][input]") {
  const mfdem::test::TempDir dir;
  const auto config = dir.write("tiny.toml", mfdem::test::kTinyBed);
  const std::string bed = (dir.path() / "bed").string();
  REQUIRE(run_mfdem({"pack", config.string(), "--out", bed, "-q", "--threads", "1"}).status == 0);
  REQUIRE(run_mfdem({"push", bed, "--check-rate", "--distance", "0.2", "--out", bed, "-q", "--threads", "1"}).status ==
          0);
  REQUIRE(fs::exists(bed + "/half_velocity/push.h5"));
  REQUIRE(fs::exists(bed + "/rate_check.toml"));

  // Refused before any work: the earlier push stays whole.
  CHECK(run_mfdem({"push", bed, "--distance", "nan", "--out", bed, "-q"}).status == 2);
  CHECK(status_of(bed + "/push_summary.toml") == "finished");
  CHECK(fs::exists(bed + "/half_velocity/push.h5"));

  // A push without the rate check: the earlier one's second push and its comparison go with it.
  const auto quiet = run_mfdem({"push", bed, "--distance", "0.2", "--out", bed, "-q", "--threads", "1"});
  REQUIRE(quiet.status == 0);
  CHECK(quiet.out.empty());  // -q: no table, no progress line
  CHECK(quiet.err.empty());
  CHECK_FALSE(fs::exists(bed + "/half_velocity"));
  CHECK_FALSE(fs::exists(bed + "/rate_check.toml"));
  CHECK(status_of(bed + "/push_summary.toml") == "finished");
  for (const auto& entry : fs::directory_iterator(bed))  // nothing left half-written
    CHECK_THAT(entry.path().string(), !Contains(".partial"));

  // A new pack into the folder, stopped after its deposition: the old bed and its push are gone,
  // so `mfdem push` of the folder cannot push the old bed as if it were the new one.
  REQUIRE(run_mfdem({"pack", config.string(), "--stop-after", "deposit", "--out", bed, "-q", "--threads", "1"})
              .status == 0);
  CHECK_FALSE(fs::exists(bed + "/packing.h5"));
  CHECK_FALSE(fs::exists(bed + "/push.h5"));
  CHECK_FALSE(fs::exists(bed + "/push_summary.toml"));
  CHECK(fs::exists(bed + "/checkpoint.h5"));
  const auto stale = run_mfdem({"push", bed, "--out", bed, "-q"});
  CHECK(stale.status == 2);
  CHECK_THAT(stale.err, Contains("checkpoint") && Contains("not a finished packing"));
}
