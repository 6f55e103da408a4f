// Two-level co-kriging (calibration/co_kriging.hpp) on the Forrester pair and on exact scalings.
#include <catch2/catch.hpp>

#include <cmath>

#include "calibration/co_kriging.hpp"
#include "calibration/sobol_design.hpp"

using namespace mfdem::calibration;

namespace {

// Forrester, Sobester & Keane (2008), Engineering Design via Surrogate Modelling, p. 164: the
// expensive function and its cheap, biased relative on [0, 1].
double forrester(double x) { return std::pow(6.0 * x - 2.0, 2) * std::sin(12.0 * x - 4.0); }
double forrester_cheap(double x) { return 0.5 * forrester(x) + 10.0 * (x - 0.5) - 5.0; }

LevelData level(const std::vector<double>& xs, double (*f)(double)) {
  LevelData d{Eigen::MatrixXd(xs.size(), 1), Eigen::VectorXd(xs.size())};
  for (std::size_t i = 0; i < xs.size(); ++i) d.points(i, 0) = xs[i], d.values(i) = f(xs[i]);
  return d;
}

// Root mean square error of the expensive level's prediction over 201 points of [0, 1].
template <class Model>
double rms_error(const Model& model) {
  double sum = 0.0;
  for (int k = 0; k <= 200; ++k) {
    const double x = k / 200.0;
    sum += std::pow(model.predict(Eigen::VectorXd::Constant(1, x)).mean - forrester(x), 2);
  }
  return std::sqrt(sum / 201.0);
}

// A deterministic output: the noise is held at 1e-10 (interpolation up to round-off).
HyperparameterSearch noise_free() {
  HyperparameterSearch s;
  s.smallest_noise = s.largest_noise = 1e-10;
  return s;
}

const std::vector<double> kCheapDesign = {0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0};
const std::vector<double> kExpensiveDesign = {0.0, 0.4, 0.6, 1.0};  // nested in the cheap one

}  // namespace

TEST_CASE("co-kriging without cheap runs is the expensive runs' Gaussian process", "[calibration][cokriging]") {
  const LevelData expensive = level(kExpensiveDesign, forrester);
  CoKriging ck({{0.0, 1.0}}, KernelKind::matern52, noise_free());
  ck.fit(LevelData{Eigen::MatrixXd(0, 1), Eigen::VectorXd(0)}, expensive);
  GaussianProcess gp({{0.0, 1.0}}, KernelKind::matern52, noise_free());
  gp.fit(expensive.points, expensive.values);
  CHECK_FALSE(ck.has_cheap_level());
  CHECK(ck.scale_factor() == 0.0);
  for (double x : {0.05, 0.33, 0.71, 0.98}) {
    const Eigen::VectorXd at = Eigen::VectorXd::Constant(1, x);
    CHECK(ck.predict(at).mean == gp.predict(at).mean);  // the same computation, bit for bit
    CHECK(ck.predict(at).variance == gp.predict(at).variance);
  }
}

TEST_CASE("an expensive level that is the cheap one scaled gives back the scale factor", "[calibration][cokriging]") {
  // y_e = 2.5 y_c + 3 exactly: the residual 3 is constant (taken out as delta's mean) at rho = 2.5,
  // where delta's likelihood peaks. Tolerance 1e-3 of rho: the local search stops at 1e-6 of its
  // range; the cheap level's interpolation error at the nested points is round-off.
  const LevelData cheap = level(kCheapDesign, forrester_cheap);
  LevelData expensive = level(kExpensiveDesign, forrester_cheap);
  expensive.values = 2.5 * expensive.values.array() + 3.0;
  CoKriging ck({{0.0, 1.0}}, KernelKind::matern52, noise_free());
  ck.fit(cheap, expensive);
  REQUIRE(ck.has_cheap_level());
  CHECK(ck.scale_factor() == Approx(2.5).epsilon(1e-3));
  // And the prediction of the expensive level follows the cheap one's shape everywhere.
  for (double x : {0.05, 0.33, 0.71, 0.98})
    CHECK(ck.predict(Eigen::VectorXd::Constant(1, x)).mean ==
          Approx(2.5 * ck.predict_cheap(Eigen::VectorXd::Constant(1, x)).mean + 3.0).margin(0.05));
}

TEST_CASE("cheap runs make the Forrester surrogate several times better than four expensive runs alone",
          "[calibration][cokriging]") {
  // Forrester et al. (2008, sec. 8.1): 11 cheap and 4 expensive runs; y_e = 2 y_c - 20 (x - 0.5) +
  // 10, so the cheap level explains the expensive one up to a linear term. Measured: RMS error
  // over [0, 1] of co-kriging 0.18 against 5.45 for the four expensive runs' own process; the
  // test asks for a factor of 5 and rho within 10 % of 2.
  const LevelData cheap = level(kCheapDesign, forrester_cheap);
  const LevelData expensive = level(kExpensiveDesign, forrester);
  CoKriging ck({{0.0, 1.0}}, KernelKind::matern52, noise_free());
  ck.fit(cheap, expensive);
  GaussianProcess alone({{0.0, 1.0}}, KernelKind::matern52, noise_free());
  alone.fit(expensive.points, expensive.values);
  const double with_cheap = rms_error(ck), without = rms_error(alone);
  CAPTURE(with_cheap, without, ck.scale_factor());
  CHECK(with_cheap * 5.0 < without);
  CHECK(ck.scale_factor() == Approx(2.0).epsilon(0.1));
}

TEST_CASE("each level keeps its own noise variance", "[calibration][cokriging]") {
  // Replicated runs with known scatter: the cheap level at 3 replicates of 9 points with noise
  // sd 0.3, the expensive at 3 replicates of 5 nested points with sd 0.05 (the deterministic
  // Forrester pair plus fixed pseudo-random offsets of those sizes). Fitted noise variances within
  // a factor 3 of the truth (27 and 15 residuals: the sampling spread of a variance is wide;
  // measured 0.073 against 0.09 and 0.0034 against 0.0025).
  const std::vector<double> cheap_x = {0.0, 0.125, 0.25, 0.375, 0.5, 0.625, 0.75, 0.875, 1.0};
  const std::vector<double> expensive_x = {0.0, 0.25, 0.5, 0.75, 1.0};
  // Standard normal values (fixed, so the test is deterministic): a table of 27.
  const double z[27] = {0.49,  -1.38, 0.65, 1.52,  -0.23, -0.23, 1.58, 0.77,  -0.47, 0.54,  -0.46, -0.47, 0.24, -1.91,
                        -1.72, -0.56, -1.01, 0.31, -0.91, -1.41, 1.47, -0.23, 0.07,  -1.42, -0.54, 0.11,  -1.15};
  LevelData cheap{Eigen::MatrixXd(27, 1), Eigen::VectorXd(27)}, expensive{Eigen::MatrixXd(15, 1), Eigen::VectorXd(15)};
  for (int r = 0; r < 3; ++r) {
    for (int i = 0; i < 9; ++i)
      cheap.points(9 * r + i, 0) = cheap_x[i], cheap.values(9 * r + i) = forrester_cheap(cheap_x[i]) + 0.3 * z[9 * r + i];
    for (int i = 0; i < 5; ++i)
      expensive.points(5 * r + i, 0) = expensive_x[i],
                              expensive.values(5 * r + i) = forrester(expensive_x[i]) + 0.05 * z[(5 * r + 2 * i + 1) % 27];
  }
  CoKriging ck({{0.0, 1.0}});
  ck.fit(cheap, expensive);
  CAPTURE(ck.cheap_noise_variance(), ck.expensive_noise_variance(), ck.scale_factor());
  CHECK(ck.cheap_noise_variance() > 0.09 / 3.0);
  CHECK(ck.cheap_noise_variance() < 0.09 * 3.0);
  CHECK(ck.expensive_noise_variance() > 0.0025 / 3.0);
  CHECK(ck.expensive_noise_variance() < 0.0025 * 3.0);
}
