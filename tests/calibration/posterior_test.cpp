// The calibration posterior (calibration/posterior.hpp): its 90 % intervals cover a known answer
// at their stated rate, on a grid and by Metropolis sampling.
#include <catch2/catch.hpp>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include <cmath>
#include <memory>

#include "calibration/posterior.hpp"
#include "calibration/sobol_design.hpp"

using namespace mfdem::calibration;

namespace {

double model(double x) { return 2.0 * x + 0.3 * std::sin(5.0 * x); }  // increasing on [0, 1]

// One calibration of x from one noisy target t = model(x0) + e, e ~ N(0, tau^2), with a
// surrogate fitted on 10 noisy runs of the model (run noise sd 0.02).
PosteriorSummary calibrate_once(double x0, double tau, gsl_rng* rng, bool sampled) {
  const auto design = sobol_design({{0.0, 1.0}}, 10, gsl_rng_get(rng));
  std::vector<Evaluation> runs;
  for (const auto& p : design)
    runs.push_back({Eigen::VectorXd::Constant(1, p[0]), Level::expensive,
                    Eigen::VectorXd::Constant(1, model(p[0]) + gsl_ran_gaussian(rng, 0.02))});
  const double t = model(x0) + gsl_ran_gaussian(rng, tau);
  MisfitSurrogate s({{0.0, 1.0}}, {Target{t, 1.0}});
  s.fit(runs);
  PosteriorOptions o;
  o.target_sd = {tau};
  if (!sampled) return calibration_posterior(s, o);
  // The same posterior by Metropolis: three parameters, the last two without influence.
  std::vector<Evaluation> runs3;
  const auto design3 = sobol_design({{0.0, 1.0}, {0.0, 1.0}, {0.0, 1.0}}, 16, gsl_rng_get(rng));
  for (const auto& p : design3)
    runs3.push_back({Eigen::Vector3d(p[0], p[1], p[2]), Level::expensive,
                     Eigen::VectorXd::Constant(1, model(p[0]) + gsl_ran_gaussian(rng, 0.02))});
  MisfitSurrogate s3({{0.0, 1.0}, {0.0, 1.0}, {0.0, 1.0}}, {Target{t, 1.0}});
  s3.fit(runs3);
  o.samples = 6000;
  o.burn_in = 2000;
  o.seed = gsl_rng_get(rng);
  return calibration_posterior(s3, o);
}

}  // namespace

TEST_CASE("the posterior's 90 % interval covers the true parameter in 90 % of repeated calibrations",
          "[calibration][posterior]") {
  // Reference: x0 drawn from the prior (uniform on [0, 1]) and the target observed with noise of
  // known sd tau = 0.1, so the exact posterior's 90 % interval covers x0 with probability 0.9.
  // Over 200 repetitions the count is binomial(200, 0.9): mean 180, sd 4.2; accepted 167-193
  // (3 sd); measured 186. The surrogate's own uncertainty (run noise sd 0.02) widens the intervals slightly.
  std::unique_ptr<gsl_rng, decltype(&gsl_rng_free)> rng(gsl_rng_alloc(gsl_rng_mt19937), gsl_rng_free);
  gsl_rng_set(rng.get(), 2026);
  int covered = 0;
  const int repetitions = 200;
  for (int k = 0; k < repetitions; ++k) {
    const double x0 = gsl_rng_uniform(rng.get());
    const PosteriorSummary p = calibrate_once(x0, 0.1, rng.get(), false);
    REQUIRE(p.method == "grid");
    REQUIRE(p.intervals.size() == 1);
    CHECK(p.intervals[0].lower <= p.intervals[0].median);
    CHECK(p.intervals[0].median <= p.intervals[0].upper);
    covered += p.intervals[0].lower <= x0 && x0 <= p.intervals[0].upper;
  }
  CAPTURE(covered);
  CHECK(covered >= 167);
  CHECK(covered <= 193);
}

TEST_CASE("Metropolis sampling gives the same coverage in three parameters", "[calibration][posterior]") {
  // As above with two parameters the model ignores (their intervals span about 90 % of the box);
  // 60 repetitions: binomial(60, 0.9) mean 54, sd 2.3, accepted 47-60; measured 53.
  std::unique_ptr<gsl_rng, decltype(&gsl_rng_free)> rng(gsl_rng_alloc(gsl_rng_mt19937), gsl_rng_free);
  gsl_rng_set(rng.get(), 7);
  int covered = 0;
  for (int k = 0; k < 60; ++k) {
    const double x0 = gsl_rng_uniform(rng.get());
    const PosteriorSummary p = calibrate_once(x0, 0.1, rng.get(), true);
    REQUIRE(p.method == "metropolis");
    CHECK(p.acceptance > 0.1);
    CHECK(p.acceptance < 0.6);
    covered += p.intervals[0].lower <= x0 && x0 <= p.intervals[0].upper;
    CHECK(p.intervals[1].upper - p.intervals[1].lower > 0.7);  // uninformed: most of the box
  }
  CAPTURE(covered);
  CHECK(covered >= 47);
}
