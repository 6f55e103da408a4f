// The statistics of a comparison (studies/campaigns/paired_statistics.hpp) against closed forms
// and tables, and the parsing of the models and seeds a study is given.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <vector>

#include "studies/campaigns/compare.hpp"
#include "studies/config/config_error.hpp"
#include "studies/railway/push_config.hpp"

using namespace mfdem::campaigns;
using Catch::Matchers::Contains;

TEST_CASE("the 95 % interval of a mean is t(0.975, n-1) s / sqrt(n)", "[campaigns][statistics]") {
  // 1..5: mean 3, s = sqrt(2.5); t(0.975, 4) = 2.776445 (Student-t tables, e.g. NIST/SEMATECH
  // e-Handbook 1.3.6.7.2), so the half-width is 2.776445 x 1.581139 / sqrt(5) = 1.963243.
  const MeanInterval m = mean_interval({1, 2, 3, 4, 5});
  CHECK(m.n == 5);
  CHECK(m.mean == Approx(3.0).epsilon(1e-15));
  CHECK(m.standard_deviation == Approx(std::sqrt(2.5)).epsilon(1e-14));
  CHECK(m.half_width == Approx(1.963243).epsilon(1e-6));  // the table's 7 digits
  CHECK(m.resolved());                                     // [1.04, 4.96] excludes 0
  // Two seeds: t(0.975, 1) = 12.706205; values 0.1, 0.3: s = 0.141421, half-width 1.270621.
  const MeanInterval two = mean_interval({0.1, 0.3});
  CHECK(two.half_width == Approx(12.706205 * std::sqrt(0.02) / std::sqrt(2.0)).epsilon(1e-6));
  CHECK_FALSE(two.resolved());
  // One seed: no spread, no interval.
  const MeanInterval one = mean_interval({0.2});
  CHECK(one.mean == 0.2);
  CHECK(std::isinf(one.half_width));
  CHECK_FALSE(one.resolved());
}

TEST_CASE("a model identical to the reference differs by exactly zero with a zero-width interval",
          "[campaigns][statistics]") {
  const std::vector<double> reference = {50.1, 47.3, 52.9};
  const std::vector<double> d = relative_differences(reference, reference);
  REQUIRE(d.size() == 3);
  const MeanInterval m = mean_interval(d);
  CHECK(m.mean == 0.0);
  CHECK(m.half_width == 0.0);
  CHECK(verdict(m, 0.05) == Verdict::within);
  // Paired: a model 10 % above the reference on every seed is +10 % exactly, however much the
  // seeds scatter, and the interval has no width.
  const MeanInterval up = mean_interval(relative_differences({55.11, 52.03, 58.19}, reference));
  CHECK(up.mean == Approx(0.10).epsilon(1e-12));
  CHECK(up.half_width == Approx(0.0).margin(1e-12));
  CHECK(verdict(up, 0.05) == Verdict::outside);
  // A failed run (NaN) leaves its seed out of the pairs.
  CHECK(relative_differences({55.11, std::numeric_limits<double>::quiet_NaN(), 58.19}, reference).size() == 2);
}

TEST_CASE("the verdict is within, outside or undecided by where the whole interval lies", "[campaigns][statistics]") {
  MeanInterval d;
  d.n = 3;
  d.mean = 0.02, d.half_width = 0.01;  // [1 %, 3 %]
  CHECK(verdict(d, 0.05) == Verdict::within);
  d.mean = -0.09, d.half_width = 0.02;  // [-11 %, -7 %]
  CHECK(verdict(d, 0.05) == Verdict::outside);
  d.mean = 0.04, d.half_width = 0.03;  // [1 %, 7 %]: straddles 5 %
  CHECK(verdict(d, 0.05) == Verdict::undecided);
}

TEST_CASE("the seeds that would decide an undecided verdict, from the spread so far", "[campaigns][statistics]") {
  MeanInterval d;
  d.n = 2;
  d.mean = -0.21, d.standard_deviation = 0.03;  // 16 % beyond the 5 % band
  // n = 2: 12.706 x 0.03 / sqrt(2) = 0.270 > 0.16; n = 3: 4.303 x 0.03 / sqrt(3) = 0.075 < 0.16.
  CHECK(seeds_to_decide(d, 0.05) == 3);
  d.mean = 0.07, d.standard_deviation = 0.05;  // 2 % beyond the band: t / sqrt(n) < 0.4
  // t_{0.975,25} / sqrt(26) = 2.060 / 5.099 = 0.404; t_{0.975,26} / sqrt(27) = 2.056 / 5.196 = 0.396.
  CHECK(seeds_to_decide(d, 0.05) == 27);
  d.mean = 0.03;  // inside the band by 2 %: the same count shows it within
  CHECK(seeds_to_decide(d, 0.05) == 27);
  d.mean = 0.05;  // on the edge: no number of seeds decides it
  CHECK(seeds_to_decide(d, 0.05) == 0);
  d.mean = 0.0501;
  CHECK(seeds_to_decide(d, 0.05, 1000) == 0);  // would need about 10^6 seeds
  d.n = 1;
  d.mean = -0.21;
  CHECK(seeds_to_decide(d, 0.05) == 0);  // one seed: no spread known
}

TEST_CASE("the normalised RMS difference of F(u) curves is 0 for equal curves and c / max F for an offset c",
          "[campaigns][statistics]") {
  std::vector<double> u, f;
  for (int k = 0; k <= 100; ++k) u.push_back(1e-5 * k), f.push_back(2000.0 * u.back() / 1e-3);  // linear, peak 2000 N
  CHECK(normalised_rms_difference(u, f, u, f) == 0.0);
  std::vector<double> shifted = f;
  for (double& x : shifted) x += 30.0;
  CHECK(normalised_rms_difference(u, shifted, u, f) == Approx(30.0 / 2000.0).epsilon(1e-12));
  // A linear curve sampled at every other point interpolates exactly onto the reference's samples.
  std::vector<double> u_half, f_half;
  for (std::size_t k = 0; k < u.size(); k += 2) u_half.push_back(u[k]), f_half.push_back(f[k]);
  CHECK(normalised_rms_difference(u_half, f_half, u, f) == Approx(0.0).margin(1e-12));
}

TEST_CASE("seeds are whole numbers and ranges, refused when empty, backwards or repeated", "[campaigns][input]") {
  CHECK(parse_seeds("1-3,7", "--seeds") == std::vector<std::uint64_t>{1, 2, 3, 7});
  CHECK(parse_seeds("5", "--seeds") == std::vector<std::uint64_t>{5});
  for (const char* bad : {"", "3-1", "-1", "1,,2", "1-2,2", "x"}) {
    CAPTURE(bad);
    CHECK_THROWS_AS(parse_seeds(bad, "--seeds"), mfdem::config::ConfigError);
  }
  CHECK_THROWS_WITH(parse_seeds("", "--seeds"), Contains("--seeds ''") && Contains("no seed"));
  CHECK_THROWS_WITH(parse_seeds("3-1", "--seeds"), Contains("runs backwards"));
}

TEST_CASE("models are policies with their parameters and balls' material, unknown names refused",
          "[campaigns][input]") {
  const auto config = mfdem::railway::load_push_config("mini");
  const auto models = parse_models("all-clump,layer-by-height:h_fraction=0.5,mu_r=0.2,zone-by-distance:d=0.03;all-ball",
                                   "--models");
  REQUIRE(models.size() == 4);
  CHECK(models[0].text(config) == "all-clump");
  CHECK(models[1].policy == "layer-by-height:h_fraction=0.5");
  CHECK(models[1].rolling_friction == 0.2);
  CHECK(models[1].text(config) == "layer-by-height:h_fraction=0.5 mu_r=0.2");
  CHECK(models[2].text(config) == "zone-by-distance:d=0.03 mu_r=0.3");  // the config's mu_r
  CHECK(models[3].policy == "all-ball");
  CHECK_THROWS_WITH(parse_models("all-clump,layer-by-heigth:h=0.1", "--models"),
                    Contains("--models") && Contains("layer-by-heigth") && Contains("zone-by-distance"));
  CHECK_THROWS_WITH(parse_models("layer-by-height:hh=0.1", "--models"), Contains("hh"));
  CHECK_THROWS_WITH(parse_models("all-ball,mu_r=-1", "--models"), Contains("mu_r must be >= 0"));
  CHECK_THROWS_WITH(parse_models("all-clump,,all-ball", "--models"), Contains("empty entry"));
}

TEST_CASE("a run's key changes with the config, the model, its balls' material and the seed, and names a folder",
          "[campaigns][runs]") {
  const auto config = mfdem::railway::load_push_config("mini");
  // What the config says, not how it is written: a comment, the name, the config's own seed key
  // and the form of a number leave the key as it is; a value does not.
  const auto replaced = [&](const std::string& from, const std::string& to) {
    std::string text = config.text;
    REQUIRE(text.find(from) != std::string::npos);
    return text.replace(text.find(from), from.size(), to);
  };
  auto reworded = config;
  reworded.text = "# another comment\n" + replaced("name = \"mini\"\nseed = 1\ntime_step_safety = 0.4",
                                                   "seed = 7\ntime_step_safety = 4e-1\nname = \"renamed\"");
  auto other = config;
  other.text = replaced("time_step_safety = 0.4", "time_step_safety = 0.3");
  const Model layer{"layer-by-height:h_fraction=0.5", 0.2, std::nullopt};
  Model rougher = layer;
  rougher.rolling_friction = 0.25;
  const std::string key = run_key(config, layer, 1);
  CHECK(key == run_key(config, layer, 1));
  CHECK(key != run_key(config, layer, 2));
  CHECK(run_key(reworded, layer, 1) == key);
  CHECK(canonical_config_text(reworded) == canonical_config_text(config));
  CHECK(key != run_key(other, layer, 1));
  CHECK(key != run_key(config, rougher, 1));
  CHECK(key != run_key(config, Model{}, 1));
  CHECK(key.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789._-") ==
        std::string::npos);
  CHECK(key.rfind("s1-layer-by-height", 0) == 0);  // readable: seed and model first
}
