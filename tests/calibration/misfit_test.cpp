// The calibration misfit's moments (calibration/misfit.hpp) and expected improvement
// (calibration/expected_improvement.hpp) against sampling, quadrature and a fitted process.
#include <catch2/catch.hpp>
#include <gsl/gsl_integration.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include <cmath>
#include <memory>
#include <vector>

#include "calibration/expected_improvement.hpp"
#include "calibration/gaussian_process.hpp"
#include "calibration/misfit.hpp"

using namespace mfdem::calibration;

TEST_CASE("the misfit's mean and variance match a million samples of the outputs", "[calibration][misfit]") {
  // Two outputs, as a calibration has (peak lateral force, maximum contact force), in N: one
  // near its target, one 10 % off, with standard deviations 3 % and 5 % of the targets.
  const std::vector<Target> targets = {relative_target(1000.0), relative_target(350.0)};
  const std::vector<Prediction> outputs = {{1010.0, 30.0 * 30.0}, {385.0, 17.5 * 17.5}};
  const std::vector<double> noise = {0.0, 0.0};
  const MisfitPrediction p = predict_misfit(outputs, noise, targets);
  std::unique_ptr<gsl_rng, decltype(&gsl_rng_free)> rng(gsl_rng_alloc(gsl_rng_mt19937), gsl_rng_free);
  gsl_rng_set(rng.get(), 11);
  const int n = 1000000;
  double sum = 0.0, sum2 = 0.0;
  Eigen::VectorXd y(2);
  for (int k = 0; k < n; ++k) {
    y(0) = 1010.0 + gsl_ran_gaussian(rng.get(), 30.0);
    y(1) = 385.0 + gsl_ran_gaussian(rng.get(), 17.5);
    const double m = misfit(y, targets);
    sum += m, sum2 += m * m;
  }
  const double mean = sum / n, variance = sum2 / n - mean * mean;
  // Tolerances: 4 standard errors of the sample mean; 1 % of the variance (its standard error
  // at 1e6 samples of this skewed sum is about 0.3 %).
  CHECK(p.mean == Approx(mean).margin(4.0 * std::sqrt(variance / n)));
  CHECK(p.variance == Approx(variance).epsilon(0.01));
  // By hand: (0.01^2 + 0.03^2) + (0.1^2 + 0.05^2) = 0.0135.
  CHECK(p.mean == Approx(0.0135).epsilon(1e-12));
  CHECK_THROWS_AS(relative_target(0.0), std::invalid_argument);
}

TEST_CASE("expected improvement matches its integral, and is zero at a noise-free incumbent", "[calibration][ei]") {
  // E[max(I - Y, 0)] for Y ~ N(m, s^2) by adaptive quadrature of (I - y) phi over y < I.
  struct Case {
    double incumbent, mean, sd;
  };
  for (const Case c : {Case{1.0, 1.3, 0.4}, Case{1.0, 0.2, 0.5}, Case{-2.0, -2.0, 1e-3}, Case{5.0, 9.0, 1.0}}) {
    gsl_function f;
    f.function = [](double y, void* p) {
      const auto* c = static_cast<const Case*>(p);
      return (c->incumbent - y) * gsl_ran_gaussian_pdf(y - c->mean, c->sd);
    };
    f.params = const_cast<Case*>(&c);
    std::unique_ptr<gsl_integration_workspace, decltype(&gsl_integration_workspace_free)> w(
        gsl_integration_workspace_alloc(1000), gsl_integration_workspace_free);
    double integral = 0.0, error = 0.0;
    gsl_integration_qags(&f, c.mean - 40.0 * c.sd, c.incumbent, 0.0, 1e-12, 1000, w.get(), &integral, &error);
    CAPTURE(c.incumbent, c.mean, c.sd, integral);
    CHECK(expected_improvement(c.incumbent, c.mean, c.sd) == Approx(integral).epsilon(1e-9).margin(1e-14));
  }
  CHECK(expected_improvement(1.0, 0.25, 0.0) == 0.75);  // certain: the gain itself
  CHECK(expected_improvement(1.0, 1.5, 0.0) == 0.0);

  // A noise-free process through five points: at the point with the smallest value (the
  // incumbent) the posterior is certain and equals it, so nothing can be gained there.
  HyperparameterSearch exact;
  exact.smallest_noise = exact.largest_noise = 1e-10;
  GaussianProcess gp({{0.0, 1.0}}, KernelKind::matern52, exact);
  Eigen::MatrixXd x(5, 1);
  x << 0.0, 0.25, 0.5, 0.75, 1.0;
  Eigen::VectorXd y(5);
  y << 1.0, 0.3, -0.4, 0.1, 0.9;
  gp.fit(x, y);
  const Prediction at_best = gp.predict(Eigen::VectorXd::Constant(1, 0.5));
  const double incumbent = at_best.mean;
  // Zero up to the process's 1e-10 noise floor (a variance of about 1e-11 there): below 1e-5 of
  // the outputs' range of 1.4.
  CHECK(at_best.mean == Approx(-0.4).margin(1e-6));
  CHECK(noise_aware_expected_improvement(incumbent, at_best.mean, at_best.variance, 0.0) < 1.4e-5);
  const Prediction between = gp.predict(Eigen::VectorXd::Constant(1, 0.6));
  CHECK(noise_aware_expected_improvement(incumbent, between.mean, between.variance, 0.0) > 1e-3);
  // Noise-aware: where the uncertainty is mostly observation noise, the gain shrinks by
  // 1 - tau / sqrt(s^2 + tau^2) (Huang et al. 2006): s = 0.1, tau = 0.3 keeps 5.1 %.
  const double plain = expected_improvement(0.0, 0.05, 0.1);
  CHECK(noise_aware_expected_improvement(0.0, 0.05, 0.01, 0.09) == Approx(plain * (1.0 - 0.3 / std::sqrt(0.1))));
}

TEST_CASE("the expected improvement of one squared error matches its integral", "[calibration][ei]") {
  // E[max(I - ((Y - t) / c)^2, 0)], Y ~ N(m, s^2), by adaptive quadrature over |y - t| < c sqrt(I).
  struct Case {
    double incumbent, mean, sd, target, scale;
  };
  for (const Case c : {Case{0.04, 1.05, 0.1, 1.0, 1.0}, Case{0.01, 0.7, 0.2, 1.0, 1.0}, Case{0.5, -3.0, 1.0, -3.86, 3.86},
                       Case{1e-4, 2.0, 1e-3, 2.0, 2.0}}) {
    gsl_function f;
    f.function = [](double y, void* p) {
      const auto* c = static_cast<const Case*>(p);
      const double m = std::pow((y - c->target) / c->scale, 2);
      return (c->incumbent - m) * gsl_ran_gaussian_pdf(y - c->mean, c->sd);
    };
    f.params = const_cast<Case*>(&c);
    std::unique_ptr<gsl_integration_workspace, decltype(&gsl_integration_workspace_free)> w(
        gsl_integration_workspace_alloc(1000), gsl_integration_workspace_free);
    const double r = c.scale * std::sqrt(c.incumbent);
    double integral = 0.0, error = 0.0;
    gsl_integration_qags(&f, c.target - r, c.target + r, 0.0, 1e-12, 1000, w.get(), &integral, &error);
    CAPTURE(c.incumbent, c.mean, c.sd, integral);
    CHECK(squared_error_expected_improvement(c.incumbent, c.mean, c.sd, c.target, c.scale) ==
          Approx(integral).epsilon(1e-8).margin(1e-15));
  }
  // Certain outputs: the gain itself, or nothing.
  CHECK(squared_error_expected_improvement(0.04, 1.1, 0.0, 1.0, 1.0) == Approx(0.03));
  CHECK(squared_error_expected_improvement(0.04, 1.3, 0.0, 1.0, 1.0) == 0.0);
}
