// `mfdem stats` over the run store (studies/campaigns/stats.hpp), on runs whose outputs are known:
// a stand-in writes each run's record as a DEM run would, so the table, the width search, the
// control variate's pairing and a restart are checked against numbers computed here.
#include <catch2/catch.hpp>

#include <cmath>
#include <sstream>

#include "studies/campaigns/stats.hpp"
#include "studies/config/config_error.hpp"
#include "tests/support/stand_in_runner.hpp"
#include "tests/support/temp_dir.hpp"

using namespace mfdem;
using Catch::Matchers::Contains;

namespace {

// A packing's outputs: seed-to-seed scatter shared by both models (the packing), plus the cheap
// model's own. Seeds listed in `failing` fail for the model.
struct StandInPackings {
  runs::RunStore& store;
  const campaigns::StatsRequest& request;
  std::vector<std::uint64_t> failing;
  int made = 0;

  static double packing(std::uint64_t seed) { return test::unit_noise(seed, 17); }
  static double own(std::uint64_t seed) { return test::unit_noise(seed, 29); }
  static double peak(std::uint64_t seed) { return 1000.0 * (1.0 + 0.1 * packing(seed)); }
  static double cheap_peak(std::uint64_t seed) { return 800.0 * (1.0 + 0.1 * packing(seed) + 0.02 * own(seed)); }

  void operator()(const campaigns::Model& model, std::uint64_t seed) {
    const bool cheap = model.policy != "all-clump";
    store.ensure(campaigns::run_key(request.config, model, seed), "test", [&](const std::filesystem::path&) {
      ++made;
      if (!cheap && std::find(failing.begin(), failing.end(), seed) != failing.end())
        throw std::runtime_error("the bed blew up");
      const double p = cheap ? cheap_peak(seed) : peak(seed);
      runs::RunRecord r;
      r.numbers = {{campaigns::number::kSeed, double(seed)},
                   {campaigns::number::kPeakForce, p},
                   {campaigns::number::kMaxContactForce, 0.3 * p},
                   {campaigns::number::kContactForceQ999, 0.1 * p},
                   {campaigns::number::kMeanForce, 0.7 * p},
                   {campaigns::number::kDepositionWall, 10.0},
                   {campaigns::number::kPreparationWall, cheap ? 5.0 : 20.0},
                   {campaigns::number::kPushWall, cheap ? 5.0 : 20.0}};
      return r;
    });
  }
};

campaigns::StatsRequest request(std::vector<std::uint64_t> seeds) {
  campaigns::StatsRequest r;
  r.config = railway::load_push_config("mini");
  r.seeds = std::move(seeds);
  r.bootstrap.resamples = 2000;
  return r;
}

}  // namespace

TEST_CASE("stats gives each output's mean and intervals over the seeds, and a restart recomputes nothing",
          "[campaigns][stats]") {
  const test::TempDir dir;
  runs::RunStore store(dir.path());
  const auto r = request({1, 2, 3, 4, 5, 6});
  StandInPackings make{store, r, {}};
  const auto seeds = campaigns::run_stats(store, r, std::ref(make));
  CHECK(seeds == std::vector<std::uint64_t>{1, 2, 3, 4, 5, 6});
  CHECK(make.made == 6);
  const campaigns::StatsTable t = campaigns::stats_table(store, r, seeds);
  REQUIRE(t.outputs.size() == 4);
  std::vector<double> peaks;
  for (std::uint64_t s : seeds) peaks.push_back(StandInPackings::peak(s));
  const campaigns::MeanInterval expected = campaigns::mean_interval(peaks);
  const campaigns::OutputSummary& peak = t.outputs[0].summary;
  CHECK(peak.mean.mean == Approx(expected.mean).epsilon(1e-14));
  CHECK(peak.mean.standard_deviation == Approx(expected.standard_deviation).epsilon(1e-12));
  CHECK(peak.mean.half_width == Approx(expected.half_width).epsilon(1e-12));
  // Every output scales the same packing: the same relative scatter.
  CHECK(t.outputs[1].summary.variation() == Approx(peak.variation()).epsilon(1e-12));
  CHECK(t.outputs[1].summary.mean.mean == Approx(0.3 * expected.mean).epsilon(1e-14));
  REQUIRE(peak.running.size() == 6);
  CHECK(peak.running[2].mean == Approx((peaks[0] + peaks[1] + peaks[2]) / 3.0).epsilon(1e-14));
  CHECK(t.preparation_wall == 20.0);
  CHECK(t.deposition_wall == 10.0);
  // The same study again: everything found, the same table.
  StandInPackings again{store, r, {}};
  CHECK(campaigns::run_stats(store, r, std::ref(again)) == seeds);
  CHECK(again.made == 0);
  CHECK(campaigns::stats_table(store, r, seeds).outputs[0].summary.mean.mean == peak.mean.mean);
}

TEST_CASE("stats --until-width adds seeds until the interval is that narrow, or says the budget ran out",
          "[campaigns][stats]") {
  const test::TempDir dir;
  runs::RunStore store(dir.path());
  auto r = request({1, 2, 3});
  r.until_width = 0.03;
  r.max_seeds = 200;
  StandInPackings make{store, r, {}};
  const auto seeds = campaigns::run_stats(store, r, std::ref(make));
  // The width is met at the last seed and not one seed before (the search stops at the first n).
  const auto half = [&](std::size_t n) {
    std::vector<double> p;
    for (std::size_t k = 0; k < n; ++k) p.push_back(StandInPackings::peak(seeds[k]));
    const auto m = campaigns::mean_interval(p);
    return m.half_width / m.mean;
  };
  REQUIRE(seeds.size() > 3);
  CHECK(seeds.size() < 200);
  CHECK(half(seeds.size()) <= 0.03);
  CHECK(half(seeds.size() - 1) > 0.03);
  CHECK(seeds.back() == seeds.size());  // the added seeds are the next numbers: 4, 5, ...
  const auto t = campaigns::stats_table(store, r, seeds);
  CHECK(t.width_met);
  std::ostringstream text;
  campaigns::print_stats_table(text, t);
  CHECK_THAT(text.str(), Contains(fmt::format("met after {} seeds", seeds.size())));

  // A budget too small: stopped at it, reported as not met with the seeds that would meet it.
  const test::TempDir small_dir;
  runs::RunStore small_store(small_dir.path());
  r.max_seeds = 5;
  StandInPackings small{small_store, r, {}};
  const auto five = campaigns::run_stats(small_store, r, std::ref(small));
  CHECK(five.size() == 5);
  const auto short_table = campaigns::stats_table(small_store, r, five);
  CHECK_FALSE(short_table.width_met);
  std::ostringstream words;
  campaigns::print_stats_table(words, short_table);
  CHECK_THAT(words.str(), Contains("NOT met, the budget of 5 seeds is spent"));
  CHECK_THAT(words.str(), Contains("seeds would meet it"));
}

TEST_CASE("stats pairs the cheap model with the model by seed for the control variate", "[campaigns][stats]") {
  const test::TempDir dir;
  runs::RunStore store(dir.path());
  auto r = request({1, 2, 3, 4, 5, 6});
  r.control = campaigns::Model{"all-ball", {}, {}};
  for (std::uint64_t s = 1; s <= 24; ++s) r.control_seeds.push_back(s);
  StandInPackings make{store, r, {}};
  const auto seeds = campaigns::run_stats(store, r, std::ref(make));
  CHECK(make.made == 6 + 24);
  const auto t = campaigns::stats_table(store, r, seeds);
  const auto& peak = t.outputs[0];
  REQUIRE(peak.control);
  CHECK(peak.control->n == 6);
  CHECK(peak.control->m == 24);
  // The same estimate from the known outputs directly.
  std::vector<double> hi, lo, extra;
  for (std::uint64_t s = 1; s <= 6; ++s) {
    hi.push_back(StandInPackings::peak(s));
    lo.push_back(StandInPackings::cheap_peak(s));
  }
  for (std::uint64_t s = 7; s <= 24; ++s) extra.push_back(StandInPackings::cheap_peak(s));
  // Costs: the model 20 + 20 s; the cheap run 5 + 5 s with its seed's 10 s deposition; plain 50 s.
  const auto direct = campaigns::control_variate_estimate(hi, lo, extra, 40.0, 20.0, 50.0);
  CHECK(peak.control->estimate == Approx(direct.estimate).epsilon(1e-13));
  CHECK(peak.control->correlation == Approx(direct.correlation).epsilon(1e-13));
  CHECK(peak.control->variance_ratio_optimal == Approx(direct.variance_ratio_optimal).epsilon(1e-13));
  CHECK(t.reference_cost == 40.0);
  CHECK(t.cheap_cost == 20.0);
  CHECK(t.plain_cost == 50.0);
  CHECK(peak.control->correlation > 0.9);  // the packing dominates both: 0.1 shared against 0.02 own
  CHECK(peak.control->pays());
}

TEST_CASE("stats records a failed seed with its message and the others complete", "[campaigns][stats]") {
  const test::TempDir dir;
  runs::RunStore store(dir.path());
  const auto r = request({1, 2, 3, 4});
  StandInPackings make{store, r, {3}};
  const auto seeds = campaigns::run_stats(store, r, std::ref(make));
  const auto t = campaigns::stats_table(store, r, seeds);
  CHECK(t.finished == 3);
  REQUIRE(t.failures.size() == 1);
  CHECK_THAT(t.failures[0], Contains("seed 3") && Contains("the bed blew up"));
  CHECK(t.outputs[0].summary.mean.n == 3);
}

TEST_CASE("stats refuses requests that cannot be answered, naming the option", "[campaigns][stats]") {
  const auto refused = [](const campaigns::StatsRequest& r, const std::string& words) {
    CHECK_THROWS_WITH(campaigns::check_stats_request(r), Contains(words));
  };
  auto r = request({1, 2, 3});
  r.control_seeds = {1, 2, 3, 4};
  refused(r, "--control-seeds: given without --control");
  r.control = campaigns::Model{"all-ball", {}, {}};
  r.control_seeds = {1, 2, 4, 5};
  refused(r, "--control-seeds 1,2,4,5: lacks seeds 3 of --seeds");
  r.control = campaigns::Model{};
  r.control_seeds = {1, 2, 3, 4};
  refused(r, "--control all-clump: the model itself");
  r.control = campaigns::Model{"all-ball", {}, {}};
  r.seeds = {1, 2};
  refused(r, "at least 3 seeds");
  r.seeds = {1, 2, 3};
  r.until_width = 0.02;
  r.max_seeds = 30;
  refused(r, "--until-width with --control");
  r.control.reset();
  r.control_seeds.clear();
  r.max_seeds = 2;
  refused(r, "--max-seeds 2: fewer than the 3 seeds");
  r.max_seeds = 30;
  r.width_output = "peak";
  refused(r, "--width-output peak");
  r.width_output = campaigns::number::kPeakForce;
  CHECK_NOTHROW(campaigns::check_stats_request(r));
}
