#pragma once
// What the calibration layer asks of a surrogate of an expensive, noisy model: fit it on points
// and outputs, then predict the output's mean and variance anywhere. The model itself is only
// ever a function of its parameters (as emukit and SMT keep it).
#include <Eigen/Dense>

namespace mfdem::calibration {

struct Prediction {
  double mean = 0.0;
  double variance = 0.0;  // of the latent function (without the observation noise)
};

class Surrogate {
 public:
  virtual ~Surrogate() = default;
  // points: n x d, in the parameters' own units; values: n.
  virtual void fit(const Eigen::MatrixXd& points, const Eigen::VectorXd& values) = 0;
  virtual Prediction predict(const Eigen::VectorXd& point) const = 0;
};

}  // namespace mfdem::calibration
