#include "calibration/kernel.hpp"

#include <cmath>

namespace mfdem::calibration {

namespace {
const double kSqrt5 = std::sqrt(5.0);
}

double kernel_correlation(KernelKind kind, double r) {
  if (kind == KernelKind::squared_exponential) return std::exp(-0.5 * r * r);
  return (1.0 + kSqrt5 * r + 5.0 * r * r / 3.0) * std::exp(-kSqrt5 * r);
}

double kernel_log_scale_factor(KernelKind kind, double r) {
  // d r / d log l_i = -((x_i - y_i) / l_i)^2 / r, so dk/dlog l_i = -dk/dr / r x (d_i / l_i)^2.
  if (kind == KernelKind::squared_exponential) return std::exp(-0.5 * r * r);
  return 5.0 / 3.0 * (1.0 + kSqrt5 * r) * std::exp(-kSqrt5 * r);
}

double scaled_distance(const Eigen::VectorXd& x, const Eigen::VectorXd& y, const Eigen::VectorXd& length_scales) {
  return ((x - y).array() / length_scales.array()).matrix().norm();
}

}  // namespace mfdem::calibration
