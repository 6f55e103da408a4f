// `mfdem calibrate`'s campaign (studies/campaigns/calibrate.hpp) on a stand-in for the DEM model:
// an analytic function of (mu_r, h_fraction) with the packing seed's scatter, its runs kept in a
// run store as DEM runs are. It recovers a synthetic truth, restarts without recomputing, and
// refuses ranges that cannot be calibrated.
#include <catch2/catch.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>
#include <string>

#include "fidelity/policy.hpp"
#include "dem/hdf5_io.hpp"
#include "studies/campaigns/calibrate.hpp"
#include "studies/campaigns/calibrate_figures.hpp"
#include "studies/campaigns/calibrate_report.hpp"
#include "studies/config/config_error.hpp"
#include "studies/railway/push_config.hpp"
#include "tests/support/stand_in_runner.hpp"
#include "tests/support/temp_dir.hpp"

using namespace mfdem;
using campaigns::CalibrationParameter;
using campaigns::Model;
using campaigns::RunOutputs;

namespace {

constexpr double kTrueMuR = 0.35, kTrueH = 0.6;

// Peak and contact force of the stand-in at (mu_r, h): both depend on both parameters, with
// independent directions, so the two targets pin one point.
std::pair<double, double> stand_in(double mu_r, double h) {
  return {1000.0 * (0.8 + 0.5 * mu_r - 0.25 * h), 300.0 * (0.7 + 0.2 * mu_r + 0.8 * h * h)};
}

// The stand-in in a run store, its reference the truth itself.
test::StandInRunner stand_in_runner(runs::RunStore& store, int fail_after = -1) {
  const auto outputs = [](double mu_r, double h) {
    const auto [peak, contact] = stand_in(mu_r, h);
    return test::StandInOutputs{peak, contact, 1.0};
  };
  return test::StandInRunner(store, outputs, outputs(kTrueMuR, kTrueH), 0.03, 0.005, fail_after);
}

campaigns::CalibrateRequest stand_in_request(const std::filesystem::path& record) {
  campaigns::CalibrateRequest r;
  r.policy = "layer-by-height";
  r.parameters = {{"mu_r", 0.0, 0.6}, {"h_fraction", 0.2, 0.9}};
  r.seeds = {1, 2, 3};
  r.verify_seeds = {11, 12, 13, 14};
  r.budget = 20;
  r.record = record;
  return r;
}

}  // namespace

TEST_CASE("calibrate recovers a synthetic truth with intervals that hold it", "[campaigns][calibrate]") {
  // Reference: the stand-in at (mu_r, h_fraction) = (0.35, 0.6) on the same seeds. Tolerances
  // of the issue: |d mu_r| <= 0.03, |d h| <= 10 % of its range (0.07).
  const test::TempDir dir;
  runs::RunStore store(dir.path() / "store");
  auto runner = stand_in_runner(store);
  const auto result = campaigns::run_calibration(runner, stand_in_request(dir.path() / "record.csv"));
  CAPTURE(result.calibrated.transpose(), result.loop.runs.size(), result.loop.stopped_by);
  CHECK(std::abs(result.calibrated(0) - kTrueMuR) <= 0.03);
  CHECK(std::abs(result.calibrated(1) - kTrueH) <= 0.07);
  REQUIRE(result.posterior.intervals.size() == 2);
  CHECK(result.posterior.intervals[0].lower <= kTrueMuR);
  CHECK(result.posterior.intervals[0].upper >= kTrueMuR);
  CHECK(result.posterior.intervals[1].lower <= kTrueH);
  CHECK(result.posterior.intervals[1].upper >= kTrueH);
  CHECK(result.loop.cost <= 20.0);
  // Verified on 4 fresh seeds: the calibrated model within 2 % of the reference on both outputs.
  REQUIRE(result.verification.size() == 4);
  CHECK(std::abs(result.peak_difference.mean) < 0.02);
  CHECK(std::abs(result.contact_difference.mean) < 0.02);

  // The figures' numbers: the grid's least predicted misfit lies within a grid step of the
  // calibrated point, where the posterior peaks too.
  const auto h5file = dir.path() / "calibration.h5";
  campaigns::write_calibration_figure_data(h5file, "stand-in", stand_in_request(dir.path() / "record.csv"), result, 41);
  const hid_t f = H5Fopen(h5file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  REQUIRE(f >= 0);
  const auto x = dem::h5::read_doubles(f, "grid/x"), y = dem::h5::read_doubles(f, "grid/y");
  const auto misfit = dem::h5::read_doubles(f, "grid/misfit"), posterior = dem::h5::read_doubles(f, "grid/posterior");
  const auto runs = dem::h5::read_doubles(f, "runs/misfit");
  H5Fclose(f);
  REQUIRE(x.size() == 41);
  REQUIRE(misfit.size() == 41 * 41);
  CHECK(runs.size() == result.loop.runs.size());
  const auto least = std::min_element(misfit.begin(), misfit.end()) - misfit.begin();
  CHECK(std::abs(x[least % 41] - result.calibrated(0)) <= 0.6 / 40 + 1e-12);
  CHECK(std::abs(y[least / 41] - result.calibrated(1)) <= 0.7 / 40 + 1e-12);
  CHECK(*std::max_element(posterior.begin(), posterior.end()) == 1.0);
  const auto peak = std::max_element(posterior.begin(), posterior.end()) - posterior.begin();
  CHECK(std::abs(x[peak % 41] - kTrueMuR) <= 0.05);
  CHECK(std::abs(y[peak / 41] - kTrueH) <= 0.1);
}

TEST_CASE("a cheap level of fewer seeds shares its runs with the expensive level and counts them once",
          "[campaigns][calibrate]") {
  const test::TempDir dir;
  runs::RunStore store(dir.path() / "store");
  auto runner = stand_in_runner(store);
  auto request = stand_in_request(dir.path() / "record.csv");
  request.two_levels = true;
  request.cheap_seeds = {1};
  request.cheap_on_same_config = true;
  request.cheap_cost = 1.0 / 3.0;
  const auto result = campaigns::run_calibration(runner, request);
  CAPTURE(result.calibrated.transpose(), result.loop.runs.size(), result.loop.stopped_by);
  std::size_t cheap = 0, expensive = 0;
  for (const auto& r : result.loop.runs) (r.level == calibration::Level::cheap ? cheap : expensive) += 1;
  CHECK(cheap > 0);
  CHECK(expensive > 0);
  // Every distinct DEM run computed is counted once: a candidate run cheap on seed 1 and later
  // expensive on seeds 1-3 costs three runs, not four. The reference (3) and the check (4 + 4)
  // are not the candidates'.
  CHECK(result.dem_runs == runner.computed - 3 - 8);
  // The report says what the cheap level carries: a cheap level of seed 1 alone is the expensive
  // one shifted by seed 1's packing (3 %), so rho is near 1.
  std::ostringstream report;
  campaigns::write_calibration_markdown(report, "title", request, result);
  CHECK_THAT(report.str(), Catch::Contains("A cheap level (seeds 1 only)"));
  CHECK_THAT(report.str(), Catch::Contains("peak: rho = "));
  REQUIRE(result.surrogate);
  CHECK(result.surrogate->outputs()[0].scale_factor() == Approx(1.0).margin(0.1));
  CHECK(result.loop.cost <= request.budget);
  CHECK(std::abs(result.calibrated(0) - kTrueMuR) <= 0.03);
  CHECK(std::abs(result.calibrated(1) - kTrueH) <= 0.07);
}

TEST_CASE("a synthetic truth's parameters are read from the reference model", "[campaigns][calibrate]") {
  auto request = stand_in_request("unused.csv");
  CHECK_FALSE(campaigns::reference_parameters(request));  // all-clump: no truth
  request.reference_model = Model{"layer-by-height:h_fraction=0.6", 0.35, std::nullopt};
  const auto truth = campaigns::reference_parameters(request);
  REQUIRE(truth);
  CHECK(truth->size() == 2);
  CHECK((*truth)(0) == 0.35);
  CHECK((*truth)(1) == 0.6);
  request.reference_model.rolling_friction.reset();  // mu_r left to the config: not a known truth
  CHECK_FALSE(campaigns::reference_parameters(request));
  request.reference_model = Model{"zone-by-distance:d=0.05", 0.35, std::nullopt};  // another policy
  CHECK_FALSE(campaigns::reference_parameters(request));
}

TEST_CASE("a killed calibration restarts from the store and its record and ends the same", "[campaigns][calibrate]") {
  const test::TempDir dir;
  runs::RunStore whole_store(dir.path() / "whole");
  auto whole_runner = stand_in_runner(whole_store);
  const auto whole = campaigns::run_calibration(whole_runner, stand_in_request(dir.path() / "whole.csv"));

  runs::RunStore store(dir.path() / "store");
  auto killed = stand_in_runner(store, 20);
  CHECK_THROWS_WITH(campaigns::run_calibration(killed, stand_in_request(dir.path() / "record.csv")), "killed");
  auto again = stand_in_runner(store);
  const auto resumed = campaigns::run_calibration(again, stand_in_request(dir.path() / "record.csv"));
  CHECK(again.computed == whole_runner.computed - 20);  // no finished run computed twice
  CHECK(resumed.calibrated == whole.calibrated);
  CHECK(resumed.loop.runs.size() == whole.loop.runs.size());
  // The cost counts the replayed runs too.
  CHECK(resumed.dem_runs == whole.dem_runs);
  CHECK(resumed.candidates_wall == whole.candidates_wall);
  // A third start replays everything: the same cost again.
  auto third = stand_in_runner(store);
  const auto replayed = campaigns::run_calibration(third, stand_in_request(dir.path() / "record.csv"));
  CHECK(third.computed == 0);
  CHECK(replayed.dem_runs == whole.dem_runs);
}

TEST_CASE("calibrate refuses parameter ranges that are empty, hold no ball or leave the bed", "[campaigns][calibrate]") {
  const auto config = railway::load_push_config("mini");
  const auto refused = [&](const std::string& policy, const std::string& text) {
    try {
      campaigns::parse_calibration_parameters(text, policy, config, "--parameters");
    } catch (const config::ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  CHECK_THAT(refused("layer-by-height", "mu_r=0.5:0.2,h_fraction=0.3:0.9"),
             Catch::Contains("--parameters") && Catch::Contains("mu_r=0.5:0.2") && Catch::Contains("empty range"));
  CHECK_THAT(refused("layer-by-height", "mu_r=0:0.6,h_fraction=0:0.9"),
             Catch::Contains("h_fraction=0:0.9") && Catch::Contains("leaves no ball"));
  CHECK_THAT(refused("layer-by-height", "mu_r=0:0.6,h_fraction=0.3:1.5"), Catch::Contains("1.5"));
  CHECK_THAT(refused("zone-by-distance", "mu_r=0:0.6,d=0.02:5"), Catch::Contains("d=0.02:5") && Catch::Contains("no ball"));
  CHECK_THAT(refused("layer-by-height", "mu_r=0:0.6,height=0.1:0.2"), Catch::Contains("height"));
  CHECK_THAT(refused("all-ball", "mu_r=0:0.6"), Catch::Contains("--policy all-ball"));
  CHECK(refused("layer-by-height", "mu_r=0:0.6,h_fraction=0.3:0.9") == "accepted");
  // A candidate's model: the calibrated height replaces the policy's own.
  const Model m = campaigns::candidate_model("layer-by-height:h_fraction=0.5",
                                             {{"mu_r", 0.0, 0.6}, {"h_fraction", 0.2, 0.9}}, Eigen::Vector2d(0.3, 0.4));
  CHECK(m.policy == "layer-by-height:h_fraction=0.4");
  CHECK(*m.rolling_friction == 0.3);
}
