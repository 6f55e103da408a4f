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

double squared_error_expected_improvement(double incumbent, double mean, double standard_deviation, double target,
                                          double scale) {
  if (!(incumbent > 0.0)) return 0.0;
  const double e = mean - target, s = standard_deviation;
  if (!(s > 0.0)) return std::max(incumbent - e * e / (scale * scale), 0.0);
  const double r = scale * std::sqrt(incumbent);  // |Y - t| below r improves
  const double a = (-r - e) / s, b = (r - e) / s;
  const double mass = gsl_cdf_ugaussian_P(b) - gsl_cdf_ugaussian_P(a);
  const double pa = gsl_ran_ugaussian_pdf(a), pb = gsl_ran_ugaussian_pdf(b);
  // E[(e + s u)^2 ; a < u < b] = e^2 mass + 2 e s (phi(a) - phi(b)) + s^2 (mass + a phi(a) - b phi(b)).
  const double second = e * e * mass + 2.0 * e * s * (pa - pb) + s * s * (mass + a * pa - b * pb);
  return std::max(incumbent * mass - second / (scale * scale), 0.0);
}

double noise_factor(double variance, double noise_variance) {
  const double s2 = std::max(variance, 0.0), tau2 = std::max(noise_variance, 0.0);
  if (tau2 == 0.0) return 1.0;
  return 1.0 - std::sqrt(tau2 / (s2 + tau2));
}

double noise_aware_expected_improvement(double incumbent, double mean, double variance, double noise_variance) {
  return expected_improvement(incumbent, mean, std::sqrt(std::max(variance, 0.0))) * noise_factor(variance, noise_variance);
}

}  // namespace mfdem::calibration
