// `mfdem pack` and `mfdem push` refuse bad input with a message naming it (exit status 1 for a
// failure while running, 2 for a bad command line), before any simulation starts.
#include <catch2/catch.hpp>
#include <fmt/format.h>
#include <toml++/toml.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include <hdf5.h>

#include "dem/hdf5_io.hpp"
#include "tests/railway/tiny_bed.hpp"

#include "tests/support/run_mfdem.hpp"
#include "tests/support/temp_dir.hpp"

using mfdem::test::run_mfdem;

TEST_CASE("pack and push name the input they cannot use", "[railway][cli]") {
  const mfdem::test::TempDir dir;
  const std::string out = (dir.path() / "out").string();
  const auto missing = run_mfdem({"push", (dir.path() / "nowhere").string(), "--out", out, "-q"});
  CHECK(missing.status == 1);
  CHECK_THAT(missing.err, Catch::Contains("nowhere") && Catch::Contains("no such file") &&
                              Catch::Contains("mfdem pack"));
  CHECK_THAT(missing.err, !Catch::Contains("HDF5-DIAG"));  // our message, not HDF5's stack
  const auto preset = run_mfdem({"pack", "maxi", "--out", out, "-q"});
  CHECK(preset.status == 1);
  CHECK_THAT(preset.err, Catch::Contains("maxi") && Catch::Contains("mini, study, standard and paper"));
  const auto stop = run_mfdem({"pack", "mini", "--stop-after", "settle", "--out", out, "-q"});
  CHECK(stop.status == 1);
  CHECK_THAT(stop.err, Catch::Contains("--stop-after settle") && Catch::Contains("expected one of: deposit"));
  const auto resume = run_mfdem({"pack", "mini", "--resume", "--out", out, "-q"});
  CHECK(resume.status == 1);
  CHECK_THAT(resume.err, Catch::Contains("checkpoint.h5") && Catch::Contains("no such checkpoint"));
  std::filesystem::create_directories(out);
  std::ofstream(out + "/checkpoint.h5") << "";
  const auto own = run_mfdem({"pack", "mini", "--deposit-from", out, "--out", out, "-q"});
  CHECK(own.status == 1);
  CHECK_THAT(own.err, Catch::Contains("this run's own checkpoint") && Catch::Contains("another --out"));
  const auto fresh = run_mfdem({"pack", "mini", "--out", out, "-q"});
  CHECK(fresh.status == 1);
  CHECK_THAT(fresh.err, Catch::Contains(out + "/checkpoint.h5") && Catch::Contains("--resume") &&
                            Catch::Contains("remove it to start over"));
  const auto velocity = run_mfdem({"push", out, "--velocity", "-5"});
  CHECK(velocity.status == 2);
  CHECK_THAT(velocity.err, Catch::Contains("--velocity"));
}

TEST_CASE("pack then push --check-rate writes both pushes and reports the change", "[railway][cli]") {
  // End to end through the command line on the tiny bed: the half-velocity push is a second run
  // of the same packing at exactly half the velocity, and the reported change is
  // (peak_half - peak) / peak of the two summaries (printed to 0.01 %), likewise for the mean force.
  const mfdem::test::TempDir dir;
  const auto config = dir.path() / "tiny.toml";
  std::ofstream(config) << mfdem::test::kTinyBed;
  const std::string bed = (dir.path() / "bed").string();
  const auto pack = run_mfdem({"pack", config.string(), "--out", bed, "--threads", "1"});
  REQUIRE(pack.status == 0);
  CHECK_THAT(pack.out, Catch::Contains("Packed bed: tiny (seed 7)"));
  CHECK_FALSE(std::filesystem::exists(bed + "/checkpoint.h5"));  // removed once the packing is written
  // Written as packing.partial.h5 and renamed: nothing of the partial file stays, and the XDMF
  // names the packing by its final name (ParaView opens it).
  CHECK_FALSE(std::filesystem::exists(bed + "/packing.partial.h5"));
  CHECK_FALSE(std::filesystem::exists(bed + "/packing.partial.xdmf"));
  {
    std::ifstream in(bed + "/packing.xdmf");
    const std::string xdmf((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    CHECK_THAT(xdmf, Catch::Contains(">packing.h5:/frames/000000/element_position<") &&
                         !Catch::Contains("partial"));
  }
  {  // The packing keeps how each stage came to rest: a check every 2 ms of simulated time
     // (stage_runner.hpp), the last within one interval of the stage's end.
    const hid_t file = H5Fopen((bed + "/packing.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    REQUIRE(file >= 0);
    for (const char* stage : {"deposit", "settle"}) {
      CAPTURE(stage);
      const std::string g = fmt::format("packing/stages/{}/", stage);
      const auto time = mfdem::dem::h5::read_doubles(file, g + "time");
      const auto ratio = mfdem::dem::h5::read_doubles(file, g + "unbalanced_force_ratio");
      const auto kinetic = mfdem::dem::h5::read_doubles(file, g + "kinetic_ratio");
      REQUIRE(time.size() >= 2);
      CHECK(ratio.size() == time.size());
      CHECK(kinetic.size() == time.size());
      for (std::size_t k = 1; k < time.size(); ++k) CHECK(time[k] - time[k - 1] == Approx(2e-3).epsilon(0.01));
      const hid_t group = H5Gopen2(file, g.c_str(), H5P_DEFAULT);
      const double simulated = mfdem::dem::h5::read_attribute(group, "simulated_time");
      H5Gclose(group);
      CHECK(time.back() <= simulated + 1e-12);
      CHECK(time.back() > simulated - 2e-3 * 1.01);
    }
    H5Fclose(file);
  }
  const std::string push_dir = bed + "/push";
  const auto push = run_mfdem({"push", bed, "--check-rate", "--distance", "0.5", "--out", push_dir, "--threads", "1"});
  REQUIRE(push.status == 0);
  const auto full = toml::parse_file(push_dir + "/push_summary.toml");
  const auto half = toml::parse_file(push_dir + "/half_velocity/push_summary.toml");
  const double v = full["velocity"].value_or(0.0), v_half = half["velocity"].value_or(0.0);
  CHECK(v == 0.05);
  CHECK(v_half == 0.5 * v);
  CHECK(full["distance"].value_or(0.0) == 5e-4);
  const double peak = full["peak_force"].value_or(0.0), peak_half = half["peak_force"].value_or(0.0);
  REQUIRE(peak > 0.0);
  CHECK_THAT(push.out, Catch::Contains(fmt::format("{:+.2f} %", 100.0 * (peak_half - peak) / peak)));
  // The mean force (work / u_end) moves less than the peak under a single slip.
  const double mean = full["mean_force"].value_or(0.0), mean_half = half["mean_force"].value_or(0.0);
  REQUIRE(mean > 0.0);
  CHECK_THAT(push.out, Catch::Contains(fmt::format("change of the mean force (work / u_end): {:+.2f} %",
                                                   100.0 * (mean_half - mean) / mean)));
  CHECK(std::filesystem::exists(push_dir + "/push.h5"));
  CHECK(std::filesystem::exists(push_dir + "/push_state.xdmf"));
  // The comparison is kept in rate_check.toml with the same figures. The 0.5 mm push makes one
  // window of the 1 mm windows (a tail of at least 0.4 of the width is kept), the whole push:
  // its mean is the mean force, so its change is the mean force's.
  const auto rate = toml::parse_file(push_dir + "/rate_check.toml");
  CHECK(rate["velocity"].value_or(0.0) == v);
  CHECK(rate["half_velocity"].value_or(0.0) == v_half);
  // The forces above come from push_summary.toml with 6 significant digits: their change is known
  // to about 4e-6 (two roundings of 1.7e-6 of a force, one of the change), not to a relative 1e-5.
  CHECK(rate["peak_change"].value_or(1.0) == Approx((peak_half - peak) / peak).margin(1e-5));
  CHECK(rate["mean_change"].value_or(1.0) == Approx((mean_half - mean) / mean).margin(1e-5));
  CHECK(rate["within_criterion"].value_or(false) == (std::abs(peak_half - peak) / peak < 0.02));
  const toml::array* windows = rate["window_change"].as_array();
  REQUIRE(windows != nullptr);
  REQUIRE(windows->size() == 1);
  CHECK(windows->get(0)->value_or(1.0) == Approx((mean_half - mean) / mean).epsilon(1e-4));
  CHECK(rate["largest_window_change"].value_or(1.0) == windows->get(0)->value_or(0.0));
  CHECK_THAT(push.out, Catch::Contains("largest change of a 1 mm window mean"));
}
