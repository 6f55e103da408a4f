#pragma once
// Two-level co-kriging: a cheap model informs the surrogate of an expensive one.
//
// The autoregressive model of Kennedy & O'Hagan (2000, Biometrika 87:1-13) in the recursive form
// of Le Gratiet & Garnier (2014, Int. J. Uncertainty Quantification 4:365-386):
//   y_expensive(x) = rho y_cheap(x) + delta(x),
// y_cheap ~ GP fitted on the cheap runs alone, delta ~ GP independent of it, fitted on the
// expensive runs' residuals y_expensive(X_e) - rho m_cheap(X_e), m_cheap the cheap level's
// posterior mean (its observations themselves on a nested, noise-free design). The scale factor
// rho maximises delta's marginal likelihood, every residual set standardised by the expensive
// outputs' one scale so that the likelihoods compare: a grid over a range around the least-squares
// slope, then a local search. Each level keeps its own noise variance. Predictions of the
// expensive level:
//   mean = rho m_cheap(x) + m_delta(x),  variance = rho^2 v_cheap(x) + v_delta(x).
// The design should be nested (every expensive run also run cheaply, as a calibration loop does);
// a non-nested one is accepted through m_cheap at the expensive points. Without cheap runs the
// surrogate is the expensive runs' own Gaussian process (rho = 0).
#include <optional>

#include "calibration/gaussian_process.hpp"

namespace mfdem::calibration {

struct LevelData {
  Eigen::MatrixXd points;  // n x d, parameters' own units
  Eigen::VectorXd values;  // n
  Eigen::Index size() const { return points.rows(); }
};

class CoKriging final : public Surrogate {
 public:
  CoKriging(std::vector<Bounds> bounds, KernelKind kind = KernelKind::matern52, HyperparameterSearch search = {});

  // Fits both levels (the cheap one may be empty: then the expensive runs' GP alone). Throws
  // std::invalid_argument as GaussianProcess::fit does, for either level.
  void fit(const LevelData& cheap, const LevelData& expensive);
  // Surrogate: the expensive runs alone.
  void fit(const Eigen::MatrixXd& points, const Eigen::VectorXd& values) override;

  Prediction predict(const Eigen::VectorXd& point) const override;  // the expensive level
  Prediction predict_cheap(const Eigen::VectorXd& point) const;     // requires cheap runs

  bool has_cheap_level() const { return cheap_.has_value(); }
  double scale_factor() const { return rho_; }
  // Observation noise variances, in the output's units squared.
  double cheap_noise_variance() const;
  double expensive_noise_variance() const;
  const GaussianProcess& difference() const { return *delta_; }

 private:
  std::vector<Bounds> bounds_;
  KernelKind kind_;
  HyperparameterSearch search_;
  std::optional<GaussianProcess> cheap_, delta_;
  double rho_ = 0.0;
};

}  // namespace mfdem::calibration
