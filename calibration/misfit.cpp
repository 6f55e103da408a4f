#include "calibration/misfit.hpp"

#include <cmath>
#include <stdexcept>

namespace mfdem::calibration {
namespace {

void require_sizes(std::size_t given, std::size_t targets) {
  if (given != targets) throw std::invalid_argument("misfit: one output per target expected");
}

}  // namespace

Target relative_target(double value) {
  if (!(std::abs(value) > 0.0) || !std::isfinite(value))
    throw std::invalid_argument("a relative target needs a finite, non-zero value");
  return {value, std::abs(value)};
}

double misfit(const Eigen::VectorXd& outputs, std::span<const Target> targets) {
  require_sizes(static_cast<std::size_t>(outputs.size()), targets.size());
  double m = 0.0;
  for (std::size_t j = 0; j < targets.size(); ++j) {
    const double e = (outputs(static_cast<Eigen::Index>(j)) - targets[j].value) / targets[j].scale;
    m += e * e;
  }
  return m;
}

MisfitPrediction predict_misfit(std::span<const Prediction> outputs, std::span<const double> noise_variances,
                                std::span<const Target> targets) {
  require_sizes(outputs.size(), targets.size());
  require_sizes(noise_variances.size(), targets.size());
  MisfitPrediction p;
  for (std::size_t j = 0; j < targets.size(); ++j) {
    const double s2 = targets[j].scale * targets[j].scale;
    const double e = outputs[j].mean - targets[j].value;
    const double v = outputs[j].variance, n = noise_variances[j];
    p.mean += (e * e + v) / s2;
    p.variance += (4.0 * e * e * v + 2.0 * v * v) / (s2 * s2);
    p.noise_variance += (4.0 * e * e * n + 2.0 * n * n) / (s2 * s2);
  }
  return p;
}

}  // namespace mfdem::calibration
