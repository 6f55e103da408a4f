// `mfdem optimise-layer`'s search (studies/campaigns/optimise_layer.hpp) on a stand-in with a known
// front: at every layer height h the peak force can be matched by mu_r, but the contact force's
// calibrated error grows as 0.14 h^2 (near enough: the best mu_r trades a little of one error for
// the other), so the highest layer within 5 % is h* = 0.60; the cost falls as the layer grows.
#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <sstream>

#include "studies/campaigns/optimise_layer.hpp"
#include "studies/campaigns/optimise_layer_report.hpp"
#include "tests/support/stand_in_runner.hpp"
#include "tests/support/temp_dir.hpp"

using namespace mfdem;

namespace {

constexpr double kCurvature = 0.14;

test::StandInOutputs layer_model(double mu_r, double h) {
  const double off = mu_r - (0.2 + 0.2 * h);  // the peak is matched at mu_r = 0.2 + 0.2 h
  return {1000.0 * (1.0 + off), 300.0 * (1.0 + kCurvature * h * h + 0.1 * off), 1.0 - 0.8 * h};
}

// The calibrated contact error at h: the best mu_r minimises off^2 + (c h^2 + 0.1 off)^2.
double calibrated_contact_error(double h) { return kCurvature * h * h / 1.01; }

campaigns::OptimiseLayerRequest request() {
  campaigns::OptimiseLayerRequest r;
  r.extent = {"h_fraction", 0.2, 0.9};
  r.seeds = {1, 2, 3};
  return r;
}

test::StandInRunner runner(runs::RunStore& store, double own_noise = 0.002, int fail_after = -1) {
  return test::StandInRunner(store, layer_model, {1000.0, 300.0, 1.0}, 0.03, own_noise, fail_after);
}

}  // namespace

TEST_CASE("optimise-layer chooses the highest layer whose calibrated error stays within 5 %", "[campaigns][optimise]") {
  const double known = std::sqrt(0.05 * 1.01 / kCurvature);  // 0.6006
  const test::TempDir dir;
  runs::RunStore store(dir.path() / "store");
  auto stand_in = runner(store);
  const auto result = campaigns::optimise_layer(stand_in, request());
  REQUIRE(result.chosen);
  const auto& chosen = result.front[*result.chosen];
  CAPTURE(chosen.extent, chosen.rolling_friction, chosen.contact_error.mean, result.front.size());
  // Bisection over 0.2-0.9 with 6 extents: within one bracket (0.7 / 2^4) below the known height.
  CHECK(chosen.extent <= known);
  CHECK(chosen.extent >= known - 0.7 / 16);
  CHECK(chosen.within);
  CHECK(std::abs(chosen.contact_error.mean) <= 0.05);
  CHECK(std::abs(chosen.contact_error.mean - calibrated_contact_error(chosen.extent)) < 0.005);
  // mu_r calibrated where the peak is matched, from a surrogate shared by all extents.
  CHECK(std::abs(chosen.rolling_friction - (0.2 + 0.2 * chosen.extent)) < 0.02);
  CHECK(std::abs(chosen.peak_error.mean) < 0.01);
  // The front: every extent evaluated, each judged as the known function says.
  CHECK(result.front.size() == 6);
  for (const auto& c : result.front) {
    CAPTURE(c.extent, c.contact_error.mean);
    CHECK(c.within == (calibrated_contact_error(c.extent) <= 0.05));
    CHECK(c.speedup == Approx(1.0 / (1.0 - 0.8 * c.extent)).epsilon(1e-9));
  }
  // Cheapest: no extent within tolerance is faster.
  for (const auto& c : result.front)
    if (c.within) CHECK(c.speedup <= chosen.speedup);
  // The seeds resolve 5 % here (own scatter 0.2 %).
  CHECK(result.resolvable_tolerance < 0.05);
  CHECK(result.seeds_to_resolve <= 3);
}

TEST_CASE("a restarted optimise-layer recomputes nothing and chooses the same layer", "[campaigns][optimise]") {
  const test::TempDir dir;
  runs::RunStore whole_store(dir.path() / "whole");
  auto whole_runner = runner(whole_store);
  const auto whole = campaigns::optimise_layer(whole_runner, request());

  runs::RunStore store(dir.path() / "store");
  auto killed = runner(store, 0.002, 25);
  CHECK_THROWS_WITH(campaigns::optimise_layer(killed, request()), "killed");
  auto again = runner(store);
  const auto resumed = campaigns::optimise_layer(again, request());
  CHECK(again.computed == whole_runner.computed - 25);
  REQUIRE(resumed.chosen);
  CHECK(resumed.front[*resumed.chosen].extent == whole.front[*whole.chosen].extent);
  CHECK(resumed.front.size() == whole.front.size());
}

TEST_CASE("a tolerance finer than the seeds resolve is reported, not met silently", "[campaigns][optimise]") {
  // Own scatter of 3 % per run: twice the standard error of a paired difference over 3 seeds is
  // about 2 x 3 % x sqrt(2/3) / sqrt(3), 2.8 %, above a tolerance of 1 %.
  const test::TempDir dir;
  runs::RunStore store(dir.path() / "store");
  auto stand_in = runner(store, 0.03);
  auto r = request();
  r.tolerance = 0.01;
  const auto result = campaigns::optimise_layer(stand_in, r);
  CAPTURE(result.resolvable_tolerance, result.seeds_to_resolve);
  CHECK(result.resolvable_tolerance > 0.01);
  CHECK(result.seeds_to_resolve > 3);
  // The verdict says at which tolerance its choice was judged.
  std::ostringstream markdown;
  campaigns::write_optimise_markdown(markdown, "title", r, {{r.policy, r.extent.name, result}}, {});
  CHECK_THAT(markdown.str(), Catch::Contains("the finest these seeds resolve; 1 % asked"));
  CHECK_THAT(markdown.str(), Catch::Contains("seeds would resolve 1 %"));
  for (const auto& c : result.front) {
    CHECK(c.tolerance_used > 0.01);  // the tolerance judged against is the resolvable one
    CHECK(c.tolerance_used >= 2.0 * c.contact_error.standard_deviation / std::sqrt(3.0) - 1e-12);
  }
}

TEST_CASE("optimise-layer needs two seeds and a range", "[campaigns][optimise]") {
  const test::TempDir dir;
  runs::RunStore store(dir.path() / "store");
  auto stand_in = runner(store);
  auto r = request();
  r.seeds = {1};
  CHECK_THROWS_WITH(campaigns::optimise_layer(stand_in, r), Catch::Contains("two seeds"));
  r = request();
  r.extent.upper = r.extent.lower;
  CHECK_THROWS_WITH(campaigns::optimise_layer(stand_in, r), Catch::Contains("empty range"));
}

TEST_CASE("optimise-layer's tables name the chosen layer and hold every candidate", "[campaigns][optimise]") {
  const test::TempDir dir;
  runs::RunStore store(dir.path() / "store");
  auto stand_in = runner(store);
  const auto r = request();
  const std::vector<campaigns::FamilyFront> fronts = {{r.policy, r.extent.name, campaigns::optimise_layer(stand_in, r)}};
  const auto& result = fronts[0].result;
  REQUIRE(result.chosen);
  const auto& chosen = result.front[*result.chosen];
  const std::vector<campaigns::MeasuredModel> uncalibrated = {{"uncalibrated stand-in", chosen}};
  std::ostringstream markdown;
  campaigns::write_optimise_markdown(markdown, "title", r, fronts, uncalibrated);
  CAPTURE(markdown.str());
  CHECK_THAT(markdown.str(), Catch::Contains(fmt::format("the cheapest within 5 % is h_fraction={:.4g}", chosen.extent)));
  CHECK_THAT(markdown.str(), Catch::Contains("(chosen)"));
  const auto csv = dir.path() / "front.csv";
  campaigns::write_optimise_csv(csv, fronts, uncalibrated);
  std::ifstream in(csv);
  std::string line;
  int rows = 0, chosen_rows = 0;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    ++rows;
    chosen_rows += line.find(",1,1,") != std::string::npos;  // calibrated, chosen
  }
  CHECK(rows == int(result.front.size()) + 1);
  CHECK(chosen_rows == 1);
}
