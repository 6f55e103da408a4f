#pragma once
// The calibration misfit: how far a model's outputs lie from their targets, as one number,
//   M(x) = sum_j ((y_j(x) - t_j) / s_j)^2,
// s_j the target's scale (|t_j| for relative errors: the peak lateral force and the maximum
// contact force of the multi-layer model against the all-clump reference). Each output comes from
// its own surrogate, y_j ~ N(m_j, v_j) independent; with e_j = m_j - t_j the misfit's moments
// are exact (a sum of scaled non-central chi-squares of one degree of freedom):
//   E[M]   = sum_j (e_j^2 + v_j) / s_j^2,
//   Var[M] = sum_j (4 e_j^2 v_j + 2 v_j^2) / s_j^4.
#include <Eigen/Dense>

#include <span>
#include <vector>

#include "calibration/surrogate.hpp"

namespace mfdem::calibration {

struct Target {
  double value = 0.0;
  double scale = 1.0;  // > 0, in the output's units
};

// A target whose misfit term is the squared relative error; throws std::invalid_argument for 0.
Target relative_target(double value);

// M of observed outputs (one per target).
double misfit(const Eigen::VectorXd& outputs, std::span<const Target> targets);

struct MisfitPrediction {
  double mean = 0.0;
  double variance = 0.0;        // from the surrogates' latent variances
  double noise_variance = 0.0;  // what one run's observation noise adds (same formula, noise variances)
};

// The misfit's moments from each output's prediction and observation noise variance.
MisfitPrediction predict_misfit(std::span<const Prediction> outputs, std::span<const double> noise_variances,
                                std::span<const Target> targets);

}  // namespace mfdem::calibration
