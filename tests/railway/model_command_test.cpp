// `mfdem push --fidelity` and `mfdem push-test --fidelity` end to end: a bad model is refused
// before any work (exit 2) naming the option or key, the value and what was expected; a good
// one converts, re-settles and pushes, and every output file records the model.
#include <catch2/catch.hpp>
#include <hdf5.h>
#include <toml++/toml.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "dem/hdf5_io.hpp"
#include "tests/railway/tiny_bed.hpp"
#include "tests/support/run_mfdem.hpp"
#include "tests/support/temp_dir.hpp"

using mfdem::test::run_mfdem;

namespace {

// The tiny bed drawn as 6-pebble clumps, the reference model.
std::string tiny_clumps() {
  std::string text = mfdem::test::kTinyBed;
  const std::string from = "representation = \"ball\"";
  return text.replace(text.find(from), from.size(), "representation = \"clump\"");
}

}  // namespace

TEST_CASE("a bad model is refused before any work, naming the option or key and the value", "[railway][cli][model]") {
  const mfdem::test::TempDir dir;
  const auto config = dir.path() / "tiny.toml";
  std::ofstream(config) << tiny_clumps();
  const std::string out = (dir.path() / "out").string();
  const auto unknown = run_mfdem({"push-test", config.string(), "--fidelity", "layer-by-heigth:h=0.04", "--out", out});
  CHECK(unknown.status == 2);
  CHECK_THAT(unknown.err, Catch::Contains("--fidelity layer-by-heigth:h=0.04") &&
                              Catch::Contains("unknown fidelity policy") && Catch::Contains("zone-by-distance (d)"));
  CHECK_FALSE(std::filesystem::exists(out + "/packing.h5"));  // refused before the packing
  const auto high = run_mfdem({"push-test", config.string(), "--fidelity", "layer-by-height:h=0.2", "--out", out});
  CHECK(high.status == 2);
  CHECK_THAT(high.err, Catch::Contains("h = 0.2") && Catch::Contains("0.08 (the sleeper base)"));
  const auto missing = run_mfdem({"push-test", config.string(), "--fidelity", "zone-by-distance", "--out", out});
  CHECK(missing.status == 2);
  CHECK_THAT(missing.err, Catch::Contains("needs d"));
  const auto rolling = run_mfdem({"push-test", config.string(), "--rolling-friction", "-0.3", "--out", out});
  CHECK(rolling.status == 2);
  CHECK_THAT(rolling.err, Catch::Contains("--rolling-friction"));
  std::ofstream(config, std::ios::app) << "[fidelity]\npolicy = \"zone-by-distance:d=-0.1\"\n";
  const auto in_file = run_mfdem({"push-test", config.string(), "--out", out});
  CHECK(in_file.status == 2);
  CHECK_THAT(in_file.err, Catch::Contains("tiny.toml") && Catch::Contains("fidelity.policy") && Catch::Contains("d = -0.1"));
  CHECK_FALSE(std::filesystem::exists(out + "/packing.h5"));
}

TEST_CASE("push --fidelity converts, re-settles and pushes, and records the model in every output",
          "[railway][cli][model]") {
  const mfdem::test::TempDir dir;
  const auto config = dir.path() / "tiny.toml";
  std::ofstream(config) << tiny_clumps();
  const std::string bed = (dir.path() / "bed").string();
  REQUIRE(run_mfdem({"pack", config.string(), "--out", bed, "-q", "--threads", "1"}).status == 0);

  // The settled sleeper base lies below the design 0.08 m: a layer up to it is refused by the bed.
  const auto above = run_mfdem({"push", bed, "--fidelity", "layer-by-height:h=0.0799", "--out", bed + "/x", "-q"});
  CHECK(above.status == 2);
  CHECK_THAT(above.err, Catch::Contains("--fidelity") && Catch::Contains("sleeper base") && Catch::Contains(bed));

  // Balls grown to size in a microsecond overlap their neighbours by half their radius at once:
  // the run stops as unstable (exit 3) and keeps the converted bed's last good state.
  const auto fast = dir.path() / "fast_growth.toml";
  std::ofstream(fast) << tiny_clumps() << "[fidelity]\ngrowth_time = 1e-6\n";
  const auto unstable = run_mfdem({"push", bed, "--config", fast.string(), "--fidelity", "all-ball", "--out",
                                   bed + "/unstable", "-q", "--threads", "1"});
  CHECK(unstable.status == 3);
  CHECK_THAT(unstable.err, Catch::Contains("unstable") && Catch::Contains("resettle.h5"));
  CHECK(std::filesystem::exists(bed + "/unstable/resettle.h5"));
  CHECK_FALSE(std::filesystem::exists(bed + "/unstable/push.h5"));

  const std::string model = bed + "/layer";
  const auto push = run_mfdem({"push", bed, "--fidelity", "layer-by-height:h_fraction=0.5", "--rolling-friction",
                               "0.25", "--distance", "0.3", "--out", model, "--threads", "1"});
  REQUIRE(push.status == 0);
  CHECK_THAT(push.out, Catch::Contains("layer-by-height:h=") && Catch::Contains("stones as clumps / balls"));
  const auto summary = toml::parse_file(model + "/push_summary.toml");
  const auto clumps = summary["model"]["clumps"].value_or(0.0), balls = summary["model"]["balls"].value_or(0.0);
  CHECK(balls > 0.0);
  CHECK(clumps > 0.0);
  CHECK(clumps + balls == summary["stones"].value_or(0.0));
  CHECK(summary["model"]["rolling_friction"].value_or(0.0) == 0.25);
  CHECK(summary["model"]["element_ratio"].value_or(1.0) < 1.0);
  CHECK(summary["model"]["elements"].value_or(0.0) == summary["elements"].value_or(-1.0));
  CHECK(summary["model"]["resettle_wall_seconds"].value_or(0.0) > 0.0);
  CHECK(summary["model"]["conversion_point"].value_or(std::string()) == "after preparation, re-settled");
  CHECK(summary["config_hash"].value_or(std::string()).size() == 16);
  CHECK(std::filesystem::exists(model + "/model_packing.h5"));
  // Growing balls in a finished packing dilates it: the sleeper rises, and a rise beyond 2 mm is
  // pointed out with the better way.
  const double rise = summary["model"]["resettle_sleeper_rise"].value_or(0.0);
  CHECK((rise > 2e-3) == (push.err.find("lifted the sleeper") != std::string::npos));
  CHECK(std::filesystem::exists(model + "/resettle.h5"));

  const hid_t file = H5Fopen((model + "/push.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  REQUIRE(file >= 0);
  const hid_t group = H5Gopen2(file, "model", H5P_DEFAULT);
  CHECK_THAT(mfdem::dem::h5::read_text_attribute(group, "policy"), Catch::StartsWith("layer-by-height:h="));
  CHECK(mfdem::dem::h5::read_attribute(group, "balls") == balls);
  CHECK(mfdem::dem::h5::read_attribute(group, "rolling_friction") == 0.25);
  H5Gclose(group);
  CHECK(mfdem::dem::h5::read_attribute(file, "seed") == 7.0);
  CHECK(mfdem::dem::h5::read_text_attribute(file, "config_hash") == summary["config_hash"].value_or(std::string()));
  CHECK_FALSE(mfdem::dem::h5::read_text_attribute(file, "revision").empty());
  H5Fclose(file);
}

TEST_CASE("push-test --fidelity prepares the model from the deposition and pushes it without converting again",
          "[railway][cli][model]") {
  const mfdem::test::TempDir dir;
  const auto config = dir.path() / "tiny.toml";
  std::ofstream(config) << tiny_clumps();
  const std::string out = (dir.path() / "model").string();
  const auto run = run_mfdem({"push-test", config.string(), "--fidelity", "layer-by-height:h_fraction=0.5",
                              "--rolling-friction", "0.2", "--distance", "0.2", "--out", out, "--threads", "1"});
  REQUIRE(run.status == 0);
  CHECK_THAT(run.out, Catch::Contains("convert"));  // the stage in the packing's table
  const auto summary = toml::parse_file(out + "/push_summary.toml");
  CHECK(summary["model"]["policy"].value_or(std::string()) == "layer-by-height:h=0.04,h_fraction=0.5");
  CHECK(summary["model"]["conversion_point"].value_or(std::string()) == "after deposition");
  CHECK(summary["model"]["converted"].value_or(-1.0) == 0.0);  // nothing converted at the push
  CHECK(summary["model"]["balls"].value_or(0.0) > 0.0);
  CHECK(summary["model"]["rolling_friction"].value_or(0.0) == 0.2);  // kept by the packing
  CHECK_FALSE(std::filesystem::exists(out + "/resettle.h5"));
  // Its preparation from the conversion on (the convert and settle stages) stands for the re-settling.
  CHECK(summary["model"]["resettle_wall_seconds"].value_or(0.0) > 0.0);
  CHECK(summary["model"]["resettle_simulated_time"].value_or(0.0) > 0.1);
}
