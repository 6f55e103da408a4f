// The statistics of repeated packings (studies/campaigns/sample_statistics.hpp) against closed
// forms, tables and their coverage over repeated samples of a known distribution.
#include <catch2/catch.hpp>

#include <gsl/gsl_cdf.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include <cmath>
#include <memory>
#include <vector>

#include "studies/campaigns/sample_statistics.hpp"

using namespace mfdem::campaigns;

namespace {

using Rng = std::unique_ptr<gsl_rng, decltype(&gsl_rng_free)>;
Rng make_rng(unsigned long seed) {
  Rng rng(gsl_rng_alloc(gsl_rng_mt19937), &gsl_rng_free);
  gsl_rng_set(rng.get(), seed);
  return rng;
}

std::vector<double> normal_sample(gsl_rng* rng, std::size_t n, double mean, double sd) {
  std::vector<double> v(n);
  for (double& x : v) x = mean + gsl_ran_gaussian(rng, sd);
  return v;
}

}  // namespace

TEST_CASE("the seeds for an interval of +-2 % at a 10 % scatter are 99, from the t quantiles", "[campaigns][stats]") {
  // s / mean = 0.1, target 0.02: n = 99 meets it, t(0.975, 98) 0.1 / sqrt(99) = 1.98447 x 0.010050
  // = 0.019945, and n = 98 does not, t(0.975, 97) 0.1 / sqrt(98) = 1.98472 x 0.010102 = 0.020049
  // (t quantiles from Student-t tables; the normal approximation (1.96 x 0.1 / 0.02)^2 gives 96.04).
  MeanInterval m;
  m.n = 5;
  m.mean = 1000.0;
  m.standard_deviation = 100.0;
  const auto n = seeds_for_relative_half_width(m, 0.02);
  REQUIRE(n);
  CHECK(*n == 99);
  // The definition both ways, for other scatters.
  for (double cv : {0.03, 0.08, 0.25}) {
    m.standard_deviation = cv * m.mean;
    const std::size_t k = *seeds_for_relative_half_width(m, 0.02);
    const auto half = [&](std::size_t j) { return gsl_cdf_tdist_Pinv(0.975, double(j - 1)) * cv / std::sqrt(double(j)); };
    CHECK(half(k) <= 0.02);
    if (k > 2) CHECK(half(k - 1) > 0.02);
  }
  // A width met by two seeds; no spread known from one seed; a zero mean has no relative width.
  m.standard_deviation = 0.0001 * m.mean;
  CHECK(*seeds_for_relative_half_width(m, 0.02) == 2);
  m.n = 1;
  CHECK_FALSE(seeds_for_relative_half_width(m, 0.02));
  m.n = 5;
  m.mean = 0.0;
  CHECK_FALSE(seeds_for_relative_half_width(m, 0.02));
}

TEST_CASE("the bootstrap interval of a mean covers the true mean about 95 % of the time", "[campaigns][stats]") {
  // 400 samples of 20 normal values: the percentile bootstrap's coverage of the known mean is
  // 0.95 less its small-sample shortfall (about 0.93 at n = 20, Efron & Tibshirani 1993, table
  // 14.2); the binomial standard error of 400 trials is 0.011, so [0.89, 0.98] holds it with margin.
  auto rng = make_rng(7);
  int covered = 0;
  const int trials = 400;
  BootstrapSettings settings;
  settings.resamples = 2000;
  for (int t = 0; t < trials; ++t) {
    const auto v = normal_sample(rng.get(), 20, 50.0, 5.0);
    settings.seed = static_cast<std::uint64_t>(t + 1);
    const Interval i = bootstrap_mean_interval(v, settings);
    CHECK(i.low < i.high);
    if (i.low <= 50.0 && 50.0 <= i.high) ++covered;
  }
  const double coverage = double(covered) / trials;
  CHECK(coverage >= 0.89);
  CHECK(coverage <= 0.98);
}

TEST_CASE("the bootstrap interval of a large normal sample is the normal interval of the mean", "[campaigns][stats]") {
  // n = 400: the bootstrap distribution of the mean is normal with sd s / sqrt(n) (central limit),
  // so its 2.5 % and 97.5 % quantiles lie 1.96 s / sqrt(n) either side of the mean; 10,000
  // resamples put each quantile within about 3 % of that half-width.
  auto rng = make_rng(11);
  const auto v = normal_sample(rng.get(), 400, 10.0, 2.0);
  const MeanInterval m = mean_interval(v);
  const Interval i = bootstrap_mean_interval(v, {});
  const double half = 1.959964 * m.standard_deviation / std::sqrt(400.0);
  CHECK(m.mean - i.low == Approx(half).epsilon(0.05));
  CHECK(i.high - m.mean == Approx(half).epsilon(0.05));
  // The same seed gives the same interval; another seed a slightly different one.
  const Interval again = bootstrap_mean_interval(v, {});
  CHECK(again.low == i.low);
  CHECK(again.high == i.high);
  BootstrapSettings other;
  other.seed = 2;
  CHECK(bootstrap_mean_interval(v, other).low != i.low);
  CHECK_THROWS_AS(bootstrap_mean_interval({1.0}, {}), std::invalid_argument);
}

TEST_CASE("the running mean of an output follows the seeds in their order", "[campaigns][stats]") {
  const OutputSummary s = summarise_output({4.0, 6.0, 8.0, 2.0}, {}, 0.05);
  REQUIRE(s.running.size() == 4);
  CHECK(s.running[0].mean == 4.0);
  CHECK(std::isinf(s.running[0].half_width));
  CHECK(s.running[1].mean == 5.0);
  CHECK(s.running[2].mean == 6.0);
  CHECK(s.running[3].mean == 5.0);
  // s = sqrt(20/3) = 2.582; the last running interval is the whole sample's.
  CHECK(s.mean.standard_deviation == Approx(std::sqrt(20.0 / 3.0)).epsilon(1e-14));
  CHECK(s.running[3].half_width == s.mean.half_width);
  CHECK(s.variation() == Approx(std::sqrt(20.0 / 3.0) / 5.0).epsilon(1e-14));
  REQUIRE(s.bootstrap);
  CHECK(s.bootstrap->low >= 2.0);   // a mean of resampled values lies within their range
  CHECK(s.bootstrap->high <= 8.0);
  REQUIRE(s.seeds_for_width);
  CHECK(*s.seeds_for_width > 4);    // +-5 % at a 52 % scatter needs many more seeds
}
