// Gaussian-process regression (calibration/gaussian_process.hpp) and the Sobol design against
// closed forms, brute force and GSL itself.
#include <catch2/catch.hpp>
#include <gsl/gsl_qrng.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include <cmath>
#include <memory>

#include "calibration/gaussian_process.hpp"
#include "calibration/sobol_design.hpp"

using namespace mfdem::calibration;

namespace {

Eigen::MatrixXd as_matrix(const std::vector<std::vector<double>>& points) {
  Eigen::MatrixXd m(points.size(), points.front().size());
  for (std::size_t i = 0; i < points.size(); ++i)
    for (std::size_t a = 0; a < points[i].size(); ++a) m(i, a) = points[i][a];
  return m;
}

double branin_like(const Eigen::VectorXd& x) { return std::sin(3.0 * x(0)) + 0.5 * x(1) * x(1) - x(0) * x(1); }

}  // namespace

TEST_CASE("the unshifted Sobol design is GSL's sequence scaled to the box, and a shift moves every point alike",
          "[calibration][design]") {
  const std::vector<Bounds> box = {{0.0, 0.6}, {0.05, 0.30}, {-1.0, 1.0}};
  const auto design = sobol_design(box, 16);
  std::unique_ptr<gsl_qrng, decltype(&gsl_qrng_free)> q(gsl_qrng_alloc(gsl_qrng_sobol, 3), gsl_qrng_free);
  double u[3];
  for (const auto& point : design) {
    gsl_qrng_get(q.get(), u);
    for (int a = 0; a < 3; ++a) CHECK(point[a] == box[a].lower + u[a] * (box[a].upper - box[a].lower));
  }
  const auto shifted = sobol_design(box, 16, 7);
  CHECK(shifted == sobol_design(box, 16, 7));  // seeded
  CHECK(shifted != sobol_design(box, 16, 8));
  for (int a = 0; a < 3; ++a) {
    const double width = box[a].upper - box[a].lower;
    const double shift = std::fmod((shifted[0][a] - design[0][a]) / width + 1.0, 1.0);
    for (std::size_t k = 0; k < design.size(); ++k) {
      CHECK(shifted[k][a] >= box[a].lower);
      CHECK(shifted[k][a] < box[a].upper);
      // The same shift modulo 1 for every point (round-off of the scaling aside).
      const double s = std::fmod((shifted[k][a] - design[k][a]) / width + 1.0, 1.0);
      CHECK(std::min(std::abs(s - shift), 1.0 - std::abs(s - shift)) < 1e-12);
    }
  }
  CHECK_THROWS_AS(sobol_design({{1.0, 1.0}}, 4), std::invalid_argument);
  CHECK_THROWS_AS(sobol_design(box, 0), std::invalid_argument);
}

TEST_CASE("two points in one dimension: the posterior mean and variance by hand", "[calibration][gp]") {
  // y(0) = 1, y(1) = 3; standardised: mean 2, scale sqrt(2), y = -+1/sqrt(2). Squared exponential,
  // l = 0.5, s2 = 1, no noise: K = [[1, c], [c, 1]], c = exp(-2); at x, k = (exp(-r0^2/2),
  // exp(-r1^2/2)) with r0 = x / 0.5, r1 = (1 - x) / 0.5, and K^-1 = [[1, -c], [-c, 1]] / (1 - c^2).
  GaussianProcess gp({{0.0, 1.0}}, KernelKind::squared_exponential);
  Eigen::MatrixXd x(2, 1);
  x << 0.0, 1.0;
  Eigen::VectorXd y(2);
  y << 1.0, 3.0;
  Hyperparameters h;
  h.length_scales = Eigen::VectorXd::Constant(1, 0.5);
  h.signal_variance = 1.0;
  h.noise_variance = 0.0;
  gp.fit(x, y, h);
  CHECK(gp.jitter() == 0.0);
  const double c = std::exp(-2.0), s = 1.0 / std::sqrt(2.0);
  for (double at : {0.25, 0.5, 0.9}) {
    const double k0 = std::exp(-0.5 * std::pow(at / 0.5, 2)), k1 = std::exp(-0.5 * std::pow((1 - at) / 0.5, 2));
    const double a0 = (-s - c * s) / (1 - c * c), a1 = (s + c * s) / (1 - c * c);  // K^-1 y
    const double mean = 2.0 + std::sqrt(2.0) * (k0 * a0 + k1 * a1);
    const double quad = (k0 * k0 - 2 * c * k0 * k1 + k1 * k1) / (1 - c * c);     // k^T K^-1 k
    const double variance = 2.0 * (1.0 - quad);
    const Prediction p = gp.predict(Eigen::VectorXd::Constant(1, at));
    CAPTURE(at);
    CHECK(p.mean == Approx(mean).epsilon(1e-12));
    CHECK(p.variance == Approx(variance).epsilon(1e-10));
  }
}

TEST_CASE("without noise the process interpolates its data with no variance there", "[calibration][gp]") {
  const std::vector<Bounds> box = {{-1.0, 2.0}, {0.0, 3.0}};
  const Eigen::MatrixXd x = as_matrix(sobol_design(box, 12, 3));
  Eigen::VectorXd y(x.rows());
  for (Eigen::Index i = 0; i < x.rows(); ++i) y(i) = branin_like(x.row(i).transpose());
  GaussianProcess gp(box);
  Hyperparameters h;
  h.length_scales = Eigen::Vector2d(0.4, 0.6);
  h.signal_variance = 1.5;
  h.noise_variance = 0.0;
  gp.fit(x, y, h);
  const double scale = gp.output_scale().scale;
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    const Prediction p = gp.predict(x.row(i).transpose());
    // To round-off in a Cholesky of a condition number about 1e6 (with any jitter it added).
    CHECK(p.mean == Approx(y(i)).margin(1e-8 * scale));
    CHECK(p.variance <= 1e-8 * scale * scale + gp.jitter() * scale * scale);
  }
  // Away from the data the variance is positive.
  CHECK(gp.predict(Eigen::Vector2d(0.5, 1.5)).variance > 1e-6);
}

TEST_CASE("the closed-form leave-one-out equals refitting without each point", "[calibration][gp]") {
  const std::vector<Bounds> box = {{0.0, 0.6}, {0.05, 0.3}};
  const Eigen::MatrixXd x = as_matrix(sobol_design(box, 10, 11));
  Eigen::VectorXd y(x.rows());
  for (Eigen::Index i = 0; i < x.rows(); ++i) y(i) = 3.0 * x(i, 0) + std::cos(10.0 * x(i, 1));
  Hyperparameters h;
  h.length_scales = Eigen::Vector2d(0.5, 0.3);
  h.signal_variance = 1.2;
  h.noise_variance = 0.05;
  GaussianProcess all(box);
  all.fit(x, y, h);
  const LeaveOneOut loo = all.leave_one_out();
  const OutputScale scale = all.output_scale();
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    Eigen::MatrixXd rest(x.rows() - 1, 2);
    Eigen::VectorXd rest_y(x.rows() - 1);
    for (Eigen::Index j = 0, k = 0; j < x.rows(); ++j)
      if (j != i) rest.row(k) = x.row(j), rest_y(k++) = y(j);
    GaussianProcess without(box);
    without.fit(rest, rest_y, h, scale);  // the same standardisation, as the closed form assumes
    const Prediction p = without.predict(x.row(i).transpose());
    CAPTURE(i);
    CHECK(loo.mean(i) == Approx(p.mean).epsilon(1e-9));
    // The closed form predicts y_i, noise included.
    CHECK(loo.variance(i) == Approx(p.variance + h.noise_variance * scale.scale * scale.scale).epsilon(1e-9));
  }
}

TEST_CASE("the gradient of the log marginal likelihood matches central differences", "[calibration][gp]") {
  const std::vector<Bounds> box = {{0.0, 1.0}, {0.0, 1.0}};
  const Eigen::MatrixXd x = as_matrix(sobol_design(box, 9, 5));
  Eigen::VectorXd y(x.rows());
  for (Eigen::Index i = 0; i < x.rows(); ++i) y(i) = branin_like(x.row(i).transpose());
  for (KernelKind kind : {KernelKind::matern52, KernelKind::squared_exponential}) {
    GaussianProcess gp(box, kind);
    Hyperparameters h;
    h.length_scales = Eigen::Vector2d(0.3, 0.7);
    h.noise_variance = 1e-3;
    gp.fit(x, y, h);
    Eigen::VectorXd theta(4);
    theta << std::log(0.35), std::log(0.8), std::log(1.3), std::log(0.02);
    Eigen::VectorXd gradient;
    gp.log_likelihood_at(theta, &gradient);
    for (Eigen::Index j = 0; j < theta.size(); ++j) {
      const double step = 1e-5;
      Eigen::VectorXd up = theta, down = theta;
      up(j) += step, down(j) -= step;
      const double numeric = (gp.log_likelihood_at(up, nullptr) - gp.log_likelihood_at(down, nullptr)) / (2 * step);
      CAPTURE(j, kind == KernelKind::matern52);
      CHECK(gradient(j) == Approx(numeric).epsilon(1e-6).margin(1e-8));  // central differences: O(step^2)
    }
  }
}

TEST_CASE("the fitted noise variance of a constant with Gaussian noise is the noise's, within its sampling error",
          "[calibration][gp]") {
  // 60 points of 5 + N(0, 0.1^2) on [0, 1]: the maximum-likelihood noise variance is about the
  // sample variance, 0.01 within its relative sampling error sqrt(2 / 59) = 0.18; allowed 3 of them.
  std::unique_ptr<gsl_rng, decltype(&gsl_rng_free)> rng(gsl_rng_alloc(gsl_rng_mt19937), gsl_rng_free);
  gsl_rng_set(rng.get(), 42);
  const std::vector<Bounds> box = {{0.0, 1.0}};
  const Eigen::MatrixXd x = as_matrix(sobol_design(box, 60, 1));
  Eigen::VectorXd y(x.rows());
  for (Eigen::Index i = 0; i < x.rows(); ++i) y(i) = 5.0 + gsl_ran_gaussian(rng.get(), 0.1);
  GaussianProcess gp(box);
  gp.fit(x, y);
  const double noise = gp.hyperparameters().noise_variance * std::pow(gp.output_scale().scale, 2);
  CHECK(noise == Approx(0.01).epsilon(3 * std::sqrt(2.0 / 59.0)));
  CHECK(std::abs(gp.predict(Eigen::VectorXd::Constant(1, 0.37)).mean - 5.0) < 0.05);
}

TEST_CASE("repeated points and a constant output are handled with a note, never a NaN", "[calibration][gp]") {
  const std::vector<Bounds> box = {{0.0, 1.0}};
  Eigen::MatrixXd x(4, 1);
  x << 0.2, 0.2, 0.7, 0.7;
  Eigen::VectorXd y(4);
  y << 1.0, 1.0, 1.0, 1.0;
  GaussianProcess gp(box);
  Hyperparameters h;
  h.length_scales = Eigen::VectorXd::Constant(1, 0.3);
  h.noise_variance = 0.0;  // repeated points without noise: K is singular, the jitter says so
  gp.fit(x, y, h);
  CHECK(gp.jitter() > 0.0);
  REQUIRE(gp.notes().size() == 2);
  CHECK_THAT(gp.notes()[0], Catch::Contains("constant"));
  CHECK_THAT(gp.notes()[1], Catch::Contains("2 points repeat"));
  const Prediction p = gp.predict(Eigen::VectorXd::Constant(1, 0.5));
  CHECK(p.mean == Approx(1.0).margin(1e-12));
  CHECK(std::isfinite(p.variance));
  GaussianProcess searched(box);
  searched.fit(x, y);  // the hyperparameter search on the same data
  CHECK(std::isfinite(searched.predict(Eigen::VectorXd::Constant(1, 0.5)).mean));
  CHECK_THROWS_AS(gp.fit(Eigen::MatrixXd::Constant(1, 1, 0.5), Eigen::VectorXd::Constant(1, 1.0)), std::invalid_argument);
  Eigen::MatrixXd outside(2, 1);
  outside << 0.5, 1.5;
  CHECK_THROWS_WITH(gp.fit(outside, Eigen::Vector2d(1, 2)), Catch::Contains("outside the bounds"));
}

TEST_CASE("length scales are recovered from a sample of a process with known ones", "[calibration][gp]") {
  // One draw of a Matern 5/2 process with l = (0.15, 0.6) in the unit square at 80 Sobol points
  // (plus noise of variance 1e-4): the maximum-likelihood length scales lie within a factor 1.6
  // of the true ones (a single draw; with 80 points the estimate's own scatter is about 20 %).
  const std::vector<Bounds> box = {{0.0, 1.0}, {0.0, 1.0}};
  const Eigen::MatrixXd x = as_matrix(sobol_design(box, 80, 2));
  const Eigen::Vector2d truth(0.15, 0.6);
  Eigen::MatrixXd k(x.rows(), x.rows());
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    for (Eigen::Index j = 0; j < x.rows(); ++j)
      k(i, j) = kernel_correlation(KernelKind::matern52,
                                   scaled_distance(x.row(i).transpose(), x.row(j).transpose(), truth)) +
                (i == j ? 1e-4 : 0.0);
  const Eigen::MatrixXd l = Eigen::LLT<Eigen::MatrixXd>(k).matrixL();
  std::unique_ptr<gsl_rng, decltype(&gsl_rng_free)> rng(gsl_rng_alloc(gsl_rng_mt19937), gsl_rng_free);
  gsl_rng_set(rng.get(), 2026);
  Eigen::VectorXd z(x.rows());
  for (Eigen::Index i = 0; i < z.size(); ++i) z(i) = gsl_ran_gaussian(rng.get(), 1.0);
  const Eigen::VectorXd y = l * z;
  GaussianProcess gp(box, KernelKind::matern52);
  gp.fit(x, y);
  const Eigen::VectorXd fitted = gp.hyperparameters().length_scales;
  CAPTURE(fitted(0), fitted(1));
  for (int a = 0; a < 2; ++a) {
    CHECK(fitted(a) / truth(a) > 1.0 / 1.6);
    CHECK(fitted(a) / truth(a) < 1.6);
  }
}

TEST_CASE("several outputs on the same points are fitted as the independent processes one by one",
          "[calibration][gp]") {
  const std::vector<Bounds> box = {{0.0, 0.6}, {0.05, 0.3}};
  const Eigen::MatrixXd x = as_matrix(sobol_design(box, 12, 9));
  Eigen::MatrixXd y(x.rows(), 2);
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    y(i, 0) = 12.0 - 4.0 * x(i, 0) + 10.0 * x(i, 1), y(i, 1) = 2.0 + std::sin(8.0 * x(i, 0)) * x(i, 1);
  const auto both = fit_outputs(box, x, y);
  REQUIRE(both.size() == 2);
  for (int j = 0; j < 2; ++j) {
    GaussianProcess alone(box);
    alone.fit(x, y.col(j));
    const Eigen::Vector2d at(0.3, 0.2);
    CHECK(both[j].predict(at).mean == alone.predict(at).mean);  // bitwise: the same fit
    CHECK(both[j].hyperparameters().length_scales == alone.hyperparameters().length_scales);
  }
  CHECK_THROWS_AS(fit_outputs(box, x, Eigen::MatrixXd::Zero(3, 2)), std::invalid_argument);
}

TEST_CASE("replicates at the same points give the noise variance of their scatter", "[calibration][gp]") {
  // 12 points x 4 replicates of 2 + 3 x + N(0, 0.05^2): the fitted noise variance is the scatter's,
  // 0.0025, within 3 relative standard errors sqrt(2 / 36) of a variance from 36 degrees of freedom.
  std::unique_ptr<gsl_rng, decltype(&gsl_rng_free)> rng(gsl_rng_alloc(gsl_rng_mt19937), gsl_rng_free);
  gsl_rng_set(rng.get(), 7);
  const std::vector<Bounds> box = {{0.0, 1.0}};
  const auto design = sobol_design(box, 12, 4);
  Eigen::MatrixXd x(48, 1);
  Eigen::VectorXd y(48);
  for (int i = 0; i < 48; ++i) {
    x(i, 0) = design[i / 4][0];
    y(i) = 2.0 + 3.0 * x(i, 0) + gsl_ran_gaussian(rng.get(), 0.05);
  }
  GaussianProcess gp(box);
  gp.fit(x, y);
  CHECK(gp.jitter() == 0.0);  // the noise makes K positive definite however the points repeat
  CHECK_THAT(gp.notes().back(), Catch::Contains("36 points repeat"));
  const double noise = gp.hyperparameters().noise_variance * std::pow(gp.output_scale().scale, 2);
  CHECK(noise == Approx(0.0025).epsilon(3 * std::sqrt(2.0 / 36.0)));
  CHECK(gp.predict(Eigen::VectorXd::Constant(1, 0.5)).mean == Approx(3.5).margin(0.03));
}

TEST_CASE("a Latin hypercube puts one point in each slice of every axis, reproducibly", "[calibration][design]") {
  const std::vector<Bounds> box = {{0.0, 0.6}, {0.05, 0.30}};
  const auto design = latin_hypercube(box, 10, 3);
  CHECK(design == latin_hypercube(box, 10, 3));
  CHECK(design != latin_hypercube(box, 10, 4));
  for (int a = 0; a < 2; ++a) {
    std::vector<int> in_slice(10, 0);
    const double width = (box[a].upper - box[a].lower) / 10;
    for (const auto& p : design) {
      const int slice = static_cast<int>(std::floor((p[a] - box[a].lower) / width));
      REQUIRE(slice >= 0);
      REQUIRE(slice < 10);
      ++in_slice[slice];
    }
    for (int count : in_slice) CHECK(count == 1);
  }
}
