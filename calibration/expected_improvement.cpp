#include "calibration/expected_improvement.hpp"

#include <gsl/gsl_cdf.h>
#include <gsl/gsl_randist.h>

#include <algorithm>
#include <cmath>

namespace mfdem::calibration {

double expected_improvement(double incumbent, double mean, double standard_deviation) {
  const double gain = incumbent - mean;
  if (!(standard_deviation > 0.0)) return std::max(gain, 0.0);
  const double z = gain / standard_deviation;
  return gain * gsl_cdf_ugaussian_P(z) + standard_deviation * gsl_ran_ugaussian_pdf(z);
}

double noise_aware_expected_improvement(double incumbent, double mean, double variance, double noise_variance) {
  const double s = std::sqrt(std::max(variance, 0.0));
  const double tau = std::sqrt(std::max(noise_variance, 0.0));
  const double ei = expected_improvement(incumbent, mean, s);
  if (tau == 0.0) return ei;
  return ei * (1.0 - tau / std::sqrt(s * s + tau * tau));
}

}  // namespace mfdem::calibration
