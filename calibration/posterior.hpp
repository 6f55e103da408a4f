#pragma once
// The calibrated parameters with their uncertainty: the posterior given the targets,
//   p(x | t) ∝ prior(x) prod_j N(t_j; m_j(x), v_j(x) + tau_j^2),
// a uniform prior on the parameters' box, m_j and v_j the expensive level's surrogate of output j
// (its latent mean and variance: the model's mean output over packings, and how sure the
// surrogate is of it), tau_j the target's own standard deviation (the reference's uncertainty,
// or one noisy observation's scatter). On a grid for one or two parameters, else by random-walk
// Metropolis with GSL's random numbers (the step tuned to an acceptance near 0.3 during burn-in).
// Reported: the marginal 5 % and 95 % quantiles (a 90 % interval) and median of each parameter,
// and the posterior's mode as the point estimate.
#include <cstdint>
#include <string>
#include <vector>

#include "calibration/misfit_surrogate.hpp"

namespace mfdem::calibration {

struct PosteriorOptions {
  std::vector<double> target_sd;  // tau_j, one per target, >= 0
  int grid_points = 201;          // per parameter, on the grid (d <= 2)
  int samples = 20000;            // Metropolis samples kept (d > 2)
  int burn_in = 4000;
  std::uint64_t seed = 1;
  double interval = 0.90;
};

struct ParameterInterval {
  double lower = 0.0, median = 0.0, upper = 0.0;
};

struct PosteriorSummary {
  Eigen::VectorXd mode;                       // the most probable parameters
  std::vector<ParameterInterval> intervals;   // one per parameter
  std::string method;                         // "grid" or "metropolis"
  double acceptance = 0.0;                    // Metropolis only
};

// log p(t | x) up to a constant (the prior is flat inside the box).
double log_likelihood(const MisfitSurrogate& surrogate, const Eigen::VectorXd& point, const std::vector<double>& target_sd);

PosteriorSummary calibration_posterior(const MisfitSurrogate& surrogate, const PosteriorOptions& options);

}  // namespace mfdem::calibration
